/// @file light/light_bounds.hpp
/// Where lights emit, as the light BVH bounds them (light/light_bvh.hpp): a light's box, power
/// and cone of emission, the bounds of two groups of lights together, and the node
/// `light_importance` weighs.
#pragma once

#include "restir/light/light_bvh_group.hpp"

#include <glm/common.hpp>
#include <glm/geometric.hpp>
#include <glm/vec3.hpp>

#include <algorithm>
#include <cmath>
#include <limits>
#include <utility>

namespace restir {

/// Where a light (or a group of lights) emits: the box of its positions, its power, and the
/// cone of its emission: normals within theta_o of `axis`, light leaving up to theta_e beyond
/// a normal. A one-sided diffuse emitter or VPL: theta_o = 0, theta_e = pi / 2; an isotropic
/// point light: theta_o = pi, theta_e = pi / 2.
struct LightBounds {
    glm::vec3 lower{std::numeric_limits<float>::max()};
    glm::vec3 upper{-std::numeric_limits<float>::max()};
    float power = 0.0f; ///< Emitted flux summed over the channels (>= 0).
    glm::vec3 axis{0.0f, 0.0f, 1.0f};
    float cos_theta_o = 1.0f;
    float cos_theta_e = 0.0f;
};

/// A flat area light (an emitter triangle or quad) with corners spanning [lower, upper],
/// emitting on the side of the unit `normal`.
inline LightBounds area_light_bounds(glm::vec3 lower, glm::vec3 upper, glm::vec3 normal,
                                     float power) {
    return {lower, upper, power, normal, 1.0f, 0.0f};
}

/// A point light: a cosine emitter facing the unit `normal` (a VPL), or isotropic for a zero
/// normal.
inline LightBounds point_light_bounds(glm::vec3 position, glm::vec3 normal, float power) {
    const bool isotropic = normal.x == 0.0f && normal.y == 0.0f && normal.z == 0.0f;
    return {position,
            position,
            power,
            isotropic ? glm::vec3(0.0f, 0.0f, 1.0f) : normal,
            isotropic ? -1.0f : 1.0f,
            0.0f};
}

namespace detail {
// The cone (axis, half-angle) that holds cones a and b (Conty Estevez and Kulla 2018, Alg. 1).
inline void merge_cones(glm::vec3& axis, float& theta, glm::vec3 other_axis, float other_theta) {
    constexpr float pi_f = 3.14159265358979f;
    if (other_theta > theta) {
        std::swap(axis, other_axis);
        std::swap(theta, other_theta);
    }
    if (theta >= pi_f) // holds every direction already
        return;
    const float between = std::acos(std::clamp(glm::dot(axis, other_axis), -1.0f, 1.0f));
    if (std::min(between + other_theta, pi_f) <= theta)
        return;
    const float merged = 0.5f * (theta + between + other_theta);
    const glm::vec3 normal = glm::cross(axis, other_axis);
    const float normal_length = glm::length(normal);
    if (merged >= pi_f || !(normal_length > 1e-7f)) {
        theta = pi_f;
        return;
    }
    // Rotate `axis` towards `other_axis` by merged - theta (Rodrigues, the rotation axis
    // perpendicular to `axis`).
    const float turn = merged - theta;
    const glm::vec3 k = normal / normal_length;
    axis = glm::normalize(axis * std::cos(turn) + glm::cross(k, axis) * std::sin(turn));
    theta = merged;
}
} // namespace detail

/// The bounds of two groups of lights together. Deprecated: nothing in the library calls it
/// (`LightBvh` merges its nodes' bounds with their cones kept as angles).
[[deprecated(
    "unused by the library and removed in 0.4: merge LightBounds yourself")]] inline LightBounds
merge_light_bounds(const LightBounds& a, const LightBounds& b) {
    if (!(a.power > 0.0f) && a.lower.x > a.upper.x)
        return b;
    if (!(b.power > 0.0f) && b.lower.x > b.upper.x)
        return a;
    LightBounds merged;
    merged.lower = glm::min(a.lower, b.lower);
    merged.upper = glm::max(a.upper, b.upper);
    merged.power = a.power + b.power;
    glm::vec3 axis = a.axis;
    float theta = std::acos(std::clamp(a.cos_theta_o, -1.0f, 1.0f));
    detail::merge_cones(axis, theta, b.axis, std::acos(std::clamp(b.cos_theta_o, -1.0f, 1.0f)));
    merged.axis = axis;
    merged.cos_theta_o = std::cos(theta);
    merged.cos_theta_e = std::min(a.cos_theta_e, b.cos_theta_e);
    return merged;
}

/// The node of a group of lights with bounds `b` (a leaf's, for one light): what
/// `light_importance` weighs.
inline LightBvhNode light_bvh_node(const LightBounds& b) {
    LightBvhNode node;
    node.centre = 0.5f * (b.lower + b.upper);
    node.radius = 0.5f * glm::length(b.upper - b.lower);
    node.axis = b.axis;
    node.cos_theta_o = b.cos_theta_o;
    node.sin_theta_o = detail::sine_of(b.cos_theta_o);
    node.cos_theta_e = b.cos_theta_e;
    node.power = b.power;
    return node;
}

} // namespace restir
