#include <restir/core/math.hpp>
#include <restir/core/rng.hpp>

#include <gtest/gtest.h>

#include <cstdint>
#include <ios>
#include <limits>

namespace {

constexpr float nan = std::numeric_limits<float>::quiet_NaN();
constexpr float inf = std::numeric_limits<float>::infinity();

TEST(Math, FiniteAndValidWeights) {
    static_assert(restir::is_finite(1.0f) && restir::is_finite(-3.0f) && restir::is_finite(0.0f));
    EXPECT_FALSE(restir::is_finite(nan));
    EXPECT_FALSE(restir::is_finite(inf));
    EXPECT_FALSE(restir::is_finite(-inf));
    EXPECT_TRUE(restir::is_valid_weight(0.0f));
    EXPECT_TRUE(restir::is_valid_weight(std::numeric_limits<float>::max()));
    EXPECT_FALSE(restir::is_valid_weight(-1e-30f));
    EXPECT_FALSE(restir::is_valid_weight(nan));
    EXPECT_FALSE(restir::is_valid_weight(inf));
}

TEST(Math, SafeDivideNeverReturnsNonFinite) {
    EXPECT_EQ(restir::safe_divide(3.0f, 2.0f), 1.5f);
    EXPECT_EQ(restir::safe_divide(3.0f, 0.0f), 0.0f);
    EXPECT_EQ(restir::safe_divide(std::numeric_limits<float>::max(), 1e-30f), 0.0f);
    EXPECT_EQ(restir::safe_divide(nan, 1.0f), 0.0f);
}

// Any float, even one outside [0, 1) or NaN, gives an index in range without converting an
// out-of-range float to an integer (undefined behaviour, caught by the sanitised build).
TEST(Math, UniformIndexTakesAnyFloat) {
    for (float u : {std::numeric_limits<float>::quiet_NaN(), std::numeric_limits<float>::infinity(),
                    -std::numeric_limits<float>::infinity(), -1.0f, -0.0f, 1.0f, 2.5f, 1e30f,
                    -1e30f, std::numeric_limits<float>::denorm_min()})
        for (std::uint32_t count : {1u, 7u, 1u << 31u, 0xffffffffu})
            EXPECT_LT(restir::uniform_index(u, count), count) << u << " " << count;
    EXPECT_EQ(restir::uniform_index(std::numeric_limits<float>::quiet_NaN(), 10u), 0u);
    EXPECT_EQ(restir::uniform_index(-5.0f, 10u), 0u);
    EXPECT_EQ(restir::uniform_index(5.0f, 10u), 9u);
}

TEST(Math, UniformIndexStaysInRange) {
    EXPECT_EQ(restir::uniform_index(0.0f, 10u), 0u);
    EXPECT_EQ(restir::uniform_index(0.999f, 10u), 9u);
    // The largest float below 1, times a count that float cannot represent, may round to
    // the count itself; the index must still be valid.
    for (std::uint32_t count : {16'777'217u, 16'777'219u, 33'554'435u, 4'294'967'295u})
        EXPECT_LT(restir::uniform_index(0x1.fffffep-1f, count), count) << count;
}

// Bit counts and the position of the n-th set bit, against a plain scan over every bit, for
// masks of every population (a fixed generator).
TEST(Math, BitCountAndNthSetBitAgreeWithAScan) {
    restir::Pcg32 rng = restir::make_pixel_rng(5u, 0u, 0u);
    for (std::uint32_t trial = 0; trial < 2000; ++trial) {
        std::uint32_t bits = rng.next_uint();
        // Thin some masks out, so that sparse and single-bit masks are tried too.
        for (std::uint32_t k = 0; k < trial % 5u; ++k)
            bits &= rng.next_uint();
        if (trial < 32u)
            bits = 1u << trial;
        std::uint32_t seen = 0u;
        for (std::uint32_t b = 0; b < 32u; ++b) {
            if ((bits >> b & 1u) == 0u)
                continue;
            ASSERT_EQ(restir::nth_set_bit(bits, seen), b) << std::hex << bits << " " << seen;
            ++seen;
        }
        ASSERT_EQ(restir::bit_count(bits), seen) << std::hex << bits;
    }
    EXPECT_EQ(restir::bit_count(0u), 0u);
    EXPECT_EQ(restir::bit_count(0xffffffffu), 32u);
    EXPECT_EQ(restir::nth_set_bit(0x80000000u, 0u), 31u);
}

} // namespace
