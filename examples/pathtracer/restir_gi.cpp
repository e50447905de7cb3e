#include "restir_gi.hpp"

#include "pt_paths.hpp"
#include "reprojection.hpp"
#include "reservoir.hpp"
#include "timing.hpp"

#include <algorithm>
#include <optional>
#include <utility>
#include <vector>

namespace pt {

namespace {

static_assert(sizeof(restir::Reservoir<restir::PathSample>) == 72u,
              "estimated_memory_bytes counts 72 bytes a ReSTIR GI reservoir");
static_assert(sizeof(restir::Reservoir<restir::PtSample>) == 112u,
              "estimated_memory_bytes counts 112 bytes a ReSTIR PT reservoir");

/// f(wo, wi) cos Lo of a path sample at surface `s`, through its BSDF (unshadowed); with a
/// `partition` (gi vpl-unbiased), its path part alone (restir::partitioned_path_radiance).
glm::vec3 path_contribution(const restir::PathSample& x, const GSurface& s,
                            const restir::VplPartition* partition) {
    return with_receiver(s, [&](const auto& receiver) {
        return partition != nullptr ? restir::partitioned_path_radiance(x, receiver, *partition)
                                    : glm::vec3(restir::path_sample_radiance(x, receiver));
    });
}

/// p-hat of a path sample at surface `s`: its contribution folded as the light samples' are.
struct PathTarget {
    const restir::VplPartition* partition = nullptr;
    float operator()(const restir::PathSample& x, const GSurface& s) const {
        return restir::fold_channels<target_norm>(path_contribution(x, s, partition));
    }
};

/// ReSTIR GI's samples: one bounce and the radiance it finds (PathTracer::path_sample),
/// reused through the reconnection shift with traced visibility; with a `partition` (gi
/// vpl-unbiased), the path part of the indirect light that the VPLs leave.
struct GiKind {
    using Sample = restir::PathSample;
    const PathTracer& paths;
    const EmbreeScene& rays;
    const RenderSettings& settings;
    float ray_offset;
    std::optional<restir::VplPartition> partition;

    const restir::VplPartition* partition_or_null() const {
        return partition ? &*partition : nullptr;
    }

    // One path sample, W = 1 / source pdf (Ouyang et al. 2021, Alg. 1), M = 1 also where the
    // bounce found nothing.
    restir::Reservoir<Sample> initial(const GSurface& s, restir::Pcg32& rng) const {
        restir::Reservoir<Sample> r;
        const Sample x = paths.path_sample(s, rng, partition_or_null());
        const float target = x.source_pdf > 0.0f ? PathTarget{partition_or_null()}(x, s) : 0.0f;
        r.stream(x, restir::safe_divide(target, x.source_pdf), target, 0.0f);
        r.finalize();
        return r;
    }
    glm::vec3 contribution(const Sample& x, const GSurface& s) const {
        return path_contribution(x, s, partition_or_null());
    }
    static void adjust(restir::DiFrameParams&) {}
    auto reuse() const {
        return restir::ReuseBridge{PathTarget{partition_or_null()},
                                   restir::ReconnectionVisibility<EmbreeScene>{&rays, ray_offset},
                                   restir::AnyMaterial{}, settings.reconnection};
    }
};

/// p-hat of a ReSTIR PT sample: its f(x) folded, at the surface it belongs to.
struct PtTarget {
    float operator()(const restir::PtSample& x, const GSurface& s) const {
        return restir::fold_channels<target_norm>(restir::pt_sample_contribution(x, s.position));
    }
};

/// ReSTIR PT's samples: whole paths (PtPaths), reused through the hybrid shift. Their f
/// includes the visibility of every segment, the shift's reconnection traced by the shift.
struct PtKind {
    using Sample = restir::PtSample;
    PtPaths paths;
    restir::ReconnectionCriterion rule;

    restir::Reservoir<Sample> initial(const GSurface& s, restir::Pcg32& rng) const {
        return paths.initial(s, rng.next_uint(), rule);
    }
    glm::vec3 contribution(const Sample& x, const GSurface& s) const {
        return restir::pt_sample_contribution(x, s.position);
    }
    // Pixels smoother than the criterion's roughness, whose paths the shift replays from the
    // visible point, read their own pixel's history: a permuted history pixel's path, replayed
    // through their narrow lobe, was worth half as much (the glossy pixels' per-frame MSE 2.2x
    // higher in the glossy box, docs/restir-pt.md).
    void adjust(restir::DiFrameParams& p) const {
        p.temporal.permutation_min_roughness =
            std::max(p.temporal.permutation_min_roughness, rule.min_roughness);
    }
    auto reuse() const {
        const auto open = [](const Sample&, const GSurface&) { return true; };
        return restir::ReuseBridge{PtTarget{}, open, restir::AnyMaterial{},
                                   restir::HybridShift<PtPaths>{&paths, rule}};
    }
};

} // namespace

struct RestirGi::Stages {
    virtual ~Stages() = default;
    virtual void render(std::uint32_t frame_index, bool history, Image& image, FrameTimings& t) = 0;
};

// The recipe's frame over the renderer's buffers: this frame's and last frame's reservoirs and
// what the recipe calls back (the initial sample, shading), for the samples of `Kind`.
template <class Kind>
struct RestirGi::KindStages final : RestirGi::Stages {
    using Sample = typename Kind::Sample;
    using PathReservoir = restir::Reservoir<Sample>;
    using Frame = restir::DiFrame<Sample, GSurface, CameraReprojection>;

