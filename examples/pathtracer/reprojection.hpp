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

/// The previous camera's pixel of this frame's surface (a restir::Reprojection).
using CameraReprojection = common::CameraReprojection<GSurface>;

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
            .reproject = {previous_camera.pinhole(), {gbuffer.surfaces().data(), w, h}}};
    if (history && frame > 0)
        f.previous_surfaces = {gbuffer.previous_surfaces().data(), w, h};
    return f;
}

} // namespace pt
