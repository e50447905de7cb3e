// The Embree 3 adapter: the scene's triangles and light shapes (as user geometry) in an Embree
// BVH, answering the library's ray-query concepts (restir::RayQuery: occluded;
// restir::ClosestHitQuery: closest_hit).
#pragma once

#include "scene.hpp"

#include <glm/vec3.hpp>

#include <cstdint>
#include <span>
#include <vector>

struct RTCDeviceTy;
struct RTCSceneTy;

namespace pt {

/// The nearest surface along a ray. Satisfies restir::Surface through the free functions below.
struct Hit {
    glm::vec3 position{0.0f};
    /// Unit geometric normal: as the triangle is wound, or the shape's `normal_at`.
    glm::vec3 normal{0.0f, 1.0f, 0.0f};
    float distance = 0.0f;
    std::uint32_t primitive = 0u; ///< A triangle, or a shape after them (Scene::material_of).
    bool found = false;
};
inline glm::vec3 surface_position(const Hit& h) { return h.position; }
inline glm::vec3 surface_normal(const Hit& h) { return h.normal; }
inline float surface_depth(const Hit& h) { return h.distance; }
inline bool is_valid_surface(const Hit& h) { return h.found; }

/// Owns an Embree device and a committed scene. Thread-safe queries; not copyable.
class EmbreeScene {
public:
    /// Builds the BVH of `scene`'s triangles and shapes. Throws SceneError when Embree fails or
    /// a shape cannot be rendered (check_shapes).
    explicit EmbreeScene(const Scene& scene);
    ~EmbreeScene();
    EmbreeScene(const EmbreeScene&) = delete;
    EmbreeScene& operator=(const EmbreeScene&) = delete;

    /// Nearest hit along origin + t * direction, t in (0, inf); `direction` need not be unit.
    Hit closest_hit(glm::vec3 origin, glm::vec3 direction) const;
    /// The nearest hit of the ray that leaves the surface point `position` (normal `normal`)
    /// along the unit `direction`, its distance from the point itself. The ray starts `offset`
    /// along its own direction, on the line from the point (and 1 % of that along the normal,
    /// against hitting its own surface at grazing angles). A start pushed along the normal
    /// alone sees lights close above from nearer than the point does: the reference path
    /// tracer's BSDF rays came out 0.3 % too bright in the many-light scene that way
    /// (docs/noise-and-bias.md).
    Hit closest_hit_from(glm::vec3 position, glm::vec3 normal, glm::vec3 direction,
                         float offset) const {
        Hit hit = closest_hit(position + direction * offset + normal * (0.01f * offset), direction);
        hit.distance += offset;
        return hit;
    }

    /// True when anything blocks the open segment (from, to). The caller offsets the ends.
    bool occluded(glm::vec3 from, glm::vec3 to) const;

    /// closest_hit(origin, directions[i]) into hits[i] for every i, traced together (coherent
    /// rays, e.g. primary rays of a pixel block). The spans have the same length.
    void closest_hits(glm::vec3 origin, std::span<const glm::vec3> directions,
                      std::span<Hit> hits) const;

    /// blocked[i] = occluded(from[i], to[i]) for every i, traced together. The spans have the
    /// same length.
    void occluded_segments(std::span<const glm::vec3> from, std::span<const glm::vec3> to,
                           std::span<std::uint8_t> blocked) const;

private:
    void attach_triangles(const Scene& scene);
    void attach_shapes();
    /// The hit's primitive and normal from Embree's geometry and primitive ids, its position
    /// at `t` along origin + t * direction.
    void complete_hit(Hit& hit, unsigned geometry, unsigned primitive, glm::vec3 origin,
                      glm::vec3 direction, float t) const;

    RTCDeviceTy* device_ = nullptr;
    RTCSceneTy* scene_ = nullptr;
    std::vector<glm::vec3> normals_; ///< Per triangle, from its winding.
    Shapes shapes_;                  ///< The scene's, which Embree's user geometry points into.
    /// Per Embree geometry id (triangles 0, then each non-empty shape list): its first
    /// primitive id.
    std::vector<std::uint32_t> first_primitive_;
};

} // namespace pt
