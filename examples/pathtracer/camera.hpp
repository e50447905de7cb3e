// A pinhole camera: rays through pixels, and the pixel a world point projects to (for
// temporal reprojection).
#pragma once

#include "../common/pinhole_camera.hpp"
#include "scene.hpp"

#include <glm/common.hpp>
#include <glm/geometric.hpp>
#include <glm/vec2.hpp>
#include <glm/vec3.hpp>

#include <algorithm>
#include <cmath>
#include <cstdint>

namespace pt {

/// Throws SceneError, naming the problem, when `setup` cannot form rays: a position or target
/// that is not finite or beyond max_coordinate, the two (nearly) the same point, a zero
/// or non-finite up vector, or a field of view outside (0, 180) degrees.
inline void check_camera(const CameraSetup& setup) {
    const auto finite = [](glm::vec3 v) {
        return std::isfinite(v.x) && std::isfinite(v.y) && std::isfinite(v.z);
    };
    const auto in_range = [](glm::vec3 v) {
        const glm::vec3 a = glm::abs(v);
        return a.x <= max_coordinate && a.y <= max_coordinate && a.z <= max_coordinate;
    };
    if (!finite(setup.look_from) || !finite(setup.look_at))
        throw SceneError("the camera position and target must be finite numbers");
    if (!in_range(setup.look_from) || !in_range(setup.look_at))
        throw SceneError("the camera position and target must lie within 1e15 of the origin "
                         "(is the scene that large?)");
    const glm::vec3 view = setup.look_at - setup.look_from;
    const float scale = std::max({1.0f, glm::length(setup.look_from), glm::length(setup.look_at)});
    if (!finite(view) || !(glm::length(view) > 1e-6f * scale))
        throw SceneError("the camera position and target are the same point: give --look-from "
                         "and --look-at apart");
    if (!finite(setup.up) || !(glm::length(setup.up) > 0.0f))
        throw SceneError("the camera's up vector must be finite and non-zero");
    if (!(setup.fov_degrees > 0.0f && setup.fov_degrees < 180.0f))
        throw SceneError("the field of view must lie between 0 and 180 degrees");
}

/// The scene's camera over the rendered image (common::PinholeCamera, shared with the CUDA
/// benchmark), built from a checked setup.
class Camera {
public:
    Camera() = default;
    Camera(const CameraSetup& setup, std::uint32_t width, std::uint32_t height)
        : pinhole_(common::PinholeCamera::look_at(setup.look_from, setup.look_at, setup.up,
                                                  setup.fov_degrees, width, height)) {}

    glm::vec3 position() const { return pinhole_.position; }
    glm::vec3 forward() const { return pinhole_.forward; }
    /// Unit direction through image point (x, y) in pixels, (0, 0) the top-left corner.
    glm::vec3 direction(glm::vec2 pixel) const { return pinhole_.direction(pixel); }
    /// The image point (in pixels) that `point` projects to; false when it is behind the camera.
    bool project(glm::vec3 point, glm::vec2& pixel) const { return pinhole_.project(point, pixel); }
    const common::PinholeCamera& pinhole() const { return pinhole_; }

private:
    common::PinholeCamera pinhole_;
};

} // namespace pt
