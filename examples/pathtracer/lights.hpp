// The scene's emitters as a restir::ReceiverLightSet: its emissive triangles (uniform points on
// each, or uniform in the solid angle it subtends from a receiver), then its emissive light
// shapes (shapes.hpp: uniform points by area, or the shape's own solid-angle sampling), one
// light per triangle or shape.
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
#include <utility>
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

/// The scene's emissive light shapes (Scene::shapes), each emitting its material's radiance
/// from the side its normal faces. Every operation is the shape's own (LightShape): this class
/// only numbers the emitters and dispatches to their shapes.
class ShapeEmitters {
public:
    static constexpr std::uint32_t none = std::numeric_limits<std::uint32_t>::max();

    explicit ShapeEmitters(const Scene& scene)
        : shapes_(scene.shapes), emitter_of_shape_(scene.shapes.count(), none) {
        check_shapes(scene);
        for (std::uint32_t k = 0; k < shapes_.count(); ++k) {
            const auto [material, area] = shapes_.visit(k, [](const auto& shape) {
                return std::pair{shape.material, shape.area()};
            });
            const Material& m = scene.materials[material];
            if (!m.is_emissive() || !(area > 0.0f))
                continue;
            emitter_of_shape_[k] = static_cast<std::uint32_t>(emitters_.size());
            emitters_.push_back({k, m.emission, area});
        }
    }

    std::uint32_t light_count() const { return static_cast<std::uint32_t>(emitters_.size()); }

    /// A point of emitter `id` uniform by area (the shape's `sample_area`).
    restir::LightSample sample_point(std::uint32_t id, glm::vec2 uv) const {
        const Emitter& e = emitters_[id];
        return shapes_.visit(
            e.shape, [&](const auto& shape) { return point_at(id, shape.sample_area(uv)); });
    }
    /// A point of emitter `id` drawn from the receiver at `from` (the shape's `sample_from`),
    /// with its density per unit area: pdf_area = pdf_solid_angle |cos theta_light| / d^2.
    /// Radiance 0 where the shape draws nothing (pdf 0: a receiver inside a sphere).
    restir::LightSample sample_point(std::uint32_t id, glm::vec2 uv, glm::vec3 from) const {
        const Emitter& e = emitters_[id];
        return shapes_.visit(e.shape, [&](const auto& shape) {
            const restir::SolidAngleSample drawn = shape.sample_from(from, uv);
            restir::LightSample s;
            s.position = drawn.point;
            s.normal = shape.normal_at(drawn.point);
            s.radiance = drawn.pdf > 0.0f ? e.radiance : glm::vec3(0.0f);
            s.area_pdf = restir::solid_angle_to_area_pdf(drawn.pdf, from, drawn.point, s.normal);
            return s;
        });
    }
    /// The density per unit area with which `sample_point(id, uv, from)` returns `point`.
    float point_pdf(std::uint32_t id, glm::vec3 point, glm::vec3 from) const {
        return shapes_.visit(emitters_[id].shape, [&](const auto& shape) {
            return restir::solid_angle_to_area_pdf(shape.pdf_from(from, point), from, point,
                                                   shape.normal_at(point));
        });
    }
    /// The point `position` of emitter `id` as `sample_point(id, uv)` returns it: its normal
    /// there, the radiance and the density 1 / area.
    restir::LightSample point_at(std::uint32_t id, glm::vec3 position) const {
        const Emitter& e = emitters_[id];
        restir::LightSample s;
        s.position = position;
        s.normal =
            shapes_.visit(e.shape, [&](const auto& shape) { return shape.normal_at(position); });
        s.radiance = e.radiance;
        s.area_pdf = 1.0f / e.area;
        return s;
    }
    const void* prefetch_address(std::uint32_t id) const { return &emitters_[id]; }

    /// The emitter index of shape k (Scene::shapes), or `none`.
    std::uint32_t emitter_of_shape(std::uint32_t k) const { return emitter_of_shape_[k]; }
    float area(std::uint32_t id) const { return emitters_[id].area; }
    glm::vec3 radiance(std::uint32_t id) const { return emitters_[id].radiance; }
    restir::LightBounds bounds(std::uint32_t id, float power) const {
        return shapes_.visit(emitters_[id].shape,
                             [&](const auto& shape) { return shape.light_bounds(power); });
    }

private:
    struct Emitter {
        std::uint32_t shape; // in Scene::shapes
        glm::vec3 radiance;
        float area;
    };
    Shapes shapes_;
    std::vector<Emitter> emitters_;
    std::vector<std::uint32_t> emitter_of_shape_;
};

