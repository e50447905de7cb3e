/// @file light/spherical_rectangle.hpp
/// The solid angle of a rectangle seen from a point and directions drawn uniformly in it
/// (Urena, Fajardo and King 2013, "An area-preserving parametrization for spherical
/// rectangles"). The rectangle is a corner and two perpendicular edges.
#pragma once

#include "restir/config.hpp"
#include "restir/core/math.hpp"
#include "restir/light/solid_angle.hpp"
#include "restir/light/spherical_triangle.hpp"

#include <glm/geometric.hpp>
#include <glm/vec2.hpp>
#include <glm/vec3.hpp>

#include <cmath>

namespace restir {

/// Solid angle (sr) of the rectangle `corner` + s `edge0` + t `edge1` (s, t in [0, 1]) seen
/// from `from`: its two triangles' (Van Oosterom and Strackee 1983), which keeps float precision
/// for small rectangles where the sum of the four angles minus 2 pi does not. 0 when `from`
/// lies in the rectangle's plane or the rectangle has no area.
RESTIR_HOST_DEVICE inline float spherical_rectangle_solid_angle(glm::vec3 from, glm::vec3 corner,
                                                                glm::vec3 edge0, glm::vec3 edge1) {
    const glm::vec3 opposite = corner + edge0 + edge1;
    return spherical_triangle_solid_angle(from, corner, corner + edge0, opposite) +
           spherical_triangle_solid_angle(from, corner, opposite, corner + edge1);
}

/// A point of the rectangle `corner` + s `edge0` + t `edge1` (perpendicular edges) whose
/// direction from `from` is uniform in the rectangle's solid angle (Urena et al. 2013, Alg. 1),
/// from two uniform numbers `u`; pdf = 1 / `spherical_rectangle_solid_angle`. pdf 0 where the
/// solid angle is 0 (receiver in the rectangle's plane, a zero edge). In float it loses
/// uniformity below about 1e-3 sr (measured in light/rectangle_light.hpp, whose
/// `sample_rectangle_from` is accurate at every size).
RESTIR_HOST_DEVICE inline SolidAngleSample
sample_spherical_rectangle(glm::vec3 from, glm::vec3 corner, glm::vec3 edge0, glm::vec3 edge1,
                           glm::vec2 u) {
    const float solid_angle = spherical_rectangle_solid_angle(from, corner, edge0, edge1);
    const float length0 = glm::length(edge0), length1 = glm::length(edge1);
    if (!(solid_angle > 0.0f) || !(length0 > 0.0f) || !(length1 > 0.0f))
        return {};
    // The local frame of Sec. 3: x, y along the edges, z towards the receiver's side.
    const glm::vec3 axis_x = edge0 / length0, axis_y = edge1 / length1;
    glm::vec3 axis_z = glm::cross(axis_x, axis_y);
    const glm::vec3 offset = corner - from;
    float z0 = glm::dot(offset, axis_z);
    if (z0 > 0.0f) {
        axis_z = -axis_z;
        z0 = -z0;
    }
    const float x0 = glm::dot(offset, axis_x), y0 = glm::dot(offset, axis_y);
    const float x1 = x0 + length0, y1 = y0 + length1;
    // Normals of the great circles through the sides, and the interior angles g2, g3.
    const glm::vec3 v00(x0, y0, z0), v01(x0, y1, z0), v10(x1, y0, z0), v11(x1, y1, z0);
    const glm::vec3 n0 = detail::normalized_or_zero(glm::cross(v00, v10));
    const glm::vec3 n2 = detail::normalized_or_zero(glm::cross(v11, v01));
    const glm::vec3 n3 = detail::normalized_or_zero(glm::cross(v01, v00));
    const float gamma2 = detail::angle_between(-n2, n3), gamma3 = detail::angle_between(-n3, n0);
    // Alg. 1: the x coordinate at which the sub-rectangle [x0, xu] has solid angle u0 S.
    const float k = two_pi - gamma2 - gamma3;
    const float angle_u = u.x * solid_angle + k;
    const float f = (std::cos(angle_u) * n0.z - n2.z) / std::sin(angle_u);
    const float cu_raw = (f > 0.0f ? 1.0f : -1.0f) / std::sqrt(f * f + n0.z * n0.z);
    const float cu = max_of(-1.0f, min_of(1.0f, cu_raw));
    const float xu_raw = -(cu * z0) / std::sqrt(max_of(0.0f, 1.0f - cu * cu));
    const float xu = max_of(x0, min_of(x1, xu_raw)); // NaN gives x1
    // Then y uniform in the sines of elevation h between the two ends of that column.
    const float column_distance = std::sqrt(xu * xu + z0 * z0);
    const float h0 = y0 / std::sqrt(column_distance * column_distance + y0 * y0);
    const float h1 = y1 / std::sqrt(column_distance * column_distance + y1 * y1);
    const float hv = h0 + u.y * (h1 - h0);
    const float yv_raw = hv * column_distance / std::sqrt(max_of(0.0f, 1.0f - hv * hv));
    const float yv = max_of(y0, min_of(y1, yv_raw));
    const glm::vec3 point = from + xu * axis_x + yv * axis_y + z0 * axis_z;
    if (!is_finite(point.x) || !is_finite(point.y) || !is_finite(point.z))
        return {};
    return {point, 1.0f / solid_angle};
}

} // namespace restir
