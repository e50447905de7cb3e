#include "restir_di.hpp"

#include "reservoir.hpp"
#include "timing.hpp"

#include <array>
#include <cmath>
#include <span>
#include <utility>
#include <vector>

namespace pt {

// The recipe's stages and the buffers they read and write.
struct RestirDi::Stages {
    const RenderSettings& settings;
    const PixelBlocks& blocks;
    GBuffer& gbuffer;
    InitialCandidates& candidates;
    const Unified& lights;
    const restir::Falloff& falloff;
    const PathTracer& paths;
    const Camera& camera;
    const Camera& previous_camera;
    const EmbreeScene& rays;
    restir::NeighbourOffsets offsets = restir::make_neighbour_offsets();

    ReservoirBuffer reservoirs, previous_reservoirs, scratch;
    // With --packed-history, the final reservoirs in storage form instead of
    // `previous_reservoirs`: next frame's history in 28 bytes a pixel instead of 64, its light
    // points decoded from the light set (`LightPointDecoder`).
    std::vector<restir::PackedPointReservoir> stored_history;

    Stages(const RenderSettings& rs, const PixelBlocks& pb, GBuffer& g, InitialCandidates& c,
           const LightSet& light_set, const PathTracer& p, const Camera& cam,
           const Camera& previous)
        : settings(rs), blocks(pb), gbuffer(g), candidates(c), lights(light_set.lights()),
          falloff(light_set.falloff()), paths(p), camera(cam), previous_camera(previous),
          rays(g.rays()) {
        const std::size_t pixels = std::size_t{settings.width} * settings.height;
        reservoirs.resize(pixels);
        if (settings.packed_history)
            stored_history.resize(pixels);
        else
            previous_reservoirs.resize(pixels);
        scratch.resize(pixels);
    }

    restir::LightPointVisibility<EmbreeScene> point_visibility() const {
        return gbuffer.point_visibility();
    }

    // The pixel blocks and the G-buffer's shadow packets.
    static constexpr std::uint32_t pixel_block = pixel_block_side;
    template <class Body>
    void for_each_pixel_of(const PixelBlock& block, Body&& body) const {
        blocks.for_each_pixel_of(block, body);
    }
    template <class BlockBody>
    void for_each_block(BlockBody&& body) {
        blocks.for_each_block(body);
    }
    template <class ReservoirAt, class NeedsTest>
    void test_visibility(const PixelBlock& block, ReservoirAt&& reservoir, NeedsTest&& needs_test) {
        gbuffer.test_visibility(block, reservoir, needs_test);
    }
    template <class ReservoirAt>
    void test_visibility(const PixelBlock& block, ReservoirAt&& reservoir) {
        gbuffer.test_visibility(block, reservoir);
    }