/// All emitters of a scene as one restir::ReceiverLightSet (and ReceiverLightDensity): ids
/// [0, triangle emitters) are the emissive triangles (TriangleEmitters), the light shapes'
/// emitters follow (ShapeEmitters).
class SceneEmitters {
public:
    static constexpr std::uint32_t none = TriangleEmitters::none;

    /// Throws SceneError for a shape that cannot be rendered (check_shapes).
    explicit SceneEmitters(const Scene& scene)
        : triangles_(scene), shapes_(scene), triangle_primitives_(scene.triangle_count()) {}

    std::uint32_t light_count() const { return triangles_.light_count() + shapes_.light_count(); }
    /// Emitters that are light shapes (the last ones).
    std::uint32_t shape_count() const { return shapes_.light_count(); }
    /// Whether emitter `id` is a light shape. Next-event estimation draws a shape's points
    /// from the receiver (by solid angle) and a triangle's by area (path_tracer.cpp).
    bool is_shape(std::uint32_t id) const { return id >= triangles_.light_count(); }

    /// restir::LightSet: a point uniform by area.
    restir::LightSample sample_point(std::uint32_t id, glm::vec2 uv) const {
        if (!is_shape(id)) [[likely]]
            return triangles_.sample_point(id, uv);
        return shapes_.sample_point(shape_id(id), uv);
    }
    const void* prefetch_address(std::uint32_t id) const {
        return is_shape(id) ? shapes_.prefetch_address(shape_id(id))
                            : triangles_.prefetch_address(id);
    }
    /// restir::ReceiverLightSet: a point uniform in the solid angle the emitter subtends from
    /// `from` (TriangleEmitters: Arvo's map; a shape: its own).
    restir::LightSample sample_point(std::uint32_t id, glm::vec2 uv, glm::vec3 from) const {
        if (!is_shape(id))
            return triangles_.sample_point(id, uv, from);
        return shapes_.sample_point(shape_id(id), uv, from);
    }
    /// restir::ReceiverLightDensity: the area density of `sample_point(id, uv, from)` at `point`.
    float point_pdf(std::uint32_t id, glm::vec3 point, glm::vec3 from) const {
        if (!is_shape(id))
            return triangles_.point_pdf(id, point, from);
        return shapes_.point_pdf(shape_id(id), point, from);
    }
    /// The point `position` of emitter `id` as `sample_point(id, uv)` returns it (a packed
    /// history's light points decoded: restir_di.cpp).
    restir::LightSample point_at(std::uint32_t id, glm::vec3 position) const {
        if (is_shape(id))
            return shapes_.point_at(shape_id(id), position);
        restir::LightSample s = triangles_.sample_point(id, glm::vec2(0.0f));
        s.position = position; // one normal, radiance and density over the whole triangle
        return s;
    }

    /// TriangleEmitters::redraw_pays_off for a triangle; never for a shape: a light tile's area
    /// point near a sphere's silhouette has a target near 0, its RIS weight W divides by it, and
    /// a redrawn point's contribution would not cancel it (unbounded variance).
    bool redraw_pays_off(std::uint32_t id, glm::vec3 position, glm::vec3 normal) const {
        return !is_shape(id) && triangles_.redraw_pays_off(id, position, normal);
    }
    /// TriangleEmitters::area_fraction_above (a triangle's; only where a redraw pays off).
    float area_fraction_above(std::uint32_t id, glm::vec3 position, glm::vec3 normal) const {
        return is_shape(id) ? 1.0f : triangles_.area_fraction_above(id, position, normal);
    }

    /// The emitter of primitive `primitive` (Scene::material_of's numbering), or `none`.
    std::uint32_t emitter_of_primitive(std::uint32_t primitive) const {
        if (primitive < triangle_primitives_)
            return triangles_.emitter_of_triangle(primitive);
        const std::uint32_t e = shapes_.emitter_of_shape(primitive - triangle_primitives_);
        return e == ShapeEmitters::none ? none : triangles_.light_count() + e;
    }
    float area(std::uint32_t id) const {
        return is_shape(id) ? shapes_.area(shape_id(id)) : triangles_.area(id);
    }
    glm::vec3 radiance(std::uint32_t id) const {
        return is_shape(id) ? shapes_.radiance(shape_id(id)) : triangles_.radiance(id);
    }
    /// Emitter `id`'s emission bounds for a light BVH, with its `power`.
    restir::LightBounds bounds(std::uint32_t id, float power) const {
        return is_shape(id) ? shapes_.bounds(shape_id(id), power) : triangles_.bounds(id, power);
    }

private:
    std::uint32_t shape_id(std::uint32_t id) const { return id - triangles_.light_count(); }

    TriangleEmitters triangles_;
    ShapeEmitters shapes_;
    std::uint32_t triangle_primitives_; // the scene's triangles, emissive or not
};

} // namespace pt
