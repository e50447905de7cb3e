/// @file light/shadow_segment.hpp
/// The shadow ray between a surface point and a point on a light, as the open segment a ray
/// query tests.
#pragma once

#include "restir/config.hpp"

#include <glm/geometric.hpp>
#include <glm/vec3.hpp>

namespace restir {

/// A shadow ray as the open segment between two points, ends already offset off their surfaces.
struct ShadowSegment {
    glm::vec3 from{0.0f};
    glm::vec3 to{0.0f};
};

/// The segment from a surface point (`position`, `normal`) to a light point (`light_position`,
/// `light_normal`), both ends pushed `ray_offset` along their normals towards each other, so
/// that it hits neither surface it starts or ends on. The light's end moves too, VPLs included:
/// a segment that ends exactly on the surface a VPL lies on hits that surface at t = 1 or not as
/// rounding decides (and single rays and packets decide differently). An isotropic point light
/// (zero normal) keeps its end.
RESTIR_HOST_DEVICE inline ShadowSegment shadow_segment(glm::vec3 position, glm::vec3 normal,
                                                       glm::vec3 light_position,
                                                       glm::vec3 light_normal,
                                                       float ray_offset) noexcept {
    const glm::vec3 towards_light = light_position - position;
    const float side = glm::dot(normal, towards_light) < 0.0f ? -1.0f : 1.0f;
    const float light_side = glm::dot(light_normal, towards_light) > 0.0f ? -1.0f : 1.0f;
    return {position + normal * (side * ray_offset),
            light_position + light_normal * (light_side * ray_offset)};
}

/// The shadow ray from a surface point towards a distant light (an environment's direction,
/// unit `direction`): its start pushed `ray_offset` off the surface to the side the direction
/// leaves from, its end `far_distance` further along the direction, past everything the ray
/// could hit (a segment longer than the scene's diameter from any point of the scene leaves it;
/// `LightPointVisibility::for_scene` takes twice the diagonal of its bounding box).
RESTIR_HOST_DEVICE inline ShadowSegment distant_shadow_segment(glm::vec3 position, glm::vec3 normal,
                                                               glm::vec3 direction,
                                                               float ray_offset,
                                                               float far_distance) noexcept {
    const float side = glm::dot(normal, direction) < 0.0f ? -1.0f : 1.0f;
    const glm::vec3 from = position + normal * (side * ray_offset);
    return {from, from + direction * far_distance};
}

} // namespace restir