    // The MIS shadow rays of a reuse pass, traced ahead as packets: pairwise MIS asks whether
    // each pixel's own (canonical) sample is visible from each neighbour's surface. A block
    // first lists those rays (`mis_rays_of`), traces them together, and the pass then reads the
    // answers (`cached_visibility`); any other visibility question is traced on the spot.
    static constexpr std::uint32_t max_cached_rays = restir::max_reuse_inputs;
    struct MisRayCache {
        restir::LightPointSample sample{};
        std::array<const GSurface*, max_cached_rays> surfaces{};
        std::array<float, max_cached_rays> target{};         ///< p-hat of `sample` there
        std::array<std::uint8_t, max_cached_rays> visible{}; ///< where target > 0
        std::uint32_t count = 0;
    };
    static bool same_sample(const restir::LightPointSample& a, const restir::LightPointSample& b) {
        return a.light_id == b.light_id && a.position == b.position && a.normal == b.normal;
    }
    // Fills `caches` (one per pixel of the block, in block order) for the canonical samples
    // `canonical(i)` (i: the pixel's index in the image) and the neighbour surfaces
    // `neighbours(k, out) -> count` (k: the pixel's place in the block), and traces them.
    template <class CanonicalAt, class NeighboursOf>
    void trace_mis_rays(const PixelBlock& block, CanonicalAt&& canonical, NeighboursOf&& neighbours,
                        std::span<MisRayCache> caches) {
        constexpr std::size_t capacity = pixel_block * pixel_block * max_cached_rays;
        std::vector<glm::vec3>& from = ray_from_scratch();
        std::vector<glm::vec3>& to = ray_to_scratch();
        std::vector<std::uint8_t>& blocked = ray_blocked_scratch();
        from.resize(capacity);
        to.resize(capacity);
        blocked.resize(capacity);
        const restir::LightPointVisibility<EmbreeScene> visibility = point_visibility();
        std::size_t n = 0, k = 0;
        for_each_pixel_of(block, [&](std::uint32_t, std::uint32_t, std::uint32_t i) {
            const auto local = static_cast<std::uint32_t>(k++);
            MisRayCache& cache = caches[local];
            cache.count = 0;
            const Reservoir& own = canonical(i);
            if (!gbuffer.surfaces()[i].valid || !own.has_sample())
                return;
            cache.sample = own.sample;
            std::array<const GSurface*, max_cached_rays> there{};
            const std::uint32_t count = neighbours(local, there);
            for (std::uint32_t j = 0; j < count; ++j) {
                const float target = point_target(own.sample, *there[j]);
                cache.surfaces[cache.count] = there[j];
                cache.target[cache.count++] = target;
                if (!(target > 0.0f))
                    continue; // the MIS weight will not ask for visibility
                const restir::ShadowSegment segment = visibility.segment(own.sample, *there[j]);
                from[n] = segment.from;
                to[n++] = segment.to;
            }
        });
        rays.occluded_segments(std::span(from.data(), n), std::span(to.data(), n),
                               std::span(blocked.data(), n));
        n = 0;
        for (std::size_t c = 0; c < k; ++c)
            for (std::uint32_t j = 0; j < caches[c].count; ++j)
                caches[c].visible[j] = caches[c].target[j] > 0.0f && blocked[n++] == 0u ? 1u : 0u;
    }
    float cached_target(const MisRayCache& cache, const restir::LightPointSample& sample,
                        const GSurface& surface) const {
        if (same_sample(sample, cache.sample))
            for (std::uint32_t j = 0; j < cache.count; ++j)
                if (cache.surfaces[j] == &surface)
                    return cache.target[j];
        return point_target(sample, surface);
    }
    bool cached_visibility(const MisRayCache& cache, const restir::LightPointSample& sample,
                           const GSurface& surface) const {
        if (same_sample(sample, cache.sample))
            for (std::uint32_t j = 0; j < cache.count; ++j)
                if (cache.surfaces[j] == &surface)
                    return cache.visible[j] != 0u;
        return point_visibility()(sample, surface);
    }
    // A reuse bridge whose MIS targets and rays towards the cached surfaces come from `cache`
    // (empty when the pass traces no MIS rays: then everything is evaluated on the spot).
    auto cached_bridge(const MisRayCache& cache) const {
        return restir::ReuseBridge{
            [this, &cache](const restir::LightPointSample& sample, const GSurface& there) {
                return cached_target(cache, sample, there);
            },
            [this, &cache](const restir::LightPointSample& sample, const GSurface& there) {
                return cached_visibility(cache, sample, there);
            }};
    }
    // Per-thread ray buffers for trace_mis_rays.
    static std::vector<glm::vec3>& ray_from_scratch() {
        thread_local std::vector<glm::vec3> buffer;
        return buffer;
    }
    static std::vector<glm::vec3>& ray_to_scratch() {
        thread_local std::vector<glm::vec3> buffer;
        return buffer;
    }
    static std::vector<std::uint8_t>& ray_blocked_scratch() {
        thread_local std::vector<std::uint8_t> buffer;
        return buffer;
    }

    // f(y) W with the shadow ray.
    glm::vec3 shade(const Reservoir& reservoir, const GSurface& s) const {
        return reservoir.has_sample() && point_visibility()(reservoir.sample, s)
                   ? unshadowed(reservoir, s)
                   : glm::vec3(0.0f);
    }

    // --- ReSTIR: the library's frame recipe (restir/reuse/di_frame.hpp), its visibility rays
    // traced by the renderer as packets per 8 x 8 block ---------------------------------------

