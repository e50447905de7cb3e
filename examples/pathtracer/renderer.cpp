#include "renderer.hpp"

#include "accumulation.hpp"
#include "bsdf_candidates.hpp"
#include "camera.hpp"
#include "candidate_sources.hpp"
#include "embree_scene.hpp"
#include "gbuffer.hpp"
#include "light_set.hpp"
#include "path_tracer.hpp"
#include "pixel_blocks.hpp"
#include "reservoir.hpp"
#include "restir_di.hpp"
#include "restir_gi.hpp"
#include "timing.hpp"

#include <tbb/task_arena.h>

#include <algorithm>
#include <array>
#include <cmath>
#include <memory>
#include <optional>

namespace pt {

namespace {

// `settings` resolved for the emitters of `scene` (SceneEmitters: throws SceneError for a
// shape that cannot be rendered).
RenderSettings resolved_for(const RenderSettings& settings, const Scene& scene) {
    const SceneEmitters emitters(scene);
    return resolved_candidates(resolved_light_points(settings, emitters.shape_count()),
                               emitters.light_count());
}

} // namespace

// The renderer: its parts (the scene's rays, the light set, the pixel blocks, the G-buffer,
// the candidate source, the path tracer, ReSTIR DI and the accumulation) and the frame loop.
struct Renderer::Impl {
    const Scene& scene;
    const RenderSettings settings;
    const EmbreeScene rays;
    tbb::task_arena arena;
    const float extent;     // scene_size: the length of the bounding box's diagonal
    const float ray_offset; // 1e-4 of the extent
    LightSet light_set;     // the emitters and the VPL set of this frame
    PixelBlocks blocks;
    GBuffer gbuffer;
    std::unique_ptr<InitialCandidates> candidates;
    Camera camera, previous_camera;
    PathTracer paths;
    std::optional<RestirDi> restir; // --method restir
    std::optional<RestirGi> gi;     // --method restir --gi restir-gi or restir-pt
    Accumulation accumulation;      // the last frame and the average

    // Builds the BVH, the emitters, the first VPL set and the frame buffers.
    Impl(const Scene& s, const RenderSettings& rs)
        : scene(s), settings(resolved_for(rs, s)), rays(scene),
          arena(settings.threads == 0 ? tbb::task_arena::automatic
                                      : static_cast<int>(settings.threads)),
          extent(scene_size(scene)), ray_offset(1e-4f * extent),
          light_set(scene, rays, settings, arena, ray_offset, extent),
          blocks(settings.width, settings.height, arena),
          gbuffer(scene, rays, blocks, std::size_t{settings.width} * settings.height, ray_offset,
                  settings.antialias, settings.seed),
          candidates(
              with_bsdf_candidates(make_initial_candidates(settings, scene, light_set, blocks),
                                   settings, rays, light_set, ray_offset)),
          camera(settings.camera, settings.width, settings.height), previous_camera(camera),
          paths(scene, rays, light_set, ray_offset, settings.max_depth, settings.environment_nee),
          accumulation(settings.width, settings.height) {
        if (settings.method == Method::restir)
            restir.emplace(settings, blocks, gbuffer, *candidates, light_set, paths, camera,
                           previous_camera);
        const bool independent_paths = settings.gi == GlobalIllumination::vpl_unbiased &&
                                       settings.vpl_path_part == VplPathPart::independent;
        if (settings.method == Method::restir && reuses_paths(settings.gi) && !independent_paths)
            gi.emplace(settings, blocks, gbuffer, rays, paths, light_set, previous_camera,
                       ray_offset);
    }

