#include "restir_gi.hpp"

#include "reprojection.hpp"
#include "reservoir.hpp"
#include "timing.hpp"

#include <algorithm>
#include <utility>
#include <vector>

namespace pt {

namespace {

using PathReservoir = restir::Reservoir<restir::PathSample>;
static_assert(sizeof(PathReservoir) == 72u, "estimated_memory_bytes counts 72 bytes a reservoir");

/// f(wo, wi) cos Lo of a path sample at surface `s`, through its BSDF (unshadowed).
glm::vec3 path_contribution(const restir::PathSample& x, const GSurface& s) {
    return with_receiver(s, [&](const auto& receiver) {
        return glm::vec3(restir::path_sample_radiance(x, receiver));
    });
}

/// p-hat of a path sample at surface `s`: its contribution folded as the light samples' are.
struct PathTarget {
    float operator()(const restir::PathSample& x, const GSurface& s) const {
        return restir::fold_channels<target_norm>(path_contribution(x, s));
    }
};

} // namespace

// The recipe's frame over the renderer's buffers: this frame's and last frame's reservoirs and
// what the recipe calls back (the initial path sample, shading).
struct RestirGi::Stages {
    const RenderSettings& settings;
    const PixelBlocks& blocks;
    const GBuffer& gbuffer;
    const EmbreeScene& rays;
    const PathTracer& paths;
    const Camera& previous_camera;
    const float ray_offset;
    // `out` of the recipe (the final reservoirs, next frame's history), last frame's, and the
    // recipe's second buffer.
    std::vector<PathReservoir> reservoirs, previous_reservoirs, scratch;

    using Frame = restir::DiFrame<restir::PathSample, GSurface, CameraReprojection>;

    Stages(const RenderSettings& rs, const PixelBlocks& pb, const GBuffer& g, const EmbreeScene& r,
           const PathTracer& p, const Camera& previous, float offset)
        : settings(rs), blocks(pb), gbuffer(g), rays(r), paths(p), previous_camera(previous),
          ray_offset(offset) {
        const std::size_t pixels = std::size_t{settings.width} * settings.height;
        reservoirs.resize(pixels);
        previous_reservoirs.resize(pixels);
        scratch.resize(pixels);
    }

    // This frame's recipe over the G-buffer that ReSTIR DI traced; `history` false in frame 0
    // and after a camera cut.
    Frame frame_of(std::uint32_t frame, bool history) const {
        Frame f = frame_over<Frame>(gbuffer, previous_camera, settings, frame, history);
        if (f.previous_surfaces.data != nullptr)
            f.history = {previous_reservoirs.data(), settings.width, settings.height};
        return f;
    }

    // The initial reservoir: one path sample, W = 1 / source pdf (Ouyang et al. 2021, Alg. 1),
    // M = 1 also where the bounce found nothing.
    PathReservoir initial_reservoir(const GSurface& s, restir::Pcg32& rng) const {
        PathReservoir r;
        const restir::PathSample x = paths.path_sample(s, rng);
        const float target = x.source_pdf > 0.0f ? PathTarget{}(x, s) : 0.0f;
        r.stream(x, restir::safe_divide(target, x.source_pdf), target, 0.0f);
        r.finalize();
        return r;
    }

    void render(std::uint32_t frame_index, bool history, Image& image, FrameTimings& t) {
        const auto start = Clock::now();
        std::swap(reservoirs, previous_reservoirs); // last frame's result: the history
        const Frame f = frame_of(frame_index, history);
        const std::uint32_t w = settings.width, h = settings.height;
        const restir::DiBuffers<restir::PathSample> buffers{{reservoirs.data(), w, h},
                                                            {scratch.data(), w, h}};
        const auto for_each_pixel = [&](const auto& body) {
            blocks.for_each_block([&](const PixelBlock& b) {
                blocks.for_each_pixel_of(b, [&](std::uint32_t x, std::uint32_t y, std::uint32_t) {
                    body(restir::PixelCoord{static_cast<std::int32_t>(x),
                                            static_cast<std::int32_t>(y)});
                });
            });
        };
        const auto initial = [&](restir::PixelCoord, const GSurface& s, restir::Pcg32& rng) {
            return initial_reservoir(s, rng);
        };
        const auto rng_for = [&](restir::PixelCoord p, std::uint32_t stream) {
            return restir::make_pixel_rng(
                static_cast<std::uint32_t>(p.x) + static_cast<std::uint32_t>(p.y) * w, frame_index,
                RenderStream::restir_gi + stream, settings.seed);
        };
        const auto shade = [&](restir::PixelCoord p, const PathReservoir& r, bool visible) {
            const std::size_t i = static_cast<std::size_t>(p.x) + static_cast<std::size_t>(p.y) * w;
            if (visible && r.has_sample())
                image.pixels[i] +=
                    path_contribution(r.sample, gbuffer.surfaces()[i]) * r.contribution_weight;
        };
        const restir::ReuseBridge reuse{
            PathTarget{}, restir::ReconnectionVisibility<EmbreeScene>{&rays, ray_offset},
            restir::AnyMaterial{}, settings.reconnection};
        restir::run_di_frame(f, buffers, restir::DiBridge{initial, reuse, rng_for, shade},
                             for_each_pixel);
        t.indirect = milliseconds_since(start);
    }
};

RestirGi::RestirGi(const RenderSettings& settings, const PixelBlocks& blocks,
                   const GBuffer& gbuffer, const EmbreeScene& rays, const PathTracer& paths,
                   const Camera& previous_camera, float ray_offset)
    : stages_(std::make_unique<Stages>(settings, blocks, gbuffer, rays, paths, previous_camera,
                                       ray_offset)) {}

RestirGi::~RestirGi() = default;

void RestirGi::render(std::uint32_t frame, bool history, Image& image, FrameTimings& timings) {
    stages_->render(frame, history, image, timings);
}

} // namespace pt