    // The previous camera's pixel of this frame's surface at `p` (temporal reuse).
    struct CameraReprojection {
        const Stages* im = nullptr;
        restir::PixelCoord operator()(restir::PixelCoord p) const {
            const GSurface& s =
                im->gbuffer.surfaces()[static_cast<std::size_t>(p.x) +
                                       static_cast<std::size_t>(p.y) * im->settings.width];
            glm::vec2 q;
            if (!im->previous_camera.project(s.position, q))
                return {-1, -1};
            return {static_cast<std::int32_t>(std::floor(q.x)),
                    static_cast<std::int32_t>(std::floor(q.y))};
        }
    };
    // A stored light point back as the sample it was made from: every light of the renderer
    // (flat emitter triangles of one radiance, sampled by area; VPLs) has one normal, radiance
    // and pdf over its whole surface, so its id and the position determine the sample.
    struct LightPointDecoder {
        const Stages* im = nullptr;
        restir::LightPointSample operator()(std::uint32_t id, glm::vec3 position) const {
            if (id >= im->lights.light_count())
                return {.light_id = restir::removed_light};
            restir::LightPointSample s = restir::make_light_point_sample(
                id, im->lights.sample_point(id, glm::vec2(0.0f)), im->falloff);
            s.position = position;
            return s;
        }
    };
    // The recipe with last frame's reservoirs viewed, or stored packed (--packed-history).
    using DiFrame = restir::DiFrame<restir::LightPointSample, GSurface, CameraReprojection>;
    using PackedDiFrame = restir::DiFrame<restir::LightPointSample, GSurface, CameraReprojection,
                                          restir::PackedPointHistory<LightPointDecoder>>;

    // The settings' recipe, a spatial radius of 0 made 30 px per 1080 rows (at least 3).
    restir::DiFrameParams di_frame_params() const {
        restir::DiFrameParams p = settings.di_frame;
        if (!(p.spatial.radius > 0.0f))
            p.spatial.radius =
                std::max(3.0f, 30.0f * static_cast<float>(settings.height) / 1080.0f);
        p.deferred_visibility = true; // test_visibility and trace_mis_rays trace in packets
        return p;
    }
    // This frame's recipe; `history` false after a new VPL set (last frame's samples belong to
    // another integrand) and in frame 0.
    template <class Frame>
    Frame di_frame(std::uint32_t frame, bool history) const {
        const std::uint32_t w = settings.width, h = settings.height;
        Frame f{.params = di_frame_params(),
                .frame_index = frame,
                .surfaces = {gbuffer.surfaces().data(), w, h},
                .reproject = {this},
                .offsets = offsets};
        if (history && frame > 0) {
            f.previous_surfaces = {gbuffer.previous_surfaces().data(), w, h};
            if constexpr (Frame::loads_history)
                f.history = {{stored_history.data(), w, h}, {this}};
            else
                f.history = {previous_reservoirs.data(), w, h};
        }
        return f;
    }
    restir::ImageView<const Reservoir> view_of(const ReservoirBuffer& buffer) const {
        return {buffer.data(), settings.width, settings.height};
    }
    static restir::PixelCoord coord(std::uint32_t x, std::uint32_t y) {
        return {static_cast<std::int32_t>(x), static_cast<std::int32_t>(y)};
    }
    // Stage 1: initial candidates into `reservoirs`, tested for visibility.
    template <class Frame>
    void di_initial(const Frame& f) {
        const auto reservoir_at = [this](std::uint32_t i) -> Reservoir& { return reservoirs[i]; };
        candidates.for_each_block_in_draw_order(
            blocks, f.frame_index, [&](const PixelBlock& block) {
                for_each_pixel_of(block, [&](std::uint32_t x, std::uint32_t y, std::uint32_t i) {
                    reservoirs[i] = Reservoir{};
                    if (!gbuffer.surfaces()[i].valid)
                        return;
                    restir::Pcg32 rng = restir::make_pixel_rng(
                        i, f.frame_index, restir::RngStream::initial, settings.seed);
                    reservoirs[i] = candidates.initial_reservoir(x, y, f.frame_index,
                                                                 gbuffer.surfaces()[i], rng);
                });
                // The recipe's `initial` with deferred visibility: this packet.
                test_visibility(block, reservoir_at, [&](std::uint32_t i) {
                    return f.needs_visibility_test(reservoirs[i]);
                });
            });
    }

