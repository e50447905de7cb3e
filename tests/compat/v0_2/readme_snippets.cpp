// The README.md snippets of version 0.2.0 (the state at the end of 2026-11-25), as
// tests/readme_snippets.cmake wrote them then: kept unchanged, they must compile against HEAD.
#include "readme/prelude.hpp"

void readme::Frame::snippets() {

    // Lights chosen in proportion to their power, one reservoir per pixel.
    restir::AliasTable table(light_powers); // std::span<const float>, host side
    restir::PowerLightSampler sampler{table.view()};
    const restir::Falloff falloff = restir::Falloff::exact(); // Falloff::yuksel(r) for VPLs

    // The unshadowed contribution of a light sample at a texel, and p-hat, its luminance. Area
    // lights include 1 / area_pdf, so a candidate's pdf is its light's pmf alone.
    auto contribution = [&](const restir::LightSampleRef& s, const MyTexel& t) {
        return albedo(t) * restir::unshadowed_irradiance(lights.sample_point(s.light_id, s.uv),
                                                         surface_position(t), surface_normal(t),
                                                         falloff);
    };
    auto target_at = [&](const restir::LightSampleRef& s, const MyTexel& t) {
        return luminance(contribution(s, t));
    };

    restir::Pcg32 rng = restir::make_pixel_rng(pixel_index, frame, /*pass=*/0);
    auto draw = [&](restir::Pcg32& g) { return restir::draw_light_candidate(sampler, g); };
    // One p-hat, target_at(sample, texel), for the candidates here and for every reuse pass.
    restir::Reservoir<restir::LightSampleRef> r =
        restir::resample_ris(rng, 32, draw, target_at, texel);

    // f(y) * W estimates the sum over all lights (Bitterli et al. 2020, Eq. 6).
    // The shadow ray leaves both surfaces by 1e-4 of the scene's extent (its bounding box's
    // diagonal, in world units): a fixed offset makes large scenes shadow themselves.
    const auto visible =
        restir::LightVisibility<MyLights, MyRays>::for_scene(lights, rays, scene_extent);
    const glm::vec3 radiance = r.has_sample() && visible(r.sample, texel)
                                   ? contribution(r.sample, texel) * r.contribution_weight
                                   : glm::vec3(0.0f);
    std::vector<restir::Vpl> vpls =
        restir::shoot_photons(lights, photon_rays /* closest_hit */, my_bsdf /* scatter */,
                              restir::default_photon_params());
    restir::UnifiedLightSet<MyLights> unified{&lights, vpls.data(), std::uint32_t(vpls.size())};
    restir::AliasTable gi_table(restir::unified_light_powers(unified)); // candidates by power
    // p-hat and shading as above, on unified.sample_point(id, uv), with Falloff::yuksel(radius)
}
