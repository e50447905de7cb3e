// A sphere as a light shape (shapes.hpp): its geometry for Embree's user geometry, its points
// uniform by area or uniform in the cone it subtends from a receiver (the library's
// light/sphere_light.hpp), and its emission bounds for the light BVH.
#pragma once

#include <restir/core/math.hpp>
#include <restir/light/light_bounds.hpp>
#include <restir/light/solid_angle.hpp>
#include <restir/light/sphere_light.hpp>
#include <restir/sampling/diffuse_direction.hpp>

#include <glm/geometric.hpp>
#include <glm/vec2.hpp>
#include <glm/vec3.hpp>

#include <cmath>
#include <cstdint>
#include <limits>
#include <string_view>

namespace pt {

/// A sphere with one material. An emissive one emits its material's radiance from every point
/// of its outside (the side its outward normal faces), as a one-sided emitter triangle does.
struct Sphere {
    static constexpr std::string_view kind = "sphere"; ///< In messages.

    glm::vec3 centre{0.0f};
    float radius = 1.0f;
    std::uint32_t material = 0u; ///< Index in Scene::materials.

    /// Why the sphere cannot be rendered, or null: its radius must be a positive float (the
    /// scene checks that its box is finite and within pt::max_coordinate).
    const char* invalid_reason() const {
        return radius > 0.0f ? nullptr : "its radius is not a positive number";
    }

    /// Its bounding box.
    glm::vec3 lower() const { return centre - radius; }
    glm::vec3 upper() const { return centre + radius; }

    /// The nearest t in (t_min, t_max) at which origin + t direction meets the sphere, or
    /// infinity. The quadratic in the form of Haines et al. 2019 (Ray Tracing Gems, ch. 7):
    /// discriminant a (r^2 - |f - (b / a) d|^2) with f = origin - centre, a = d.d, b = f.d,
    /// which keeps its precision for small spheres far away, and roots c / q and q / a with
    /// q = -b - sign(b) sqrt(discriminant), without cancellation.
    float intersect(glm::vec3 origin, glm::vec3 direction, float t_min, float t_max) const {
        constexpr float miss = std::numeric_limits<float>::infinity();
        const glm::vec3 f = origin - centre;
        const float a = glm::dot(direction, direction);
        const float b = glm::dot(f, direction);
        const glm::vec3 closest = f - (b / a) * direction;
        const float discriminant = a * (radius * radius - glm::dot(closest, closest));
        if (!(discriminant >= 0.0f) || !(a > 0.0f))
            return miss;
        const float q = -b - std::copysign(std::sqrt(discriminant), b);
        if (q == 0.0f)
            return miss; // grazing at the origin itself
        const float c = glm::dot(f, f) - radius * radius;
        const float t0 = c / q, t1 = q / a;
        const float near = std::fmin(t0, t1), far = std::fmax(t0, t1);
        if (near > t_min && near < t_max)
            return near;
        return far > t_min && far < t_max ? far : miss;
    }
    /// The outward unit normal at a point of the sphere.
    glm::vec3 normal_at(glm::vec3 point) const { return glm::normalize(point - centre); }

    /// 4 pi r^2.
    float area() const { return 4.0f * restir::pi * radius * radius; }
    /// A point uniform on the whole sphere: a uniform direction from the centre (the library's
    /// sample_diffuse_direction with no normal: z = 1 - 2 u0, phi = 2 pi u1).
    glm::vec3 sample_area(glm::vec2 uv) const {
        return centre + radius * restir::sample_diffuse_direction(glm::vec3(0.0f), uv.x, uv.y);
    }
    /// A point of the cap visible from `from`, its direction uniform in the cone the sphere
    /// subtends (restir::sample_sphere_cone; pdf 0 from inside the sphere).
    restir::SolidAngleSample sample_from(glm::vec3 from, glm::vec2 uv) const {
        return restir::sample_sphere_cone(from, centre, radius, uv);
    }
    /// The solid-angle density of `sample_from(from, .)` at a point of the visible cap:
    /// 1 / (2 pi (1 - cos theta_max)), the same for every point.
    float pdf_from(glm::vec3 from, glm::vec3 /*point*/) const {
        return restir::sphere_cone_pdf(from, centre, radius);
    }

    /// Its emission bounds for the light BVH: its box, and normals in every direction
    /// (theta_o = pi), each emitting over its hemisphere (theta_e = pi / 2).
    restir::LightBounds light_bounds(float power) const {
        return {lower(), upper(), power, glm::vec3(0.0f, 0.0f, 1.0f), -1.0f, 0.0f};
    }
};

} // namespace pt
