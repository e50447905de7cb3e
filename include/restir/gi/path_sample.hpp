/// @file gi/path_sample.hpp
/// The sample of ReSTIR GI (Ouyang et al. 2021, Sec. 3): a path from a pixel's visible point
/// through one BSDF-sampled bounce to a sample point, with the radiance that leaves the sample
/// point towards the visible point. Its contribution at a receiver is f(wo, wi) cos * Lo, in
/// the solid-angle measure at the receiver; its storage form keeps it in 40 bytes.
#pragma once

#include "restir/config.hpp"
#include "restir/core/math.hpp"
#include "restir/light/receiver.hpp"

#include <glm/geometric.hpp>
#include <glm/vec3.hpp>

#include <cmath>
#include <cstdint>
#include <type_traits>

namespace restir {

/// A path sample (Ouyang et al. 2021, Sec. 3.1). Lo is the radiance reflected at the sample
/// point towards the visible point (its own emission excluded: that is direct light, which
/// light samples estimate), estimated once when the sample is made.
struct PathSample {
    glm::vec3 visible_point{
        0.0f}; ///< x_v: the surface the sample belongs to (after a shift, the receiver's).
    glm::vec3 sample_point{0.0f};  ///< x_s: where the bounce from x_v landed.
    glm::vec3 sample_normal{0.0f}; ///< n_s: unit, on the side that Lo leaves (towards x_v).
    glm::vec3 radiance{0.0f};      ///< Lo(x_s -> x_v), per channel.
    /// The solid-angle density at x_v with which the bounce's direction was drawn (the source
    /// pdf of the initial candidate, W = 1 / source_pdf before any reuse).
    float source_pdf = 0.0f;
    /// The roughness of the surface at x_s, 1 for a Lambertian one: the reconnection shift
    /// carries a sample to another visible point only where Lo hardly depends on the direction
    /// it leaves in (`ReconnectionShift::min_roughness`).
    float sample_roughness = 1.0f;

