// The light set: the scene's emitters and the VPLs of photon mapping as one
// restir::UnifiedLightSet, the VPLs reshot every few frames, and its sampling tables.
#pragma once

#include "embree_scene.hpp"
#include "lights.hpp"
#include "renderer.hpp"
#include "scene.hpp"

#include <restir/restir.hpp>

#include <tbb/task_arena.h>

#include <cstdint>
#include <optional>
#include <vector>

namespace pt {

/// Emitters first (ids [0, emitter count): triangles, then light shapes), then the environment
/// (one id, with one), then this set's VPLs.
using Unified = restir::UnifiedLightSet<SceneEmitters>;

/// The emitters and the VPL set of this frame, with power tables over all of them, the
/// emitters alone and the VPLs alone.
class LightSet {
public:
    /// Shoots the first VPL set (with --gi vpl; the environment shoots photons too). Throws
    /// SceneError for a scene without emitters and without an environment, with a shining
    /// emitter whose power is no float, or with a shape that cannot be rendered. `ray_offset`: how
    /// far photon rays start off surfaces; `extent`: the scene's size (the VPLs' falloff radius).
    LightSet(const Scene& scene, const EmbreeScene& rays, const RenderSettings& settings,
             tbb::task_arena& arena, float ray_offset, float extent);
    LightSet(const LightSet&) = delete;
    LightSet& operator=(const LightSet&) = delete;

    /// A new VPL set every `vpl_reshoot_interval` frames: true when frame `frame` shot one.
    /// Temporal reuse skips that frame (as after a camera cut): the history's samples belong to
    /// the old set, which is not this frame's integrand (docs/noise-and-bias.md).
    bool reshoot_vpls(std::uint32_t frame);

    /// All lights: emitters, the environment, VPLs.
    const Unified& lights() const { return lights_; }
    const SceneEmitters& emitters() const { return emitters_; }
    const std::vector<restir::Vpl>& vpls() const { return vpls_; }
    /// All lights by power (candidates).
    const restir::AliasTable& power_table() const { return light_table_; }
    /// The environment beside samplers of the local lights (the light BVH, the grid): its id and
    /// the probability of choosing it, its share of `power_table` (no distant light without an
    /// environment; probability 0 under --env-sampling bsdf).
    restir::DistantLights<> distant_lights() const { return distant_; }
    /// The local lights (emitters and VPLs, the environment left out) by power, in local ids
    /// (`distant_lights().local_id`); empty when there are none.
    const restir::AliasTable& local_power_table() const { return local_table_; }
    /// The emitters alone by power (path tracing NEE).
    const restir::AliasTable& emitter_table() const { return emitter_table_; }
    /// The density per steradian at `from` with which next-event estimation (an emitter by
    /// power, then its point: a triangle's by area, a shape's by its solid angle from `from`)
    /// draws the point that a ray from `from` found on `emitter` (`hit`, cos_light > 0 the
    /// cosine there), for MIS against BSDF sampling.
    float emitter_hit_pdf(std::uint32_t emitter, const Hit& hit, glm::vec3 from,
                          float cos_light) const {
        const float pmf = emitter_table_.pmf(emitter);
        const float area_pdf = emitters_.is_shape(emitter)
                                   ? pmf * emitters_.point_pdf(emitter, hit.position, from)
                                   : pmf / emitters_.area(emitter);
        return area_pdf * hit.distance * hit.distance / cos_light;
    }
    /// The VPLs alone by power (the reference's VPL NEE); empty without VPLs.
    const restir::AliasTable& vpl_table() const { return vpl_table_; }
    /// The VPLs' distance falloff: Yuksel's (gi vpl), or the partition's clamped one (gi
    /// vpl-unbiased).
    const restir::Falloff& falloff() const { return falloff_; }
    /// The split of indirect light between VPLs and path samples (gi vpl-unbiased); its radius
    /// is the falloff's.
    restir::VplPartition partition() const { return {falloff_.parameter}; }
    /// Every local light's emission bounds (emitters as their shapes bound them, VPLs as cosine
    /// emitters), in local id order (the environment left out): for a light BVH or per-light
    /// bounds.
    std::vector<restir::LightBounds> light_bounds() const;

    /// Milliseconds the last photon shooting took.
    double photon_ms() const { return photon_ms_; }
    /// Photons per VPL set, from the pilot pass of the first set (none without VPLs).
    std::optional<std::uint32_t> photons_per_set() const { return photons_per_set_; }

private:
    void shoot_vpls(std::uint32_t generation);
    std::vector<restir::Vpl> shoot_photons(const restir::PhotonParams& params);
    template <class Scatter>
    std::vector<restir::Vpl> shoot_photons_with(const Scatter& scatter,
                                                const restir::PhotonParams& params);
    std::uint32_t pilot_photon_count(restir::PhotonParams params);
    void build_light_set(std::uint32_t generation);
    float environment_weight() const;
    void build_local_table(std::vector<float> powers);

    const Scene& scene_;
    const EmbreeScene& rays_;
    const RenderSettings& settings_;
    tbb::task_arena& arena_;
    const float ray_offset_;
    const restir::Falloff falloff_;
    const SceneEmitters emitters_;
    std::vector<restir::Vpl> vpls_;
    double photon_ms_ = 0.0;
    std::optional<std::uint32_t> photons_per_set_;
    Unified lights_;
    std::vector<float> powers_; ///< `light_table_`'s weights, by light id
    restir::AliasTable light_table_, local_table_, emitter_table_, vpl_table_;
    restir::DistantLights<> distant_;
};

} // namespace pt
