/// @file sampling/diffuse_direction.hpp
/// Cosine-weighted directions (diffuse emission and Lambertian reflection) and their density,
/// a sample/pdf pair.
#pragma once

#include "restir/config.hpp"
#include "restir/core/math.hpp"

#include <glm/geometric.hpp>
#include <glm/vec3.hpp>

#include <cmath>

namespace restir {

/// Unit vector with density cos(theta) / pi about `normal` (Malley's method), or uniform over
/// the sphere (density 1 / 4 pi) when `normal` is zero: the emission of a diffuse emitter or
/// an isotropic point light, and the reflection of a Lambertian BSDF. `diffuse_direction_pdf`
/// is its density.
RESTIR_HOST_DEVICE inline glm::vec3 sample_diffuse_direction(glm::vec3 normal, float u0, float u1) {
    const float phi = two_pi * u1;
    if (normal.x == 0.0f && normal.y == 0.0f && normal.z == 0.0f) {
        const float z = 1.0f - 2.0f * u0;
        const float r = std::sqrt(max_of(0.0f, 1.0f - z * z));
        return {r * std::cos(phi), r * std::sin(phi), z};
    }
    const float r = std::sqrt(u0);
    const float z = std::sqrt(max_of(0.0f, 1.0f - u0));
    // Orthonormal basis about the normal (Duff et al. 2017).
    const float sign = normal.z >= 0.0f ? 1.0f : -1.0f;
    const float a = -1.0f / (sign + normal.z);
    const float b = normal.x * normal.y * a;
    const glm::vec3 tangent{1.0f + sign * normal.x * normal.x * a, sign * b, -sign * normal.x};
    const glm::vec3 bitangent{b, sign + normal.y * normal.y * a, -normal.y};
    // The frame is orthonormal, so the result is unit length up to rounding.
    return tangent * (r * std::cos(phi)) + bitangent * (r * std::sin(phi)) + normal * z;
}

/// The density per unit solid angle with which `sample_diffuse_direction(normal, ...)` returns
/// the unit vector `direction`: max(0, cos theta) / pi, or 1 / (4 pi) when `normal` is zero.
RESTIR_HOST_DEVICE inline float diffuse_direction_pdf(glm::vec3 normal, glm::vec3 direction) {
    if (normal.x == 0.0f && normal.y == 0.0f && normal.z == 0.0f)
        return 0.25f * inv_pi;
    return max_of(0.0f, glm::dot(normal, direction)) * inv_pi;
}

/// `sample_diffuse_direction`'s name before 0.2 (when it lived in vpl/photon_shooter.hpp).
[[deprecated("use restir::sample_diffuse_direction")]] RESTIR_HOST_DEVICE inline glm::vec3
sample_emission_direction(glm::vec3 normal, float u0, float u1) {
    return sample_diffuse_direction(normal, u0, u1);
}

} // namespace restir
