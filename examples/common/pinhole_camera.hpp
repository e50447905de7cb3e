// The pinhole camera of restir-render (examples/pathtracer/camera.hpp) and the CUDA benchmark
// (benchmarks/cuda/analytic_scene.hpp): rays through pixels, the pixel a world point projects
// to, and the reprojection of temporal reuse through last frame's camera. Callable from device
// code; built on the host.
#pragma once

#include <restir/config.hpp>
#include <restir/reuse/image_view.hpp>

#include <glm/common.hpp>
#include <glm/geometric.hpp>
#include <glm/vec2.hpp>
#include <glm/vec3.hpp>

#include <cmath>
#include <cstdint>

namespace common {

/// A pinhole camera over a width x height image, (0, 0) its top-left corner.
struct PinholeCamera {
    glm::vec3 position{0.0f}, forward{0.0f, 0.0f, -1.0f}, right{1.0f, 0.0f, 0.0f},
        up{0.0f, 1.0f, 0.0f};
    float width = 1.0f, height = 1.0f, tan_half = 1.0f, aspect = 1.0f;

    /// The camera at `from` looking at `at` (apart), `up_hint` giving the image's up unless the
    /// view looks (nearly) along it, then the world axis least aligned with the view, so that
    /// looking straight down still has a right vector; vertical field of view in degrees.
    static PinholeCamera look_at(glm::vec3 from, glm::vec3 at, glm::vec3 up_hint, float fov_degrees,
                                 std::uint32_t w, std::uint32_t h) {
        PinholeCamera c;
        c.position = from;
        c.width = static_cast<float>(w);
        c.height = static_cast<float>(h);
        c.forward = glm::normalize(at - from);
        c.right = glm::normalize(glm::cross(c.forward, up_for(c.forward, up_hint)));
        c.up = glm::cross(c.right, c.forward);
        c.tan_half = std::tan(0.5f * fov_degrees * 0.017453292519943295f);
        c.aspect = c.width / c.height;
        return c;
    }

    /// Unit direction through image point (x, y) in pixels.
    RESTIR_HOST_DEVICE glm::vec3 direction(glm::vec2 pixel) const {
        const float sx = (2.0f * pixel.x / width - 1.0f) * tan_half * aspect;
        const float sy = (1.0f - 2.0f * pixel.y / height) * tan_half;
        return glm::normalize(forward + sx * right + sy * up);
    }

    /// The image point (in pixels) that `point` projects to; false when it is behind the camera.
    RESTIR_HOST_DEVICE bool project(glm::vec3 point, glm::vec2& pixel) const {
        const glm::vec3 d = point - position;
        const float z = glm::dot(d, forward);
        if (!(z > 0.0f))
            return false;
        const float sx = glm::dot(d, right) / (z * tan_half * aspect);
        const float sy = glm::dot(d, up) / (z * tan_half);
        pixel = {0.5f * (sx + 1.0f) * width, 0.5f * (1.0f - sy) * height};
        return true;
    }

private:
    static glm::vec3 up_for(glm::vec3 forward, glm::vec3 up) {
        const glm::vec3 side = glm::cross(forward, up);
        if (glm::dot(side, side) > 1e-8f * glm::dot(up, up))
            return up;
        const glm::vec3 a = glm::abs(forward);
        return a.x <= a.y && a.x <= a.z ? glm::vec3(1.0f, 0.0f, 0.0f)
               : a.y <= a.z             ? glm::vec3(0.0f, 1.0f, 0.0f)
                                        : glm::vec3(0.0f, 0.0f, 1.0f);
    }
};

/// The previous camera's pixel of this frame's surface at `p` (a restir::Reprojection): where
/// `previous` projects the surface's position (`surface_position`, found by argument-dependent
/// lookup), outside the image where it is behind that camera.
template <class Texel>
struct CameraReprojection {
    PinholeCamera previous;
    restir::ImageView<const Texel> surfaces{};
    RESTIR_HOST_DEVICE restir::PixelCoord operator()(restir::PixelCoord p) const {
        glm::vec2 q;
        if (!previous.project(surface_position(surfaces[p]), q))
            return {-1, -1};
        return {static_cast<std::int32_t>(floorf(q.x)), static_cast<std::int32_t>(floorf(q.y))};
    }
};

} // namespace common
