/// @file vpl/unified_light_set.hpp
/// Emitters and VPLs as one light set with one id space, so that RIS and ReSTIR sample direct
/// and indirect light through the same reservoirs and the same candidate distribution.
#pragma once

#include "restir/concepts.hpp"
#include "restir/config.hpp"
#include "restir/light/light_sample.hpp"
#include "restir/vpl/emitter_points.hpp"
#include "restir/vpl/vpl.hpp"

#include <glm/vec2.hpp>
#include <glm/vec3.hpp>

#include <cstdint>
#include <vector>

namespace restir {

/// Ids [0, E) are the application's emitters, [E, E + V) the VPLs. Holds views: the emitter set
/// and the VPL array must outlive it. Satisfies `LightSet`; a `LightSampleRef` into it stays
/// meaningful for as long as the VPL array is unchanged (reshooting photons invalidates the VPL
/// ids held by reservoirs, so clear or rebuild them then).
template <LightSet Emitters>
struct UnifiedLightSet {
    const Emitters* emitters = nullptr;
    const Vpl* vpls = nullptr;
    std::uint32_t vpl_count = 0u;

    RESTIR_HOST_DEVICE std::uint32_t emitter_count() const { return emitters->light_count(); }
    RESTIR_HOST_DEVICE std::uint32_t light_count() const { return emitter_count() + vpl_count; }
    RESTIR_HOST_DEVICE bool is_vpl(std::uint32_t id) const { return id >= emitter_count(); }

    /// The emitter's point for `uv`, or the VPL (which ignores `uv`).
    RESTIR_HOST_DEVICE LightSample sample_point(std::uint32_t id, glm::vec2 uv) const {
        const std::uint32_t emitter_total = emitter_count();
        if (id >= emitter_total)
            return vpl_light_sample(vpls[id - emitter_total]);
        return to_light_sample(emitters->sample_point(id, uv));
    }

    /// The emitter's point for `uv` drawn from the receiver at `from` (`ReceiverLightSet`), or
    /// the VPL, which stays a point. Only when the emitter set draws points from receivers.
    RESTIR_HOST_DEVICE LightSample sample_point(
        std::uint32_t id, glm::vec2 uv, glm::vec3 from) const requires ReceiverLightSet<Emitters> {
        const std::uint32_t emitter_total = emitter_count();
        if (id >= emitter_total)
            return vpl_light_sample(vpls[id - emitter_total]);
        return to_light_sample(emitters->sample_point(id, uv, from));
    }
};

/// The power of each light of a unified set, the weights of its candidate distribution
/// (feed them to an `AliasTable` and a `PowerLightSampler`): emitted flux summed over the
/// colour channels for emitters (`emitted_flux` of the emitter's centre point: pi L / area_pdf
/// for area lights, 4 pi I for isotropic point lights), reflected flux for VPLs.
template <LightSet Emitters>
std::vector<float> unified_light_powers(const UnifiedLightSet<Emitters>& lights) {
    std::vector<float> powers(lights.light_count());
    for (std::uint32_t id = 0; id < lights.light_count(); ++id) {
        const glm::vec3 flux = lights.is_vpl(id)
                                   ? lights.vpls[id - lights.emitter_count()].flux
                                   : emitted_flux(lights.sample_point(id, glm::vec2(0.5f)), 1u);
        const float power = flux.x + flux.y + flux.z;
        powers[id] = power >= 0.0f && power < 3.0e38f ? power : 0.0f;
    }
    return powers;
}

} // namespace restir