    // Stage 2: temporal reuse from `reservoirs` into `scratch`, then swapped; the MIS ray
    // towards the history's surface traced ahead, and the results that a spatial pass reads
    // retested (a pixel that kept its own sample needs no ray).
    template <class Frame>
    void di_temporal(const Frame& f) {
        const auto reservoir_at = [this](std::uint32_t i) -> Reservoir& { return reservoirs[i]; };
        const auto scratch_at = [this](std::uint32_t i) -> Reservoir& { return scratch[i]; };
        const bool mis_rays = f.mis_weights_trace_rays();
        for_each_block([&](const PixelBlock& block) {
            // Each pixel's history looked up once: its MIS ray is traced ahead, then combined.
            std::array<decltype(f.temporal_input({})), pixel_block * pixel_block> inputs;
            std::uint32_t k = 0;
            for_each_pixel_of(block, [&](std::uint32_t x, std::uint32_t y, std::uint32_t) {
                inputs[k++] = f.temporal_input(coord(x, y));
            });
            std::array<MisRayCache, pixel_block * pixel_block> caches;
            if (mis_rays)
                trace_mis_rays(
                    block, reservoir_at,
                    [&](std::uint32_t local, std::array<const GSurface*, max_cached_rays>& out) {
                        out[0] = inputs[local].surface;
                        return out[0] != nullptr ? 1u : 0u;
                    },
                    caches);
            k = 0;
            for_each_pixel_of(block, [&](std::uint32_t x, std::uint32_t y, std::uint32_t i) {
                restir::Pcg32 rng = restir::make_pixel_rng(
                    i, f.frame_index, restir::RngStream::temporal, settings.seed);
                scratch[i] = f.temporal_combine(coord(x, y), reservoirs[i], inputs[k],
                                                cached_bridge(caches[k]), rng);
                ++k;
            });
            if (f.params.spatial_passes > 0)
                test_visibility(block, scratch_at, [&](std::uint32_t i) {
                    return f.needs_visibility_test(scratch[i], reservoirs[i]);
                });
        });
        std::swap(reservoirs, scratch);
    }

    // Stage 3, one pass from `reservoirs` into `scratch`, then swapped: in two steps, so that
    // the MIS rays of the whole block go out as packets in between (the neighbours found, the
    // rays from each pixel's own sample towards them traced, then the reservoirs combined with a
    // bridge that answers those rays and targets from the cache).
    template <class Frame>
    void di_spatial(const Frame& f, std::uint32_t pass) {
        const auto reservoir_at = [this](std::uint32_t i) -> Reservoir& { return reservoirs[i]; };
        const auto scratch_at = [this](std::uint32_t i) -> Reservoir& { return scratch[i]; };
        const restir::ImageView<const Reservoir> input = view_of(reservoirs);
        const bool mis_rays = f.mis_weights_trace_rays();
        for_each_block([&](const PixelBlock& block) {
            constexpr std::uint32_t pixels = pixel_block * pixel_block;
            using Input = restir::ReuseInput<restir::LightPointSample, GSurface>;
            std::array<std::array<Input, restir::max_reuse_inputs>, pixels> inputs;
            std::array<std::uint32_t, pixels> counts{};
            std::array<restir::Pcg32, pixels> rngs;
            std::uint32_t k = 0;
            for_each_pixel_of(block, [&](std::uint32_t x, std::uint32_t y, std::uint32_t i) {
                rngs[k] = restir::make_pixel_rng(i, f.frame_index,
                                                 restir::RngStream::spatial + pass, settings.seed);
                const auto set =
                    f.spatial_neighbours(coord(x, y), input, restir::AnyMaterial{}, rngs[k]);
                for (std::uint32_t j = 0; j < set.size(); ++j)
                    inputs[k][j] = set[j];
                counts[k++] = set.size();
            });
            std::array<MisRayCache, pixels> caches;
            if (mis_rays)
                trace_mis_rays(
                    block, reservoir_at,
                    [&](std::uint32_t local, std::array<const GSurface*, max_cached_rays>& out) {
                        for (std::uint32_t j = 0; j < counts[local]; ++j)
                            out[j] = inputs[local][j].surface;
                        return counts[local];
                    },
                    caches);
            k = 0;
            for_each_pixel_of(block, [&](std::uint32_t x, std::uint32_t y, std::uint32_t i) {
                scratch[i] =
                    f.spatial_combine(coord(x, y), pass, input,
                                      restir::ReuseInputSpan<restir::LightPointSample, GSurface>{
                                          inputs[k].data(), counts[k]},
                                      cached_bridge(caches[k]), rngs[k]);
                ++k;
            });
            if (pass + 1u < f.params.spatial_passes)
                test_visibility(block, scratch_at, [&](std::uint32_t i) {
                    return f.needs_visibility_test(scratch[i], reservoirs[i]);
                });
        });
        std::swap(reservoirs, scratch);
    }

