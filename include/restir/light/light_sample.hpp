/// @file light/light_sample.hpp
/// How a light sample is stored (a reference: light id + uv) and what evaluating it gives
/// (a point on the light with its normal, emitted radiance and density).
#pragma once

#include "restir/concepts.hpp"
#include "restir/config.hpp"

#include <glm/vec2.hpp>
#include <glm/vec3.hpp>

#include <cstdint>
#include <type_traits>

namespace restir {

/// A light sample as reservoirs store it: which light, and where on it. Reused samples are
/// re-evaluated from this reference at each surface that reuses them, so nothing in it
/// depends on the surface that drew it. 12 bytes.
struct LightSampleRef {
    std::uint32_t light_id = 0u;
    glm::vec2 uv{0.0f}; ///< Primary sample-space point on the light, in [0, 1)^2.

    /// The same light and point (the frame recipe skips retesting a sample it kept).
    RESTIR_HOST_DEVICE friend constexpr bool operator==(const LightSampleRef& a,
                                                        const LightSampleRef& b) noexcept {
        return a.light_id == b.light_id && a.uv.x == b.uv.x && a.uv.y == b.uv.y;
    }
};

/// A point on a light, as a light set evaluates a `LightSampleRef`. Point lights and VPLs
/// are the degenerate case: the same point for every uv, `area_pdf` of 1 and `is_delta`.
/// A distant light (an environment, `is_distant`) gives a direction instead of a point: the
/// same direction from every receiver, with its density per steradian (docs/bridge.md,
/// "Measures").
struct LightSample {
    /// The point; for a distant light the unit direction from any receiver towards the light.
    glm::vec3 position{0.0f};
    /// Emitting side of an area light; VPL surface normal; zero for a distant light.
    glm::vec3 normal{0.0f, 0.0f, 1.0f};
    glm::vec3 radiance{0.0f}; ///< Emitted radiance toward the receiver side (intensity for points).
    /// Density of the point per unit area of the light, given the light; per steradian for a
    /// distant light.
    float area_pdf = 0.0f;
    bool is_delta = false;   ///< True for point lights and VPLs (no area measure).
    bool is_distant = false; ///< True for a direction (an environment's sample), not a point.
};

/// Any `LightPoint` (the application's own point record) as a `LightSample`.
template <LightPoint P>
RESTIR_HOST_DEVICE constexpr LightSample to_light_sample(const P& p) {
    LightSample point;
    point.position = p.position;
    point.normal = p.normal;
    point.radiance = p.radiance;
    point.area_pdf = p.area_pdf;
    point.is_delta = p.is_delta;
    point.is_distant = is_distant_point(p);
    return point;
}

static_assert(std::is_trivially_copyable_v<LightSampleRef>);
static_assert(std::is_trivially_copyable_v<LightSample>);

} // namespace restir
