/// @file light/rectangle_light.hpp
/// Points on a rectangular light drawn from a receiver, uniform in the solid angle it subtends
/// at every size: Urena et al.'s mapping (light/spherical_rectangle.hpp) where it is accurate,
/// otherwise the rectangle's two triangles by Arvo's (light/spherical_triangle.hpp), and area
/// sampling below the triangles' switch (light/triangle_light.hpp).
///
/// The switch. Urena et al.'s mapping in float (its angle u0 S + 2 pi - g2 - g3 carries a
/// rounding of float epsilon times pi, large against a small S) fails a chi-square test of
/// uniformity (8 x 8 sub-rectangles, 4 million samples, p < 1e-4) from 3e-4 sr for a 20:1
/// rectangle, from 1e-4 sr for a square seen face on, and from 1e-4 sr in a grazing view
/// (p = 0.002 at 3e-4 sr); at 1e-3 sr and above every case passed. Below
/// `min_solid_angle_for_urena` = 1e-2 sr (thirty times the largest failure) the front end takes
/// the two triangles, whose half-angle form of Arvo's mapping measured uniform down to 1e-17 sr.
#pragma once

#include "restir/config.hpp"
#include "restir/core/math.hpp"
#include "restir/light/solid_angle.hpp"
#include "restir/light/spherical_rectangle.hpp"
#include "restir/light/spherical_triangle.hpp"
#include "restir/light/triangle_light.hpp"

#include <glm/geometric.hpp>
#include <glm/vec2.hpp>
#include <glm/vec3.hpp>

namespace restir {

/// Below this solid angle (sr) `sample_rectangle_from` samples the rectangle's two triangles
/// by Arvo's method instead of Urena et al.'s (see the file comment).
inline constexpr float min_solid_angle_for_urena = 1e-2f;

/// A point of the rectangle `corner` + s `edge0` + t `edge1` (perpendicular edges) drawn from
/// the receiver `from`, uniform in its solid angle (Urena et al. 2013 at and above
/// `min_solid_angle_for_urena`, its two triangles by Arvo's method below, by area below
/// `min_solid_angle_for_arvo`); `pdf` is per unit solid angle. 0 where the receiver lies in the
/// rectangle's plane or an edge is zero. `rectangle_pdf_from` gives the same density.
RESTIR_HOST_DEVICE inline SolidAngleSample sample_rectangle_from(glm::vec3 from, glm::vec3 corner,
                                                                 glm::vec3 edge0, glm::vec3 edge1,
                                                                 glm::vec2 u) {
    const glm::vec3 opposite = corner + edge0 + edge1;
    const float first = spherical_triangle_solid_angle(from, corner, corner + edge0, opposite);
    const float second = spherical_triangle_solid_angle(from, corner, opposite, corner + edge1);
    const float solid_angle = first + second;
    if (solid_angle >= min_solid_angle_for_urena)
        return sample_spherical_rectangle(from, corner, edge0, edge1, u);
    if (solid_angle >= min_solid_angle_for_arvo) {
        // One triangle in proportion to its solid angle, u0 reused inside it.
        const float split = first / solid_angle;
        const bool in_first = u.x < split;
        const float reused = in_first ? u.x / split : (u.x - split) / (1.0f - split);
        const glm::vec2 inner(min_of(reused, 0.99999994f), u.y);
        SolidAngleSample s = in_first ? detail::sample_spherical_triangle_of(
                                            from, corner, corner + edge0, opposite, first, inner)
                                      : detail::sample_spherical_triangle_of(
                                            from, corner, opposite, corner + edge1, second, inner);
        s.pdf = s.pdf > 0.0f ? 1.0f / solid_angle : 0.0f;
        return s;
    }
    const glm::vec3 normal = glm::cross(edge0, edge1);
    const float area = glm::length(normal);
    if (!(area > 0.0f) || !is_finite(area))
        return {};
    const glm::vec3 point = corner + u.x * edge0 + u.y * edge1;
    return {point, area_to_solid_angle_pdf(1.0f / area, from, point, normal / area)};
}

/// The solid-angle density with which `sample_rectangle_from(from, corner, edge0, edge1, ...)`
/// returns `point` (a point of the rectangle): 1 / solid angle, or the area density converted
/// below `min_solid_angle_for_arvo`. 0 where the sampler returns nothing.
RESTIR_HOST_DEVICE inline float rectangle_pdf_from(glm::vec3 from, glm::vec3 corner,
                                                   glm::vec3 edge0, glm::vec3 edge1,
                                                   glm::vec3 point) {
    const float solid_angle = spherical_rectangle_solid_angle(from, corner, edge0, edge1);
    if (solid_angle >= min_solid_angle_for_arvo)
        return 1.0f / solid_angle;
    const glm::vec3 normal = glm::cross(edge0, edge1);
    const float area = glm::length(normal);
    if (!(area > 0.0f) || !is_finite(area))
        return 0.0f;
    return area_to_solid_angle_pdf(1.0f / area, from, point, normal / area);
}

} // namespace restir
