// ReSTIR GI (--gi restir-gi): a path sample per pixel (one BSDF-sampled bounce and the radiance
// that leaves the surface it finds), reused over time and space with the reconnection shift by
// the library's frame recipe (restir/reuse/di_frame.hpp with restir::ReconnectionShift), and
// shaded with the pixel's BSDF: the indirect light that ReSTIR DI leaves out. ReSTIR PT (--gi
// restir-pt) runs the same frame over whole paths (pt_paths.hpp) with restir::HybridShift.
#pragma once

#include "camera.hpp"
#include "embree_scene.hpp"
#include "gbuffer.hpp"
#include "image_io.hpp"
#include "light_set.hpp"
#include "path_tracer.hpp"
#include "pixel_blocks.hpp"
#include "renderer.hpp"

#include <cstdint>
#include <memory>

namespace pt {

/// One ReSTIR GI (or PT, as `settings.gi` says) frame after another, its reservoirs (and last
/// frame's, the history) kept here.
class RestirGi {
public:
    /// The parts are the renderer's and must outlive this; `previous_camera` is read at every
    /// frame.
    RestirGi(const RenderSettings& settings, const PixelBlocks& blocks, const GBuffer& gbuffer,
             const EmbreeScene& rays, const PathTracer& paths, const LightSet& lights,
             const Camera& previous_camera, float ray_offset);
    ~RestirGi();
    RestirGi(const RestirGi&) = delete;
    RestirGi& operator=(const RestirGi&) = delete;

    /// Adds frame `frame`'s indirect light to `image`, over the G-buffer that this frame's ReSTIR
    /// DI traced; its time goes to `timings.indirect`. `history` false in frame 0 and after a
    /// camera cut.
    void render(std::uint32_t frame, bool history, Image& image, FrameTimings& timings);

private:
    struct Stages;
    template <class Kind>
    struct KindStages;
    std::unique_ptr<Stages> stages_;
};

} // namespace pt
