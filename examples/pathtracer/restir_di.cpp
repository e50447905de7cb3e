#include "restir_di.hpp"

#include "reprojection.hpp"
#include "reservoir.hpp"
#include "timing.hpp"

#include <algorithm>
#include <cmath>
#include <span>
#include <utility>
#include <vector>

namespace pt {

// The recipe's frame over the renderer's buffers: the reservoirs of this frame and the last,
// the reprojection, and what the recipe calls back (candidates, shading).
struct RestirDi::Stages {
    const RenderSettings& settings;
    const PixelBlocks& blocks;
    GBuffer& gbuffer;
    InitialCandidates& candidates;
    const Unified& lights;
    const restir::Falloff& falloff;
    const restir::VplPartition partition; // gi vpl-unbiased
    const PathTracer& paths;
    const Camera& camera;
    const Camera& previous_camera;

    // `out` of the recipe (the final reservoirs, next frame's history), last frame's, and the
    // recipe's second buffer.
    ReservoirBuffer reservoirs, previous_reservoirs, scratch;
    // With --packed-history, the final reservoirs in storage form instead of
    // `previous_reservoirs`: next frame's history in 28 bytes a pixel instead of 64, its light
    // points decoded from the light set (`LightPointDecoder`).
    std::vector<restir::PackedPointReservoir> stored_history;

    Stages(const RenderSettings& rs, const PixelBlocks& pb, GBuffer& g, InitialCandidates& c,
           const LightSet& light_set, const PathTracer& p, const Camera& cam,
           const Camera& previous)
        : settings(rs), blocks(pb), gbuffer(g), candidates(c), lights(light_set.lights()),
          falloff(light_set.falloff()), partition(light_set.partition()), paths(p), camera(cam),
          previous_camera(previous) {
        const std::size_t pixels = std::size_t{settings.width} * settings.height;
        reservoirs.resize(pixels);
        if (settings.packed_history)
            stored_history.resize(pixels);
        else
            previous_reservoirs.resize(pixels);
        scratch.resize(pixels);
    }

    // A stored light point back as the sample it was made from (`restir::LightSetDecoder`):
    // every light of the renderer (emitter triangles and light shapes of one radiance, sampled
    // by area; VPLs) has one radiance and pdf over its whole surface and a normal its position
    // gives (`SceneEmitters::point_at`), so its id and the position determine the sample; the
    // environment's "position" is its direction, whose radiance and pdf the map gives.
    using LightPointDecoder = restir::LightSetDecoder<Unified>;
    // The recipe with last frame's reservoirs viewed, or stored packed (--packed-history).
    using DiFrame = restir::DiFrame<restir::LightPointSample, GSurface, CameraReprojection>;
    using PackedDiFrame = restir::DiFrame<restir::LightPointSample, GSurface, CameraReprojection,
                                          restir::PackedPointHistory<LightPointDecoder>>;

    // This frame's recipe; `history` false after a new VPL set (last frame's samples belong to
    // another integrand) and in frame 0.
    template <class Frame>
    Frame di_frame(std::uint32_t frame, bool history) const {
        const std::uint32_t w = settings.width, h = settings.height;
        Frame f = frame_over<Frame>(gbuffer, previous_camera, settings, frame, history);
        if (f.previous_surfaces.data != nullptr) {
            if constexpr (Frame::loads_history)
                f.history = {{stored_history.data(), w, h}, {lights, falloff}};
            else
                f.history = {previous_reservoirs.data(), w, h};
        }
        return f;
    }

    // One ReSTIR frame: the G-buffer, the candidates' tiles, then the recipe's steps.
    void restir_frame(std::uint32_t frame, bool history, Image& image, FrameTimings& t) {
        auto start = Clock::now();
        gbuffer.keep_as_previous();
        gbuffer.trace(camera, frame);
        t.primary = milliseconds_since(start);
        start = Clock::now();
        candidates.prepare_frame(frame, gbuffer.surfaces());
        t.tiles = milliseconds_since(start);
        if (settings.packed_history) {
            run(di_frame<PackedDiFrame>(frame, history), image, t);
        } else {
            std::swap(reservoirs, previous_reservoirs); // last frame's result: the history
            run(di_frame<DiFrame>(frame, history), image, t);
        }
    }

