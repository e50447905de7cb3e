#include <restir/core/rng.hpp>

#include "support/chi2.hpp"

#include <gtest/gtest.h>

#include <cstdint>
#include <set>
#include <type_traits>
#include <vector>

namespace {

using restir::Pcg32;

TEST(Pcg32, MatchesTheReferenceSequence) {
    // First outputs of the reference implementation's demo, seeded with (42, 54).
    Pcg32 rng;
    rng.seed(42u, 54u);
    const std::uint32_t expected[] = {0xa15c02b7u, 0x7b47f409u, 0xba1d3330u,
                                      0x83d2f293u, 0xbfa4784bu, 0xcbed606eu};
    for (std::uint32_t value : expected)
        EXPECT_EQ(rng.next_uint(), value);
}

TEST(Pcg32, IsTriviallyCopyableAndSmall) {
    static_assert(std::is_trivially_copyable_v<Pcg32>);
    static_assert(sizeof(Pcg32) == 16);
    static_assert(restir::UniformRng<Pcg32>);
}

TEST(Pcg32, FloatsAreInTheHalfOpenUnitInterval) {
    Pcg32 rng;
    rng.seed(7u, 1u);
    for (int i = 0; i < 1'000'000; ++i) {
        const float u = next_float(rng);
        ASSERT_GE(u, 0.0f);
        ASSERT_LT(u, 1.0f);
    }
}

TEST(Pcg32, FloatsAreUniform) {
    constexpr int bins = 64;
    constexpr int draws = 640'000;
    Pcg32 rng;
    rng.seed(123u, 9u);
    std::vector<double> histogram(bins, 0.0);
    for (int i = 0; i < draws; ++i)
        histogram[static_cast<std::size_t>(next_float(rng) * bins)] += 1.0;
    EXPECT_TRUE(
        restir::test::fits_distribution(histogram, std::vector<double>(bins, 1.0 / bins), 0.01));
}

TEST(PixelRng, IsDeterministicForTheSameCounters) {
    Pcg32 a = restir::make_pixel_rng(1234u, 7u, 2u, 99u);
    Pcg32 b = restir::make_pixel_rng(1234u, 7u, 2u, 99u);
    for (int i = 0; i < 100; ++i)
        EXPECT_EQ(a.next_uint(), b.next_uint());
}

TEST(PixelRng, DiffersWhenAnyCounterDiffers) {
    const auto first = [](Pcg32 rng) {
        return (std::uint64_t{rng.next_uint()} << 32u) | rng.next_uint();
    };
    std::set<std::uint64_t> seen;
    seen.insert(first(restir::make_pixel_rng(10u, 3u, 1u, 5u)));
    seen.insert(first(restir::make_pixel_rng(11u, 3u, 1u, 5u)));
    seen.insert(first(restir::make_pixel_rng(10u, 4u, 1u, 5u)));
    seen.insert(first(restir::make_pixel_rng(10u, 3u, 2u, 5u)));
    seen.insert(first(restir::make_pixel_rng(10u, 3u, 1u, 6u)));
    // Swapping pixel and frame must not give the same stream either.
    seen.insert(first(restir::make_pixel_rng(3u, 10u, 1u, 5u)));
    EXPECT_EQ(seen.size(), 6u);
}

TEST(PixelRng, FirstNumbersAcrossNeighbouringPixelsAreUniform) {
    // Adjacent pixels' streams must not be correlated: the first float of each of many
    // consecutive pixels is itself a uniform sample.
    constexpr int bins = 32;
    constexpr std::uint32_t pixels = 320'000;
    std::vector<double> histogram(bins, 0.0);
    for (std::uint32_t pixel = 0; pixel < pixels; ++pixel) {
        Pcg32 rng = restir::make_pixel_rng(pixel, 0u, 0u);
        histogram[static_cast<std::size_t>(next_float(rng) * bins)] += 1.0;
    }
    EXPECT_TRUE(
        restir::test::fits_distribution(histogram, std::vector<double>(bins, 1.0 / bins), 0.01));
}

} // namespace
