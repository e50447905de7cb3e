// A pinhole camera: rays through pixels, and the pixel a world point projects to (for
// temporal reprojection).
#pragma once

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

class Camera {
public:
    Camera() = default;
    Camera(const CameraSetup& setup, std::uint32_t width, std::uint32_t height)
        : position_(setup.look_from), width_(static_cast<float>(width)),
          height_(static_cast<float>(height)) {
        forward_ = glm::normalize(setup.look_at - setup.look_from);
        right_ = glm::normalize(glm::cross(forward_, up_for(forward_, setup.up)));
        up_ = glm::cross(right_, forward_);
        tan_half_ = std::tan(0.5f * setup.fov_degrees * 0.017453292519943295f);
        aspect_ = width_ / height_;
    }

    glm::vec3 position() const { return position_; }
    glm::vec3 forward() const { return forward_; }

    /// Unit direction through image point (x, y) in pixels, (0, 0) the top-left corner.
    glm::vec3 direction(glm::vec2 pixel) const {
        const float sx = (2.0f * pixel.x / width_ - 1.0f) * tan_half_ * aspect_;
        const float sy = (1.0f - 2.0f * pixel.y / height_) * tan_half_;
        return glm::normalize(forward_ + sx * right_ + sy * up_);
    }

    /// The image point (in pixels) that `point` projects to; false when it is behind the camera.
    bool project(glm::vec3 point, glm::vec2& pixel) const {
        const glm::vec3 d = point - position_;
        const float z = glm::dot(d, forward_);
        if (!(z > 0.0f))
            return false;
        const float sx = glm::dot(d, right_) / (z * tan_half_ * aspect_);
        const float sy = glm::dot(d, up_) / (z * tan_half_);
        pixel = {0.5f * (sx + 1.0f) * width_, 0.5f * (1.0f - sy) * height_};
        return true;
    }

private:
    // `up`, or when the view looks (nearly) along it, the world axis least aligned with the
    // view, so that looking straight down still has a right vector.
    static glm::vec3 up_for(glm::vec3 forward, glm::vec3 up) {
        const glm::vec3 side = glm::cross(forward, up);
        if (glm::dot(side, side) > 1e-8f * glm::dot(up, up))
            return up;
        const glm::vec3 a = glm::abs(forward);
        return a.x <= a.y && a.x <= a.z ? glm::vec3(1.0f, 0.0f, 0.0f)
               : a.y <= a.z             ? glm::vec3(0.0f, 1.0f, 0.0f)
                                        : glm::vec3(0.0f, 0.0f, 1.0f);
    }

    glm::vec3 position_{0.0f}, forward_{0.0f, 0.0f, -1.0f}, right_{1.0f, 0.0f, 0.0f},
        up_{0.0f, 1.0f, 0.0f};
    float width_ = 1.0f, height_ = 1.0f, tan_half_ = 1.0f, aspect_ = 1.0f;
};

} // namespace pt
