/// @file light/light_point_sample.hpp
/// A light sample that carries its evaluated point in a folded form, so that reuse evaluates
/// p-hat at other surfaces without looking the light up again: no random reads into the
/// application's light and VPL buffers for every neighbour (the cost of `LightSampleRef`
/// reuse, whose sample is re-evaluated with `sample_point` each time).
#pragma once

#include "restir/concepts.hpp"
#include "restir/config.hpp"
#include "restir/core/math.hpp"
#include "restir/light/falloff.hpp"
#include "restir/light/irradiance.hpp"
#include "restir/light/light_sample.hpp"
#include "restir/light/receiver.hpp"
#include "restir/light/shadow_segment.hpp"

#include <glm/geometric.hpp>
#include <glm/vec3.hpp>

#include <cmath>
#include <concepts>
#include <cstdint>
#include <type_traits>

namespace restir {

/// Unshadowed irradiance of a light point per unit intensity, in a folded form that makes
/// area lights, VPLs and point lights one formula without branches. With x the offset from the
/// receiver to the light, d^2 = x.x and e = max(d^2, d_min^2):
///   E / I = max(0, n.x) C / (d^2 D),  C = max(0, -n_l.x), or d for an isotropic light,
///   D = (e + r^2 + sqrt(e (e + r^2))) / 2,
/// which is Yuksel's falloff 2 / (d^2 + r^2 + d sqrt(d^2 + r^2)) for r > 0 (its d sqrt(...)
/// written as one square root), the clamped inverse square for d_min > 0, and 1/d^2 otherwise
/// (area lights, whose 1 / area_pdf is folded into I). Times cos(theta_receiver)
/// cos(theta_light) as in `unshadowed_irradiance`. Plain float arithmetic: a loop over
/// structure-of-arrays lights that calls it vectorises. Returns 0 for a light at the receiver.
RESTIR_HOST_DEVICE inline float folded_irradiance_factor(float x, float y, float z,
                                                         glm::vec3 receiver_normal, float nx,
                                                         float ny, float nz, float isotropic,
                                                         float yuksel_radius_squared,
                                                         float min_distance_squared) {
    const float d2 = x * x + y * y + z * z;
    const float receiver =
        max_of(0.0f, receiver_normal.x * x + receiver_normal.y * y + receiver_normal.z * z);
    const float emitter = max_of(0.0f, -(nx * x + ny * y + nz * z)) + isotropic * std::sqrt(d2);
    const float e = max_of(d2, min_distance_squared);
    const float r2 = yuksel_radius_squared;
    const float factor = 2.0f * receiver * emitter / (d2 * (e + r2 + std::sqrt(e * (e + r2))));
    return is_valid_weight(factor) ? factor : 0.0f;
}

/// Light arriving from a light point per unit intensity, before the receiver reflects it: the
/// emitter's cosine times the falloff, cos(theta_light) falloff(d) (1/d^2 for area lights), in
/// the folded form of `folded_irradiance_factor` without its receiver cosine, with the offset
/// (x, y, z) from the receiver to the light and `inverse_distance` = 1/|x| (0 for a light at the
/// receiver). Times the receiver's f(wo, wi) max(0, n.wi) at wi = x / |x| and the intensity, it
/// is the unshadowed outgoing radiance. Plain float arithmetic, for vectorised loops.
RESTIR_HOST_DEVICE inline float folded_arrival_factor(float x, float y, float z, float nx, float ny,
                                                      float nz, float isotropic,
                                                      float yuksel_radius_squared,
                                                      float min_distance_squared,
                                                      float inverse_distance) {
    const float d2 = x * x + y * y + z * z;
    // max(0, -n_l.x) = d cos(theta_light); d for an isotropic light (cos 1).
    const float emitter = max_of(0.0f, -(nx * x + ny * y + nz * z)) + isotropic * std::sqrt(d2);
    const float e = max_of(d2, min_distance_squared);
    const float r2 = yuksel_radius_squared;
    const float factor = 2.0f * emitter * inverse_distance / (e + r2 + std::sqrt(e * (e + r2)));
    return is_valid_weight(factor) ? factor : 0.0f;
}

/// A light sample with its point: which light, and the point that evaluating its sample gave,
/// folded for `folded_irradiance_factor` (the point stands in for the light's uv, which is not
/// kept). 48 bytes with its alignment, so that a `Reservoir<LightPointSample>` fills one
/// 64-byte cache line. The point stays valid while the light does not move (for reservoirs kept
/// across frames, as a `LightSampleRef` does). A distant light's sample (`positional` 0) keeps
/// its direction in `position`: the offset from every receiver to the light is that direction,
/// x = position - positional * receiver, at distance 1 from an isotropic "point", so the
/// folded formulas give L cos(theta_receiver) / pdf for it with no branch and no shift.
struct alignas(16) LightPointSample {
    std::uint32_t light_id = 0u;
    glm::vec3 position{0.0f};
    glm::vec3 normal{0.0f};    ///< Emitting side; zero for an isotropic light.
    glm::vec3 intensity{0.0f}; ///< Radiance / area_pdf (area lights), radiance (delta lights).
    /// The falloff of a delta light: r^2 of Yuksel's (> 0), -d_min^2 of the clamped inverse
    /// square (< 0), or 0 for the exact inverse square and for area lights.
    float falloff = 0.0f;
    /// 1 for a point; 0 for a distant light's direction (`LightSample::is_distant`).
    float positional = 1.0f;

