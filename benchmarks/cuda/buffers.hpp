// The per-frame buffers of both sides (host vectors, device allocations) pointed at by a
// box::Context, and the frame-to-frame bookkeeping: the camera of a frame and the G-buffer and
// history handed on to the next.
#pragma once

#include "cuda_memory.hpp"
#include "di_pipeline.hpp"

#include <glm/vec3.hpp>

#include <cstddef>
#include <cstdint>
#include <utility>
#include <vector>

namespace bench {

using box::Context;

// The per-frame buffers of one side, and the context pointing at them.
struct HostBuffers {
    std::vector<box::Texel> surfaces, previous_surfaces;
    std::vector<box::Reservoir> out, scratch, history;
    std::vector<box::Packed> packed_history;
    std::vector<glm::vec3> image;
    std::vector<std::uint8_t> visible;
    std::vector<float> planes;
    std::vector<restir::LightSampleRef> references;
    void allocate(std::size_t pixels, std::size_t entries) {
        surfaces.assign(pixels, {});
        previous_surfaces.assign(pixels, {});
        out.assign(pixels, {});
        scratch.assign(pixels, {});
        history.assign(pixels, {});
        packed_history.assign(pixels, {});
        image.assign(pixels, glm::vec3(0.0f));
        visible.assign(pixels, 0u);
        planes.assign(entries * restir::tile_plane_count, 0.0f);
        references.assign(entries, {});
    }
    void point(Context& c) {
        c.surfaces = surfaces.data();
        c.previous_surfaces = previous_surfaces.data();
        c.out = out.data();
        c.scratch = scratch.data();
        c.history = history.data();
        c.packed_history = packed_history.data();
        c.image = image.data();
        c.visible = visible.data();
        c.tiles.planes = planes.data();
        c.tiles.references = references.data();
    }
};

inline void point_device(Context& c, std::size_t pixels, std::size_t entries) {
    c.surfaces = device_alloc<box::Texel>(pixels);
    c.previous_surfaces = device_alloc<box::Texel>(pixels);
    c.out = device_alloc<box::Reservoir>(pixels);
    c.scratch = device_alloc<box::Reservoir>(pixels);
    c.history = device_alloc<box::Reservoir>(pixels);
    c.packed_history = device_alloc<box::Packed>(pixels);
    c.image = device_alloc<glm::vec3>(pixels);
    c.visible = device_alloc<std::uint8_t>(pixels);
    c.tiles.planes = device_alloc<float>(entries * restir::tile_plane_count);
    c.tiles.references = device_alloc<restir::LightSampleRef>(entries);
}

// Next frame's view of the buffers: this frame's G-buffer becomes last frame's, and (plain
// layout) the final reservoirs in `out` the history.
inline void end_frame(Context& c) {
    std::swap(c.surfaces, c.previous_surfaces);
    if (!c.packed)
        std::swap(c.out, c.history);
}
inline void begin_frame(Context& c, std::uint32_t frame, bool moving_camera) {
    c.frame = frame;
    c.has_history = frame > 0u;
    const std::uint32_t shown = moving_camera ? frame : 0u;
    c.camera = box::camera_of_frame(c.view, shown, c.width, c.height);
    c.previous_camera =
        box::camera_of_frame(c.view, shown > 0u ? shown - 1u : 0u, c.width, c.height);
}

} // namespace bench
