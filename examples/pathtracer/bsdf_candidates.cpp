#include "bsdf_candidates.hpp"

#include <algorithm>
#include <optional>
#include <utility>

namespace pt {

namespace {

class BsdfCandidates final : public InitialCandidates {
public:
    BsdfCandidates(std::unique_ptr<InitialCandidates> source, const RenderSettings& settings,
                   const EmbreeScene& rays, const LightSet& lights, float ray_offset)
        : source_(std::move(source)), counts_{settings.bsdf_light_candidates == 0u
                                                  ? settings.candidates
                                                  : std::min(settings.candidates,
                                                             settings.bsdf_light_candidates),
                                              settings.bsdf_candidates},
          rays_(rays), lights_(lights), ray_offset_(ray_offset),
          max_roughness_(settings.bsdf_max_roughness),
          everywhere_(settings.environment_sampling == EnvironmentSampling::bsdf &&
                      lights.lights().environment_count() > 0u),
          points_(settings.light_points) {}

    void use_light_set() override { source_->use_light_set(); }
    void prepare_frame(std::uint32_t frame_index, std::span<const GSurface> surfaces) override {
        source_->prepare_frame(frame_index, surfaces);
    }

    Reservoir initial_reservoir(std::uint32_t x, std::uint32_t y, std::uint32_t frame_index,
                                const GSurface& s, restir::Pcg32& rng) const override {
        // surface_roughness is 1 at Lambertian pixels.
        if (!(surface_roughness(s) < max_roughness_) && !everywhere_)
            return source_->initial_reservoir(x, y, frame_index, s, rng);
        const restir::GlossyReceiver receiver = glossy_receiver(s); // as p-hat and shading see it
        const EmitterHits hits{&rays_, &lights_.lights(), s.normal, ray_offset_};
        // The source's own light candidates where it can weigh them against BSDF rays' hits
        // (tiles, the BVH); else light candidates drawn here by power.
        if (std::optional<Reservoir> both =
                source_->with_bsdf_candidates(x, y, frame_index, counts_, receiver, hits, rng))
            return *both;
        return resample_lights_and_bsdf(restir::PowerLightSampler{lights_.power_table().view()},
                                        points_, counts_, lights_, receiver, hits, rng);
    }

    const restir::LightTileArrays& block_tiles() const override { return source_->block_tiles(); }

private:
    std::unique_ptr<InitialCandidates> source_;
    restir::CandidateCounts counts_;
    const EmbreeScene& rays_;
    const LightSet& lights_;
    float ray_offset_;
    float max_roughness_; // --bsdf-max-roughness
    // --env-sampling bsdf: BSDF candidates at diffuse pixels too (cosine-weighted), the only
    // way to the environment.
    bool everywhere_;
    LightPoints points_; // --light-points
};

} // namespace

std::unique_ptr<InitialCandidates> with_bsdf_candidates(std::unique_ptr<InitialCandidates> source,
                                                        const RenderSettings& settings,
                                                        const EmbreeScene& rays,
                                                        const LightSet& lights, float ray_offset) {
    if (settings.bsdf_candidates == 0u)
        return source;
    return std::make_unique<BsdfCandidates>(std::move(source), settings, rays, lights, ray_offset);
}

} // namespace pt
