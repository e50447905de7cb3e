// Light selection stays exact at large light counts. A single float has 24 bits: drawing one
// of 10 million lights from it gave some lights 1.192x their pmf and others 0.596x (and above
// 2^24 lights, some were never drawn). The samplers now draw from 48 bits; these tests measure
// every light's share of the 2^48 values exactly, by the boundaries between lights.
#include <restir/restir.hpp>

#include <gtest/gtest.h>

#include <algorithm>
#include <cmath>
#include <cstdint>
#include <functional>
#include <limits>
#include <vector>

namespace {

constexpr std::uint64_t two_48 = std::uint64_t{1} << 48;

// The smallest 48-bit value that wide_uniform_index maps to `index` or above, computed
// independently: ceil(index 2^48 / count).
// Long division in two 24-bit steps, so that nothing exceeds 64 bits.
std::uint64_t first_value(std::uint32_t index, std::uint32_t count) {
    const std::uint64_t high = (std::uint64_t{index} << 24) / count;
    const std::uint64_t rest = (std::uint64_t{index} << 24) % count;
    const std::uint64_t low = (rest << 24) / count;
    const bool exact = (rest << 24) % count == 0u;
    return (high << 24) + low + (exact ? 0u : 1u);
}

// The two uniform numbers that carry the 48-bit value `bits` (24 bits each).
float high_number(std::uint64_t bits) { return static_cast<float>(bits >> 24) * 0x1p-24f; }
float low_number(std::uint64_t bits) { return static_cast<float>(bits & 0xffffffu) * 0x1p-24f; }

restir::WideIndex wide(std::uint64_t bits, std::uint32_t count) {
    return restir::wide_uniform_index(high_number(bits), low_number(bits), count);
}

// Every one of `count` indices: its boundaries are where the exact formula puts them, so it
// receives floor or ceil of 2^48 / count values; its fraction starts at 0.
TEST(WideUniformIndex, EveryIndexReceivesItsShareOfThe48BitValues) {
    for (std::uint32_t count : {1u, 3u, 1000u, 10'000'000u}) {
        std::uint64_t wrong = 0;
        double worst = 0.0;
        const double share = static_cast<double>(two_48) / count;
        for (std::uint32_t b = 0; b < count; ++b) {
            const std::uint64_t first = first_value(b, count);
            const restir::WideIndex at = wide(first, count);
            if (at.index != b || at.fraction != 0u)
                ++wrong;
            if (b > 0u && wide(first - 1u, count).index != b - 1u)
                ++wrong;
            const std::uint64_t next = b + 1u < count ? first_value(b + 1u, count) : two_48;
            worst = std::max(worst, std::abs(static_cast<double>(next - first) / share - 1.0));
        }
        EXPECT_EQ(wide(two_48 - 1u, count).index, count - 1u);
        EXPECT_EQ(wrong, 0u) << count;
        EXPECT_LE(worst, static_cast<double>(count) / static_cast<double>(two_48) + 1e-15) << count;
    }
}

// The fraction runs through the index: for count 2, index 0 takes the values below 2^47 and
// its fraction is their top 24 bits times 2, so half of them fall below 2^23.
TEST(WideUniformIndex, FractionSpreadsOverTheIndexAndAnyFloatIsDefined) {
    EXPECT_EQ(wide((std::uint64_t{1} << 46) - 1u, 2u).fraction, (1u << 23) - 1u);
    EXPECT_EQ(wide(std::uint64_t{1} << 46, 2u).fraction, 1u << 23);
    EXPECT_EQ(wide(std::uint64_t{1} << 47, 2u).index, 1u);
    EXPECT_EQ(restir::unit_bits24(1.0f - 0x1p-24f), (1u << 24) - 1u);
    for (float u : {std::nanf(""), -1.0f, 0.0f, -0.0f})
        EXPECT_EQ(restir::unit_bits24(u), 0u) << u;
    for (float u : {1.0f, 2.0f, 1e30f, std::numeric_limits<float>::infinity()})
        EXPECT_EQ(restir::unit_bits24(u), (1u << 24) - 1u) << u;
}

// The share of all (u0, u1) pairs of 24-bit numbers for which `draw` returns `light`, for a
// `draw` that is non-decreasing in (u0, u1) (equal weights): found by bisection.
double drawn_share(const std::function<std::uint32_t(float, float)>& draw, std::uint32_t light) {
    const auto first_at_least = [&](std::uint32_t target) {
        std::uint64_t lo = 0, hi = two_48; // the answer lies in [lo, hi]
        while (lo < hi) {
            const std::uint64_t mid = lo + (hi - lo) / 2u;
            if (draw(high_number(mid), low_number(mid)) >= target)
                hi = mid;
            else
                lo = mid + 1u;
        }
        return lo;
    };
    const std::uint64_t begin = light == 0u ? 0u : first_at_least(light);
    return static_cast<double>(first_at_least(light + 1u) - begin) / static_cast<double>(two_48);
}

// Lights at both ends, the ones the review named (0 and 3), and 2000 spread over the range.
std::vector<std::uint32_t> probed_lights(std::uint32_t count) {
    std::vector<std::uint32_t> lights{0u, 1u, 2u, 3u, count - 1u};
    for (std::uint32_t k = 0; k < 2000u; ++k)
        lights.push_back(static_cast<std::uint32_t>((std::uint64_t{k} * 4999u + 7u) % count));
    return lights;
}

void expect_exact_shares(const std::function<std::uint32_t(float, float)>& draw,
                         std::uint32_t count, const char* what) {
    double worst = 0.0;
    for (std::uint32_t light : probed_lights(count))
        worst = std::max(worst, std::abs(drawn_share(draw, light) * count - 1.0));
    EXPECT_LT(worst, 1e-3) << what << ": the worst light's share is off its pmf by this much";
}

TEST(LargeLightCounts, TenMillionLightsAreEachDrawnAtTheirPmf) {
    constexpr std::uint32_t count = 10'000'000u;
    const restir::AliasTable table(std::vector<float>(count, 1.0f));
    expect_exact_shares([&](float u0, float u1) { return table.sample(u0, u1).index; }, count,
                        "alias table");
    const restir::UniformLightSampler uniform{count};
    expect_exact_shares([&](float u0, float u1) { return uniform.sample(u0, u1).index; }, count,
                        "uniform sampler");
    EXPECT_FLOAT_EQ(table.pmf(3u), 1e-7f);
}

TEST(LargeLightCounts, TileEntriesAreEachDrawnEqually) {
    constexpr std::uint32_t size = 1u << 20;
    std::vector<restir::PresampledLight> entries(2u * size);
    const restir::LightTilesView tiles{entries.data(), 2u, size};
    expect_exact_shares(
        [&](float u0, float u1) {
            return static_cast<std::uint32_t>(&tiles.draw(1u, u0, u1) - entries.data() - size);
        },
        size, "light tile");
}

} // namespace
