/// @file light/receiver.hpp
/// Where light arrives and how much of it leaves towards the viewer: the receiver that target
/// functions, batch RIS and shading evaluate, so that p-hat is the full unshadowed contribution
/// f(wo, wi) Le G for whatever BSDF the application brings.
#pragma once

#include "restir/config.hpp"
#include "restir/core/math.hpp"

#include <glm/geometric.hpp>
#include <glm/vec3.hpp>

#include <concepts>

namespace restir {

/// A receiving surface point and its BSDF, seen from one outgoing direction. Required
/// expressions, for `const R r` and a unit direction `wi` from the receiver towards a light:
///   `r.position`       -> glm::vec3, the world-space position;
///   `r.reflected(wi)`  -> glm::vec3, f(wo, wi) max(0, n.wi): the BSDF towards the viewer times
///                         the cosine at the receiver, per colour channel (0 below the surface).
/// The batch target loop (`evaluate_tile_block`) calls `reflected` once per candidate in a
/// plain loop: written without branches, it vectorises with the loop.
/// Optional: `r.reflected(wi, sphere_radius)` -> glm::vec3, the same for light from a sphere of
/// angular radius `sphere_radius` (radius / distance): the library calls it instead, with 0
/// for points of area lights and isotropic points without a radius, and r / d for point lights
/// with Yuksel's falloff of radius r (VPLs), so that a glossy receiver may widen its lobe for
/// them (`GlossyReceiver::sphere_min_alpha`).
/// Optional: `r.reflected(wi, sphere_radius, from_vpl)` -> glm::vec3, the same, where
/// `from_vpl` is true for point lights with the clamped inverse-square falloff (the VPLs of a
/// `VplPartition`), so that a receiver may let them reach only some of its lobes
/// (`GlossyReceiver::vpls_diffuse_only`); the library calls it before the form above.
template <class R>
concept Receiver = requires(const R& r, glm::vec3 wi) {
    { r.position } -> std::convertible_to<glm::vec3>;
    { r.reflected(wi) } -> std::convertible_to<glm::vec3>;
};

/// A direction drawn from a BSDF: `wi` (unit, world space) and its solid-angle density `pdf`
/// (0: no direction).
struct DirectionSample {
    glm::vec3 wi{0.0f};
    float pdf = 0.0f;
};

/// A `Receiver` that can also draw directions from its BSDF. Required expressions, for floats
/// `u0, u1, u2` in [0, 1) and a unit direction `wi`:
///   `r.sample_direction(u0, u1, u2)` -> convertible to DirectionSample (u0 picks the lobe of
///                                       a BSDF of several, u1 and u2 the direction in it);
///   `r.direction_pdf(wi)`            -> float, the solid-angle density of that draw at wi.
template <class R>
concept SamplingReceiver = Receiver<R> && requires(const R& r, glm::vec3 wi, float u) {
    { r.sample_direction(u, u, u) } -> std::convertible_to<DirectionSample>;
    { r.direction_pdf(wi) } -> std::convertible_to<float>;
};

/// A Lambertian receiver: f = albedo / pi. The default receiver, and the fast one: the library
/// evaluates it through the folded irradiance formulas (`unshadowed_irradiance`), exactly as a
/// diffuse surface's p-hat was computed before receivers existed.
struct LambertianReceiver {
    glm::vec3 position{0.0f};
    glm::vec3 normal{0.0f, 0.0f, 1.0f}; ///< Unit; the side light is gathered on.
    glm::vec3 albedo{0.0f};

    /// albedo / pi max(0, n.wi).
    RESTIR_HOST_DEVICE glm::vec3 reflected(glm::vec3 wi) const noexcept {
        return albedo * (inv_pi * max_of(0.0f, glm::dot(normal, wi)));
    }
};

static_assert(Receiver<LambertianReceiver>);

/// `receiver.reflected(wi, sphere_radius, from_vpl)` where the receiver has it, else
/// `receiver.reflected(wi, sphere_radius)` where it has that, else `receiver.reflected(wi)`.
template <Receiver R>
RESTIR_HOST_DEVICE RESTIR_FORCE_INLINE glm::vec3
reflected_from(const R& receiver, glm::vec3 wi, float sphere_radius, bool from_vpl = false) {
    if constexpr (requires { receiver.reflected(wi, sphere_radius, from_vpl); })
        return receiver.reflected(wi, sphere_radius, from_vpl);
    else if constexpr (requires { receiver.reflected(wi, sphere_radius); })
        return receiver.reflected(wi, sphere_radius);
    else
        return receiver.reflected(wi);
}

} // namespace restir
