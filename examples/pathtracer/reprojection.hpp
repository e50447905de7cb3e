// Where last frame's camera saw this frame's surfaces: the reprojection of temporal reuse.
#pragma once

#include "camera.hpp"
#include "gbuffer.hpp"

#include <restir/restir.hpp>

#include <cmath>
#include <cstddef>
#include <cstdint>

namespace pt {

/// The previous camera's pixel of this frame's surface at `p` (a restir::Reprojection); outside
/// the image where the previous camera did not see it.
struct CameraReprojection {
    const GBuffer* gbuffer = nullptr;
    const Camera* previous_camera = nullptr;
    std::uint32_t width = 0u;

    restir::PixelCoord operator()(restir::PixelCoord p) const {
        const GSurface& s =
            gbuffer
                ->surfaces()[static_cast<std::size_t>(p.x) + static_cast<std::size_t>(p.y) * width];
        glm::vec2 q;
        if (!previous_camera->project(s.position, q))
            return {-1, -1};
        return {static_cast<std::int32_t>(std::floor(q.x)),
                static_cast<std::int32_t>(std::floor(q.y))};
    }
};

} // namespace pt
