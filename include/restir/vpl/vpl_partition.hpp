/// @file vpl/vpl_partition.hpp
/// VPL global illumination without bias: the indirect light at a receiver x is split between
/// VPLs and path samples so that the two parts sum to the exact integral,
///   L(x) = int_A Lr(y -> x) f(x) G(x, y) V(x, y) dA(y),   G = cos_x cos_y / d^2, d = |x - y|.
/// With f = f_v + (f - f_v), f_v the lobes through which VPL light reaches x (the diffuse lobe
/// of a `GlossyReceiver` with `vpls_diffuse_only`, all of a Lambertian one), h(y) = 1 where the
/// surface at y holds VPLs (Lambertian: a VPL's flux Phi albedo is then exactly the flux y
/// reflects) and w(d) = min(1, d^2 / r^2):
///   VPL part:  int Lr f_v cos_x cos_y w(d) / d^2 h V dA = int Lr f_v cos_x cos_y h V dA /
///              max(d, r)^2, which photon-traced VPLs with the clamped falloff estimate (each
///              bounded by 1 / r^2: no fireflies);
///   path part: int Lr (f - f_v h w(d)) cos_x V dw, which path samples estimate: the specular
///              lobes whole, and the diffuse lobe near x (d < r) and from surfaces without VPLs.
/// This is Kollig and Keller's (2004) bias compensation of clamped VPLs, its compensation
/// estimated by path samples that ReSTIR can reuse.
#pragma once

#include "restir/config.hpp"
#include "restir/core/math.hpp"
#include "restir/gi/path_sample.hpp"
#include "restir/light/irradiance.hpp"
#include "restir/light/receiver.hpp"

#include <glm/geometric.hpp>
#include <glm/vec3.hpp>

#include <cmath>

namespace restir {

/// The split of indirect light between VPLs and path samples at the radius `radius` (r, in
/// scene units, > 0). A larger r bounds each VPL's light lower (1 / r^2) and leaves more of the
/// integral to path samples.
struct VplPartition {
    float radius = 0.0f;

    /// The VPLs' falloff, 1 / max(d, r)^2 = w(d) / d^2: `Falloff::clamped(r)`. A point light
    /// with this falloff is a VPL of the partition to a `Receiver` (`from_vpl`).
    RESTIR_HOST_DEVICE constexpr Falloff vpl_falloff() const noexcept {
        return Falloff::clamped(radius);
    }
    /// w(d) = min(1, d^2 / r^2): the VPLs' share of the light from a surface that holds VPLs
    /// at distance `distance`.
    RESTIR_HOST_DEVICE float vpl_share(float distance) const noexcept {
        RESTIR_ASSERT(radius > 0.0f);
        const float q = distance / radius;
        return min_of(1.0f, q * q);
    }
};

/// Whether a path sample's surface holds VPLs: Lambertian, which `PathSample` marks with a
/// roughness of 1 (a glossy surface of roughness 1 must report less).
RESTIR_HOST_DEVICE inline bool holds_vpls(const PathSample& x) noexcept {
    return x.sample_roughness >= 1.0f;
}

/// The path part of a path sample at `receiver`: (f - f_v h(y) w(d)) max(0, n.wi) Lo, with
/// f = `receiver.reflected(wi)` and f_v its VPL lobes (`reflected_from(..., from_vpl = true)`);
/// 0 where the receiver lies behind the sample point's surface, as `path_sample_radiance`.
/// Beside the partition's VPLs it estimates the indirect light without bias.
template <Receiver R>
RESTIR_HOST_DEVICE glm::vec3 partitioned_path_radiance(const PathSample& x, const R& receiver,
                                                       const VplPartition& partition) {
    const glm::vec3 to_sample = x.sample_point - receiver.position;
    const float distance2 = glm::dot(to_sample, to_sample);
    if (!(distance2 > 0.0f) || !(glm::dot(x.sample_normal, to_sample) < 0.0f))
        return glm::vec3(0.0f);
    const float distance = std::sqrt(distance2);
    const glm::vec3 wi = to_sample / distance;
    glm::vec3 f = receiver.reflected(wi);
    if (holds_vpls(x))
        f -= reflected_from(receiver, wi, 0.0f, true) * partition.vpl_share(distance);
    // f_v <= f channel by channel; rounding must not make the path part negative.
    return glm::max(f, glm::vec3(0.0f)) * x.radiance;
}

} // namespace restir
