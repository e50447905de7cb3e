#include <restir/sampling/light_sampler.hpp>

#include <restir/core/rng.hpp>
#include <restir/sampling/alias_table.hpp>

#include "support/chi2.hpp"

#include <gtest/gtest.h>

#include <vector>

namespace {

TEST(UniformLightSampler, SamplesEveryLightEqually) {
    const restir::UniformLightSampler sampler{10u};
    std::vector<double> histogram(10, 0.0);
    restir::Pcg32 rng = restir::make_pixel_rng(0u, 0u, 0u, 8u);
    for (int i = 0; i < 100'000; ++i) {
        const restir::DiscreteSample s = restir::sample_light(sampler, rng);
        ASSERT_FLOAT_EQ(s.pmf, 0.1f);
        histogram[s.index] += 1.0;
    }
    EXPECT_TRUE(restir::test::fits_distribution(histogram, std::vector<double>(10, 0.1), 0.01));
    EXPECT_FLOAT_EQ(sampler.pmf(3u), 0.1f);
    EXPECT_EQ(sampler.pmf(10u), 0.0f);
}

TEST(UniformLightSampler, NoLightsGivesNoSample) {
    const restir::UniformLightSampler sampler{0u};
    EXPECT_EQ(sampler.sample(0.5f, 0.5f).pmf, 0.0f);
    EXPECT_EQ(sampler.pmf(0u), 0.0f);
}

TEST(PowerLightSampler, FollowsTheAliasTable) {
    const std::vector<float> power = {1.0f, 0.0f, 3.0f};
    const restir::AliasTable table(power);
    const restir::PowerLightSampler sampler{table.view()};
    EXPECT_EQ(sampler.light_count(), 3u);
    EXPECT_FLOAT_EQ(sampler.pmf(2u), 0.75f);
    for (float u : {0.0f, 0.3f, 0.6f, 0.99f}) {
        const restir::DiscreteSample s = sampler.sample(u, 0.5f);
        EXPECT_NE(s.index, 1u);
        EXPECT_EQ(s.pmf, sampler.pmf(s.index));
    }
}

} // namespace