    // One uniformly chosen light sample as a one-candidate reservoir: W = 1 / p, so that
    // f W = f / p (shaded after its shadow ray, as RIS's are).
    Reservoir uniform_reservoir(const GSurface& s, restir::Pcg32& rng) const {
        const restir::DiscreteSample c = restir::sample_light(
            restir::UniformLightSampler{light_set.lights().light_count()}, rng);
        const float u = next_float(rng);
        const float v = next_float(rng);
        Reservoir reservoir;
        if (!(c.pmf > 0.0f))
            return reservoir;
        const restir::LightSampleRef ref{c.index, {u, v}};
        const bool from_surface = settings.light_points == LightPoints::solid_angle;
        const restir::LightPointSample sample = restir::make_light_point_sample(
            ref.light_id,
            from_surface ? light_set.lights().sample_point(ref.light_id, ref.uv, s.position)
                         : light_set.lights().sample_point(ref.light_id, ref.uv),
            light_set.falloff());
        const float target = point_target(sample, s);
        reservoir.stream(sample, target / c.pmf, target, 0.0f);
        reservoir.finalize();
        return reservoir;
    }

    // --- Frames ----------------------------------------------------------------------------

    // The next frame, added to the accumulation; the first frame's timings (and those of a
    // frame with a new VPL set) include photon shooting.
    FrameTimings render_frame() {
        FrameTimings t;
        const auto frame_start = Clock::now();
        const bool new_vpl_set = reshoot_vpls();
        if (accumulation.frames() == 0 || new_vpl_set)
            t.photons = light_set.photon_ms();
        if (settings.motion == CameraMotion::orbit)
            orbit_camera(accumulation.frames());
        if (settings.method == Method::restir) {
            restir->render(accumulation.frames(), !new_vpl_set, accumulation.frame(), t);
            if (gi)
                gi->render(accumulation.frames(), true, accumulation.frame(), t);
        } else
            independent_frame(accumulation.frames(), t);
        accumulation.add_frame();
        t.total = milliseconds_since(frame_start);
        return t;
    }

    // A new VPL set every `vpl_reshoot_interval` frames: true when this frame shot one.
    bool reshoot_vpls() {
        const bool new_vpl_set = light_set.reshoot_vpls(accumulation.frames());
        if (new_vpl_set)
            candidates->use_light_set();
        return new_vpl_set;
    }

    // The camera of frame `frame` turned about the look-at point, last frame's kept for
    // reprojection.
    void orbit_camera(std::uint32_t frame) {
        CameraSetup setup = settings.camera;
        const float angle = 0.004f * static_cast<float>(frame);
        const glm::vec3 offset = setup.look_from - setup.look_at;
        setup.look_from =
            setup.look_at + glm::vec3(offset.x * std::cos(angle) + offset.z * std::sin(angle),
                                      offset.y,
                                      -offset.x * std::sin(angle) + offset.z * std::cos(angle));
        previous_camera = camera;
        camera = Camera(setup, settings.width, settings.height);
    }

    // uniform, ris and reference: `spp` independent samples per pixel, each with its own
    // G-buffer (and light tiles for ris), averaged into the frame image.
    void independent_frame(std::uint32_t frame, FrameTimings& t) {
        std::fill(accumulation.frame().pixels.begin(), accumulation.frame().pixels.end(),
                  glm::vec3(0.0f));
        for (std::uint32_t sample = 0; sample < settings.spp; ++sample) {
            const std::uint32_t index = frame * settings.spp + sample;
            auto start = Clock::now();
            gbuffer.trace(camera, index);
            t.primary += milliseconds_since(start);
            if (settings.method == Method::ris) {
                start = Clock::now();
                candidates->prepare_frame(index, gbuffer.surfaces());
                t.tiles += milliseconds_since(start);
            }
            start = Clock::now();
            const auto shade_block = [&](const PixelBlock& block) {
                shade_independent(block, index);
            };
            if (settings.method == Method::ris)
                candidates->for_each_block_in_draw_order(blocks, index, shade_block);
            else
                blocks.for_each_block(shade_block);
            t.shading += milliseconds_since(start);
        }
    }

