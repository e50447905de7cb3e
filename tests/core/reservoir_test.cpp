#include <restir/core/reservoir.hpp>
#include <restir/core/rng.hpp>

#include "support/chi2.hpp"

#include <gtest/gtest.h>

#include <cstdint>
#include <limits>
#include <type_traits>
#include <vector>

namespace {

using restir::Pcg32;
using Reservoir = restir::Reservoir<std::uint32_t>;

constexpr float nan = std::numeric_limits<float>::quiet_NaN();
constexpr float inf = std::numeric_limits<float>::infinity();

// Three chi-square tests in this file share a family-wise significance of 1%.
const double alpha = restir::test::sidak_significance(0.01, 3);

std::vector<double> normalized(const std::vector<float>& weights) {
    double total = 0.0;
    for (float w : weights)
        total += static_cast<double>(w);
    std::vector<double> pmf;
    for (float w : weights)
        pmf.push_back(static_cast<double>(w) / total);
    return pmf;
}

// Hostile inputs: a negative or NaN target never gives a negative or NaN W, and M saturates
// instead of wrapping around (1 + 3e9 + 3e9 used to give 1,705,032,705).
TEST(Reservoir, BadTargetsAndHugeCountsStaySane) {
    const float not_a_number = std::numeric_limits<float>::quiet_NaN();
    for (float target : {-1.0f, not_a_number, std::numeric_limits<float>::infinity()}) {
        restir::Reservoir<std::uint32_t> r;
        EXPECT_TRUE(r.stream(1u, 1.0f, target, 0.0f));
        r.finalize();
        EXPECT_TRUE(r.is_well_formed()) << target;
        EXPECT_EQ(r.contribution_weight, 0.0f) << target;
        EXPECT_FALSE(r.has_sample()) << target;
        restir::Reservoir<std::uint32_t> merged;
        // A good reservoir merged with a bad target at the receiver stays well formed.
        restir::Reservoir<std::uint32_t> good;
        good.stream(2u, 1.0f, 1.0f, 0.0f);
        good.finalize();
        merged.merge_with_mis(good, target, 1.0f, 0.0f);
        merged.finalize_normalized();
        EXPECT_TRUE(merged.is_well_formed()) << target;
    }
    restir::Reservoir<std::uint32_t> r;
    r.stream(1u, 1.0f, 1.0f, 0.0f);
    r.stream_group(2u, 1.0f, 1.0f, 3'000'000'000u, 0.5f);
    r.stream_group(3u, 1.0f, 1.0f, 3'000'000'000u, 0.5f);
    EXPECT_EQ(r.candidate_count, 0xffffffffu);
}

TEST(Reservoir, IsTriviallyCopyable) {
    static_assert(std::is_trivially_copyable_v<Reservoir>);
    static_assert(std::is_trivially_copyable_v<restir::Reservoir<float>>);
}

TEST(Reservoir, StreamingSelectsProportionallyToWeight) {
    // Alg. 2: candidate i is kept with probability w_i / sum w, zero weights never.
    const std::vector<float> weights = {1.0f, 0.0f, 3.0f, 0.5f, 10.0f, 2.0f, 0.25f, 7.0f};
    std::vector<double> histogram(weights.size(), 0.0);
    Pcg32 rng = restir::make_pixel_rng(0u, 0u, 0u, 1u);
    for (int trial = 0; trial < 200'000; ++trial) {
        Reservoir r;
        for (std::uint32_t i = 0; i < weights.size(); ++i)
            r.stream(i, weights[i], weights[i], next_float(rng));
        ASSERT_TRUE(r.has_sample());
        histogram[r.sample] += 1.0;
    }
    EXPECT_EQ(histogram[1], 0.0);
    EXPECT_TRUE(restir::test::fits_distribution(histogram, normalized(weights), alpha));
}

TEST(Reservoir, MergingFinalisedReservoirsKeepsTheJointDistribution) {
    // Alg. 4: with the same target at the receiver, merging reservoirs built from disjoint
    // candidate sets of different sizes selects like streaming all candidates into one
    // reservoir (the merge weight p-hat * W * M equals the source's weight sum).
    const std::vector<float> weights = {2.0f, 1.0f, 4.0f,                    // reservoir a
                                        0.5f, 3.0f, 1.0f, 6.0f, 0.25f, 2.0f, // reservoir b
                                        5.0f};                               // reservoir c
    const std::uint32_t ranges[][2] = {{0u, 3u}, {3u, 9u}, {9u, 10u}};
    std::vector<double> histogram(weights.size(), 0.0);
    Pcg32 rng = restir::make_pixel_rng(0u, 0u, 0u, 2u);
    for (int trial = 0; trial < 200'000; ++trial) {
        Reservoir merged;
        for (const auto& range : ranges) {
            Reservoir part;
            for (std::uint32_t i = range[0]; i < range[1]; ++i)
                part.stream(i, weights[i], weights[i], next_float(rng));
            part.finalize();
            merged.merge(part, weights[part.sample], next_float(rng));
        }
        merged.finalize();
        ASSERT_EQ(merged.candidate_count, 10u);
        histogram[merged.sample] += 1.0;
    }
    EXPECT_TRUE(restir::test::fits_distribution(histogram, normalized(weights), alpha));
}

TEST(Reservoir, MergingWithMisWeightsSelectsProportionallyToTheirProduct) {
    // Resampling weight m_i * p-hat(y_i) * W_i: with one-candidate inputs of known W the
    // selection must follow m_i * p-hat_i * W_i.
    const std::vector<float> mis = {0.5f, 0.25f, 0.25f};
    const std::vector<float> target = {1.0f, 4.0f, 2.0f};
    const std::vector<float> contribution = {2.0f, 1.0f, 3.0f};
    std::vector<float> expected_weights;
    for (std::size_t i = 0; i < mis.size(); ++i)
        expected_weights.push_back(mis[i] * target[i] * contribution[i]);
    std::vector<double> histogram(mis.size(), 0.0);
    Pcg32 rng = restir::make_pixel_rng(0u, 0u, 0u, 3u);
    for (int trial = 0; trial < 100'000; ++trial) {
        Reservoir merged;
        for (std::uint32_t i = 0; i < mis.size(); ++i) {
            Reservoir input;
            input.sample = i;
            input.contribution_weight = contribution[i];
            input.candidate_count = 1u;
            merged.merge_with_mis(input, target[i], mis[i], next_float(rng));
        }
        histogram[merged.sample] += 1.0;
    }
    EXPECT_TRUE(restir::test::fits_distribution(histogram, normalized(expected_weights), alpha));
}

TEST(Reservoir, FinalizeComputesEquationSix) {
    Reservoir r;
    r.stream(5u, 2.0f, 4.0f, 0.0f); // selected: u * w_sum < w
    r.stream(6u, 6.0f, 3.0f, 0.9f); // not selected: 0.9 * 8 >= 6
    r.stream(7u, 0.0f, 0.0f, 0.0f); // zero weight: counted, never kept
    r.finalize();
    EXPECT_EQ(r.sample, 5u);
    EXPECT_EQ(r.candidate_count, 3u);
    EXPECT_FLOAT_EQ(r.weight_sum, 8.0f);
    EXPECT_FLOAT_EQ(r.target_value, 4.0f);
    EXPECT_FLOAT_EQ(r.contribution_weight, 8.0f / (3.0f * 4.0f)); // W = w_sum / (M p-hat)

    r.finalize_normalized(0.5f);
    EXPECT_FLOAT_EQ(r.contribution_weight, 0.5f * 8.0f / 4.0f); // W = w_sum / (Z p-hat)
}

TEST(Reservoir, EmptyReservoirFinalisesToZero) {
    Reservoir r;
    r.finalize();
    EXPECT_EQ(r.contribution_weight, 0.0f);
    EXPECT_FALSE(r.has_sample());
    r.stream(1u, 0.0f, 0.0f, 0.5f);
    r.finalize();
    EXPECT_EQ(r.contribution_weight, 0.0f);
    EXPECT_EQ(r.candidate_count, 1u);
    EXPECT_FALSE(r.has_sample());
}

TEST(Reservoir, InvalidWeightsAreCountedButNeverKept) {
    Reservoir r;
    r.stream(1u, 2.0f, 2.0f, 0.5f);
    for (float bad : {nan, inf, -inf, -1.0f}) {
        EXPECT_FALSE(r.stream(9u, bad, 1.0f, 0.0f)) << bad;
        EXPECT_TRUE(r.is_well_formed()) << bad;
    }
    EXPECT_EQ(r.sample, 1u);
    EXPECT_EQ(r.candidate_count, 5u);
    EXPECT_FLOAT_EQ(r.weight_sum, 2.0f);
    // The reservoir still works after rejecting them.
    EXPECT_TRUE(r.stream(3u, 2.0f, 2.0f, 0.25f));
    EXPECT_EQ(r.sample, 3u);
}

TEST(Reservoir, AWeightThatWouldOverflowTheSumIsRejected) {
    Reservoir r;
    const float huge = std::numeric_limits<float>::max();
    EXPECT_TRUE(r.stream(1u, huge, 1.0f, 0.5f));
    EXPECT_FALSE(r.stream(2u, huge, 1.0f, 0.0f));
    EXPECT_TRUE(restir::is_finite(r.weight_sum));
    EXPECT_EQ(r.sample, 1u);
}

TEST(Reservoir, MergeIgnoresNonFiniteReservoirs) {
    Reservoir r;
    r.stream(1u, 1.0f, 1.0f, 0.5f);
    r.finalize();
    Reservoir poisoned = r;
    poisoned.contribution_weight = nan;
    poisoned.candidate_count = 7u;
    EXPECT_FALSE(r.merge(poisoned, 1.0f, 0.0f));
    poisoned.contribution_weight = 1.0f;
    poisoned.weight_sum = inf;
    EXPECT_FALSE(r.merge(poisoned, 1.0f, 0.0f));
    EXPECT_FALSE(r.merge_with_mis(poisoned, 1.0f, 1.0f, 0.0f));
    EXPECT_EQ(r.candidate_count, 1u);
    EXPECT_TRUE(r.is_well_formed());
    // A NaN target at the receiver is an invalid weight: counted, not kept.
    Reservoir fine = r;
    EXPECT_FALSE(r.merge(fine, nan, 0.0f));
    EXPECT_EQ(r.candidate_count, 2u);
    EXPECT_TRUE(r.is_well_formed());
}

TEST(Reservoir, CapLimitsTheCandidateCountAndKeepsW) {
    Reservoir r;
    for (std::uint32_t i = 0; i < 100u; ++i)
        r.stream(i, 1.0f + static_cast<float>(i % 3u), 2.0f, 0.5f);
    r.finalize();
    const float w_before = r.contribution_weight;
    r.cap_candidate_count(20u);
    EXPECT_EQ(r.candidate_count, 20u);
    r.finalize();
    EXPECT_FLOAT_EQ(r.contribution_weight, w_before);
    // The capped reservoir's share in a merge shrinks by M_cap / M.
    Reservoir receiver;
    receiver.merge(r, r.target_value, 0.5f);
    EXPECT_FLOAT_EQ(receiver.weight_sum, r.target_value * w_before * 20.0f);
    // A cap above M changes nothing.
    r.cap_candidate_count(1000u);
    EXPECT_EQ(r.candidate_count, 20u);
}

TEST(Reservoir, SanitizeResetsCorruptedState) {
    Reservoir r;
    r.stream(4u, 1.0f, 1.0f, 0.5f);
    r.finalize();
    EXPECT_FALSE(r.sanitize());
    EXPECT_EQ(r.sample, 4u);
    r.contribution_weight = inf;
    EXPECT_TRUE(r.sanitize());
    EXPECT_EQ(r.candidate_count, 0u);
    EXPECT_EQ(r.contribution_weight, 0.0f);
    r.target_value = -1.0f;
    EXPECT_TRUE(r.sanitize());
}

TEST(Reservoir, LazyStreamBuildsOnlyKeptSamples) {
    Reservoir r;
    int built = 0;
    const auto make = [&built] {
        ++built;
        return 42u;
    };
    EXPECT_TRUE(r.stream_lazy(1.0f, 1.0f, 0.3f, make));  // first candidate: always kept
    EXPECT_FALSE(r.stream_lazy(1.0f, 1.0f, 0.9f, make)); // 0.9 * 2 >= 1: rejected
    EXPECT_FALSE(r.stream_lazy(nan, 1.0f, 0.0f, make));  // invalid: rejected
    EXPECT_EQ(built, 1);
    EXPECT_EQ(r.sample, 42u);
    EXPECT_EQ(r.candidate_count, 3u);
}

} // namespace
