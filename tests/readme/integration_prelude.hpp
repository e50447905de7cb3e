// What docs/integration.md takes from "your renderer", so that a test compiles and runs its
// snippets exactly as the page shows them (tests/readme_snippets.cmake): a small scene (a floor
// with a box on it, under two emissive quads), its occlusion test, the G-buffer fill and the
// display.
#pragma once

#include <restir/restir.hpp>

#include <glm/geometric.hpp>

#include <cstddef>
#include <cstdint>
#include <utility>
#include <vector>

namespace integration {

inline constexpr std::uint32_t width = 16, height = 12, frame_count = 4;

inline float luminance(glm::vec3 c) { return 0.2126f * c.x + 0.7152f * c.y + 0.0722f * c.z; }

/// The scene's acceleration structure: an axis-aligned box on the floor z = 0.
struct MyScene {
    glm::vec3 box_min{-0.2f, -0.2f, 0.0f}, box_max{0.2f, 0.2f, 0.5f};
    /// Whether the open segment from -> to meets the box (slab test).
    bool any_hit(glm::vec3 from, glm::vec3 to) const {
        const glm::vec3 d = to - from;
        float enter = 1e-4f, leave = 1.0f - 1e-4f;
        for (int axis = 0; axis < 3; ++axis) {
            if (d[axis] == 0.0f) {
                if (from[axis] < box_min[axis] || from[axis] > box_max[axis])
                    return false;
                continue;
            }
            float t0 = (box_min[axis] - from[axis]) / d[axis];
            float t1 = (box_max[axis] - from[axis]) / d[axis];
            if (t0 > t1)
                std::swap(t0, t1);
            enter = t0 > enter ? t0 : enter;
            leave = t1 < leave ? t1 : leave;
        }
        return enter < leave;
    }
};
inline const MyScene scene{};
/// The diagonal of the scene's bounding box (floor [-1, 1]^2, lights up to z = 2), the scale of
/// its shadow-ray offsets.
inline constexpr float scene_extent = 3.5f;

/// The G-buffer pass: a camera looking straight down at the floor [-1, 1]^2 (the box's top
/// face where it covers the floor); one pixel column of sky on the right.
template <class Texel>
void render_gbuffer(std::vector<Texel>& gbuffer, std::uint32_t /*frame*/) {
    for (std::uint32_t y = 0; y < height; ++y)
        for (std::uint32_t x = 0; x < width; ++x) {
            Texel& t = gbuffer[x + y * width];
            t = Texel{};
            if (x + 1 == width)
                continue;
            const glm::vec3 floor{2.0f * (float(x) + 0.5f) / width - 1.0f,
                                  2.0f * (float(y) + 0.5f) / height - 1.0f, 0.0f};
            const bool on_box = floor.x > scene.box_min.x && floor.x < scene.box_max.x &&
                                floor.y > scene.box_min.y && floor.y < scene.box_max.y;
            t.position = on_box ? glm::vec3(floor.x, floor.y, scene.box_max.z) : floor;
            t.normal = {0.0f, 0.0f, 1.0f};
            t.albedo = glm::vec3(0.7f);
            t.depth = 3.0f - t.position.z;
            t.valid = true;
        }
}

/// The frames the snippets presented, in order.
inline std::vector<std::vector<glm::vec3>>& presented() {
    static std::vector<std::vector<glm::vec3>> images;
    return images;
}
inline void present(const std::vector<glm::vec3>& image) { presented().push_back(image); }

/// The page's snippets, in order, as one function body.
void render_frames();

} // namespace integration