    // Sample `index` of a block's pixels, added to the frame image with weight 1 / spp.
    // uniform and ris: one light sample per pixel as a reservoir (uniform: one candidate,
    // W = 1 / p), their shadow rays as one packet; reference: a path per pixel.
    void shade_independent(const PixelBlock& block, std::uint32_t index) {
        std::array<Reservoir, pixels_per_block> picked;
        std::array<restir::Pcg32, pixels_per_block> rngs;
        const auto local = [&block, this](std::uint32_t i) {
            return (i / settings.width - block.y0) * pixel_block_side + i % settings.width -
                   block.x0;
        };
        const bool light_sample = settings.method != Method::reference;
        blocks.for_each_pixel_of(block, [&](std::uint32_t x, std::uint32_t y, std::uint32_t i) {
            restir::Pcg32& rng = rngs[local(i)];
            rng = restir::make_pixel_rng(i, index, RenderStream::independent, settings.seed);
            Reservoir& reservoir = picked[local(i)];
            reservoir = Reservoir{};
            const GSurface& s = gbuffer.surfaces()[i];
            if (!s.valid || !light_sample)
                return;
            reservoir = settings.method == Method::ris
                            ? candidates->initial_reservoir(x, y, index, s, rng)
                            : uniform_reservoir(s, rng);
        });
        if (light_sample) // visibility: each block's shadow rays as packets
            restir::apply_visibility_batch<restir::LightPointSample, GSurface>(
                gbuffer.shadow_packets(), [&](const auto& ask) {
                    blocks.for_each_pixel_of(block,
                                             [&](std::uint32_t, std::uint32_t, std::uint32_t i) {
                                                 if (picked[local(i)].has_sample())
                                                     ask(picked[local(i)], gbuffer.surfaces()[i]);
                                             });
                });
        blocks.for_each_pixel_of(block, [&](std::uint32_t, std::uint32_t, std::uint32_t i) {
            const GSurface& s = gbuffer.surfaces()[i];
            if (s.valid)
                accumulation.frame().pixels[i] +=
                    independent_radiance(s, picked[local(i)], rngs[local(i)]) /
                    static_cast<float>(settings.spp);
            else if (!settings.indirect_only) // the environment in its direction (or black)
                accumulation.frame().pixels[i] +=
                    escaped_radiance(scene, s) / static_cast<float>(settings.spp);
        });
    }

