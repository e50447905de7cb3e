/// @file light/spherical_triangle.hpp
/// The solid angle of a triangle seen from a point (Van Oosterom and Strackee 1983) and
/// directions drawn uniformly in it (Arvo 1995, "Stratified sampling of spherical triangles").
/// Arvo's mapping, as usually written, loses precision in float for small solid angles; the form
/// here does not (light/triangle_light.hpp has the measurement and the front end's switch).
#pragma once

#include "restir/config.hpp"
#include "restir/core/math.hpp"
#include "restir/light/solid_angle.hpp"

#include <glm/geometric.hpp>
#include <glm/vec2.hpp>
#include <glm/vec3.hpp>

#include <cmath>

namespace restir {

/// Solid angle (sr, in [0, 2 pi)) of the triangle `a`, `b`, `c` seen from `from`, either
/// winding. 0 when `from` lies in the triangle's plane (on it, at a vertex, or beside it) or
/// the triangle has no area.
RESTIR_HOST_DEVICE inline float spherical_triangle_solid_angle(glm::vec3 from, glm::vec3 a,
                                                               glm::vec3 b, glm::vec3 c) {
    const glm::vec3 ra = a - from, rb = b - from, rc = c - from;
    const float la = glm::length(ra), lb = glm::length(rb), lc = glm::length(rc);
    // Van Oosterom and Strackee 1983: tan(Omega / 2) = |ra . (rb x rc)| / (la lb lc +
    // (ra.rb) lc + (ra.rc) lb + (rb.rc) la). The triple product is taken as ra . ((b - a) x
    // (c - a)), equal in exact arithmetic, which keeps its precision for small, distant
    // triangles (rb x rc of nearly parallel vectors cancels).
    const float triple = std::fabs(glm::dot(ra, glm::cross(b - a, c - a)));
    if (!(triple > 0.0f))
        return 0.0f;
    const float denominator =
        la * lb * lc + glm::dot(ra, rb) * lc + glm::dot(ra, rc) * lb + glm::dot(rb, rc) * la;
    const float omega = 2.0f * std::atan2(triple, denominator);
    return is_finite(omega) ? omega : 0.0f;
}

namespace detail {

/// Angle in [0, pi] between two non-zero vectors of any length (atan2 form: accurate near 0
/// and pi, where acos of a dot product is not).
RESTIR_HOST_DEVICE inline float angle_between(glm::vec3 x, glm::vec3 y) {
    return std::atan2(glm::length(glm::cross(x, y)), glm::dot(x, y));
}

/// `v / |v|`, or zero for a zero or non-finite length.
RESTIR_HOST_DEVICE inline glm::vec3 normalized_or_zero(glm::vec3 v) {
    const float length = glm::length(v);
    return length > 0.0f && is_finite(length) ? v / length : glm::vec3(0.0f);
}

/// Arvo's sampling of the triangle whose solid angle from `from` is `solid_angle` (> 0).
/// Arvo's construction, written in half angles and in differences of nearby vectors so that it
/// keeps float precision for small solid angles: the textbook form (cosines of the arcs A C'
/// and B P, then 1 - cos^2) loses it from about 1e-4 sr down (light/triangle_light.hpp).
RESTIR_HOST_DEVICE inline SolidAngleSample sample_spherical_triangle_of(glm::vec3 from, glm::vec3 a,
                                                                        glm::vec3 b, glm::vec3 c,
                                                                        float solid_angle,
                                                                        glm::vec2 u) {
    const glm::vec3 ra = a - from, rb = b - from;
    const glm::vec3 edge_ab = b - a, edge_ac = c - a;
    const float la = glm::length(ra), lb = glm::length(rb);
    const glm::vec3 unit_a = ra / la, unit_b = rb / lb;
    // Normals of the great circles AB and AC from the edges (ra x rb = ra x (b - a)); the
    // angle between them is the interior angle alpha at A.
    const glm::vec3 normal_ab = glm::cross(ra, edge_ab);
    const glm::vec3 normal_ac = glm::cross(ra, edge_ac);
    const float alpha = angle_between(normal_ab, normal_ac);
    const glm::vec3 tangent_ac = normalized_or_zero(glm::cross(normal_ac, ra)); // At A, to C.
    // tan(c / 2) of the arc c = A B: |ra x rb| / (|ra| |rb| + ra.rb).
    const float tan_half_ab = glm::length(normal_ab) / (la * lb + glm::dot(ra, rb));
    // Arvo 1995, Alg. 1: the sub-triangle A B C' of area u0 Omega, C' on the arc A C. Its arc
    // b' = A C' from the area of two sides and their angle, tan(E / 2) = tan(b'/2) tan(c/2)
    // sin alpha / (1 + tan(b'/2) tan(c/2) cos alpha), solved for tan(b'/2).
    const float half_area = 0.5f * u.x * solid_angle;
    const float tan_half_arc = std::sin(half_area) / (tan_half_ab * std::sin(alpha - half_area));
    const float tan_squared = tan_half_arc * tan_half_arc;
    const float cos_arc_minus_one = -2.0f * tan_squared / (1.0f + tan_squared);
    const float sin_arc = 2.0f * tan_half_arc / (1.0f + tan_squared);
    // The chord C' - B = (A - B) + (cos b' - 1) A + sin b' T_AC, with A - B from the edge:
    // (a - b) / |ra| + rb (|rb| - |ra|) / (|ra| |rb|), |rb| - |ra| = (b - a).(ra + rb) / (|ra| +
    // |rb|).
    const float length_difference = glm::dot(edge_ab, ra + rb) / (la + lb);
    const glm::vec3 a_minus_b = rb * (length_difference / (la * lb)) - edge_ab / la;
    const glm::vec3 chord = a_minus_b + cos_arc_minus_one * unit_a + sin_arc * tangent_ac;
    // Arvo's second step, 1 - cos(arc B P) = u1 (1 - cos(arc B C')), in half angles:
    // sin^2(arc B P / 2) = u1 |C' - B|^2 / 4. The tangent at B to C' is C' - B + (1 - cos) B.
    const float half_chord_squared = 0.25f * glm::dot(chord, chord);
    const glm::vec3 tangent_b = normalized_or_zero(chord + (2.0f * half_chord_squared) * unit_b);
    const float sin_half_squared = u.y * half_chord_squared;
    const float sin_arc_bp =
        2.0f * std::sqrt(sin_half_squared * max_of(0.0f, 1.0f - sin_half_squared));
    const glm::vec3 offset = -2.0f * sin_half_squared * unit_b + sin_arc_bp * tangent_b; // P - B
    // The triangle's point in the direction P = B + offset, written from the vertex b (the ray
    // along B meets it at b): b + t offset - (t - |rb|) B, t = |rb| (n.B) / (n.P).
    const glm::vec3 normal = glm::cross(edge_ab, edge_ac);
    const float normal_dot_direction = glm::dot(normal, unit_b + offset);
    const float distance = lb * glm::dot(normal, unit_b) / normal_dot_direction;
    const float along_b = lb * glm::dot(normal, offset) / normal_dot_direction;
    const glm::vec3 point = b + distance * offset - along_b * unit_b;
    if (!(distance > 0.0f) || !is_finite(distance) || !is_finite(along_b))
        return {};
    return {point, 1.0f / solid_angle};
}

} // namespace detail

/// A point of the triangle `a`, `b`, `c` whose direction from `from` is uniform in the solid
/// angle the triangle subtends (Arvo 1995), from two uniform numbers `u`; pdf = 1 / solid
/// angle. pdf 0 where the solid angle is 0 (receiver in the triangle's plane, zero area).
/// Measured uniform down to 1e-17 sr in float (light/triangle_light.hpp has the measurement).
RESTIR_HOST_DEVICE inline SolidAngleSample
sample_spherical_triangle(glm::vec3 from, glm::vec3 a, glm::vec3 b, glm::vec3 c, glm::vec2 u) {
    const float solid_angle = spherical_triangle_solid_angle(from, a, b, c);
    if (!(solid_angle > 0.0f))
        return {};
    return detail::sample_spherical_triangle_of(from, a, b, c, solid_angle, u);
}

} // namespace restir
