/// @file vpl/unified_light_set.hpp
/// Emitters and VPLs as one light set with one id space, so that RIS and ReSTIR sample direct
/// and indirect light through the same reservoirs and the same candidate distribution.
#pragma once

#include "restir/concepts.hpp"
#include "restir/config.hpp"
#include "restir/light/environment_light.hpp"
#include "restir/light/environment_map.hpp"
#include "restir/light/light_sample.hpp"
#include "restir/vpl/emitter_points.hpp"
#include "restir/vpl/vpl.hpp"

#include <glm/vec2.hpp>
#include <glm/vec3.hpp>

#include <cstdint>
#include <stdexcept>
#include <vector>

namespace restir {

/// Ids [0, E) are the application's emitters, then the environment (one id, E, when there is
/// one), then the VPLs [first_vpl(), light_count()). Holds views: the emitter set, the VPL array
/// and the environment's tables must outlive it. Satisfies `LightSet`; a `LightSampleRef` into
/// it stays meaningful for as long as the VPL array is unchanged (reshooting photons invalidates
/// the VPL ids held by reservoirs, so clear or rebuild them then); the emitters' and the
/// environment's ids do not move when the VPLs change.
///
/// The environment is a distant light: its points are directions (`LightSample::is_distant`),
/// drawn by `EnvironmentMapView::sample` from the uv, with their density per steradian.
template <LightSet Emitters>
struct UnifiedLightSet {
    const Emitters* emitters = nullptr;
    const Vpl* vpls = nullptr;
    std::uint32_t vpl_count = 0u;
    EnvironmentMapView environment{}; ///< Empty: no environment light.

    RESTIR_HOST_DEVICE std::uint32_t emitter_count() const { return emitters->light_count(); }
    /// 1 with an environment, else 0.
    RESTIR_HOST_DEVICE std::uint32_t environment_count() const {
        return environment.empty() ? 0u : 1u;
    }
    /// The environment's id (meaningful when `environment_count()` is 1).
    RESTIR_HOST_DEVICE std::uint32_t environment_id() const { return emitter_count(); }
    RESTIR_HOST_DEVICE std::uint32_t first_vpl() const {
        return emitter_count() + environment_count();
    }
    RESTIR_HOST_DEVICE std::uint32_t light_count() const { return first_vpl() + vpl_count; }
    RESTIR_HOST_DEVICE bool is_vpl(std::uint32_t id) const { return id >= first_vpl(); }
    RESTIR_HOST_DEVICE bool is_environment(std::uint32_t id) const {
        return environment_count() == 1u && id == environment_id();
    }

    /// The emitter's point for `uv`, the environment's direction for `uv`, or the VPL (which
    /// ignores `uv`).
    RESTIR_HOST_DEVICE LightSample sample_point(std::uint32_t id, glm::vec2 uv) const {
        const std::uint32_t emitter_total = emitter_count();
        if (id < emitter_total)
            return to_light_sample(emitters->sample_point(id, uv));
        if (is_environment(id))
            return environment_light_sample(environment.sample(uv));
        return vpl_light_sample(vpls[id - first_vpl()]);
    }

    /// Light `id`'s point at `position` (`LightPointLookup`): the emitter's, the environment's
    /// direction `position`, or the VPL. Only when the emitter set gives its own.
    RESTIR_HOST_DEVICE LightSample
    point_at(std::uint32_t id, glm::vec3 position) const requires LightPointLookup<Emitters> {
        if (id < emitter_count())
            return to_light_sample(emitters->point_at(id, position));
        if (is_environment(id))
            return environment_light_point(environment, position);
        return vpl_light_sample(vpls[id - first_vpl()]);
    }

    /// What `sample_point(id, uv)` reads, for a prefetch: the VPL, or the emitter's data where
    /// the emitter set tells it (`emitters->prefetch_address(id)`); else this object (an id
    /// out of range too).
    RESTIR_HOST_DEVICE const void* prefetch_address(std::uint32_t id) const {
        if (id >= first_vpl() && id < light_count())
            return vpls + (id - first_vpl());
        if constexpr (requires { emitters->prefetch_address(id); })
            if (id < emitter_count())
                return emitters->prefetch_address(id);
        return this;
    }

    /// Asks for what `sample_point(id, uv)` reads (host prefetches): the environment's table
    /// entry and texel for `uv`, else `prefetch_address(id)`.
    RESTIR_HOST_DEVICE RESTIR_FORCE_INLINE void prefetch_point(std::uint32_t id,
                                                               glm::vec2 uv) const {
        if (is_environment(id))
            environment.prefetch_sample(uv);
        else
            RESTIR_PREFETCH(prefetch_address(id));
    }

    /// The emitter's point for `uv` drawn from the receiver at `from` (`ReceiverLightSet`), or
    /// the environment's direction or the VPL, which do not depend on the receiver. Only when
    /// the emitter set draws points from receivers.
    RESTIR_HOST_DEVICE LightSample sample_point(
        std::uint32_t id, glm::vec2 uv, glm::vec3 from) const requires ReceiverLightSet<Emitters> {
        if (id < emitter_count())
            return to_light_sample(emitters->sample_point(id, uv, from));
        return sample_point(id, uv);
    }

    /// The density per unit area of `sample_point(id, ., from)` at the emitter's `point`
    /// (`ReceiverLightDensity`), the environment's density per steradian of the direction
    /// `point`, or 1 for a VPL (a delta light: no ray finds it). Only when the emitter set
    /// gives its own.
    RESTIR_HOST_DEVICE float
    point_pdf(std::uint32_t id, glm::vec3 point,
              glm::vec3 from) const requires ReceiverLightDensity<Emitters> {
        if (id < emitter_count())
            return static_cast<float>(emitters->point_pdf(id, point, from));
        if (is_environment(id))
            return environment.pdf(point);
        return 1.0f;
    }
};

/// The power of each light of a unified set, the weights of its candidate distribution
/// (feed them to an `AliasTable` and a `PowerLightSampler`): emitted flux summed over the
/// colour channels for emitters (`emitted_flux` of the emitter's centre point: pi L / area_pdf
/// for area lights, 4 pi I for isotropic point lights), reflected flux for VPLs, and
/// `environment_weight` for the environment: `environment_power(map, scene_radius)`, the flux it
/// sends into the scene's bounding sphere, or any other weight that gives it the share wanted.
/// Throws std::invalid_argument when the set has an environment and its weight is not positive
/// and finite (an environment without a share is never sampled: its light would be missing).
template <LightSet Emitters>
std::vector<float> unified_light_powers(const UnifiedLightSet<Emitters>& lights,
                                        float environment_weight = 0.0f) {
    if (lights.environment_count() > 0u &&
        !(environment_weight > 0.0f && environment_weight < 3.0e38f))
        throw std::invalid_argument("unified_light_powers: the environment needs a positive "
                                    "weight (environment_power(map, scene_radius))");
    std::vector<float> powers(lights.light_count());
    for (std::uint32_t id = 0; id < lights.light_count(); ++id) {
        float power = environment_weight;
        if (!lights.is_environment(id)) {
            const glm::vec3 flux = lights.is_vpl(id)
                                       ? lights.vpls[id - lights.first_vpl()].flux
                                       : emitted_flux(lights.sample_point(id, glm::vec2(0.5f)), 1u);
            power = flux.x + flux.y + flux.z;
        }
        powers[id] = power >= 0.0f && power < 3.0e38f ? power : 0.0f;
    }
    return powers;
}

} // namespace restir