    // The radiance of one independent sample at a visible surface: its emission and, with a
    // visible light sample `picked` (uniform, ris), that sample's light, or (reference) a
    // path's; plus the indirect light that --gi asks for.
    glm::vec3 independent_radiance(const GSurface& s, const Reservoir& picked,
                                   restir::Pcg32& rng) const {
        // The reference of gi vpl-unbiased is the path tracer's indirect light.
        const bool gi_path =
            traces_indirect_paths(settings.gi) || (settings.method == Method::reference &&
                                                   settings.gi == GlobalIllumination::vpl_unbiased);
        if (settings.indirect_only)
            return gi_path ? paths.path_radiance(s, rng, false, true) : glm::vec3(0.0f);
        glm::vec3 color = emitted(scene, s);
        if (settings.method == Method::reference) {
            color += paths.path_radiance(s, rng, true, gi_path);
            if (settings.gi == GlobalIllumination::vpl)
                color += paths.vpl_nee(s, rng);
        } else {
            color += unshadowed(picked, s);
            if (gi_path)
                color += paths.path_radiance(s, rng, false, true);
        }
        return color;
    }
};

restir::DiFrameParams frame_params(const RenderSettings& settings) {
    restir::DiFrameParams p = settings.di_frame;
    // Two thirds of the preset's radius at 1080 rows: less error a frame in every scene
    // measured (docs/performance.md, "The spatial radius").
    const float at_1080_rows =
        restir::di_frame_preset(settings.preset).spatial.radius * 2.0f / 3.0f;
    if (!(p.spatial.radius > 0.0f))
        p.spatial.radius =
            std::max(3.0f, at_1080_rows * static_cast<float>(settings.height) / 1080.0f);
    return p;
}

std::uint64_t estimated_memory_bytes(const RenderSettings& settings, bool with_reference) {
    const std::uint64_t pixels = std::uint64_t{settings.width} * settings.height;
    // The two G-buffers hold 2 x 96 bytes of GSurface a pixel (80 more since it carries wo and
    // the BSDF).
    // ReSTIR GI adds three buffers of 72-byte path reservoirs, ReSTIR PT three of 112 bytes.
    const bool restir = settings.method == Method::restir;
    // gi vpl-unbiased keeps ReSTIR GI's buffers only when it reuses its path samples.
    const bool gi_buffers = settings.gi == GlobalIllumination::restir_gi ||
                            (settings.gi == GlobalIllumination::vpl_unbiased &&
                             settings.vpl_path_part == VplPathPart::reuse);
    const std::uint64_t paths = !restir                                        ? 0u
                                : gi_buffers                                   ? 216u
                                : settings.gi == GlobalIllumination::restir_pt ? 336u
                                                                               : 0u;
    const std::uint64_t per_pixel = (restir ? 384u : 192u) + paths + (with_reference ? 48u : 0u);
    const std::uint64_t vpls = uses_vpls(settings.gi) ? settings.vpls : 0u;
    // bvh's light tree: 124 bytes more per VPL measured at 1M VPLs (grid's per-light nodes
    // need less); the grid at most: its cells' tile indices (4 bytes a cell), and its tiles (a
    // cell looked up has fewer than 2 entries per pixel that looks it up, and at least 32, of
    // 64 bytes each).
    const bool bvh = settings.source == CandidateSource::bvh ||
                     settings.source == CandidateSource::grid ||
                     settings.source == CandidateSource::automatic; // at most the BVH's
    const std::uint64_t cells =
        std::uint64_t{settings.grid_cells} * settings.grid_cells * settings.grid_cells;
    const std::uint64_t grid = settings.source == CandidateSource::grid
                                   ? cells * 4u + pixels * 128u + std::min(pixels, cells) * 2048u
                                   : 0u;
    return (32u << 20u) + pixels * per_pixel + vpls * (bvh ? 224u : 96u) + grid;
}

Renderer::Renderer(const Scene& scene, const RenderSettings& settings)
    : impl_(std::make_unique<Impl>(scene, settings)) {}

Renderer::~Renderer() = default;

FrameTimings Renderer::render_frame() { return impl_->render_frame(); }

const Image& Renderer::accumulated() const { return impl_->accumulation.average(); }
const Image& Renderer::last_frame() const { return impl_->accumulation.frame(); }
std::uint32_t Renderer::frames_rendered() const { return impl_->accumulation.frames(); }
std::uint32_t Renderer::photons_per_set() const {
    return impl_->light_set.photons_per_set().value_or(0u);
}
const std::vector<restir::Vpl>& Renderer::vpls() const { return impl_->light_set.vpls(); }
std::uint32_t Renderer::emitter_count() const { return impl_->light_set.emitters().light_count(); }

const RenderSettings& Renderer::settings() const { return impl_->settings; }

RenderSettings resolved_candidates(RenderSettings settings, std::uint32_t emitter_count) {
    if (settings.source == CandidateSource::automatic)
        settings.source =
            emitter_count >= bvh_source_emitters ? CandidateSource::bvh : CandidateSource::power;
    if (settings.candidates == 0u)
        settings.candidates = settings.source == CandidateSource::bvh ? default_bvh_candidates
                                                                      : default_tile_candidates;
    return settings;
}

RenderSettings resolved_light_points(RenderSettings settings, std::uint32_t shape_emitters) {
    if (settings.light_points == LightPoints::automatic)
        settings.light_points = shape_emitters > 0u && !settings.packed_history
                                    ? LightPoints::solid_angle
                                    : LightPoints::area;
    if (settings.source == CandidateSource::automatic && shape_emitters > 0u &&
        settings.light_points == LightPoints::solid_angle)
        settings.source = CandidateSource::bvh;
    return settings;
}

std::size_t Renderer::surface_pixel_count() const {
    return static_cast<std::size_t>(std::count_if(impl_->gbuffer.surfaces().begin(),
                                                  impl_->gbuffer.surfaces().end(),
                                                  [](const GSurface& s) { return s.valid; }));
}

std::vector<std::uint8_t> Renderer::glossy_pixels() const {
    const auto& surfaces = impl_->gbuffer.surfaces();
    std::vector<std::uint8_t> glossy(surfaces.size());
    for (std::size_t i = 0; i < surfaces.size(); ++i)
        glossy[i] = surfaces[i].valid && !is_lambertian(surfaces[i]) ? 1u : 0u;
    return glossy;
}

} // namespace pt
