// Presampled light tiles: candidates drawn from tiles follow the light sampler's distribution,
// and RIS over them is unbiased although candidates of one pixel share a tile.
#include <restir/restir.hpp>

#include "support/chi2.hpp"
#include "support/statistics.hpp"
#include "support/stub_bridge.hpp"

#include <gtest/gtest.h>

#include <cstdint>
#include <vector>

namespace {

// Eight point lights on a line, with powers spread over a decade.
struct LineLights {
    std::uint32_t light_count() const { return 8u; }
    restir::LightSample sample_point(std::uint32_t id, glm::vec2) const {
        restir::LightSample p;
        p.position = {static_cast<float>(id), 1.0f, 0.0f};
        p.normal = glm::vec3(0.0f);
        p.radiance = glm::vec3(power(id));
        p.area_pdf = 1.0f;
        p.is_delta = true;
        return p;
    }
    static float power(std::uint32_t id) { return 1.0f + static_cast<float>((id * 5u) % 8u); }
};

std::vector<float> powers() {
    std::vector<float> p;
    for (std::uint32_t i = 0; i < 8u; ++i)
        p.push_back(LineLights::power(i));
    return p;
}

std::vector<restir::PresampledLight> fill(const restir::AliasTable& table, std::uint32_t count,
                                          std::uint64_t seed) {
    const LineLights lights;
    const restir::PowerLightSampler sampler{table.view()};
    std::vector<restir::PresampledLight> entries(count);
    for (std::uint32_t i = 0; i < count; ++i) {
        restir::Pcg32 rng = restir::make_pixel_rng(i, 0u, 0u, seed);
        entries[i] = restir::presample_light(sampler, lights, rng);
    }
    return entries;
}

TEST(LightTiles, EntriesCarryTheirPdfAndEvaluatedPoint) {
    const restir::AliasTable table(powers());
    for (const restir::PresampledLight& e : fill(table, 64u, 1u)) {
        EXPECT_FLOAT_EQ(e.pdf, table.pmf(e.reference.light_id));
        EXPECT_EQ(e.point.position.x, static_cast<float>(e.reference.light_id));
        EXPECT_GE(e.reference.uv.x, 0.0f);
        EXPECT_LT(e.reference.uv.y, 1.0f);
    }
}

// A light set that says what its points read, to be asked for ahead.
struct PrefetchedLineLights : LineLights {
    const void* prefetch_address(std::uint32_t id) const {
        asked.push_back(id);
        return this;
    }
    mutable std::vector<std::uint32_t> asked;
};

// The batched fill hands out the entries of one-by-one draws, bit for bit, over a partial last
// chunk too, and asks for each drawn light's data ahead where the light set tells it how.
TEST(LightTiles, BatchedFillEqualsOneByOneDraws) {
    const restir::AliasTable table(powers());
    const restir::PowerLightSampler sampler{table.view()};
    constexpr std::uint32_t count = 150u;
    const std::vector<restir::PresampledLight> expected = fill(table, count, 9u);
    const PrefetchedLineLights lights;
    std::vector<restir::PresampledLight> got(count);
    std::vector<int> stored(count, 0);
    restir::presample_lights(
        sampler, lights, count,
        [](std::uint32_t k) { return restir::make_pixel_rng(k, 0u, 0u, 9u); },
        [&](std::uint32_t k, const restir::PresampledLight& e) {
            got[k] = e;
            ++stored[k];
        });
    for (std::uint32_t k = 0; k < count; ++k) {
        EXPECT_EQ(stored[k], 1) << k;
        EXPECT_EQ(got[k].reference.light_id, expected[k].reference.light_id) << k;
        EXPECT_EQ(got[k].reference.uv, expected[k].reference.uv) << k;
        EXPECT_EQ(got[k].pdf, expected[k].pdf) << k;
        EXPECT_EQ(got[k].point.position, expected[k].point.position) << k;
        EXPECT_EQ(got[k].point.radiance, expected[k].point.radiance) << k;
    }
    ASSERT_EQ(lights.asked.size(), count);
    for (std::uint32_t k = 0; k < count; ++k)
        EXPECT_EQ(lights.asked[k], expected[k].reference.light_id) << k;
}

// Draws from random tiles of freshly filled tile sets follow the sampler's pmf.
TEST(LightTiles, TileDrawsFollowTheSourceDistribution) {
    const restir::AliasTable table(powers());
    std::vector<double> histogram(8, 0.0);
    for (std::uint32_t set = 0; set < 200u; ++set) {
        const std::vector<restir::PresampledLight> entries = fill(table, 16u * 64u, 100u + set);
        const restir::LightTilesView tiles{entries.data(), 16u, 64u};
        restir::Pcg32 rng = restir::make_pixel_rng(set, 1u, 0u, 5u);
        for (std::uint32_t group = 0; group < 50u; ++group)
            for (int draw = 0; draw < 10; ++draw) {
                const float u0 = next_float(rng);
                const float u1 = next_float(rng);
                histogram[tiles.draw(tiles.tile_for(group, set), u0, u1).reference.light_id] += 1.0;
            }
    }
    std::vector<double> pmf;
    for (std::uint32_t i = 0; i < 8u; ++i)
        pmf.push_back(static_cast<double>(table.pmf(i)));
    EXPECT_TRUE(restir::test::fits_distribution(histogram, pmf, 0.01));
}

// RIS whose candidates all come from one tile: E[f(Y) W] is the sum of f over the lights.
TEST(LightTiles, RisOverOneTileIsUnbiased) {
    const restir::AliasTable table(powers());
    const auto f = [](std::uint32_t id) { // integrand: power falling off along the line
        return LineLights::power(id) / (1.0f + static_cast<float>(id * id));
    };
    double truth = 0.0;
    for (std::uint32_t i = 0; i < 8u; ++i)
        truth += static_cast<double>(f(i));
    restir::test::RunningStats estimate;
    for (std::uint32_t trial = 0; trial < 20'000u; ++trial) {
        const std::vector<restir::PresampledLight> tile = fill(table, 16u, 1000u + trial);
        restir::Pcg32 rng = restir::make_pixel_rng(trial, 2u, 0u, 9u);
        const auto r = restir::resample_ris(
            rng, 8u,
            [&](restir::Pcg32& g) {
                const std::uint32_t index = restir::uniform_index(next_float(g), 16u);
                return restir::SourceSample<std::uint32_t>{index, tile[index].pdf};
            },
            [&](std::uint32_t index) {
                return 1.0f / (1.0f + tile[index].point.position.x); // a rough target
            });
        const auto stored = r.with_sample(tile[r.sample].reference);
        EXPECT_EQ(stored.candidate_count, 8u);
        estimate.add(static_cast<double>(f(stored.sample.light_id) * stored.contribution_weight));
    }
    EXPECT_TRUE(restir::test::agrees_with(estimate, truth));
}

} // namespace