    // Stage 4: the boiling filter (empties reservoirs far brighter than their neighbourhood;
    // they stay empty in the history too).
    template <class Frame>
    void di_boiling(const Frame& f) {
        const restir::ImageView<const Reservoir> input = view_of(reservoirs);
        for_each_block([&](const PixelBlock& block) {
            for_each_pixel_of(block, [&](std::uint32_t x, std::uint32_t y, std::uint32_t i) {
                scratch[i] = f.boiling(coord(x, y), input);
            });
        });
        std::swap(reservoirs, scratch);
    }

    // Stage 5 and shading: the final visibility ray, which with visibility reuse zeroes W of an
    // occluded sample before the reservoir is stored as next frame's history.
    template <class Frame>
    void di_finish_and_shade(const Frame& f, Image& image) {
        const auto reservoir_at = [this](std::uint32_t i) -> Reservoir& { return reservoirs[i]; };
        for_each_block([&](const PixelBlock& block) {
            test_visibility(block, reservoir_at, [&](std::uint32_t i) {
                return f.needs_visibility_test(reservoirs[i]);
            });
            for_each_pixel_of(block, [&](std::uint32_t, std::uint32_t, std::uint32_t i) {
                const GSurface& s = gbuffer.surfaces()[i];
                glm::vec3 color(0.0f);
                if (s.valid) {
                    // The recipe's `finish` with deferred visibility: the packet above.
                    const Reservoir& reservoir = reservoirs[i];
                    color = s.emitted + (f.params.reuse.visibility_reuse ? unshadowed(reservoir, s)
                                                                         : shade(reservoir, s));
                    if (settings.gi == GlobalIllumination::path) {
                        restir::Pcg32 rng = restir::make_pixel_rng(
                            i, f.frame_index, RenderStream::path, settings.seed);
                        color += paths.path_radiance(s, rng, false, true);
                    }
                }
                image.pixels[i] = color;
                if constexpr (Frame::loads_history)
                    stored_history[i] = restir::pack_reservoir(reservoirs[i]);
            });
        });
    }

    // One ReSTIR frame: the G-buffer, then the recipe's stages, timed by phase.
    void restir_frame(std::uint32_t frame, bool history, Image& image, FrameTimings& t) {
        auto start = Clock::now();
        gbuffer.keep_as_previous();
        gbuffer.trace(camera, frame);
        t.primary = milliseconds_since(start);
        start = Clock::now();
        candidates.prepare_frame(frame, gbuffer.surfaces());
        t.tiles = milliseconds_since(start);
        if (settings.packed_history) {
            di_stages(di_frame<PackedDiFrame>(frame, history), image, t);
        } else {
            std::swap(reservoirs, previous_reservoirs); // last frame's result: the history
            di_stages(di_frame<DiFrame>(frame, history), image, t);
        }
    }
    // The recipe's stages, timed by phase.
    template <class Frame>
    void di_stages(const Frame& f, Image& image, FrameTimings& t) {
        auto start = Clock::now();
        di_initial(f);
        t.candidates = milliseconds_since(start);
        start = Clock::now();
        if (f.has_history())
            di_temporal(f);
        t.temporal = milliseconds_since(start);
        start = Clock::now();
        for (std::uint32_t pass = 0; pass < f.params.spatial_passes; ++pass)
            di_spatial(f, pass);
        if (f.params.boiling_filter)
            di_boiling(f);
        t.spatial = milliseconds_since(start);
        start = Clock::now();
        di_finish_and_shade(f, image);
        t.shading = milliseconds_since(start);
    }
};

RestirDi::RestirDi(const RenderSettings& settings, const PixelBlocks& blocks, GBuffer& gbuffer,
                   InitialCandidates& candidates, const LightSet& lights, const PathTracer& paths,
                   const Camera& camera, const Camera& previous_camera)
    : stages_(std::make_unique<Stages>(settings, blocks, gbuffer, candidates, lights, paths, camera,
                                       previous_camera)) {}

RestirDi::~RestirDi() = default;

void RestirDi::render(std::uint32_t frame, bool history, Image& image, FrameTimings& timings) {
    stages_->restir_frame(frame, history, image, timings);
}

} // namespace pt
