// Small analytic scenes for the photon shooter tests: an axis-aligned box seen from inside
// (closed, or without its ceiling), a floor square, rectangular emitters that are not part of
// the geometry, and a Lambertian scatter hook.
#pragma once

#include <restir/restir.hpp>

#include <glm/geometric.hpp>
#include <glm/vec2.hpp>
#include <glm/vec3.hpp>

#include <cmath>
#include <cstdint>
#include <vector>

namespace restir::test {

struct SceneHit {
    glm::vec3 position{0.0f};
    glm::vec3 normal{0.0f, 1.0f, 0.0f};
    bool found = false;
};
inline glm::vec3 surface_position(const SceneHit& h) { return h.position; }
inline glm::vec3 surface_normal(const SceneHit& h) { return h.normal; }
inline float surface_depth(const SceneHit&) { return 1.0f; }
inline bool is_valid_surface(const SceneHit& h) { return h.found; }

/// The inside of the box [-1, 1]^3: every ray from inside hits a wall.
struct ClosedBox {
    SceneHit closest_hit(glm::vec3 origin, glm::vec3 direction) const {
        float best = 1e30f;
        int axis = -1;
        for (int a = 0; a < 3; ++a) {
            if (direction[a] == 0.0f)
                continue;
            const float wall = direction[a] > 0.0f ? 1.0f : -1.0f;
            const float t = (wall - origin[a]) / direction[a];
            if (t > 0.0f && t < best) {
                best = t;
                axis = a;
            }
        }
        if (axis < 0)
            return {};
        SceneHit hit;
        hit.position = origin + best * direction;
        hit.normal = glm::vec3(0.0f);
        hit.normal[axis] = direction[axis] > 0.0f ? -1.0f : 1.0f;
        hit.found = true;
        return hit;
    }
};

/// The floor square [-half, half]^2 at y = 0, facing up; nothing else.
struct FloorOnly {
    float half = 2.0f;
    SceneHit closest_hit(glm::vec3 origin, glm::vec3 direction) const {
        if (direction.y == 0.0f)
            return {};
        const float t = -origin.y / direction.y;
        if (!(t > 0.0f))
            return {};
        const glm::vec3 p = origin + t * direction;
        if (std::abs(p.x) > half || std::abs(p.z) > half)
            return {};
        return {p, {0.0f, 1.0f, 0.0f}, true};
    }
};

/// Lambertian surfaces of one (per-channel) albedo, sampled by cosine: weight = albedo.
struct Lambertian {
    glm::vec3 albedo{0.5f};
    template <class Rng>
    Scattering operator()(const SceneHit& hit, glm::vec3 incoming, Rng& rng) const {
        const glm::vec3 facing = glm::dot(hit.normal, incoming) > 0.0f ? -hit.normal : hit.normal;
        const float u0 = next_float(rng);
        const float u1 = next_float(rng);
        return {sample_diffuse_direction(facing, u0, u1), albedo, albedo, true, false};
    }
};

/// Rectangular diffuse emitters facing down (-y), not part of the geometry.
struct Rectangle {
    glm::vec3 corner{0.0f};
    glm::vec3 edge_u{1.0f, 0.0f, 0.0f};
    glm::vec3 edge_v{0.0f, 0.0f, 1.0f};
    glm::vec3 radiance{1.0f};
    float area() const { return glm::length(glm::cross(edge_u, edge_v)); }
};

struct RectangleLights {
    std::vector<Rectangle> rectangles;
    std::uint32_t light_count() const { return static_cast<std::uint32_t>(rectangles.size()); }
    LightSample sample_point(std::uint32_t id, glm::vec2 uv) const {
        const Rectangle& r = rectangles[id];
        LightSample s;
        s.position = r.corner + uv.x * r.edge_u + uv.y * r.edge_v;
        s.normal = glm::normalize(glm::cross(r.edge_u, r.edge_v)); // -y for the defaults
        s.radiance = r.radiance;
        s.area_pdf = 1.0f / r.area();
        s.is_delta = false;
        return s;
    }
    glm::vec3 flux() const {
        glm::vec3 total(0.0f);
        for (const Rectangle& r : rectangles)
            total += r.radiance * (3.14159265358979f * r.area());
        return total;
    }
};

/// A square emitter of side `size` centred above the origin at `height`, facing down.
inline Rectangle ceiling_light(float height, float size, glm::vec3 radiance) {
    return {{-0.5f * size, height, -0.5f * size}, {size, 0.0f, 0.0f}, {0.0f, 0.0f, size}, radiance};
}

} // namespace restir::test
