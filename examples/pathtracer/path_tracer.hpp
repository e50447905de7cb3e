// The path tracer: next-event estimation of the emitters and of the environment (each with MIS
// against the BSDF's sampling) and of the VPLs, and paths that sample the surfaces' BSDFs; the
// reference (--method reference) and --gi path.
#pragma once

#include "embree_scene.hpp"
#include "environment.hpp"
#include "gbuffer.hpp"
#include "light_set.hpp"
#include "scene.hpp"

#include <restir/restir.hpp>

#include <cstdint>

namespace pt {

/// Paths from G-buffer surfaces through the scene, lit by the light set's emitters and VPLs.
class PathTracer {
public:
    /// `ray_offset`: how far rays start off surfaces; `max_depth`: the path length limit;
    /// `environment_nee`: sample the scene's environment at every vertex (with MIS), or leave
    /// it to BSDF-sampled rays that escape (for tests).
    PathTracer(const Scene& scene, const EmbreeScene& rays, const LightSet& lights,
               float ray_offset, std::uint32_t max_depth, bool environment_nee = true)
        : scene_(scene), rays_(rays), lights_(lights), ray_offset_(ray_offset),
          max_depth_(max_depth), environment_(scene.environment ? scene.environment->view()
                                                                : restir::EnvironmentMapView{}),
          environment_nee_(environment_nee && !environment_.empty()),
          escape_distance_(scene.environment ? 2.0f * scene_size(scene) : 0.0f) {}

    /// Radiance reflected at `start` towards the previous vertex (its own emission excluded).
    /// With `direct` the direct light at `start` of the emitters and of the environment is
    /// included (NEE + MIS); without it, the caller has estimated it, and only light that
    /// bounced at least once more is added. `bounce_further` continues beyond the first bounce
    /// (gi path; otherwise the path stops after the BSDF-sampled ray that MIS needs). A
    /// BSDF-sampled ray that leaves the scene sees the environment.
    glm::vec3 path_radiance(const GSurface& start, restir::Pcg32& rng, bool direct,
                            bool bounce_further) const;
    /// A ReSTIR GI sample at `s` (--gi restir-gi): one bounce drawn from its BSDF, and Lo, the
    /// radiance reflected towards `s` at the surface the bounce finds (its emission excluded),
    /// estimated as `path_radiance` continues a path there: NEE of the emitters and the
    /// environment, then BSDF sampling with Russian roulette, the bounce counted towards the
    /// path length limit. No sample (source_pdf 0) where the bounce leaves the scene. With a
    /// `partition` (gi vpl-unbiased), Lo is left 0 where the sample's path part is 0.
    restir::PathSample path_sample(const GSurface& s, restir::Pcg32& rng,
                                   const restir::VplPartition* partition = nullptr) const;
    /// One path sample's path part at `s` over its density (gi vpl-unbiased with independent
    /// path samples): restir::partitioned_path_radiance / source pdf.
    glm::vec3 partitioned_indirect(const GSurface& s, restir::Pcg32& rng,
                                   const restir::VplPartition& partition) const;
    /// One VPL chosen by power, its light reflected at `s` by its BSDF (no MIS: VPLs are
    /// points). VPLs emit as diffuse surfaces whatever the material they lie on.
    glm::vec3 vpl_nee(const GSurface& s, restir::Pcg32& rng) const;

private:
    /// `path_radiance` from a vertex at depth `first_depth` of its path.
    glm::vec3 radiance_from(const GSurface& start, restir::Pcg32& rng, bool direct,
                            bool bounce_further, std::uint32_t first_depth) const;
    glm::vec3 emitter_nee(const GSurface& s, restir::Pcg32& rng) const;
    /// One direction from the environment's sampler, its light reflected at `s` if nothing
    /// blocks the way out, MIS-weighted (balance heuristic) against the BSDF's sampling.
    glm::vec3 environment_nee(const GSurface& s, restir::Pcg32& rng) const;
    /// The environment seen by a BSDF-sampled ray `bounce` that left the scene from `s`,
    /// MIS-weighted against environment_nee when that runs.
    glm::vec3 escaped(const restir::BsdfSample& bounce) const;
    /// Light of a point `light` (unshadowed) reflected at `s` towards its viewer.
    glm::vec3 reflected(const GSurface& s, const restir::LightSample& light) const;
    /// Whether nothing blocks the segment between `s` and the point `light` (an emitter's or
    /// a VPL's), each end off its surface by the ray offset.
    bool visible(const restir::LightSample& light, const GSurface& s) const;

    const Scene& scene_;
    const EmbreeScene& rays_;
    const LightSet& lights_;
    const float ray_offset_;
    const std::uint32_t max_depth_;
    const restir::EnvironmentMapView environment_; ///< Empty without an environment.
    const bool environment_nee_;
    /// Length of shadow rays towards the environment: twice the scene's diagonal, well past
    /// its bounds from any point inside them.
    const float escape_distance_;
};

} // namespace pt