    // `for_each_tile` of the recipe: the pixel blocks as tiles (the initial stage's grouped by
    // the light tile they draw from, so that each is read once), each step's time added to its
    // phase.
    auto timed_tiles(std::uint32_t frame_index, FrameTimings& t) {
        return [this, frame_index, &t](const restir::DiStep& step, const auto& body) {
            const auto start = Clock::now();
            const auto tile_body = [&](const PixelBlock& b) {
                body(restir::PixelTile{
                    {static_cast<std::int32_t>(b.x0), static_cast<std::int32_t>(b.y0)},
                    {static_cast<std::int32_t>(b.x1), static_cast<std::int32_t>(b.y1)}});
            };
            if (step.stage == restir::DiStage::initial)
                candidates.for_each_block_in_draw_order(blocks, frame_index, tile_body);
            else
                blocks.for_each_block(tile_body);
            phase_of(step, t) += milliseconds_since(start);
        };
    }
    static double& phase_of(const restir::DiStep& step, FrameTimings& t) {
        switch (step.stage) {
        case restir::DiStage::initial:
            return t.candidates;
        case restir::DiStage::temporal:
            return t.temporal;
        case restir::DiStage::spatial:
        case restir::DiStage::boiling:
            return t.spatial;
        case restir::DiStage::finish:
            break;
        }
        return t.shading;
    }

    // The recipe's steps over 8 x 8 tiles, each stage's rays as packets, timed by stage.
    template <class Frame>
    void run(const Frame& f, Image& image, FrameTimings& t) {
        const std::uint32_t w = settings.width, h = settings.height;
        const restir::DiBuffers<restir::LightPointSample> buffers{{reservoirs.data(), w, h},
                                                                  {scratch.data(), w, h}};
        const auto initial = [&](restir::PixelCoord p, const GSurface& s, restir::Pcg32& rng) {
            return candidates.initial_reservoir(static_cast<std::uint32_t>(p.x),
                                                static_cast<std::uint32_t>(p.y), f.frame_index, s,
                                                rng);
        };
        const auto rng_for = [&](restir::PixelCoord p, std::uint32_t stream) {
            return restir::make_pixel_rng(static_cast<std::uint32_t>(p.x) +
                                              static_cast<std::uint32_t>(p.y) * w,
                                          f.frame_index, stream, settings.seed);
        };
        const auto shade = [&](restir::PixelCoord p, const Reservoir& r, bool visible) {
            const std::uint32_t i =
                static_cast<std::uint32_t>(p.x) + static_cast<std::uint32_t>(p.y) * w;
            image.pixels[i] = radiance(i, f.frame_index, r, visible);
            if constexpr (Frame::loads_history)
                stored_history[i] = restir::pack_reservoir(r);
        };
        const restir::ReuseBridge reuse{
            [](const restir::LightPointSample& x, const GSurface& s) { return point_target(x, s); },
            gbuffer.shadow_packets()};
        restir::run_di_frame(f, buffers, restir::DiBridge{initial, reuse, rng_for, shade},
                             timed_tiles(f.frame_index, t));
    }

    // A pixel's radiance: its emission, the reservoir's light where `visible`, and with --gi
    // path the path-traced indirect light; the environment where its camera ray left the scene.
    // With --indirect-only, the path-traced indirect light alone (gi restir-gi adds its own).
    glm::vec3 radiance(std::uint32_t i, std::uint32_t frame_index, const Reservoir& r,
                       bool visible) const {
        const GSurface& s = gbuffer.surfaces()[i];
        if (!s.valid)
            return settings.indirect_only ? glm::vec3(0.0f) : escaped_radiance(gbuffer.scene(), s);
        glm::vec3 color(0.0f);
        if (!settings.indirect_only)
            color = emitted(gbuffer.scene(), s) + (visible ? unshadowed(r, s) : glm::vec3(0.0f));
        if (settings.gi == GlobalIllumination::path) {
            restir::Pcg32 rng =
                restir::make_pixel_rng(i, frame_index, RenderStream::path, settings.seed);
            color += paths.path_radiance(s, rng, false, true);
        }
        if (settings.gi == GlobalIllumination::vpl_unbiased &&
            settings.vpl_path_part == VplPathPart::independent) {
            restir::Pcg32 rng =
                restir::make_pixel_rng(i, frame_index, RenderStream::path, settings.seed);
            color += paths.partitioned_indirect(s, rng, partition);
        }
        return color;
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
