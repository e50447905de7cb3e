#include <restir/sampling/alias_table.hpp>

#include <restir/core/rng.hpp>

#include "support/chi2.hpp"

#include <gtest/gtest.h>

#include <cmath>
#include <cstdint>
#include <limits>
#include <stdexcept>
#include <string>
#include <vector>

namespace {

using restir::AliasTable;

// Two chi-square tests in this file share a family-wise significance of 1%.
const double alpha = restir::test::sidak_significance(0.01, 2);

std::vector<double> histogram_of(const AliasTable& table, int draws, std::uint64_t seed) {
    std::vector<double> histogram(table.size(), 0.0);
    restir::Pcg32 rng = restir::make_pixel_rng(0u, 0u, 0u, seed);
    for (int i = 0; i < draws; ++i) {
        const float u_bucket = next_float(rng);
        const restir::DiscreteSample s = table.sample(u_bucket, next_float(rng));
        histogram[s.index] += 1.0;
        EXPECT_EQ(s.pmf, table.pmf(s.index));
    }
    return histogram;
}

std::vector<double> pmf_of(const AliasTable& table) {
    std::vector<double> pmf;
    for (std::uint32_t i = 0; i < table.size(); ++i)
        pmf.push_back(static_cast<double>(table.pmf(i)));
    return pmf;
}

TEST(AliasTable, SamplesProportionallyToWeights) {
    const std::vector<float> weights = {0.1f, 5.0f, 0.0f, 1.0f, 1.0f, 20.0f, 0.0f, 3.5f, 0.01f};
    const AliasTable table(weights);
    const std::vector<double> histogram = histogram_of(table, 500'000, 11u);
    EXPECT_EQ(histogram[2], 0.0);
    EXPECT_EQ(histogram[6], 0.0);
    EXPECT_TRUE(restir::test::fits_distribution(histogram, pmf_of(table), alpha));
}

TEST(AliasTable, SamplesManyWeightsSpanningDecades) {
    // 1000 weights from 1e-3 to 1e3: exercises long chains of alias moves.
    std::vector<float> weights(1000);
    restir::Pcg32 rng = restir::make_pixel_rng(0u, 0u, 0u, 5u);
    for (float& w : weights)
        w = std::pow(10.0f, 6.0f * next_float(rng) - 3.0f);
    const AliasTable table(weights);
    EXPECT_TRUE(
        restir::test::fits_distribution(histogram_of(table, 2'000'000, 12u), pmf_of(table), alpha));
}

TEST(AliasTable, PmfIsTheNormalisedWeight) {
    const std::vector<float> weights = {1.0f, 3.0f, 0.0f, 4.0f};
    const AliasTable table(weights);
    EXPECT_FLOAT_EQ(table.pmf(0), 0.125f);
    EXPECT_FLOAT_EQ(table.pmf(1), 0.375f);
    EXPECT_EQ(table.pmf(2), 0.0f);
    EXPECT_FLOAT_EQ(table.pmf(3), 0.5f);
    EXPECT_EQ(table.pmf(4), 0.0f); // outside the table
    double total = 0.0;
    for (const restir::AliasEntry& e : table.entries())
        total += static_cast<double>(e.pmf);
    EXPECT_NEAR(total, 1.0, 1e-6);
}

TEST(AliasTable, SingleWeightAlwaysReturnsIt) {
    const std::vector<float> weights = {0.3f};
    const AliasTable table(weights);
    for (float u : {0.0f, 0.5f, 0x1.fffffep-1f}) {
        const restir::DiscreteSample s = table.sample(u, u);
        EXPECT_EQ(s.index, 0u);
        EXPECT_EQ(s.pmf, 1.0f);
    }
}

TEST(AliasTable, EmptyViewReturnsNoSample) {
    const restir::AliasTableView empty;
    EXPECT_EQ(empty.sample(0.5f, 0.5f).pmf, 0.0f);
    EXPECT_EQ(empty.pmf(0), 0.0f);
    EXPECT_TRUE(AliasTable{}.empty());
}

void expect_rejected(const std::vector<float>& weights, const std::string& reason) {
    try {
        const AliasTable table(weights);
        ADD_FAILURE() << "accepted weights that should be rejected (" << reason << ")";
    } catch (const std::invalid_argument& error) {
        EXPECT_NE(std::string(error.what()).find(reason), std::string::npos) << error.what();
    }
}

TEST(AliasTable, RejectsBadWeightsWithAClearError) {
    expect_rejected({}, "empty");
    expect_rejected({0.0f, 0.0f, 0.0f}, "all weights are zero");
    expect_rejected({1.0f, -2.0f}, "weight 1 is negative or not finite");
    expect_rejected({std::numeric_limits<float>::quiet_NaN()}, "weight 0");
    expect_rejected({1.0f, 2.0f, std::numeric_limits<float>::infinity()}, "weight 2");
}

} // namespace
