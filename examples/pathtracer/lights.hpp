// The scene's emissive triangles as a restir::LightSet: uniform points on each triangle, one
// light per triangle.
#pragma once

#include "scene.hpp"

#include <restir/light/light_bvh.hpp>
#include <restir/light/light_sample.hpp>

#include <glm/common.hpp>
#include <glm/geometric.hpp>
#include <glm/vec2.hpp>
#include <glm/vec3.hpp>

#include <cmath>
#include <cstdint>
#include <limits>
#include <vector>

namespace pt {

/// One-sided diffuse emitting triangles.
class TriangleEmitters {
public:
    static constexpr std::uint32_t none = std::numeric_limits<std::uint32_t>::max();

    explicit TriangleEmitters(const Scene& scene)
        : emitter_of_triangle_(scene.triangle_count(), none) {
        for (std::uint32_t t = 0; t < scene.triangle_count(); ++t) {
            const Material& m = scene.materials[scene.triangle_materials[t]];
            if (!m.is_emissive())
                continue;
            const Triangle triangle(scene, t);
            const float twice_area = triangle.twice_area();
            if (!(twice_area > 0.0f))
                continue; // degenerate: emits nothing
            emitter_of_triangle_[t] = static_cast<std::uint32_t>(triangles_.size());
            triangles_.push_back({triangle.a, triangle.ab, triangle.ac, triangle.normal(),
                                  m.emission, 0.5f * twice_area});
        }
    }

    /// restir::LightSet
    std::uint32_t light_count() const { return static_cast<std::uint32_t>(triangles_.size()); }

    /// A uniformly distributed point of emitter `id` (square-root parameterisation of the
    /// barycentrics: a bijection of [0, 1)^2 onto the triangle).
    restir::LightSample sample_point(std::uint32_t id, glm::vec2 uv) const {
        const Emitter& e = triangles_[id];
        const float su = std::sqrt(uv.x);
        restir::LightSample s;
        s.position = e.a + e.ab * (su * (1.0f - uv.y)) + e.ac * (su * uv.y);
        s.normal = e.normal;
        s.radiance = e.radiance;
        s.area_pdf = 1.0f / e.area;
        s.is_delta = false;
        return s;
    }

    /// The emitter index of triangle `t`, or `none`.
    std::uint32_t emitter_of_triangle(std::uint32_t t) const { return emitter_of_triangle_[t]; }
    float area(std::uint32_t id) const { return triangles_[id].area; }
    /// Emitter `id`'s emission bounds for a light BVH, with its `power`.
    restir::LightBounds bounds(std::uint32_t id, float power) const {
        const Emitter& e = triangles_[id];
        const glm::vec3 b = e.a + e.ab, c = e.a + e.ac;
        return restir::area_light_bounds(glm::min(e.a, glm::min(b, c)),
                                         glm::max(e.a, glm::max(b, c)), e.normal, power);
    }
    glm::vec3 radiance(std::uint32_t id) const { return triangles_[id].radiance; }

private:
    struct Emitter {
        glm::vec3 a, ab, ac, normal, radiance;
        float area;
    };
    std::vector<Emitter> triangles_;
    std::vector<std::uint32_t> emitter_of_triangle_;
};

} // namespace pt