    /// Whether the sample is a direction (a distant light's), not a point.
    RESTIR_HOST_DEVICE constexpr bool is_distant() const noexcept { return positional == 0.0f; }
    /// The offset from a receiver at `receiver_position` to the light: the point minus the
    /// receiver, or the direction of a distant light.
    RESTIR_HOST_DEVICE glm::vec3 offset_from(glm::vec3 receiver_position) const noexcept {
        return position - receiver_position * positional;
    }

    /// The same light and point (the frame recipe skips retesting a sample it kept).
    RESTIR_HOST_DEVICE friend constexpr bool operator==(const LightPointSample& a,
                                                        const LightPointSample& b) noexcept {
        return a.light_id == b.light_id && a.position.x == b.position.x &&
               a.position.y == b.position.y && a.position.z == b.position.z &&
               a.normal.x == b.normal.x && a.normal.y == b.normal.y && a.normal.z == b.normal.z &&
               a.intensity.x == b.intensity.x && a.intensity.y == b.intensity.y &&
               a.intensity.z == b.intensity.z && a.falloff == b.falloff &&
               a.positional == b.positional;
    }
};

static_assert(std::is_trivially_copyable_v<LightPointSample>);
static_assert(sizeof(LightPointSample) == 48u);

/// The folded falloff parameter of a delta light under `falloff` (see LightPointSample).
RESTIR_HOST_DEVICE inline float folded_falloff(const Falloff& falloff) noexcept {
    const float squared = falloff.parameter * falloff.parameter;
    switch (falloff.kind) {
    case FalloffKind::yuksel:
        return squared;
    case FalloffKind::clamped_inverse_square:
        return -squared;
    case FalloffKind::inverse_square:
        break;
    }
    return 0.0f;
}

/// Light `light_id` with its evaluated `point`, folded; delta lights take `falloff`. A point
/// that cannot emit (an area light with area_pdf 0) gets zero intensity. A distant light's
/// direction keeps radiance / pdf (per steradian) as its intensity, a zero normal and
/// `positional` 0.
template <LightPoint P>
RESTIR_HOST_DEVICE LightPointSample make_light_point_sample(std::uint32_t light_id, const P& point,
                                                            const Falloff& falloff) {
    const bool distant = is_distant_point(point);
    LightPointSample s;
    s.light_id = light_id;
    s.position = point.position;
    s.normal = distant ? glm::vec3(0.0f) : glm::vec3(point.normal);
    s.positional = distant ? 0.0f : 1.0f;
    const float area_pdf = static_cast<float>(point.area_pdf);
    const float scale = point.is_delta ? 1.0f : area_pdf > 0.0f ? 1.0f / area_pdf : 0.0f;
    s.intensity = glm::vec3(point.radiance) * scale;
    s.falloff = point.is_delta && !distant ? folded_falloff(falloff) : 0.0f;
    return s;
}

/// Unshadowed irradiance at (`position`, `normal`) from the sample's point: the value of
/// `unshadowed_irradiance` for the point it was made from, up to float rounding.
RESTIR_HOST_DEVICE inline glm::vec3 unshadowed_irradiance(const LightPointSample& s,
                                                          glm::vec3 position, glm::vec3 normal) {
    const glm::vec3 x = s.offset_from(position);
    const bool isotropic = s.normal.x == 0.0f && s.normal.y == 0.0f && s.normal.z == 0.0f;
    return s.intensity * folded_irradiance_factor(x.x, x.y, x.z, normal, s.normal.x, s.normal.y,
                                                  s.normal.z, isotropic ? 1.0f : 0.0f,
                                                  max_of(s.falloff, 0.0f),
                                                  max_of(-s.falloff, 0.0f));
}

/// Unshadowed radiance that `receiver` reflects towards its viewer from the sample's point:
/// intensity cos(theta_light) falloff(d) f(wo, wi) max(0, n.wi) (for an area light, with the
/// 1 / area_pdf that the sample's intensity carries). A `LambertianReceiver` takes the folded
/// irradiance formula, albedo / pi `unshadowed_irradiance`, as diffuse targets always have.
template <Receiver R>
RESTIR_HOST_DEVICE glm::vec3 unshadowed_radiance(const LightPointSample& s, const R& receiver) {
    if constexpr (std::same_as<R, LambertianReceiver>) {
        return receiver.albedo * inv_pi *
               unshadowed_irradiance(s, receiver.position, receiver.normal);
    } else {
        const glm::vec3 x = s.offset_from(glm::vec3(receiver.position));
        const float d2 = glm::dot(x, x);
        const float inverse_distance = d2 > 0.0f ? 1.0f / std::sqrt(d2) : 0.0f;
        const bool isotropic = s.normal.x == 0.0f && s.normal.y == 0.0f && s.normal.z == 0.0f;
        const float factor = folded_arrival_factor(
            x.x, x.y, x.z, s.normal.x, s.normal.y, s.normal.z, isotropic ? 1.0f : 0.0f,
            max_of(s.falloff, 0.0f), max_of(-s.falloff, 0.0f), inverse_distance);
        const float sphere_radius = std::sqrt(max_of(s.falloff, 0.0f)) * inverse_distance;
        const bool from_vpl = s.falloff < 0.0f; // the clamped falloff: a `VplPartition`'s VPL
        return s.intensity *
               reflected_from(receiver, x * inverse_distance, sphere_radius, from_vpl) * factor;
    }
}

/// `VisibilityFunction` for `LightPointSample`s, without a light lookup: the segment that
/// `LightVisibility` tests, from the surface to the sample's point, both ends pushed
/// `ray_offset` off their surfaces towards each other (a VPL's end too; an isotropic point's
/// end stays). Holds a pointer: the query must outlive it.
///
/// The ray offset has no default, as `LightVisibility`'s: a world-space length that must be
/// scaled to the scene (`for_scene`: 1e-4 of the diagonal of its bounding box), positive and
/// finite (a debug build checks). `{&query}` without it does not compile. A distant light's
/// sample is tested along its direction up to `far_distance` (`distant_shadow_segment`).
template <RayQuery Query>
struct LightPointVisibility {
    /// The offset `for_scene` takes, relative to the scene's extent.
    static constexpr float relative_ray_offset = 1e-4f;
    /// The length of shadow rays towards distant lights `for_scene` takes, relative to the
    /// scene's extent: from any point of the scene, twice its diagonal leaves it.
    static constexpr float relative_far_distance = 2.0f;

