/// @file light/sphere_light.hpp
/// Points on a spherical light drawn from a receiver outside it: directions uniform in the cone
/// of the visible cap (the cone about the centre whose half-angle has sine radius / distance),
/// each mapped to the nearest point of the sphere along it.
#pragma once

#include "restir/config.hpp"
#include "restir/core/math.hpp"
#include "restir/light/solid_angle.hpp"

#include <glm/geometric.hpp>
#include <glm/vec2.hpp>
#include <glm/vec3.hpp>

#include <cmath>

namespace restir {

namespace detail {

/// 1 - cos(theta_max) of the cone that a sphere of `radius` at squared distance
/// `distance_squared` subtends, as sin^2 / (1 + cos) (no cancellation for small spheres); 0 at
/// or inside the sphere.
RESTIR_HOST_DEVICE inline float cone_one_minus_cos(float distance_squared, float radius) {
    const float sin_squared = safe_divide(radius * radius, distance_squared);
    if (!(sin_squared < 1.0f))
        return 0.0f;
    return sin_squared / (1.0f + std::sqrt(1.0f - sin_squared));
}

} // namespace detail

/// 1 / the solid angle of the cone that the sphere (`centre`, `radius`) subtends from `from`:
/// 1 / (2 pi (1 - cos theta_max)); 0 at or inside the sphere.
RESTIR_HOST_DEVICE inline float sphere_cone_pdf(glm::vec3 from, glm::vec3 centre, float radius) {
    const glm::vec3 axis = centre - from;
    const float one_minus_cos = detail::cone_one_minus_cos(glm::dot(axis, axis), radius);
    return one_minus_cos > 0.0f ? safe_divide(1.0f, two_pi * one_minus_cos) : 0.0f;
}

/// A point of the sphere's visible cap whose direction from `from` is uniform in the cone the
/// sphere subtends, from two uniform numbers `u`: 1 - cos theta = u0 (1 - cos theta_max),
/// phi = 2 pi u1, then the nearest point of the sphere along the direction. pdf =
/// `sphere_cone_pdf`; 0 at or inside the sphere.
RESTIR_HOST_DEVICE inline SolidAngleSample sample_sphere_cone(glm::vec3 from, glm::vec3 centre,
                                                              float radius, glm::vec2 u) {
    const glm::vec3 axis = centre - from;
    const float distance_squared = glm::dot(axis, axis);
    const float one_minus_cos_max = detail::cone_one_minus_cos(distance_squared, radius);
    if (!(one_minus_cos_max > 0.0f))
        return {};
    const float distance = std::sqrt(distance_squared);
    const glm::vec3 w = axis / distance;
    // An orthonormal frame about w (Duff et al. 2017, "Building an orthonormal basis, revisited").
    const float sign = std::copysign(1.0f, w.z);
    const float a = -1.0f / (sign + w.z), b = w.x * w.y * a;
    const glm::vec3 t(1.0f + sign * w.x * w.x * a, sign * b, -sign * w.x);
    const glm::vec3 s(b, sign + w.y * w.y * a, -w.y);
    const float one_minus_cos = u.x * one_minus_cos_max;
    const float cos_theta = 1.0f - one_minus_cos;
    const float sin_theta = std::sqrt(max_of(0.0f, one_minus_cos * (2.0f - one_minus_cos)));
    const float phi = two_pi * u.y;
    const glm::vec3 around = std::cos(phi) * t + std::sin(phi) * s;
    // The nearest hit at distance d cos theta - sqrt(r^2 - d^2 sin^2 theta) along the
    // direction, written from the centre (precise for small spheres): its angle gamma from the
    // axis at the centre has sin gamma = hit sin theta / r.
    const float discriminant =
        max_of(0.0f, radius * radius - distance_squared * sin_theta * sin_theta);
    const float hit = distance * cos_theta - std::sqrt(discriminant);
    const float sin_gamma = min_of(1.0f, hit * sin_theta / radius);
    const float cos_gamma = std::sqrt(max_of(0.0f, 1.0f - sin_gamma * sin_gamma));
    const glm::vec3 point = centre + radius * (sin_gamma * around - cos_gamma * w);
    return {point, safe_divide(1.0f, two_pi * one_minus_cos_max)};
}

} // namespace restir
