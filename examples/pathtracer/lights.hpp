// The scene's emissive triangles as a restir::ReceiverLightSet: uniform points on each triangle
// (or uniform in the solid angle it subtends from a receiver), one light per triangle.
#pragma once

#include "scene.hpp"

#include <restir/light/light_bvh.hpp>
#include <restir/light/light_sample.hpp>
#include <restir/light/solid_angle.hpp>
#include <restir/light/triangle_light.hpp>

#include <glm/common.hpp>
#include <glm/geometric.hpp>
#include <glm/vec2.hpp>
#include <glm/vec3.hpp>

#include <algorithm>
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

    /// A uniformly distributed point of emitter `id` (the library's square-root warp of the
    /// barycentrics: a bijection of [0, 1)^2 onto the triangle).
    restir::LightSample sample_point(std::uint32_t id, glm::vec2 uv) const {
        const Emitter& e = triangles_[id];
        restir::LightSample s;
        s.position = restir::sample_triangle_area_from_edges(e.a, e.ab, e.ac, uv);
        s.normal = e.normal;
        s.radiance = e.radiance;
        s.area_pdf = 1.0f / e.area;
        s.is_delta = false;
        return s;
    }

    /// What `sample_point` reads of emitter `id`, for a prefetch.
    const void* prefetch_address(std::uint32_t id) const { return &triangles_[id]; }

    /// restir::ReceiverLightSet: a point of emitter `id` uniform in the solid angle it subtends
    /// from `from` (Arvo; by area where it subtends less than restir::min_solid_angle_for_arvo),
    /// with its density per unit area.
    restir::LightSample sample_point(std::uint32_t id, glm::vec2 uv, glm::vec3 from) const {
        const Emitter& e = triangles_[id];
        const restir::SolidAngleSample drawn =
            restir::sample_triangle_from(from, e.a, e.a + e.ab, e.a + e.ac, uv);
        restir::LightSample s;
        s.position = drawn.point;
        s.normal = e.normal;
        s.radiance = e.radiance;
        s.area_pdf = restir::solid_angle_to_area_pdf(drawn.pdf, from, drawn.point, e.normal);
        s.is_delta = false;
        return s;
    }
    /// The density per unit area with which `sample_point(id, uv, from)` returns `point`, a
    /// point of emitter `id` (restir::ReceiverLightDensity: BSDF candidates' MIS weights).
    float point_pdf(std::uint32_t id, glm::vec3 point, glm::vec3 from) const {
        const Emitter& e = triangles_[id];
        return restir::solid_angle_to_area_pdf(
            restir::triangle_pdf_from(from, e.a, e.a + e.ab, e.a + e.ac, point), from, point,
            e.normal);
    }
    /// The share of emitter `id`'s area above the plane through `position` with normal
    /// `normal`: where a surface there sees it.
    float area_fraction_above(std::uint32_t id, glm::vec3 position, glm::vec3 normal) const {
        const Emitter& e = triangles_[id];
        return restir::triangle_area_fraction_above(e.a, e.a + e.ab, e.a + e.ac, position, normal);
    }

    /// Whether a point of emitter `id` drawn again from a surface at `position` (normal
    /// `normal`) pays off (candidate_sources.cpp): the emitter lies wholly above the surface's
    /// tangent plane with receiver cosines at its vertices within a factor 2 of each other (no
    /// grazing part, where the area point's small target would make the redrawn estimate
    /// large), and it is near: its vertices' squared distances differ by more than a factor 4
    /// (far away, area points are as good). Depends on the emitter and the surface only.
    bool redraw_pays_off(std::uint32_t id, glm::vec3 position, glm::vec3 normal) const {
        const Emitter& e = triangles_[id];
        const glm::vec3 v[3] = {e.a - position, e.a + e.ab - position, e.a + e.ac - position};
        float d2[3], cosine[3];
        for (int k = 0; k < 3; ++k) {
            d2[k] = glm::dot(v[k], v[k]);
            cosine[k] = glm::dot(normal, v[k]) / std::sqrt(d2[k]);
        }
        const float min_d2 = std::min({d2[0], d2[1], d2[2]});
        const float max_d2 = std::max({d2[0], d2[1], d2[2]});
        const float min_cos = std::min({cosine[0], cosine[1], cosine[2]});
        const float max_cos = std::max({cosine[0], cosine[1], cosine[2]});
        return min_cos > 0.0f && 2.0f * min_cos >= max_cos && max_d2 > 4.0f * min_d2;
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
