// The path tracer: next-event estimation of the emitters (with MIS against the BSDF's
// sampling) and of the VPLs, and paths that sample the surfaces' BSDFs; the reference
// (--method reference) and --gi path.
#pragma once

#include "embree_scene.hpp"
#include "gbuffer.hpp"
#include "light_set.hpp"
#include "scene.hpp"

#include <restir/restir.hpp>

#include <cstdint>

namespace pt {

/// Paths from G-buffer surfaces through the scene, lit by the light set's emitters and VPLs.
class PathTracer {
public:
    /// `ray_offset`: how far rays start off surfaces; `max_depth`: the path length limit.
    PathTracer(const Scene& scene, const EmbreeScene& rays, const LightSet& lights,
               float ray_offset, std::uint32_t max_depth)
        : scene_(scene), rays_(rays), lights_(lights), ray_offset_(ray_offset),
          max_depth_(max_depth) {}

    /// Radiance reflected at `start` towards the previous vertex (its own emission excluded).
    /// With `direct` the emitters' direct light at `start` is included (NEE + MIS); without
    /// it, the caller has estimated it, and only light that bounced at least once more is
    /// added. `bounce_further` continues beyond the first bounce (gi path; otherwise the path
    /// stops after the BSDF-sampled ray that MIS needs).
    glm::vec3 path_radiance(const GSurface& start, restir::Pcg32& rng, bool direct,
                            bool bounce_further) const;
    /// One VPL chosen by power, its light reflected at `s` by its BSDF (no MIS: VPLs are
    /// points). VPLs emit as diffuse surfaces whatever the material they lie on.
    glm::vec3 vpl_nee(const GSurface& s, restir::Pcg32& rng) const;

private:
    glm::vec3 emitter_nee(const GSurface& s, restir::Pcg32& rng) const;
    /// Light of a point `light` (unshadowed) reflected at `s` towards its viewer.
    glm::vec3 reflected(const GSurface& s, const restir::LightSample& light) const;
    bool visible(const restir::LightSampleRef& ref, const GSurface& s) const;

    const Scene& scene_;
    const EmbreeScene& rays_;
    const LightSet& lights_;
    const float ray_offset_;
    const std::uint32_t max_depth_;
};

} // namespace pt
