// The benchmark's two scenes as analytic geometry, and their cameras: the Cornell box
// (examples/common/cornell_box.hpp, shared with restir-render) and the many-lights scene (its
// floor, camera and rules for the lights) as triangles intersected one by one, their emitters
// as a restir::LightSet, the photons' scattering, and restir-render's pinhole camera swaying
// from frame to frame. The frame that renders them is di_pipeline.hpp.
#pragma once

#include "../../examples/common/cornell_box.hpp"
#include "../../examples/common/pinhole_camera.hpp"

#include <restir/restir.hpp>

#include <glm/geometric.hpp>
#include <glm/vec2.hpp>
#include <glm/vec3.hpp>

#include <array>
#include <cmath>
#include <cstdint>
#include <utility>
#include <vector>

namespace box {

// --- Scene ----------------------------------------------------------------------------------

using cornell::green;
using cornell::light;
using cornell::red;
using cornell::white;

constexpr glm::vec3 to_vec3(const float (&v)[3]) { return {v[0], v[1], v[2]}; }

RESTIR_HOST_DEVICE inline glm::vec3 albedo_of(std::uint32_t m) {
    const cornell::MaterialData data = cornell::material(m);
    return {data.albedo[0], data.albedo[1], data.albedo[2]};
}
RESTIR_HOST_DEVICE inline glm::vec3 emission_of(std::uint32_t m) {
    const cornell::MaterialData data = cornell::material(m);
    return {data.emission[0], data.emission[1], data.emission[2]};
}

/// A triangle a + s ab + t ac with its unit normal (the side it faces) and material.
struct Triangle {
    glm::vec3 a, ab, ac, normal;
    std::uint32_t material;
};

/// A G-buffer texel and a ray hit: the surface point, its normal (facing the ray's origin),
/// the distance along the ray (0: no surface) and the material.
struct alignas(16) Texel {
    glm::vec3 position{0.0f};
    glm::vec3 normal{0.0f, 1.0f, 0.0f};
    float depth = 0.0f;
    std::uint32_t material = white;
};
static_assert(sizeof(Texel) == 32u);
RESTIR_HOST_DEVICE inline glm::vec3 surface_position(const Texel& t) { return t.position; }
RESTIR_HOST_DEVICE inline glm::vec3 surface_normal(const Texel& t) { return t.normal; }
RESTIR_HOST_DEVICE inline float surface_depth(const Texel& t) { return t.depth; }
RESTIR_HOST_DEVICE inline bool is_valid_surface(const Texel& t) { return t.depth > 0.0f; }

inline constexpr std::uint32_t max_triangles = 32u;

/// The box's 32 triangles, intersected one by one (Moeller-Trumbore): the ray query of the
/// G-buffer, the photons and the shadow rays.
struct Scene {
    Triangle triangles[max_triangles];
    std::uint32_t count = 0u;

    // Distance along `direction` (not unit for shadow segments) to triangle i, or 0.
    RESTIR_HOST_DEVICE float hit_distance(std::uint32_t i, glm::vec3 origin,
                                          glm::vec3 direction) const {
        const Triangle& t = triangles[i];
        const glm::vec3 p = glm::cross(direction, t.ac);
        const float det = glm::dot(t.ab, p);
        if (det == 0.0f)
            return 0.0f;
        const float inv = 1.0f / det;
        const glm::vec3 s = origin - t.a;
        const float u = glm::dot(s, p) * inv;
        if (!(u >= 0.0f && u <= 1.0f))
            return 0.0f;
        const glm::vec3 q = glm::cross(s, t.ab);
        const float v = glm::dot(direction, q) * inv;
        if (!(v >= 0.0f && u + v <= 1.0f))
            return 0.0f;
        const float distance = glm::dot(t.ac, q) * inv;
        return distance > 0.0f ? distance : 0.0f;
    }

    /// restir::ClosestHitQuery: the nearest surface along the unit `direction`.
    RESTIR_HOST_DEVICE Texel closest_hit(glm::vec3 origin, glm::vec3 direction) const {
        Texel hit;
        std::uint32_t nearest = count;
        float best = 3.0e38f;
        for (std::uint32_t i = 0; i < count; ++i) {
            const float d = hit_distance(i, origin, direction);
            if (d > 0.0f && d < best) {
                best = d;
                nearest = i;
            }
        }
        if (nearest == count)
            return hit;
        const Triangle& t = triangles[nearest];
        hit.position = origin + best * direction;
        hit.normal = glm::dot(t.normal, direction) < 0.0f ? t.normal : -t.normal;
        hit.depth = best;
        hit.material = t.material;
        return hit;
    }

