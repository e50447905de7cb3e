// The storage forms of light-sample reservoirs (reuse/packed_reservoir.hpp): exact round trips
// for what the library's generators draw, hostile fields stored empty, the packed history's
// light-id translation, and light points decoded from their light and position.
#include "restir/reuse/packed_reservoir.hpp"

#include "restir/core/rng.hpp"
#include "restir/reuse/visibility.hpp"
#include "restir/sampling/ris.hpp"

#include <gtest/gtest.h>

#include <cmath>
#include <cstdint>
#include <limits>

namespace {

using restir::LightSampleRef;
using restir::PackedReservoir;
using Reservoir = restir::Reservoir<LightSampleRef>;

// A finalised reservoir of `count` candidates with uv drawn by `next_float`.
Reservoir drawn_reservoir(restir::Pcg32& rng, std::uint32_t count) {
    Reservoir r;
    for (std::uint32_t i = 0; i < count; ++i) {
        const LightSampleRef x{restir::uniform_index(next_float(rng), 1000u),
                               {next_float(rng), next_float(rng)}};
        const float target = 0.1f + 10.0f * next_float(rng);
        r.stream(x, target * 1000.0f, target, next_float(rng));
    }
    r.finalize();
    return r;
}

TEST(PackedReservoir, RoundTripIsExactForDrawnSamples) {
    restir::Pcg32 rng = restir::make_pixel_rng(0u, 0u, 0u, 17u);
    for (std::uint32_t trial = 0; trial < 10000; ++trial) {
        const Reservoir r = drawn_reservoir(rng, 1u + trial % 64u);
        const Reservoir back = restir::unpack_reservoir(restir::pack_reservoir(r));
        ASSERT_EQ(back.sample, r.sample) << trial;
        ASSERT_EQ(back.contribution_weight, r.contribution_weight) << trial;
        ASSERT_EQ(back.target_value, r.target_value) << trial;
        ASSERT_EQ(back.candidate_count, r.candidate_count) << trial;
        ASSERT_EQ(back.has_sample(), r.has_sample()) << trial;
    }
    EXPECT_EQ(sizeof(PackedReservoir), 20u);
}

TEST(PackedReservoir, EmptyStaysEmpty) {
    const Reservoir back = restir::unpack_reservoir(restir::pack_reservoir(Reservoir{}));
    EXPECT_FALSE(back.has_sample());
    EXPECT_EQ(back.candidate_count, 0u);
    EXPECT_EQ(back.contribution_weight, 0.0f);
}

TEST(PackedReservoir, HostileFieldsAreStoredEmptyAndMSaturates) {
    const float nan = std::numeric_limits<float>::quiet_NaN();
    const float inf = std::numeric_limits<float>::infinity();
    for (const float bad : {nan, inf, -inf, -1.0f}) {
        Reservoir r;
        r.sample = {7u, {0.5f, 0.5f}};
        r.weight_sum = 1.0f;
        r.target_value = 1.0f;
        r.contribution_weight = bad;
        r.candidate_count = 3u;
        const Reservoir back = restir::unpack_reservoir(restir::pack_reservoir(r));
        EXPECT_FALSE(back.has_sample()) << bad;
        EXPECT_TRUE(back.is_well_formed()) << bad;
    }
    Reservoir many;
    many.sample = {1u, {nan, 1.5f}};
    many.weight_sum = 3.0e38f;
    many.target_value = 3.0e38f;
    many.contribution_weight = 3.0e38f;
    many.candidate_count = 100000u;
    const Reservoir back = restir::unpack_reservoir(restir::pack_reservoir(many));
    EXPECT_EQ(back.candidate_count, restir::packed_max_candidate_count);
    EXPECT_TRUE(back.is_well_formed()); // M p-hat W overflows float: the weight sum stays finite
    EXPECT_TRUE(back.has_sample());
    EXPECT_EQ(back.sample.uv.x, 0.0f);            // NaN -> 0
    EXPECT_LT(back.sample.uv.y, 1.0f);            // 1.5 -> the largest uv below 1
    EXPECT_GT(back.sample.uv.y, 1.0f - 0x1p-23f); // ...which is 1 - 2^-24
}

TEST(PackedHistory, TranslatesLightIdsAndDropsRemovedLights) {
    restir::Pcg32 rng = restir::make_pixel_rng(0u, 0u, 0u, 5u);
    const Reservoir r = drawn_reservoir(rng, 8u);
    ASSERT_TRUE(r.has_sample());
    const PackedReservoir stored[2] = {restir::pack_reservoir(r), PackedReservoir{}};
    const restir::ImageView<const PackedReservoir> image{stored, 2u, 1u};

    const restir::PackedHistory<> same{image};
    EXPECT_FALSE(same.empty());
    EXPECT_TRUE(same.contains({1, 0}));
    EXPECT_FALSE(same.contains({2, 0}));
    EXPECT_EQ(same.load({0, 0}).sample, r.sample);
    EXPECT_FALSE(same.load({1, 0}).has_sample());

    const auto shifted = [](std::uint32_t id) { return id + 3u; };
    const restir::PackedHistory<decltype(shifted)> moved{image, shifted};
    EXPECT_EQ(moved.load({0, 0}).sample.light_id, r.sample.light_id + 3u);
    EXPECT_EQ(moved.load({0, 0}).contribution_weight, r.contribution_weight);

    const auto removed = [](std::uint32_t) { return restir::removed_light; };
    const restir::PackedHistory<decltype(removed)> gone{image, removed};
    EXPECT_FALSE(gone.load({0, 0}).has_sample());
    EXPECT_EQ(gone.load({0, 0}).candidate_count, 0u);
    EXPECT_TRUE(restir::PackedHistory<>{}.empty());
}

// A light set of uniform emitters: light i's normal, intensity and falloff are functions of i
// (even ids area lights, odd ids point lights with Yuksel's falloff). Counts its decodes.
struct UniformLights {
    std::uint32_t count = 0u;
    std::uint32_t* decodes = nullptr;
    restir::LightPointSample operator()(std::uint32_t id, glm::vec3 position) const {
        ++*decodes;
        restir::LightPointSample s;
        if (id >= count) {
            s.light_id = restir::removed_light;
            return s;
        }
        const float f = static_cast<float>(id);
        s.light_id = id;
        s.position = position;
        s.normal = id % 2u == 0u ? glm::vec3(0.0f, -1.0f, 0.0f) : glm::vec3(0.0f);
        s.intensity = glm::vec3(1.0f + f, 2.0f, 0.5f * f);
        s.falloff = id % 2u == 0u ? 0.0f : 0.01f * f;
        return s;
    }
};

using PointReservoir = restir::Reservoir<restir::LightPointSample>;

TEST(PackedPointReservoir, RoundTripIsExactWhereTheLightDeterminesThePoint) {
    std::uint32_t decodes = 0u;
    const UniformLights lights{100u, &decodes};
    restir::Pcg32 rng = restir::make_pixel_rng(0u, 0u, 0u, 23u);
    for (std::uint32_t trial = 0; trial < 10000; ++trial) {
        PointReservoir r;
        for (std::uint32_t i = 0; i < 1u + trial % 16u; ++i) {
            const glm::vec3 p(next_float(rng) - 0.5f, 1.0f, 3.0f * next_float(rng));
            const float target = 0.1f + 10.0f * next_float(rng);
            r.stream(lights(restir::uniform_index(next_float(rng), 100u), p), target * 7.0f, target,
                     next_float(rng));
        }
        r.finalize();
        const PointReservoir back = restir::unpack_reservoir(restir::pack_reservoir(r), lights);
        ASSERT_EQ(back.sample, r.sample) << trial;
        ASSERT_EQ(back.contribution_weight, r.contribution_weight) << trial;
        ASSERT_EQ(back.target_value, r.target_value) << trial;
        ASSERT_EQ(back.candidate_count, r.candidate_count) << trial;
        ASSERT_EQ(back.has_sample(), r.has_sample()) << trial;
    }
    EXPECT_EQ(sizeof(restir::PackedPointReservoir), 28u);
}

TEST(PackedPointReservoir, WithoutASampleKeepsMAndDecodesNothing) {
    std::uint32_t decodes = 0u;
    const UniformLights lights{4u, &decodes};
    PointReservoir none; // 32 candidates, none of which could be drawn
    for (std::uint32_t i = 0; i < 32u; ++i)
        none.stream(lights(1u, glm::vec3(0.0f)), 0.0f, 0.0f, 0.5f);
    none.finalize();
    PointReservoir occluded; // visibility reuse zeroed W and the weight sum, kept M and p-hat
    occluded.stream(lights(2u, glm::vec3(1.0f)), 3.0f, 3.0f, 0.5f);
    occluded.finalize();
    restir::apply_visibility(occluded, false);
    decodes = 0u;
    for (const PointReservoir& r : {none, occluded}) {
        const PointReservoir back = restir::unpack_reservoir(restir::pack_reservoir(r), lights);
        EXPECT_FALSE(back.has_sample());
        EXPECT_EQ(back.candidate_count, r.candidate_count);
        EXPECT_EQ(back.contribution_weight, 0.0f);
    }
    EXPECT_EQ(decodes, 0u);
}

TEST(PackedPointReservoir, HostileFieldsAndRemovedLightsComeBackEmpty) {
    std::uint32_t decodes = 0u;
    const UniformLights lights{4u, &decodes};
    PointReservoir good;
    good.stream(lights(3u, glm::vec3(0.25f)), 2.0f, 2.0f, 0.5f);
    good.finalize();
    ASSERT_TRUE(good.has_sample());
    for (const float bad :
         {std::numeric_limits<float>::quiet_NaN(), std::numeric_limits<float>::infinity(), -1.0f}) {
        PointReservoir r = good;
        r.contribution_weight = bad;
        const PointReservoir back = restir::unpack_reservoir(restir::pack_reservoir(r), lights);
        EXPECT_FALSE(back.has_sample());
        EXPECT_EQ(back.candidate_count, 0u);
    }
    // Light 3 is gone from a set of 3 lights: the pixel lends nothing, not even its M.
    const restir::PackedPointReservoir stored[1] = {restir::pack_reservoir(good)};
    const restir::PackedPointHistory<UniformLights> history{{stored, 1u, 1u}, {3u, &decodes}};
    EXPECT_FALSE(history.load({0, 0}).has_sample());
    EXPECT_EQ(history.load({0, 0}).candidate_count, 0u);
    const restir::PackedPointHistory<UniformLights> same{{stored, 1u, 1u}, lights};
    EXPECT_EQ(same.load({0, 0}).sample, good.sample);
    EXPECT_TRUE((restir::PackedPointHistory<UniformLights>{}.empty()));
}

} // namespace
