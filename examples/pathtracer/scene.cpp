// What every scene shares, however it was made: its quads as triangles (scene_quad.hpp), its
// bounds and size, its triangles' normals, the check of its shapes, a camera framing it, and its
// materials made diffuse.
#include "scene.hpp"
#include "scene_quad.hpp"

#include <glm/common.hpp>
#include <glm/geometric.hpp>
#include <glm/vec3.hpp>

#include <algorithm>
#include <cmath>
#include <cstdint>
#include <numbers>
#include <string>
#include <utility>

namespace pt {

void add_quad(Scene& scene, Quad quad, glm::vec3 towards, std::uint32_t material) {
    const glm::vec3 normal = glm::cross(quad[2] - quad[0], quad[3] - quad[1]);
    if (glm::dot(normal, towards) < 0.0f) {
        std::swap(quad[1], quad[3]);
    }
    const auto base = static_cast<std::uint32_t>(scene.positions.size());
    scene.positions.insert(scene.positions.end(), quad.begin(), quad.end());
    for (const std::uint32_t corner : {0u, 1u, 2u, 0u, 2u, 3u}) {
        scene.indices.push_back(base + corner);
    }
    scene.triangle_materials.push_back(material);
    scene.triangle_materials.push_back(material);
}

void make_materials_diffuse(Scene& scene) {
    for (Material& material : scene.materials)
        material = material.diffuse();
}

SceneBounds bounds_of(const Scene& scene) {
    SceneBounds bounds;
    for (const glm::vec3& position : scene.positions) {
        bounds.lower = glm::min(bounds.lower, position);
        bounds.upper = glm::max(bounds.upper, position);
    }
    scene.shapes.for_each_list([&](const auto& list) {
        for (const auto& shape : list) {
            bounds.lower = glm::min(bounds.lower, shape.lower());
            bounds.upper = glm::max(bounds.upper, shape.upper());
        }
    });
    return bounds;
}

namespace {

// Whether a shape's box is finite and within max_coordinate of the origin.
bool box_within_limits(glm::vec3 lower, glm::vec3 upper) {
    for (int k = 0; k < 3; ++k)
        if (!(std::abs(lower[k]) <= max_coordinate && std::abs(upper[k]) <= max_coordinate))
            return false;
    return true;
}

} // namespace

void check_shapes(const Scene& scene) {
    scene.shapes.for_each_list([&](const auto& list) {
        for (std::size_t i = 0; i < list.size(); ++i) {
            const auto& shape = list[i];
            const char* reason = shape.invalid_reason();
            if (reason == nullptr && !box_within_limits(shape.lower(), shape.upper()))
                reason = "its box is not finite or reaches beyond 1e15 of the origin";
            if (reason == nullptr && shape.material >= scene.materials.size())
                reason = "its material index is out of range";
            if (reason != nullptr)
                throw SceneError(std::string(shape.kind) + " " + std::to_string(i) + " of scene '" +
                                 scene.name + "' cannot be rendered: " + reason);
        }
    });
}

glm::vec3 Triangle::normal(glm::vec3 degenerate) const {
    const glm::vec3 n = normal_times_twice_area();
    const float length = glm::length(n);
    return length > 0.0f ? n / length : degenerate;
}

float scene_size(const Scene& scene) {
    const auto [lower, upper] = bounds_of(scene);
    return scene.positions.empty() && scene.shapes.count() == 0u
               ? 1e-6f
               : std::max(glm::length(upper - lower), 1e-6f);
}

CameraSetup frame_bounds(const Scene& scene, float aspect) {
    CameraSetup camera;
    camera.up = {0.0f, 1.0f, 0.0f};
    camera.fov_degrees = 40.0f;
    if (scene.positions.empty() && scene.shapes.count() == 0u) {
        return camera;
    }
    const auto [lower, upper] = bounds_of(scene);
    const glm::vec3 centre = 0.5f * (lower + upper);
    const glm::vec3 half = glm::max(0.5f * (upper - lower), glm::vec3(1e-6f));
    // The box's front face (at z = upper.z) fills the view in its tighter direction.
    const float tan_half = std::tan(0.5f * camera.fov_degrees * std::numbers::pi_v<float> / 180.0f);
    const float fit = std::max(half.y / tan_half, half.x / (tan_half * std::max(aspect, 1e-3f)));
    camera.look_at = centre;
    camera.look_from = centre + glm::vec3{0.0f, 0.0f, half.z + 1.02f * fit};
    return camera;
}

} // namespace pt
