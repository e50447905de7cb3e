/// @file sampling/light_candidates.hpp
/// RIS candidates drawn from a light set: a light and a point on it, with the source pdf in
/// the measure the irradiance functions use.
#pragma once

#include "restir/concepts.hpp"
#include "restir/config.hpp"
#include "restir/core/discrete_sample.hpp"
#include "restir/core/rng.hpp"
#include "restir/light/light_sample.hpp"
#include "restir/sampling/light_sampler.hpp"
#include "restir/sampling/ris.hpp"

#include <glm/vec2.hpp>

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

} // namespace restir
