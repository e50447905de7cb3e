/// @file vpl/emitter_points.hpp
/// Step 1 of instant radiosity: the emitters of a light set become point lights that carry
/// their share of the emitted flux, stratified over each emitter.
#pragma once

#include "restir/concepts.hpp"
#include "restir/core/math.hpp"
#include "restir/core/rng.hpp"

#include <glm/vec2.hpp>
#include <glm/vec3.hpp>

#include <cmath>
#include <cstdint>
#include <type_traits>
#include <vector>

namespace restir {

/// A point on an emitter from which photons leave, with the flux it stands for.
struct EmitterPoint {
    glm::vec3 position{0.0f};
    glm::vec3 normal{0.0f}; ///< Emitting side; zero for an isotropic point light.
    glm::vec3 flux{0.0f};   ///< Share of the emitter's flux (watts per channel).
};

static_assert(std::is_trivially_copyable_v<EmitterPoint>);

/// Emitted flux that one light point stands for, when `sample_count` points of its emitter are
/// drawn with density `area_pdf`: pi L / (area_pdf n) for a diffuse area emitter (the flux of a
/// Lambertian emitter is pi L times its area), 4 pi I / n for an isotropic point light.
template <LightPoint P>
RESTIR_HOST_DEVICE glm::vec3 emitted_flux(const P& point, std::uint32_t sample_count) {
    const auto n = static_cast<float>(sample_count);
    if (point.is_delta)
        return glm::vec3(point.radiance) * (4.0f * pi / n);
    return glm::vec3(point.radiance) * safe_divide(pi, static_cast<float>(point.area_pdf) * n);
}

/// Converts every emitter of `lights` (ids 0 .. light_count - 1) into `points_per_emitter`
/// point lights (a jittered s x s grid in the emitter's uv square, s = floor(sqrt(n)), then
/// n - s^2 random points; delta lights once), each carrying its share of the emitter's flux,
/// so that their fluxes sum to an unbiased estimate of the emitted flux. Deterministic in
/// `seed`. Points with zero or non-finite flux are left out, and so are distant lights.
template <LightSet Lights>
std::vector<EmitterPoint>
make_emitter_points(const Lights& lights, std::uint32_t points_per_emitter, std::uint64_t seed) {
    std::vector<EmitterPoint> points;
    const std::uint32_t emitter_count = lights.light_count();
    if (points_per_emitter == 0u)
        return points;
    const auto side =
        static_cast<std::uint32_t>(std::sqrt(static_cast<double>(points_per_emitter)));
    for (std::uint32_t id = 0; id < emitter_count; ++id) {
        Pcg32 rng = make_pixel_rng(id, 0u, RngStream::emitter_points, seed);
        const auto keep = [&](const auto& point, std::uint32_t count) {
            const glm::vec3 flux = emitted_flux(point, count);
            if (is_valid_weight(flux.x) && is_valid_weight(flux.y) && is_valid_weight(flux.z) &&
                flux.x + flux.y + flux.z > 0.0f)
                points.push_back({point.position, point.normal, flux});
        };
        if (is_distant_point(lights.sample_point(id, glm::vec2(0.5f))))
            continue; // a distant light shoots its photons from the sky (`PhotonSource`)
        if (lights.sample_point(id, glm::vec2(0.5f)).is_delta) {
            keep(lights.sample_point(id, glm::vec2(0.5f)), 1u);
            continue;
        }
        for (std::uint32_t i = 0; i < points_per_emitter; ++i) {
            glm::vec2 uv{next_float(rng), next_float(rng)};
            if (i < side * side) { // stratum (i % side, i / side), kept below 1 after rounding
                uv = (glm::vec2(static_cast<float>(i % side), static_cast<float>(i / side)) + uv) /
                     static_cast<float>(side);
                uv = glm::vec2(min_of(uv.x, 0x1.fffffep-1f), min_of(uv.y, 0x1.fffffep-1f));
            }
            keep(lights.sample_point(id, uv), points_per_emitter);
        }
    }
    return points;
}

} // namespace restir
