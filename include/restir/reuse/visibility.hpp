/// @file reuse/visibility.hpp
/// Visibility of a reservoir's sample from a surface: the contract the reuse passes use, an
/// adapter that answers it for light-sample references through the application's light set
/// and ray query, and the final visibility test with visibility reuse (Bitterli et al. 2020,
/// Alg. 5: a reservoir whose sample is occluded keeps its M but gets W = 0).
#pragma once

#include "restir/concepts.hpp"
#include "restir/config.hpp"
#include "restir/core/reservoir.hpp"
#include "restir/light/light_sample.hpp"
#include "restir/light/shadow_segment.hpp"

#include <glm/geometric.hpp>
#include <glm/vec3.hpp>

#include <concepts>

namespace restir {

/// Visibility of a sample from a surface. Required expression:
///   `visible(sample, surface)` -> bool, true when nothing blocks the light path that the
///   sample describes, as seen from the surface.
template <class F, class Sample, class SurfaceT>
concept VisibilityFunction = requires(const F& visible, const Sample& sample,
                                      const SurfaceT& surface) {
    { visible(sample, surface) } -> std::convertible_to<bool>;
};

/// `VisibilityFunction` for `LightSampleRef` samples: evaluates the reference with the light
/// set and asks the ray query whether `shadow_segment` between the two points is blocked.
/// Holds pointers: the light set and the query must outlive it.
///
/// The ray offset has no default: it is a world-space length, and no single value suits both
/// a scene one unit wide and one of hundreds (1e-4 in a scene 550 units wide leaves the ends
/// of the segment inside the surfaces' rounding error, so surfaces shadow themselves: acne,
/// and a darker image). State it, `{&lights, &query, offset}`, or take the usual scale,
/// `for_scene(lights, query, scene_extent)`: 1e-4 of the scene's extent (the diagonal of its
/// bounding box). It must be positive and finite (a debug build checks). A distant light's
/// direction is tested up to `far_distance` along it (`distant_shadow_segment`), as
/// `LightPointVisibility` does.
template <LightSet Lights, RayQuery Query>
struct LightVisibility {
    /// The offset `for_scene` takes, relative to the scene's extent.
    static constexpr float relative_ray_offset = 1e-4f;
    /// The length of shadow rays towards distant lights `for_scene` takes, relative to the
    /// scene's extent.
    static constexpr float relative_far_distance = 2.0f;

    const Lights* lights;
    const Query* query;
    /// World-space, > 0: both ends of a shadow segment leave their surfaces by it.
    float ray_offset;
    float far_distance; ///< World-space length of shadow rays towards distant lights, > 0.

    /// `far_distance` defaults to 2e4 times the offset (the scene extent the offset implies
    /// when it is `relative_ray_offset` of it): state it for any other offset.
    RESTIR_HOST_DEVICE constexpr LightVisibility(const Lights* light_set, const Query* ray_query,
                                                 float offset) noexcept
        : LightVisibility(light_set, ray_query, offset,
                          offset * (relative_far_distance / relative_ray_offset)) {}
    RESTIR_HOST_DEVICE constexpr LightVisibility(const Lights* light_set, const Query* ray_query,
                                                 float offset, float far) noexcept
        : lights(light_set), query(ray_query), ray_offset(offset), far_distance(far) {
        RESTIR_ASSERT(offset > 0.0f && is_finite(offset));
        RESTIR_ASSERT(far > 0.0f && is_finite(far));
    }

    /// The offset and far distance scaled to the scene: `relative_ray_offset` and
    /// `relative_far_distance` times `scene_extent` (the diagonal of the scene's bounding box,
    /// in world units).
    RESTIR_HOST_DEVICE static constexpr LightVisibility
    for_scene(const Lights& light_set, const Query& ray_query, float scene_extent) noexcept {
        return {&light_set, &ray_query, relative_ray_offset * scene_extent,
                relative_far_distance * scene_extent};
    }

    template <Surface S>
    RESTIR_HOST_DEVICE bool operator()(const LightSampleRef& sample, const S& surface) const {
        const auto point = lights->sample_point(sample.light_id, sample.uv);
        const ShadowSegment segment =
            is_distant_point(point)
                ? distant_shadow_segment(surface_position(surface), surface_normal(surface),
                                         glm::vec3(point.position), ray_offset, far_distance)
                : shadow_segment(surface_position(surface), surface_normal(surface),
                                 glm::vec3(point.position), glm::vec3(point.normal), ray_offset);
        return !query->occluded(segment.from, segment.to);
    }
};

/// `apply_visibility` below with the ray already traced (for renderers that trace shadow rays
/// in batches): `visible` says whether the reservoir's sample is visible from its surface.
template <class Sample>
RESTIR_HOST_DEVICE bool apply_visibility(Reservoir<Sample>& reservoir, bool visible) {
    if (!reservoir.has_sample())
        return false;
    if (visible)
        return true;
    reservoir.weight_sum = 0.0f;
    reservoir.contribution_weight = 0.0f;
    return false;
}

/// Final visibility with visibility reuse: when the reservoir's sample is occluded from
/// `surface`, its contribution weight and weight sum become 0 (it shades nothing and lends
/// nothing to later reuse) while M and the sample stay. Returns whether the sample is visible.
/// Reuse passes must then be told (`ReuseParams::visibility`) so that their MIS weights
/// test visibility at the neighbours too.
template <class Sample, Surface S, VisibilityFunction<Sample, S> Visibility>
RESTIR_HOST_DEVICE bool apply_visibility(Reservoir<Sample>& reservoir, const S& surface,
                                         const Visibility& visible) {
    if (!reservoir.has_sample())
        return false;
    return apply_visibility(reservoir, visible(reservoir.sample, surface));
}

} // namespace restir
