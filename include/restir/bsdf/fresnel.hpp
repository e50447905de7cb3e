/// @file bsdf/fresnel.hpp
/// Schlick's Fresnel approximation with a grazing reflectance that vanishes with F0, and the
/// normal-incidence reflectance of a dielectric.
#pragma once

#include "restir/config.hpp"
#include "restir/core/math.hpp"

#include <glm/vec3.hpp>

namespace restir {

/// (1 - c)^5 with c clamped to [0, 1], by multiplications: the weight of the grazing
/// reflectance in Schlick's approximation (Schlick 1994, eq. 24).
RESTIR_HOST_DEVICE inline float schlick_weight(float cos_theta) {
    const float x = 1.0f - min_of(max_of(cos_theta, 0.0f), 1.0f);
    const float x2 = x * x;
    return x2 * x2 * x;
}

/// The reflectance at grazing incidence for a normal-incidence reflectance `f0`:
/// min(1, 50 average(f0)). Lagarde & de Rousiers 2014 ("Moving Frostbite to Physically Based
/// Rendering", sec. 4.4.1) take reflectances below 2 % as pre-shadowed (no real material has
/// them), so F0 = 0 gives no reflection at any angle.
RESTIR_HOST_DEVICE inline float fresnel_f90(glm::vec3 f0) {
    return min_of(1.0f, 50.0f * ((f0.x + f0.y + f0.z) * (1.0f / 3.0f)));
}

/// Schlick's approximation of one channel: f0 + (f90 - f0) (1 - cos_theta)^5.
RESTIR_HOST_DEVICE inline float fresnel_schlick(float f0, float f90, float cos_theta) {
    return f0 + (f90 - f0) * schlick_weight(cos_theta);
}

/// Schlick 1994 ("An Inexpensive BRDF Model for Physically-based Rendering", eq. 24) with the
/// grazing value f90 = `fresnel_f90(f0)` instead of 1: f0 + (f90 - f0) (1 - cos_theta)^5,
/// cos_theta clamped to [0, 1]. Exactly 0 for f0 = 0, exactly 1 for f0 = 1.
RESTIR_HOST_DEVICE inline glm::vec3 fresnel_schlick(glm::vec3 f0, float cos_theta) {
    const float f90 = fresnel_f90(f0);
    const float w = schlick_weight(cos_theta);
    return {f0.x + (f90 - f0.x) * w, f0.y + (f90 - f0.y) * w, f0.z + (f90 - f0.z) * w};
}

/// Reflectance at normal incidence of a dielectric of relative index of refraction `ior`
/// (Fresnel's equations at theta = 0): ((ior - 1) / (ior + 1))^2; 0.04 for ior = 1.5.
RESTIR_HOST_DEVICE inline float dielectric_f0(float ior) {
    const float r = (ior - 1.0f) / (ior + 1.0f);
    return r * r;
}

} // namespace restir
