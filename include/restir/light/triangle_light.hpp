/// @file light/triangle_light.hpp
/// Points on a triangle light drawn from a receiver: uniform in the solid angle it subtends
/// (Arvo 1995, light/spherical_triangle.hpp) where that is accurate, uniform in area otherwise,
/// with the density of either per unit solid angle, so that light sets can mix them.
///
/// The switch. The textbook form of Arvo's mapping (the cosine q of the arc A C', then
/// sqrt(1 - q^2), and the cosine of the arc B P) fails a chi-square test of uniformity (4^3
/// sub-triangles, 4 million samples, p < 2e-4) from 1e-4 sr for a compact triangle and from
/// 3e-3 sr for a 20:1 sliver; the half-angle form of spherical_triangle.hpp passes the same
/// test for a compact triangle, a sliver and a grazing view from 1e-2 down to 1e-17 sr and fails
/// from 1e-20 or 1e-24 sr on, by shape (squared angles leave float's range). Below
/// `min_solid_angle_for_arvo` = 1e-9 sr (eight decades inside what was measured, and far from
/// flushed denormals on a GPU) the front end draws by area: there the Jacobian d^2 / |cos|
/// varies across the shape by a relative amount of the order of its angular size (3e-5 rad for
/// a compact one), so area sampling is as good as uniform in solid angle, and it is cheaper.
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

/// Below this solid angle (sr) `sample_triangle_from` samples by area (see the file comment).
inline constexpr float min_solid_angle_for_arvo = 1e-9f;

/// A point uniform in the area of the triangle with corner `a` and edges `ab` = b - a, `ac` =
/// c - a (as renderers that store their emitters' edges keep it) from two uniform numbers: the
/// square-root warp of the barycentrics, b0 = 1 - sqrt(u0), b1 = u1 sqrt(u0) (the weight of
/// b), b2 = sqrt(u0) - b1.
RESTIR_HOST_DEVICE inline glm::vec3 sample_triangle_area_from_edges(glm::vec3 a, glm::vec3 ab,
                                                                    glm::vec3 ac, glm::vec2 u) {
    const float root = std::sqrt(u.x);
    const float weight_b = u.y * root;
    const float weight_c = root - weight_b; // root (1 - u1)
    return a + weight_b * ab + weight_c * ac;
}

/// `sample_triangle_area_from_edges` for the triangle `a`, `b`, `c`.
RESTIR_HOST_DEVICE inline glm::vec3 sample_triangle_area(glm::vec3 a, glm::vec3 b, glm::vec3 c,
                                                         glm::vec2 u) {
    return sample_triangle_area_from_edges(a, b - a, c - a, u);
}

/// A point of the triangle `a`, `b`, `c` drawn from the receiver `from`: uniform in solid angle
/// (Arvo) when the triangle subtends at least `min_solid_angle_for_arvo`, uniform in area
/// otherwise; `pdf` is per unit solid angle either way (area pdf times d^2 / |cos theta_light|),
/// 0 where the receiver lies in the triangle's plane or the triangle has no area.
/// `triangle_pdf_from` gives the same density for a point of the triangle.
RESTIR_HOST_DEVICE inline SolidAngleSample
sample_triangle_from(glm::vec3 from, glm::vec3 a, glm::vec3 b, glm::vec3 c, glm::vec2 u) {
    const float solid_angle = spherical_triangle_solid_angle(from, a, b, c);
    if (solid_angle >= min_solid_angle_for_arvo)
        return detail::sample_spherical_triangle_of(from, a, b, c, solid_angle, u);
    const glm::vec3 normal = glm::cross(b - a, c - a);
    const float double_area = glm::length(normal);
    if (!(double_area > 0.0f) || !is_finite(double_area))
        return {};
    const glm::vec3 point = sample_triangle_area(a, b, c, u);
    return {point, area_to_solid_angle_pdf(2.0f / double_area, from, point, normal / double_area)};
}

/// The solid-angle density with which `sample_triangle_from(from, a, b, c, ...)` returns
/// `point` (a point of the triangle): 1 / solid angle, or the area density converted, by the
/// same switch. 0 where the sampler returns nothing.
RESTIR_HOST_DEVICE inline float triangle_pdf_from(glm::vec3 from, glm::vec3 a, glm::vec3 b,
                                                  glm::vec3 c, glm::vec3 point) {
    const float solid_angle = spherical_triangle_solid_angle(from, a, b, c);
    if (solid_angle >= min_solid_angle_for_arvo)
        return 1.0f / solid_angle;
    const glm::vec3 normal = glm::cross(b - a, c - a);
    const float double_area = glm::length(normal);
    if (!(double_area > 0.0f) || !is_finite(double_area))
        return 0.0f;
    return area_to_solid_angle_pdf(2.0f / double_area, from, point, normal / double_area);
}

/// The fraction of the area of the triangle `a`, `b`, `c` strictly above the plane through
/// `plane_point` with normal `plane_normal` (where dot(plane_normal, x - plane_point) > 0): the
/// share of a uniform area sample's points that a receiver there can see, in [0, 1]. With the
/// signed heights h of the vertices, a linear function over the triangle, the part on the
/// lone vertex v's side is the triangle cut at the edges' zeros, of area fraction
/// h_v^2 / ((h_v - h_1)(h_v - h_2)).
RESTIR_HOST_DEVICE inline float triangle_area_fraction_above(glm::vec3 a, glm::vec3 b, glm::vec3 c,
                                                             glm::vec3 plane_point,
                                                             glm::vec3 plane_normal) {
    const float ha = glm::dot(plane_normal, a - plane_point);
    const float hb = glm::dot(plane_normal, b - plane_point);
    const float hc = glm::dot(plane_normal, c - plane_point);
    const int above = (ha > 0.0f ? 1 : 0) + (hb > 0.0f ? 1 : 0) + (hc > 0.0f ? 1 : 0);
    if (above == 0 || above == 3)
        return above == 0 ? 0.0f : 1.0f;
    // The lone vertex: the one above when one is, the one not above when two are.
    const bool lone_a = (ha > 0.0f) == (above == 1);
    const bool lone_b = !lone_a && (hb > 0.0f) == (above == 1);
    const float lone = lone_a ? ha : lone_b ? hb : hc;
    const float first = lone_a ? hb : ha;
    const float second = lone_a || lone_b ? hc : hb;
    const float corner =
        min_of(max_of(safe_divide(lone * lone, (lone - first) * (lone - second)), 0.0f), 1.0f);
    return above == 1 ? corner : 1.0f - corner;
}

} // namespace restir
