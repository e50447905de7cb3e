/// @file reuse/similarity.hpp
/// When a neighbour's (or the previous frame's) surface is close enough to the receiver's for
/// its reservoir to be reused: the geometric tests of Bitterli et al. 2020, Sec. 6 (normals
/// within 25 degrees, depths within 10 %), plus an optional hook for materials (one for
/// roughness, `SimilarRoughness`).
#pragma once

#include "restir/concepts.hpp"
#include "restir/config.hpp"

#include <glm/geometric.hpp>

namespace restir {

/// Thresholds of the geometric similarity test.
struct SimilarityParams {
    /// Smallest accepted cosine between the two shading normals (0.906 = cos 25 degrees).
    float min_normal_cosine = 0.906f;
    /// Largest accepted |depth_a - depth_b| / depth_a (linear view depth).
    float max_relative_depth = 0.1f;
};

/// The paper's thresholds.
RESTIR_HOST_DEVICE constexpr SimilarityParams default_similarity_params() noexcept { return {}; }

/// Accepts every pair: the default material hook.
struct AnyMaterial {
    template <class S>
    RESTIR_HOST_DEVICE constexpr bool operator()(const S&, const S&) const noexcept {
        return true;
    }
};

/// A surface's perceptual roughness for reuse decisions: `surface_roughness(s)`, found by
/// argument-dependent lookup, where the surface type has it, else 1 (a Lambertian surface).
template <class S>
RESTIR_HOST_DEVICE float reuse_roughness(const S& s) {
    if constexpr (requires { surface_roughness(s); })
        return static_cast<float>(surface_roughness(s));
    else
        return 1.0f;
}

/// A material hook for glossy surfaces: accepts a neighbour whose roughness is within
/// `max_difference` of the receiver's, so that a narrow lobe does not take samples chosen for a
/// much wider one, nor the reverse (the lobe mismatch behind flicker on glossy surfaces). Reads
/// `surface_roughness(s)`, found by argument-dependent lookup: perceptual roughness in [0, 1],
/// 1 for a Lambertian surface.
struct SimilarRoughness {
    float max_difference = 0.2f;

    template <class S>
    RESTIR_HOST_DEVICE bool operator()(const S& receiver, const S& candidate) const {
        const float d = surface_roughness(receiver) - surface_roughness(candidate);
        return (d < 0.0f ? -d : d) <= max_difference;
    }
};

/// True when `candidate` may lend its reservoir to `receiver`: both valid, normals and depths
/// within the thresholds, and `material_test(receiver, candidate)` true (for instance: same
/// material class, similar roughness).
template <Surface S, class MaterialTest = AnyMaterial>
RESTIR_HOST_DEVICE bool surfaces_similar(const S& receiver, const S& candidate,
                                         const SimilarityParams& params,
                                         const MaterialTest& material_test = {}) {
    if (!is_valid_surface(receiver) || !is_valid_surface(candidate))
        return false;
    const glm::vec3 n_receiver = surface_normal(receiver);
    const glm::vec3 n_candidate = surface_normal(candidate);
    if (glm::dot(n_receiver, n_candidate) < params.min_normal_cosine)
        return false;
    const float depth_receiver = surface_depth(receiver);
    const float depth_difference = surface_depth(candidate) - depth_receiver;
    const float abs_difference = depth_difference < 0.0f ? -depth_difference : depth_difference;
    if (abs_difference > params.max_relative_depth * depth_receiver)
        return false;
    return material_test(receiver, candidate);
}

} // namespace restir
