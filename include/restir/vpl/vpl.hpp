/// @file vpl/vpl.hpp
/// The virtual point light record that the photon shooter deposits, and how it looks as a
/// light point.
#pragma once

#include "restir/config.hpp"
#include "restir/core/math.hpp"
#include "restir/light/light_sample.hpp"

#include <glm/vec3.hpp>

#include <type_traits>

namespace restir {

/// A virtual point light: a point of a diffuse surface that re-emits the photon flux it
/// received. Flux convention: `flux` is the REFLECTED flux Phi_r = Phi_incident * albedo (per
/// colour channel), so the VPL radiates like a tiny diffuse emitter of power Phi_r, with
/// intensity Phi_r cos(theta) / pi about `normal`. The VPLs of one shooting pass sum, in
/// expectation, to the flux the scene's diffuse surfaces reflect (docs/algorithms.md). 48 bytes.
struct Vpl {
    glm::vec3 position{0.0f};
    glm::vec3 normal{0.0f, 0.0f, 1.0f}; ///< Unit surface normal on the side the photon came from.
    glm::vec3 flux{0.0f};               ///< Reflected flux Phi_r (watts per channel).
    glm::vec3 albedo{0.0f};             ///< Diffuse albedo of the surface where it was deposited.
};

static_assert(std::is_trivially_copyable_v<Vpl>);

/// The VPL as a light point: a delta light of intensity-per-cosine Phi_r / pi facing `normal`
/// (see `unshadowed_irradiance`). `area_pdf` is 1 by the delta convention.
RESTIR_HOST_DEVICE inline LightSample vpl_light_sample(const Vpl& vpl) noexcept {
    LightSample point;
    point.position = vpl.position;
    point.normal = vpl.normal;
    point.radiance = vpl.flux * inv_pi;
    point.area_pdf = 1.0f;
    point.is_delta = true;
    return point;
}

} // namespace restir
