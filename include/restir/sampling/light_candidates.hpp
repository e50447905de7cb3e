/// @file sampling/light_candidates.hpp
/// RIS candidates drawn from a light set: a light and a point on it, with the source pdf in
/// the measure the irradiance functions use.
#pragma once

#include "restir/concepts.hpp"
#include "restir/config.hpp"
#include "restir/core/discrete_sample.hpp"
#include "restir/core/reservoir.hpp"
#include "restir/core/rng.hpp"
#include "restir/light/falloff.hpp"
#include "restir/light/light_point_sample.hpp"
#include "restir/light/light_sample.hpp"
#include "restir/sampling/light_sampler.hpp"
#include "restir/sampling/ris.hpp"

#include <glm/vec2.hpp>
#include <glm/vec3.hpp>

namespace restir {

/// The light `choice` with a uniform point uv on it (two numbers), as a candidate whose source
/// pdf is the light's pmf.
template <UniformRng Rng>
RESTIR_HOST_DEVICE SourceSample<LightSampleRef> with_uniform_point(const DiscreteSample& choice,
                                                                   Rng& rng) {
    const float u = next_float(rng); // named: the order of the draws is fixed
    const float v = next_float(rng);
    return {{choice.index, glm::vec2(u, v)}, choice.pmf};
}

/// A light drawn from `sampler` (two numbers, `sample_light`) and a uniform point uv on it
/// (two more), with its source pdf: the light's pmf alone.
///
/// The measure is the primary sample space (light, uv), where uv is uniform (density 1). The
/// target must be expressed in the same measure: for an area light, the contribution of the
/// point with the Jacobian 1 / area_pdf of the map from uv to the light's surface, which is
/// what `unshadowed_irradiance` (and `light_point_sample`, `evaluate_tile_block`) compute.
/// So p = pmf, never pmf * area_pdf, and p-hat is not Le * BSDF * cos / d^2 alone for area
/// lights (that is the integrand over area, without the 1 / area_pdf). Delta lights (point
/// lights, VPLs) have area_pdf 1 and no uv dependence.
template <LightSampler Sampler, UniformRng Rng>
RESTIR_HOST_DEVICE SourceSample<LightSampleRef> draw_light_candidate(const Sampler& sampler,
                                                                     Rng& rng) {
    return with_uniform_point(sample_light(sampler, rng), rng);
}

/// `draw_light_candidate` from a sampler that reads the shading point (`ContextLightSampler`):
/// the source pdf is the light's pmf at `at`, so RIS at `at` stays unbiased as long as that pmf
/// is positive wherever the target is.
template <ContextLightSampler Sampler, UniformRng Rng>
RESTIR_HOST_DEVICE SourceSample<LightSampleRef>
draw_light_candidate(const Sampler& sampler, const ShadingPoint& at, Rng& rng) {
    return with_uniform_point(sample_light(sampler, at, rng), rng);
}

/// The light `choice` with a point drawn from the receiver at `from` (two numbers:
/// `lights.sample_point(id, uv, from)`, `ReceiverLightSet`), folded, as a candidate whose source
/// pdf is the light's pmf. The measure is that of `draw_light_candidate`, the primary sample
/// space (light, uv); the map from uv to the light now depends on the receiver, and its
/// Jacobian 1 / area_pdf, which the sample's intensity carries, is bounded where area sampling's
/// is not: next to the light, a solid-angle map's is d^2 / (cos theta_light solid angle). A
/// light that the sampler cannot draw (pmf 0) gives an empty candidate.
template <ReceiverLightSet Lights, UniformRng Rng>
RESTIR_HOST_DEVICE SourceSample<LightPointSample>
with_receiver_point(const DiscreteSample& choice, const Lights& lights, glm::vec3 from,
                    const Falloff& falloff, Rng& rng) {
    const float u = next_float(rng); // named: the order of the draws is fixed
    const float v = next_float(rng);
    SourceSample<LightPointSample> candidate{{}, choice.pmf};
    if (choice.pmf > 0.0f)
        candidate.sample = make_light_point_sample(
            choice.index, lights.sample_point(choice.index, glm::vec2(u, v), from), falloff);
    return candidate;
}

/// A light drawn from `sampler` (two numbers) with its point drawn from the receiver at `from`
/// (two more): `with_receiver_point`. With the target `unshadowed_irradiance` (or any p-hat of
/// the sample's stored intensity), RIS over these candidates is unbiased wherever the sampler's
/// pmf is positive for every light that reaches `from`.
template <LightSampler Sampler, ReceiverLightSet Lights, UniformRng Rng>
RESTIR_HOST_DEVICE SourceSample<LightPointSample>
draw_receiver_light_candidate(const Sampler& sampler, const Lights& lights, glm::vec3 from,
                              const Falloff& falloff, Rng& rng) {
    return with_receiver_point(sample_light(sampler, rng), lights, from, falloff, rng);
}

/// The reservoir `chosen` of RIS over area-sampled candidates (light, uniform uv), with its
/// light's point drawn again from the receiver at `from` (`lights.sample_point(id, uv, from)`)
/// and its W corrected: for presampled candidates (light tiles) whose points cannot depend on
/// the receiver. `coverage` is the fraction of the chosen light's uv square where the first
/// RIS's target is positive at this receiver (for a one-sided planar light under a cosine
/// receiver, the share of its area above the receiver's tangent plane:
/// `triangle_area_fraction_above`); `target(sample)` is p-hat at the receiver.
///
/// Why it is unbiased. W of the first RIS is an unbiased contribution weight of (l, u): for
/// any g that is 0 where that target is, E[g(l, u) W] = sum_l int g(l, u) du. Take
/// g(l, u) = [p-hat(l, u) > 0] h(l) / coverage(l), h(l) = int f(l, u') du' the light's whole
/// contribution in the new map: sum_l int g = sum_l h(l). And f(l, u') for an independent
/// uniform u' is an unbiased estimate of h(l). So f(l, u') W / coverage(l) is unbiased, and
/// W' = W / coverage is a contribution weight of (l, u') for reuse as well. Delta lights keep
/// their sample (their point does not depend on uv), and so do distant lights (their direction
/// does not depend on the receiver, and has no coverage to correct). A redrawn point that the
/// receiver cannot see (p-hat 0) leaves an empty reservoir, which changes no estimate.
template <ReceiverLightSet Lights, class Target>
RESTIR_HOST_DEVICE Reservoir<LightPointSample>
redraw_point_from_receiver(const Reservoir<LightPointSample>& chosen, float coverage,
                           const Lights& lights, glm::vec2 uv, glm::vec3 from,
                           const Falloff& falloff, const Target& target) {
    if (!chosen.has_sample() || !(chosen.contribution_weight > 0.0f) || chosen.sample.is_distant())
        return chosen;
    const std::uint32_t id = chosen.sample.light_id;
    const auto point = lights.sample_point(id, uv, from);
    if (point.is_delta)
        return chosen;
    Reservoir<LightPointSample> redrawn = chosen;
    redrawn.sample = make_light_point_sample(id, point, falloff);
    const float target_value = static_cast<float>(target(redrawn.sample));
    redrawn.target_value = is_valid_weight(target_value) ? target_value : 0.0f;
    const float weight = safe_divide(chosen.contribution_weight, coverage);
    redrawn.contribution_weight = redrawn.target_value > 0.0f ? weight : 0.0f;
    // W = w_sum / (M p-hat(y)), as `finalize` leaves it, for passes that read w_sum.
    redrawn.weight_sum = redrawn.contribution_weight * static_cast<float>(redrawn.candidate_count) *
                         redrawn.target_value;
    return redrawn;
}

} // namespace restir