    const RenderSettings& settings;
    const PixelBlocks& blocks;
    const GBuffer& gbuffer;
    const Camera& previous_camera;
    const Kind kind;
    // `out` of the recipe (the final reservoirs, next frame's history), last frame's, and the
    // recipe's second buffer.
    std::vector<PathReservoir> reservoirs, previous_reservoirs, scratch;

    KindStages(const RenderSettings& rs, const PixelBlocks& pb, const GBuffer& g,
               const Camera& previous, Kind k)
        : settings(rs), blocks(pb), gbuffer(g), previous_camera(previous), kind(std::move(k)) {
        const std::size_t pixels = std::size_t{settings.width} * settings.height;
        reservoirs.resize(pixels);
        previous_reservoirs.resize(pixels);
        scratch.resize(pixels);
    }

    // This frame's recipe over the G-buffer that ReSTIR DI traced; `history` false in frame 0
    // and after a camera cut.
    Frame frame_of(std::uint32_t frame, bool history) const {
        Frame f = frame_over<Frame>(gbuffer, previous_camera, settings, frame, history);
        kind.adjust(f.params);
        if (f.previous_surfaces.data != nullptr)
            f.history = {previous_reservoirs.data(), settings.width, settings.height};
        return f;
    }

    void render(std::uint32_t frame_index, bool history, Image& image, FrameTimings& t) override {
        const auto start = Clock::now();
        std::swap(reservoirs, previous_reservoirs); // last frame's result: the history
        const Frame f = frame_of(frame_index, history);
        const std::uint32_t w = settings.width, h = settings.height;
        const restir::DiBuffers<Sample> buffers{{reservoirs.data(), w, h}, {scratch.data(), w, h}};
        const auto for_each_pixel = [&](const auto& body) {
            blocks.for_each_block([&](const PixelBlock& b) {
                blocks.for_each_pixel_of(b, [&](std::uint32_t x, std::uint32_t y, std::uint32_t) {
                    body(restir::PixelCoord{static_cast<std::int32_t>(x),
                                            static_cast<std::int32_t>(y)});
                });
            });
        };
        const auto initial = [&](restir::PixelCoord, const GSurface& s, restir::Pcg32& rng) {
            return kind.initial(s, rng);
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
                    kind.contribution(r.sample, gbuffer.surfaces()[i]) * r.contribution_weight;
        };
        restir::run_di_frame(f, buffers, restir::DiBridge{initial, kind.reuse(), rng_for, shade},
                             for_each_pixel);
        t.indirect = milliseconds_since(start);
    }
};

RestirGi::RestirGi(const RenderSettings& settings, const PixelBlocks& blocks,
                   const GBuffer& gbuffer, const EmbreeScene& rays, const PathTracer& paths,
                   const LightSet& lights, const Camera& previous_camera, float ray_offset) {
    if (settings.gi == GlobalIllumination::restir_pt) {
        const Scene& scene = gbuffer.scene();
        restir::ReconnectionCriterion rule = settings.pt_reconnection;
        rule.min_distance *= scene_size(scene);
        stages_ = std::make_unique<KindStages<PtKind>>(
            settings, blocks, gbuffer, previous_camera,
            PtKind{PtPaths(scene, rays, lights, ray_offset, settings.max_depth,
                           settings.environment_nee),
                   rule});
    } else {
        std::optional<restir::VplPartition> partition;
        if (settings.gi == GlobalIllumination::vpl_unbiased)
            partition = lights.partition();
        stages_ = std::make_unique<KindStages<GiKind>>(
            settings, blocks, gbuffer, previous_camera,
            GiKind{paths, rays, settings, ray_offset, partition});
    }
}

RestirGi::~RestirGi() = default;

void RestirGi::render(std::uint32_t frame, bool history, Image& image, FrameTimings& timings) {
    stages_->render(frame, history, image, timings);
}

} // namespace pt