    const Query* query;
    float ray_offset;   ///< World-space, > 0.
    float far_distance; ///< World-space length of shadow rays towards distant lights, > 0.

    /// `far_distance` defaults to the scene extent that `offset` implies when it came from
    /// `relative_ray_offset` (2e4 times the offset): state it for any other offset.
    RESTIR_HOST_DEVICE constexpr LightPointVisibility(const Query* ray_query, float offset) noexcept
        : LightPointVisibility(ray_query, offset,
                               offset * (relative_far_distance / relative_ray_offset)) {}
    RESTIR_HOST_DEVICE constexpr LightPointVisibility(const Query* ray_query, float offset,
                                                      float far) noexcept
        : query(ray_query), ray_offset(offset), far_distance(far) {
        RESTIR_ASSERT(offset > 0.0f && is_finite(offset));
        RESTIR_ASSERT(far > 0.0f && is_finite(far));
    }
    /// The offset and the far distance scaled to the scene: `relative_ray_offset` and
    /// `relative_far_distance` times `scene_extent` (the diagonal of the scene's bounding box,
    /// in world units).
    RESTIR_HOST_DEVICE static constexpr LightPointVisibility
    for_scene(const Query& ray_query, float scene_extent) noexcept {
        return {&ray_query, relative_ray_offset * scene_extent,
                relative_far_distance * scene_extent};
    }

    /// The segment that `operator()` tests, for renderers that trace many at once (packets).
    template <Surface S>
    RESTIR_HOST_DEVICE ShadowSegment segment(const LightPointSample& sample,
                                             const S& surface) const {
        if (sample.is_distant())
            return distant_shadow_segment(surface_position(surface), surface_normal(surface),
                                          sample.position, ray_offset, far_distance);
        return shadow_segment(surface_position(surface), surface_normal(surface), sample.position,
                              sample.normal, ray_offset);
    }

    template <Surface S>
    RESTIR_HOST_DEVICE bool operator()(const LightPointSample& sample, const S& surface) const {
        const ShadowSegment s = segment(sample, surface);
        return !query->occluded(s.from, s.to);
    }
};

} // namespace restir
