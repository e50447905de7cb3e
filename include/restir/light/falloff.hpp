/// @file light/falloff.hpp
/// Distance falloff of point lights and VPLs without the 1/d^2 singularity.
#pragma once

#include "restir/config.hpp"
#include "restir/core/math.hpp"

#include <cmath>

namespace restir {

/// The smallest divisor of the falloffs below (a normal float): they never exceed 2e37.
inline constexpr float smallest_falloff_divisor = 1e-37f;

/// Yuksel's point-light attenuation (Yuksel 2020, "Point Light Attenuation Without
/// Singularity"): the irradiance falloff of a point light spread over a sphere of radius r,
///   f(d) = 2 / (d^2 + r^2 + d * sqrt(d^2 + r^2)).
/// f(0) = 2 / r^2 is finite, f(d) -> 1/d^2 as d / r grows, and f(d) < 1/d^2 everywhere.
/// `radius` should be positive; with radius 0 this is exactly 1/d^2, and at d = r = 0 it is
/// 2e37 rather than infinity. Precondition: both non-negative (a debug build
/// checks).
RESTIR_HOST_DEVICE inline float yuksel_falloff(float distance, float radius) noexcept {
    RESTIR_ASSERT(distance >= 0.0f && radius >= 0.0f);
    const float d2 = distance * distance;
    const float r2 = radius * radius;
    return 2.0f / max_of(d2 + r2 + distance * std::sqrt(d2 + r2), smallest_falloff_divisor);
}

/// Plain inverse-square falloff with the distance clamped from below:
///   f(d) = 1 / max(d, d_min)^2, at most 1 / d_min^2.
RESTIR_HOST_DEVICE inline float clamped_inverse_square(float distance,
                                                       float min_distance) noexcept {
    RESTIR_ASSERT(min_distance > 0.0f);
    const float d = max_of(distance, min_distance);
    return 1.0f / max_of(d * d, smallest_falloff_divisor);
}

/// Which falloff a point light or VPL uses.
enum class FalloffKind {
    yuksel,                 ///< `yuksel_falloff`, parameter = sphere radius r.
    clamped_inverse_square, ///< `clamped_inverse_square`, parameter = minimum distance.
    inverse_square,         ///< Exact 1/d^2, unbounded near the light (reference computations).
};

/// Falloff of the chosen kind; `parameter` is the radius or the minimum distance (unused for
/// the exact inverse square).
RESTIR_HOST_DEVICE inline float evaluate_falloff(FalloffKind kind, float distance,
                                                 float parameter) noexcept {
    switch (kind) {
    case FalloffKind::yuksel:
        return yuksel_falloff(distance, parameter);
    case FalloffKind::clamped_inverse_square:
        return clamped_inverse_square(distance, parameter);
    case FalloffKind::inverse_square:
        break;
    }
    return 1.0f / (distance * distance);
}

// --- Names of version 0.1, kept until at least 0.3 -------------------------------------------
// light/attenuation.hpp became light/falloff.hpp and "attenuation" became "falloff"
// everywhere: the enum, its evaluation, Yuksel's function and the divisor's bound.

/// The kind of falloff; renamed `FalloffKind` (its enumerators are unchanged).
using Attenuation [[deprecated("use restir::FalloffKind")]] = FalloffKind;

/// Renamed `smallest_falloff_divisor`.
[[deprecated(
    "use restir::smallest_falloff_divisor")]] inline constexpr float smallest_attenuation_divisor =
    smallest_falloff_divisor;

/// Renamed `yuksel_falloff`.
[[deprecated("use restir::yuksel_falloff")]] RESTIR_HOST_DEVICE inline float
yuksel_attenuation(float distance, float radius) noexcept {
    return yuksel_falloff(distance, radius);
}

/// Renamed `evaluate_falloff`.
[[deprecated("use restir::evaluate_falloff")]] RESTIR_HOST_DEVICE inline float
attenuate(FalloffKind kind, float distance, float parameter) noexcept {
    return evaluate_falloff(kind, distance, parameter);
}

} // namespace restir
