/// @file core/rng.hpp
/// The random-number contract of the library, a PCG32 generator that satisfies it, and
/// counter-based seeding so that results do not depend on thread scheduling.
#pragma once

#include "restir/config.hpp"

#include <concepts>
#include <cstdint>

namespace restir {

/// A source of uniform numbers. Required expression, found by argument-dependent lookup:
///   `next_float(rng)` -> float in [0, 1), advancing `rng`.
/// The library never creates or seeds a generator itself: randomness is always passed in.
template <class Rng>
concept UniformRng = requires(Rng& rng) {
    { next_float(rng) } -> std::same_as<float>;
};

/// Finaliser of SplitMix64 (Steele et al. 2014): a bijective 64-bit mix.
RESTIR_HOST_DEVICE constexpr std::uint64_t mix64(std::uint64_t x) noexcept {
    x ^= x >> 30;
    x *= 0xbf58476d1ce4e5b9ull;
    x ^= x >> 27;
    x *= 0x94d049bb133111ebull;
    x ^= x >> 31;
    return x;
}

/// PCG32 (O'Neill 2014, "PCG XSH RR 64/32"): 64-bit LCG state, 32-bit permuted output,
/// 2^63 selectable streams. Trivially copyable, 16 bytes, device-callable.
struct Pcg32 {
    std::uint64_t state = 0x853c49e6748fea9bull;
    std::uint64_t increment = 0xda3e39cb94b95bdbull; ///< Stream selector, always odd.

    /// Seeds with a starting state and a stream index (`pcg32_srandom_r` of the reference).
    RESTIR_HOST_DEVICE constexpr void seed(std::uint64_t initial_state,
                                           std::uint64_t stream) noexcept {
        state = 0u;
        increment = (stream << 1u) | 1u;
        next_uint();
        state += initial_state;
        next_uint();
    }

    /// Next 32 uniformly distributed bits.
    RESTIR_HOST_DEVICE constexpr std::uint32_t next_uint() noexcept {
        const std::uint64_t old = state;
        state = old * 6364136223846793005ull + increment;
        const auto xorshifted = static_cast<std::uint32_t>(((old >> 18u) ^ old) >> 27u);
        const auto rotation = static_cast<std::uint32_t>(old >> 59u);
        return (xorshifted >> rotation) | (xorshifted << ((32u - rotation) & 31u));
    }

    /// Uniform float in [0, 1): the top 24 bits scaled by 2^-24, so 1 is never returned.
    RESTIR_HOST_DEVICE constexpr float next_unit_float() noexcept {
        return static_cast<float>(next_uint() >> 8u) * 0x1p-24f;
    }
};

/// `UniformRng` hook for Pcg32.
RESTIR_HOST_DEVICE constexpr float next_float(Pcg32& rng) noexcept { return rng.next_unit_float(); }

/// The random streams (the `stream` of `make_pixel_rng`), one per purpose, so that no two
/// purposes draw the same numbers for the same index and frame. The frame recipe's stages
/// draw from `initial`, `temporal` and `spatial + p` for spatial pass p (p < 16); the photon
/// shooter from `photons` (index: photon), emitter points from `emitter_points` (index:
/// emitter). Applications number their own streams from `application` on.
struct RngStream {
    static constexpr std::uint32_t initial = 1u;
    static constexpr std::uint32_t temporal = 2u;
    static constexpr std::uint32_t spatial = 3u;
    static constexpr std::uint32_t emitter_points = 32u;
    static constexpr std::uint32_t photons = 33u;
    static constexpr std::uint32_t application = 64u;
};

/// Counter-based seeding: a generator determined only by (pixel, frame, stream, seed).
/// Every tuple gets its own state and its own stream, so a pixel's random numbers are the
/// same whichever thread, tile order or GPU block computes it. `pixel` is any index (a
/// pixel, a photon, a light); `stream` names the purpose (`RngStream`).
RESTIR_HOST_DEVICE constexpr Pcg32 make_pixel_rng(std::uint32_t pixel, std::uint32_t frame,
                                                  std::uint32_t stream,
                                                  std::uint64_t seed = 0u) noexcept {
    const std::uint64_t key = mix64(seed ^ mix64((std::uint64_t{pixel} << 32u) | frame));
    Pcg32 rng;
    rng.seed(mix64(key ^ (std::uint64_t{stream} * 0x9e3779b97f4a7c15ull)),
             mix64(key + std::uint64_t{stream} + 0x632be59bd9b4e019ull));
    return rng;
}

static_assert(UniformRng<Pcg32>);

} // namespace restir
