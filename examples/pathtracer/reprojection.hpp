// Where last frame's camera saw this frame's surfaces (the reprojection of temporal reuse), and
// the recipe's frame over the G-buffer that ReSTIR DI's and ReSTIR GI's frames share.
#pragma once

#include "camera.hpp"
#include "gbuffer.hpp"
#include "renderer.hpp"

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

/// Frame `frame` of the recipe `Frame` over this frame's G-buffer, with the settings' parameters
/// (`frame_params`) and the reprojection into `previous_camera`; where `history` holds (and not
/// in frame 0), last frame's G-buffer as its previous surfaces, whose reservoirs the caller
/// sets as `history`.
template <class Frame>
Frame frame_over(const GBuffer& gbuffer, const Camera& previous_camera,
                 const RenderSettings& settings, std::uint32_t frame, bool history) {
    const std::uint32_t w = settings.width, h = settings.height;
    Frame f{.params = frame_params(settings),
            .frame_index = frame,
            .surfaces = {gbuffer.surfaces().data(), w, h},
            .reproject = {&gbuffer, &previous_camera, w}};
    if (history && frame > 0)
        f.previous_surfaces = {gbuffer.previous_surfaces().data(), w, h};
    return f;
}

} // namespace pt
