/// @file core/math.hpp
/// Small numeric helpers shared by the sampling code; all device-callable.
#pragma once

#include "restir/config.hpp"

#include <bit>
#include <cstdint>

namespace restir {

inline constexpr float pi = 3.14159265358979f;      ///< pi, rounded to float.
inline constexpr float two_pi = 6.28318530717959f;  ///< 2 pi, rounded to float.
inline constexpr float inv_pi = 0.318309886183791f; ///< 1 / pi, rounded to float.

/// True when `x` is neither NaN nor infinite. Written on the bit pattern so that it stays
/// correct under -ffast-math, where `std::isfinite` may be folded to `true`.
RESTIR_HOST_DEVICE constexpr bool is_finite(float x) noexcept {
    const auto bits = __builtin_bit_cast(std::uint32_t, x);
    return (bits & 0x7f800000u) != 0x7f800000u;
}

/// A usable resampling weight or pdf: finite and not negative. One unsigned comparison on
/// the bit pattern: the sign bit must be clear and the exponent not all ones (-0 counts as
/// invalid, which is harmless since it would weigh nothing).
RESTIR_HOST_DEVICE constexpr bool is_valid_weight(float w) noexcept {
    return __builtin_bit_cast(std::uint32_t, w) < 0x7f800000u;
}

/// `numerator / denominator`, or 0 where the denominator is 0 or the result is not finite.
RESTIR_HOST_DEVICE constexpr float safe_divide(float numerator, float denominator) noexcept {
    if (denominator == 0.0f)
        return 0.0f;
    const float q = numerator / denominator;
    return is_finite(q) ? q : 0.0f;
}

/// Smallest of two values, device-callable (std::min is not annotated for CUDA).
template <class T>
RESTIR_HOST_DEVICE constexpr T min_of(T a, T b) noexcept {
    return b < a ? b : a;
}

/// Largest of two values, device-callable.
template <class T>
RESTIR_HOST_DEVICE constexpr T max_of(T a, T b) noexcept {
    return a < b ? b : a;
}

/// The number of set bits of `bits`.
RESTIR_HOST_DEVICE constexpr std::uint32_t bit_count(std::uint32_t bits) noexcept {
#if defined(__CUDA_ARCH__)
    return static_cast<std::uint32_t>(__popc(bits));
#else
    return static_cast<std::uint32_t>(std::popcount(bits));
#endif
}

/// The position of set bit `n` of `bits` (n = 0: the lowest), which has more than n set bits.
RESTIR_HOST_DEVICE constexpr std::uint32_t nth_set_bit(std::uint32_t bits,
                                                       std::uint32_t n) noexcept {
    for (std::uint32_t k = 0; k < n; ++k)
        bits &= bits - 1u; // clears the lowest set bit
#if defined(__CUDA_ARCH__)
    return static_cast<std::uint32_t>(__ffs(static_cast<int>(bits)) - 1);
#else
    return static_cast<std::uint32_t>(std::countr_zero(bits));
#endif
}

/// `condition ? a : b` through a bit mask, without a branch.
RESTIR_HOST_DEVICE constexpr std::uint32_t select_bits(bool condition, std::uint32_t a,
                                                       std::uint32_t b) noexcept {
    return b ^ ((a ^ b) & (0u - static_cast<std::uint32_t>(condition)));
}

/// `condition ? a : b` for floats through a bit mask. Both values are computed before the
/// choice, so it stays a select (a vector blend). From a plain `?:` a compiler may move the
/// untaken side's arithmetic under the condition, and a loop with such conditional operations
/// does not vectorise without masked vector instructions; use this in loops meant to vectorise.
RESTIR_HOST_DEVICE constexpr float select_float(bool condition, float a, float b) noexcept {
    return __builtin_bit_cast(float, select_bits(condition, __builtin_bit_cast(std::uint32_t, a),
                                                 __builtin_bit_cast(std::uint32_t, b)));
}

/// Index in [0, count) from a uniform number u in [0, 1) (count > 0); robust to u rounding up
/// to 1, and defined for any float: u <= 0 or NaN gives 0, u >= 1 gives count - 1.
RESTIR_HOST_DEVICE constexpr std::uint32_t uniform_index(float u, std::uint32_t count) noexcept {
    const float scaled = u * static_cast<float>(count);
    if (!(scaled > 0.0f))
        return 0u;
    // Compared in float: count - 1 itself may round up to 2^32, which no uint32 holds.
    if (!(scaled < static_cast<float>(count)) || !(scaled < 4294967040.0f))
        return count - 1u;
    const auto i = static_cast<std::uint32_t>(scaled);
    return i < count ? i : count - 1u;
}

/// The 24 bits of a uniform number in [0, 1) (all that a float from `next_float` holds), as
/// an integer in [0, 2^24). Defined for any float: u <= 0 or NaN gives 0, u >= 1 gives
/// 2^24 - 1.
RESTIR_HOST_DEVICE constexpr std::uint32_t unit_bits24(float u) noexcept {
    // In this order NaN ends as 0 (every comparison with it is false); min and max
    // instructions, no branches.
    return static_cast<std::uint32_t>(max_of(0.0f, min_of(u * 16777216.0f, 16777215.0f)));
}

/// An index drawn from two uniform numbers, with what is left of their bits.
struct WideIndex {
    std::uint32_t index = 0u;    ///< In [0, count).
    std::uint32_t fraction = 0u; ///< In [0, 2^24): the position inside the index.
};

/// Index in [0, count) (count > 0) from the 48 bits x of two uniform numbers (`u0` the high
/// half): floor(x count / 2^48) by fixed-point multiplication. Each index receives floor or
/// ceil of 2^48 / count of the 2^48 values, so its probability is 1 / count within a relative
/// count / 2^48 (below 1.6e-5 for any 32-bit count; one float's 24 bits left some of 10
/// million lights at 0.6x and others at 1.2x). `fraction` is the top 24 bits of
/// (x count) mod 2^48, which runs through values count apart inside the index: the test
/// fraction < t 2^24 is true with probability t to within 2^-24 + count / 2^48, the
/// precision of a float t.
RESTIR_HOST_DEVICE constexpr WideIndex wide_uniform_index(float u0, float u1,
                                                          std::uint32_t count) noexcept {
    // x count needs 80 bits: with x = hi 2^24 + lo, floor(x count / 2^24) is
    // hi count + floor(lo count / 2^24) < 2^57.
    const std::uint64_t high =
        std::uint64_t{unit_bits24(u0)} * count + ((std::uint64_t{unit_bits24(u1)} * count) >> 24);
    return {static_cast<std::uint32_t>(high >> 24), static_cast<std::uint32_t>(high & 0xffffffu)};
}

} // namespace restir
