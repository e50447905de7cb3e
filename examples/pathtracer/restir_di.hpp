// ReSTIR DI: the library's frame recipe (restir/reuse/di_frame.hpp) over the G-buffer, with
// initial candidates, temporal and spatial reuse, the boiling filter and shading; its
// visibility rays traced as packets per pixel block.
#pragma once

#include "camera.hpp"
#include "candidate_sources.hpp"
#include "gbuffer.hpp"
#include "image_io.hpp"
#include "light_set.hpp"
#include "path_tracer.hpp"
#include "pixel_blocks.hpp"
#include "renderer.hpp"

#include <cstdint>
#include <memory>

namespace pt {

/// One ReSTIR frame after another, its reservoirs (and last frame's, the history) kept here.
class RestirDi {
public:
    /// The parts are the renderer's and must outlive this; `camera` and `previous_camera` are
    /// read at every frame.
    RestirDi(const RenderSettings& settings, const PixelBlocks& blocks, GBuffer& gbuffer,
             InitialCandidates& candidates, const LightSet& lights, const PathTracer& paths,
             const Camera& camera, const Camera& previous_camera);
    ~RestirDi();
    RestirDi(const RestirDi&) = delete;
    RestirDi& operator=(const RestirDi&) = delete;

    /// Frame `frame` into `image`: the G-buffer, the candidates, then the recipe's stages,
    /// timed by phase into `timings`. `history` false after a new VPL set (last frame's samples
    /// belong to another integrand) and in frame 0.
    void render(std::uint32_t frame, bool history, Image& image, FrameTimings& timings);

private:
    struct Stages;
    std::unique_ptr<Stages> stages_;
};

} // namespace pt