    /// restir::RayQuery: whether a surface lies between `from` and `to`.
    RESTIR_HOST_DEVICE bool occluded(glm::vec3 from, glm::vec3 to) const {
        const glm::vec3 d = to - from;
        for (std::uint32_t i = 0; i < count; ++i) {
            const float t = hit_distance(i, from, d);
            if (t > 0.0f && t < 1.0f)
                return true;
        }
        return false;
    }
};

/// The light's triangles as a restir::LightSet (uniform points by area; one light each).
struct Emitter {
    glm::vec3 a, ab, ac, normal, radiance;
    float area;
};
struct Emitters {
    const Emitter* emitters = nullptr;
    std::uint32_t count = 0u;
    RESTIR_HOST_DEVICE std::uint32_t light_count() const { return count; }
    RESTIR_HOST_DEVICE restir::LightSample sample_point(std::uint32_t id, glm::vec2 uv) const {
        const Emitter& e = emitters[id];
        restir::LightSample s;
        s.position = restir::sample_triangle_area_from_edges(e.a, e.ab, e.ac, uv);
        s.normal = e.normal;
        s.radiance = e.radiance;
        s.area_pdf = 1.0f / e.area;
        s.is_delta = false;
        return s;
    }
    /// The point `position` of emitter `id` (restir::LightPointLookup): one normal, radiance and
    /// density over the whole triangle.
    RESTIR_HOST_DEVICE restir::LightSample point_at(std::uint32_t id, glm::vec3 position) const {
        restir::LightSample s = sample_point(id, glm::vec2(0.0f));
        s.position = position;
        return s;
    }
};
using Lights = restir::UnifiedLightSet<Emitters>;

/// The photon shooter's scatter hook: Lambertian by cosine; the light reflects but holds no VPL.
struct Lambertian {
    template <class Rng>
    RESTIR_HOST_DEVICE restir::Scattering operator()(const Texel& hit, glm::vec3, Rng& rng) const {
        const float u0 = next_float(rng);
        const float u1 = next_float(rng);
        const glm::vec3 albedo = albedo_of(hit.material);
        return {restir::sample_diffuse_direction(hit.normal, u0, u1), albedo, albedo, true,
                hit.material == light};
    }
};

/// The Cornell box of restir-render (examples/common/cornell_box.hpp): room, light, two blocks,
/// each quad as two triangles (a, b, c) and (a, c, d) facing the side the box names.
inline Scene make_cornell_box() {
    constexpr cornell::Box box = cornell::box();
    Scene scene;
    using Quad = glm::vec3[4];
    const auto add = [&](const Quad& q, glm::vec3 towards, std::uint32_t material) {
        glm::vec3 c[4] = {q[0], q[1], q[2], q[3]};
        if (glm::dot(glm::cross(c[2] - c[0], c[3] - c[1]), towards) < 0.0f)
            std::swap(c[1], c[3]);
        for (const auto [i, j, k] : {std::array{0, 1, 2}, std::array{0, 2, 3}}) {
            Triangle t{c[i], c[j] - c[i], c[k] - c[i], glm::vec3(0.0f), material};
            t.normal = glm::normalize(glm::cross(t.ab, t.ac));
            scene.triangles[scene.count++] = t;
        }
    };
    const auto corners = [](const cornell::Quad& q, Quad& out) {
        for (std::uint32_t k = 0; k < 4u; ++k)
            out[k] = to_vec3(q.corners[k]);
    };
    const auto centroid = [](const Quad& q) { return 0.25f * (q[0] + q[1] + q[2] + q[3]); };
    for (std::uint32_t i = 0; i < 6u; ++i) {
        Quad q;
        corners(box.room[i], q);
        add(q,
            i == cornell::light_quad ? to_vec3(box.light_facing)
                                     : to_vec3(box.interior) - centroid(q),
            box.room_materials[i]);
    }
    const auto block = [&](const cornell::Quad(&faces)[5]) {
        Quad f[5];
        for (std::uint32_t k = 0; k < 5u; ++k)
            corners(faces[k], f[k]);
        glm::vec3 centre(0.0f);
        for (const Quad& q : f)
            centre += centroid(q) / 5.0f;
        for (const Quad& q : f)
            add(q, centroid(q) - centre, white);
    };
    block(box.short_block.faces);
    block(box.tall_block.faces);
    return scene;
}

/// The light's triangles of `scene` as emitters.
inline std::vector<Emitter> make_emitters(const Scene& scene) {
    std::vector<Emitter> out;
    for (std::uint32_t i = 0; i < scene.count; ++i) {
        const Triangle& t = scene.triangles[i];
        if (t.material == light)
            out.push_back({t.a, t.ab, t.ac, t.normal, emission_of(light),
                           0.5f * glm::length(glm::cross(t.ab, t.ac))});
    }
    return out;
}

/// The many-lights scene's floor ([-50, 50]^2) and `count` square lights facing down over
/// [-40, 40]^2, 1 to 3 above it, as restir-render's generator makes them (sides in [max/3, max],
/// 16 colours of unit luminance times 0.25 to 1.75, 15000 W in all), in a layout of their own.
/// The lights are emitters only: unlike restir-render's, they are not in the G-buffer and cast no
/// shadows (only the floor is geometry).
inline Scene make_many_lights(std::uint32_t count, std::uint64_t seed,
                              std::vector<Emitter>& emitters) {
    Scene scene;
    const glm::vec3 corner(-50.0f, 0.0f, -50.0f);
    // Normal up: (b - a) x (c - a) with a = corner, b = +z, c = +x.
    const glm::vec3 along_x(100.0f, 0.0f, 0.0f), along_z(0.0f, 0.0f, 100.0f);
    scene.triangles[scene.count++] = {corner, along_z, along_x, {0.0f, 1.0f, 0.0f}, white};
    scene.triangles[scene.count++] = {
        corner + along_x + along_z, -along_z, -along_x, {0.0f, 1.0f, 0.0f}, white};
    restir::Pcg32 rng = restir::make_pixel_rng(0u, 0u, restir::RngStream::application, seed);
    glm::vec3 colours[16];
    float intensities[16];
    for (std::uint32_t k = 0; k < 16u; ++k) {
        const glm::vec3 c(0.2f + 0.8f * next_float(rng), 0.2f + 0.8f * next_float(rng),
                          0.2f + 0.8f * next_float(rng));
        colours[k] = c / (0.2126f * c.x + 0.7152f * c.y + 0.0722f * c.z);
        intensities[k] = 0.25f + 1.5f * next_float(rng);
    }
    const float max_side = std::min(0.3f, 0.5f * std::sqrt(6400.0f / static_cast<float>(count)));
    emitters.clear();
    std::vector<std::uint32_t> entry_of(count);
    double weighted_area = 0.0;
    for (std::uint32_t i = 0; i < count; ++i) {
        const float x = 40.0f * (2.0f * next_float(rng) - 1.0f);
        const float z = 40.0f * (2.0f * next_float(rng) - 1.0f);
        const float y = 1.0f + 2.0f * next_float(rng);
        const float side = max_side / 3.0f + (max_side - max_side / 3.0f) * next_float(rng);
        const std::uint32_t entry =
            std::min(15u, static_cast<std::uint32_t>(next_float(rng) * 16.0f));
        const float h = 0.5f * side;
        // Facing down: (b - a) x (c - a) with b along +x, c along +z.
        const glm::vec3 a(x - h, y, z - h), dx(side, 0.0f, 0.0f), dz(0.0f, 0.0f, side);
        const glm::vec3 down(0.0f, -1.0f, 0.0f);
        emitters.push_back(
            {a, dx, dz, down, glm::vec3(static_cast<float>(entry)), 0.5f * side * side});
        emitters.push_back({a + dx + dz, -dx, -dz, down, glm::vec3(static_cast<float>(entry)),
                            0.5f * side * side});
        entry_of[i] = entry;
        weighted_area += static_cast<double>(intensities[entry]) * side * side;
    }
    // A diffuse emitter of radiance L and area A emits pi L A.
    const auto scale = static_cast<float>(15000.0 / (3.14159265358979 * weighted_area));
    for (std::uint32_t i = 0; i < count; ++i) {
        const glm::vec3 radiance = colours[entry_of[i]] * (intensities[entry_of[i]] * scale);
        emitters[2 * i].radiance = emitters[2 * i + 1].radiance = radiance;
    }
    return scene;
}

// --- Camera ---------------------------------------------------------------------------------

/// A pinhole camera: restir-render's (examples/common/pinhole_camera.hpp).
using Camera = common::PinholeCamera;

/// A scene's camera: restir-render's position, target and vertical field of view.
struct View {
    glm::vec3 from{0.0f}, at{0.0f, 0.0f, 1.0f};
    float fov_degrees = 40.0f;
};
inline constexpr View cornell_view{to_vec3(cornell::box().camera.look_from),
                                   to_vec3(cornell::box().camera.look_at),
                                   cornell::box().camera.fov_degrees};
inline constexpr View many_lights_view{{0.0f, 120.0f, 100.0f}, {0.0f, 0.0f, 0.0f}, 40.0f};

/// The camera of frame `frame`: `view` swaying sideways along x (by up to 7.5 % of its distance
/// to the target, a period of about 125 frames), so that temporal reuse reprojects every frame.
inline Camera camera_of_frame(const View& view, std::uint32_t frame, std::uint32_t w,
                              std::uint32_t h) {
    const float sway =
        0.075f * glm::length(view.at - view.from) * std::sin(0.05f * static_cast<float>(frame));
    return Camera::look_at(view.from + glm::vec3(sway, 0.0f, 0.0f), view.at,
                           glm::vec3(0.0f, 1.0f, 0.0f), view.fov_degrees, w, h);
}

} // namespace box
