// A pinhole camera: rays through pixels, and the pixel a world point projects to (for
// temporal reprojection).
#pragma once

#include "scene.hpp"

#include <glm/geometric.hpp>
#include <glm/vec2.hpp>
#include <glm/vec3.hpp>

#include <cmath>
#include <cstdint>

namespace pt {

class Camera {
public:
    Camera() = default;
    Camera(const CameraSetup& setup, std::uint32_t width, std::uint32_t height)
        : position_(setup.look_from), width_(static_cast<float>(width)),
          height_(static_cast<float>(height)) {
        forward_ = glm::normalize(setup.look_at - setup.look_from);
        right_ = glm::normalize(glm::cross(forward_, setup.up));
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
    glm::vec3 position_{0.0f}, forward_{0.0f, 0.0f, -1.0f}, right_{1.0f, 0.0f, 0.0f},
        up_{0.0f, 1.0f, 0.0f};
    float width_ = 1.0f, height_ = 1.0f, tan_half_ = 1.0f, aspect_ = 1.0f;
};

} // namespace pt
