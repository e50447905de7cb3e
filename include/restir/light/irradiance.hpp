/// @file light/irradiance.hpp
/// What one light point contributes to the irradiance at a receiver, without visibility: the
/// common core of target functions and shading for emitters and VPLs alike.
#pragma once

#include "restir/concepts.hpp"
#include "restir/config.hpp"
#include "restir/core/math.hpp"
#include "restir/light/falloff.hpp"

#include <glm/geometric.hpp>
#include <glm/vec3.hpp>

#include <cmath>

namespace restir {

/// Distance falloff applied to delta lights (VPLs and point lights); area lights use the exact
/// geometry term, which their area density keeps finite in expectation. The default is the
/// exact 1/d^2 (unbiased, unbounded near a light); `yuksel` and `clamped` bound it and are
/// biased (docs/noise-and-bias.md): VPL renderers want one of them, by name.
struct Falloff {
    FalloffKind kind = FalloffKind::inverse_square;
    float parameter = 0.0f; ///< Yuksel radius or minimum distance, in scene units.

    /// Exact inverse square (the default).
    RESTIR_HOST_DEVICE static constexpr Falloff exact() noexcept { return {}; }
    /// Yuksel's attenuation with sphere radius `radius` (biased, finite everywhere).
    RESTIR_HOST_DEVICE static constexpr Falloff yuksel(float radius) noexcept {
        return {FalloffKind::yuksel, radius};
    }
    /// 1 / max(d, `min_distance`)^2 (biased, finite everywhere).
    RESTIR_HOST_DEVICE static constexpr Falloff clamped(float min_distance) noexcept {
        return {FalloffKind::clamped_inverse_square, min_distance};
    }
};

/// Emission towards `direction` (unit, from the light to the receiver) relative to the
/// light's `radiance`: max(0, cos theta) about the light's normal for one-sided emitters (area
/// lights, and VPLs, which are points of diffuse surfaces), 1 when the normal is zero
/// (isotropic point lights, whose `radiance` is an intensity).
RESTIR_HOST_DEVICE inline float emission_cosine(glm::vec3 light_normal,
                                                glm::vec3 direction) noexcept {
    if (light_normal.x == 0.0f && light_normal.y == 0.0f && light_normal.z == 0.0f)
        return 1.0f;
    return max_of(0.0f, glm::dot(light_normal, direction));
}

/// Unshadowed irradiance at (`position`, `normal`) from one light point, as a Monte Carlo
/// estimate per point:
///   area light: L cos(theta_light) cos(theta_receiver) / (d^2 area_pdf)   (one sample of E);
///   delta light: I cos(theta_light) cos(theta_receiver) falloff(d)        (exact, with the
///                chosen falloff in place of 1/d^2).
///   distant light: L cos(theta_receiver) / pdf                             (one sample of E,
///                pdf per steradian: the direction is the same from every receiver, d = 1).
/// For a VPL of reflected flux Phi, I = Phi / pi (`vpl_light_sample`). Multiply by the
/// receiver's BRDF (albedo / pi for a diffuse one) for outgoing radiance.
template <LightPoint P>
RESTIR_HOST_DEVICE glm::vec3 unshadowed_irradiance(const P& light, glm::vec3 position,
                                                   glm::vec3 normal, const Falloff& falloff) {
    const glm::vec3 offset =
        glm::vec3(light.position) - (is_distant_point(light) ? glm::vec3(0.0f) : position);
    const float distance_squared = glm::dot(offset, offset);
    if (!(distance_squared > 0.0f))
        return glm::vec3(0.0f);
    const float distance = std::sqrt(distance_squared);
    const glm::vec3 direction = offset * (1.0f / distance); // receiver -> light, one division
    const float cos_receiver = max_of(0.0f, glm::dot(normal, direction));
    const float cos_light = emission_cosine(light.normal, -direction);
    // Both falloffs, then a select: candidates mix area lights and VPLs at random, and half of
    // them face away, so branches here would mispredict often.
    const float delta_falloff = evaluate_falloff(falloff.kind, distance, falloff.parameter);
    const float area_falloff =
        safe_divide(1.0f, distance_squared * static_cast<float>(light.area_pdf));
    const float geometry = cos_receiver * cos_light;
    return glm::vec3(light.radiance) * (geometry * (light.is_delta ? delta_falloff : area_falloff));
}

} // namespace restir
