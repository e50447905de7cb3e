/// @file light/solid_angle.hpp
/// Points on lights drawn by direction from a receiver: the sample record and the change of
/// measure between solid angle (about the receiver) and area (on the light).
#pragma once

#include "restir/config.hpp"
#include "restir/core/math.hpp"

#include <glm/geometric.hpp>
#include <glm/vec3.hpp>

#include <cmath>
#include <type_traits>

namespace restir {

/// A point on a light drawn from a receiver, and the solid-angle density of its direction
/// (0: none; the point is then meaningless).
struct SolidAngleSample {
    glm::vec3 point{0.0f}; ///< On the light's surface.
    float pdf = 0.0f;      ///< Density of the direction from the receiver to `point`, per sr.
};

static_assert(std::is_trivially_copyable_v<SolidAngleSample>);

/// Area density of a point drawn with solid-angle density `pdf` from `from`:
/// pdf_area = pdf_solid_angle |cos theta_light| / d^2, with theta_light between the unit
/// `light_normal` and the direction. 0 for a point at the receiver or a non-finite result.
RESTIR_HOST_DEVICE inline float solid_angle_to_area_pdf(float pdf, glm::vec3 from, glm::vec3 point,
                                                        glm::vec3 light_normal) {
    const glm::vec3 offset = point - from;
    const float distance_squared = glm::dot(offset, offset);
    // |cos| / d^2 = |n.x| / d^3.
    const float cosine_times_distance = std::fabs(glm::dot(light_normal, offset));
    return safe_divide(pdf * cosine_times_distance, distance_squared * std::sqrt(distance_squared));
}

/// Solid-angle density (from `from`) of a point drawn with area density `pdf`:
/// pdf_solid_angle = pdf_area d^2 / |cos theta_light|. 0 for a degenerate configuration (the
/// receiver in the light's tangent plane through `point`, or at the point).
RESTIR_HOST_DEVICE inline float area_to_solid_angle_pdf(float pdf, glm::vec3 from, glm::vec3 point,
                                                        glm::vec3 light_normal) {
    const glm::vec3 offset = point - from;
    const float distance_squared = glm::dot(offset, offset);
    const float cosine_times_distance = std::fabs(glm::dot(light_normal, offset));
    if (distance_squared == 0.0f)
        return 0.0f;
    return safe_divide(pdf * distance_squared * std::sqrt(distance_squared), cosine_times_distance);
}

} // namespace restir