    friend constexpr bool operator==(const PathSample&, const PathSample&) = default;
};
static_assert(std::is_trivially_copyable_v<PathSample>);

/// f(wo, wi) max(0, n.wi) Lo at `receiver` (a `Receiver`), wi the direction from the receiver
/// to the sample point: the sample's unshadowed contribution in the solid-angle measure (Ouyang
/// et al. 2021, Eq. 2, the integrand of the indirect light). 0 where the receiver lies behind
/// the sample point's surface, whose Lo leaves on the other side.
template <Receiver R>
RESTIR_HOST_DEVICE glm::vec3 path_sample_radiance(const PathSample& x, const R& receiver) {
    const glm::vec3 to_sample = x.sample_point - receiver.position;
    const float distance2 = glm::dot(to_sample, to_sample);
    if (!(distance2 > 0.0f) || !(glm::dot(x.sample_normal, to_sample) < 0.0f))
        return glm::vec3(0.0f);
    return receiver.reflected(to_sample / std::sqrt(distance2)) * x.radiance;
}

/// A `PathSample` in storage form: both points exactly, the normal in 32 bits (octahedral, 16
/// bits a coordinate: within 6.5e-5 rad, the worst case at the octahedron's face centres), Lo in
/// 32 bits (shared exponent, 9-bit mantissas: within half a unit, at most 1/511.5 of the largest
/// channel, up to 65408), the source pdf exactly and the roughness in 16 bits.
struct PackedPathSample {
    glm::vec3 visible_point{0.0f};
    glm::vec3 sample_point{0.0f};
    std::uint32_t sample_normal = 0u; ///< Octahedral, x in the low 16 bits.
    std::uint32_t radiance = 0u; ///< RGB9E5: r, g, b in 9 bits each from bit 0, exponent on top.
    float source_pdf = 0.0f;
    std::uint32_t sample_roughness = 0u; ///< In units of 1/65535, in the low 16 bits.
};
static_assert(std::is_trivially_copyable_v<PackedPathSample>);
static_assert(sizeof(PackedPathSample) == 40u);

namespace detail {

/// v in [0, 2^31) rounded to the nearest integer.
RESTIR_HOST_DEVICE constexpr std::uint32_t round_to_uint(float v) {
    return static_cast<std::uint32_t>(v + 0.5f);
}
/// 2^k for -126 <= k <= 127.
RESTIR_HOST_DEVICE constexpr float power_of_two(int k) {
    return __builtin_bit_cast(float, static_cast<std::uint32_t>(k + 127) << 23u);
}
/// floor(log2(v)) of a normal positive float v.
RESTIR_HOST_DEVICE constexpr int binary_exponent(float v) {
    return static_cast<int>((__builtin_bit_cast(std::uint32_t, v) >> 23u) & 0xffu) - 127;
}

/// A float in [-1, 1] as 16 bits, and back.
RESTIR_HOST_DEVICE inline std::uint32_t snorm16(float v) {
    const float c = min_of(1.0f, max_of(-1.0f, v)); // NaN: -1
    return round_to_uint((c * 0.5f + 0.5f) * 65535.0f);
}
RESTIR_HOST_DEVICE inline float from_snorm16(std::uint32_t bits) {
    return static_cast<float>(bits & 0xffffu) * (2.0f / 65535.0f) - 1.0f;
}

/// A unit vector on the octahedron, unfolded into the square [-1, 1]^2 (Cigolle et al. 2014).
RESTIR_HOST_DEVICE inline std::uint32_t encode_octahedral(glm::vec3 n) {
    const float l1 = std::fabs(n.x) + std::fabs(n.y) + std::fabs(n.z);
    if (!(l1 > 0.0f))
        return snorm16(0.0f) | (snorm16(0.0f) << 16u);
    float x = n.x / l1;
    float y = n.y / l1;
    if (n.z < 0.0f) { // the lower half folded over the diagonals
        const float fx = (1.0f - std::fabs(y)) * (x >= 0.0f ? 1.0f : -1.0f);
        const float fy = (1.0f - std::fabs(x)) * (y >= 0.0f ? 1.0f : -1.0f);
        x = fx;
        y = fy;
    }
    return snorm16(x) | (snorm16(y) << 16u);
}
RESTIR_HOST_DEVICE inline glm::vec3 decode_octahedral(std::uint32_t bits) {
    const float x = from_snorm16(bits);
    const float y = from_snorm16(bits >> 16u);
    glm::vec3 n(x, y, 1.0f - std::fabs(x) - std::fabs(y));
    const float fold = max_of(-n.z, 0.0f);
    n.x += n.x >= 0.0f ? -fold : fold;
    n.y += n.y >= 0.0f ? -fold : fold;
    return glm::normalize(n);
}

/// Non-negative RGB as a shared exponent and 9-bit mantissas (RGB9E5, bias 15); negative and NaN
/// channels become 0, channels above 65408 (and infinities) 65408.
RESTIR_HOST_DEVICE inline std::uint32_t encode_rgb9e5(glm::vec3 c) {
    constexpr float largest = 65408.0f; // 511 / 512 * 2^16
    const auto clamp = [](float v) { return v > 0.0f ? min_of(v, largest) : 0.0f; };
    const float r = clamp(c.x), g = clamp(c.y), b = clamp(c.z);
    const float top = max_of(r, max_of(g, b));
    // The smallest exponent e >= -15 with top < 2^e; mantissas in units of 2^(e - 9).
    int exponent = top >= power_of_two(-16) ? binary_exponent(top) + 1 : -15;
    exponent = exponent < -15 ? -15 : exponent;
    float scale = power_of_two(9 - exponent);
    if (round_to_uint(top * scale) == 512u) { // rounded up to 2^9
        ++exponent;
        scale *= 0.5f;
    }
    const auto mantissa = [scale](float v) { return min_of(round_to_uint(v * scale), 511u); };
    return mantissa(r) | (mantissa(g) << 9u) | (mantissa(b) << 18u) |
           (static_cast<std::uint32_t>(exponent + 15) << 27u);
}
RESTIR_HOST_DEVICE inline glm::vec3 decode_rgb9e5(std::uint32_t bits) {
    const int exponent = static_cast<int>(bits >> 27u) - 15;
    const float scale = power_of_two(exponent - 9);
    return glm::vec3(static_cast<float>(bits & 511u), static_cast<float>((bits >> 9u) & 511u),
                     static_cast<float>((bits >> 18u) & 511u)) *
           scale;
}

} // namespace detail

/// `x` in storage form (`PackedPathSample`).
RESTIR_HOST_DEVICE inline PackedPathSample pack_path_sample(const PathSample& x) {
    PackedPathSample p;
    p.visible_point = x.visible_point;
    p.sample_point = x.sample_point;
    p.sample_normal = detail::encode_octahedral(x.sample_normal);
    p.radiance = detail::encode_rgb9e5(x.radiance);
    p.source_pdf = x.source_pdf;
    const float roughness = min_of(1.0f, max_of(0.0f, x.sample_roughness)); // NaN: 0
    p.sample_roughness = detail::round_to_uint(roughness * 65535.0f);
    return p;
}

/// The path sample a stored one holds (its normal, Lo and roughness as quantised).
RESTIR_HOST_DEVICE inline PathSample unpack_path_sample(const PackedPathSample& p) {
    PathSample x;
    x.visible_point = p.visible_point;
    x.sample_point = p.sample_point;
    x.sample_normal = detail::decode_octahedral(p.sample_normal);
    x.radiance = detail::decode_rgb9e5(p.radiance);
    x.source_pdf = p.source_pdf;
    x.sample_roughness = static_cast<float>(p.sample_roughness & 0xffffu) * (1.0f / 65535.0f);
    return x;
}

} // namespace restir
