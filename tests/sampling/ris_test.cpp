// Unbiasedness of resampled importance sampling: E[f(Y) W] equals the integral of f, checked
// over many independent trials as |mean - truth| < 4 standard errors measured from them.
#include <restir/sampling/ris.hpp>

#include <restir/sampling/alias_table.hpp>
#include <restir/sampling/light_sampler.hpp>

#include "support/discrete_lights.hpp"
#include "support/statistics.hpp"

#include <gtest/gtest.h>

#include <cmath>
#include <cstdint>
#include <vector>

namespace {

using restir::Pcg32;
using restir::SourceSample;
using restir::test::RunningStats;

constexpr int trials = 40'000;

// Integrand on [0, 1] with a closed-form integral, and a target that only approximates it.
double integrand(float x) {
    const auto xd = static_cast<double>(x);
    return 1.0 + xd * xd + 0.5 * std::sin(6.0 * xd);
}
const double integrand_integral = 4.0 / 3.0 + 0.5 * (1.0 - std::cos(6.0)) / 6.0;
float rough_target(float x) { return 1.0f + x * x; }

SourceSample<float> draw_uniform(Pcg32& rng) { return {next_float(rng), 1.0f}; }
// p(x) = 2x by inversion: x = sqrt(u).
SourceSample<float> draw_linear(Pcg32& rng) {
    const float x = std::sqrt(next_float(rng));
    return {x, 2.0f * x};
}

template <class Draw, class Target, class Integrand>
RunningStats run_ris(std::uint32_t candidates, Draw draw, Target target, Integrand f,
                     std::uint64_t seed) {
    RunningStats stats;
    for (std::uint32_t trial = 0; trial < trials; ++trial) {
        Pcg32 rng = restir::make_pixel_rng(trial, 0u, 0u, seed);
        const auto r = restir::resample_ris(rng, candidates, draw, target);
        stats.add(f(r.sample) * static_cast<double>(r.contribution_weight));
    }
    return stats;
}

TEST(Ris, UnbiasedFromAUniformSource) {
    for (std::uint32_t m : {1u, 4u, 32u}) {
        const RunningStats s = run_ris(m, draw_uniform, rough_target, integrand, 100u + m);
        EXPECT_TRUE(restir::test::agrees_with(s, integrand_integral)) << "M = " << m;
    }
}

TEST(Ris, UnbiasedFromANonUniformSource) {
    const RunningStats s = run_ris(8u, draw_linear, rough_target, integrand, 7u);
    EXPECT_TRUE(restir::test::agrees_with(s, integrand_integral));
}

TEST(Ris, MoreCandidatesReduceVarianceWhenTheTargetMatches) {
    // With p-hat proportional to f, f(Y) W tends to the integral as M grows.
    const auto f = [](float x) { return 1.0 + 3.0 * static_cast<double>(x); };
    const auto target = [](float x) { return 1.0f + 3.0f * x; };
    const RunningStats one = run_ris(1u, draw_uniform, target, f, 1u);
    const RunningStats many = run_ris(32u, draw_uniform, target, f, 2u);
    EXPECT_TRUE(restir::test::agrees_with(many, 2.5));
    EXPECT_LT(many.variance(), 0.1 * one.variance());
}

TEST(Ris, UnbiasedOverDiscreteLights) {
    // Sum of 64 light contributions, candidates from the uniform and from a power sampler
    // whose weights only roughly follow the contributions.
    const restir::test::DiscreteLights lights(77u);
    const std::vector<double>& contribution = lights.contribution;
    const double truth = lights.truth;
    const restir::AliasTable table(lights.power);
    const restir::PowerLightSampler by_power{table.view()};
    const restir::UniformLightSampler uniform{64u};
    const auto target = [&](std::uint32_t light) { return lights.target(light); };
    const auto f = [&](std::uint32_t light) { return contribution[light]; };
    const auto from = [](const auto& sampler) {
        return [sampler](Pcg32& rng) {
            const restir::DiscreteSample c = restir::sample_light(sampler, rng);
            return SourceSample<std::uint32_t>{c.index, c.pmf};
        };
    };
    EXPECT_TRUE(restir::test::agrees_with(run_ris(16u, from(uniform), target, f, 3u), truth));
    EXPECT_TRUE(restir::test::agrees_with(run_ris(16u, from(by_power), target, f, 4u), truth));
}

TEST(Ris, SupportCondition) {
    // f(Y) W estimates the integral of f over the support of p-hat, which must lie inside
    // the support of the source pdf. So RIS is unbiased for f exactly when f is zero
    // wherever p-hat is zero.
    const auto half_target = [](float x) { return x < 0.5f ? rough_target(x) : 0.0f; };
    // (a) f vanishes where p-hat does, although the source covers [0, 1]: unbiased.
    const auto half_f = [](float x) { return x < 0.5f ? integrand(x) : 0.0; };
    const double half_integral = 0.5 + 1.0 / 24.0 + 0.5 * (1.0 - std::cos(3.0)) / 6.0;
    EXPECT_TRUE(restir::test::agrees_with(run_ris(8u, draw_uniform, half_target, half_f, 21u),
                                          half_integral));
    // (b) f is non-zero where p-hat is zero: the estimate converges to the integral over
    // x < 0.5 only, and misses the rest. This is the documented failure mode.
    const RunningStats violated = run_ris(8u, draw_uniform, half_target, integrand, 22u);
    EXPECT_TRUE(restir::test::agrees_with(violated, half_integral));
    EXPECT_TRUE(restir::test::differs_from(violated, integrand_integral));
}

// Three techniques over [0, 1]: uniform, linear p(x) = 2x, and uniform on [0, 0.5] only.
auto uniform_strategy(std::uint32_t m) {
    return restir::SourceStrategy{m, [](Pcg32& rng) { return next_float(rng); },
                                  [](float) { return 1.0f; }};
}
auto linear_strategy(std::uint32_t m) {
    return restir::SourceStrategy{m, [](Pcg32& rng) { return std::sqrt(next_float(rng)); },
                                  [](float x) { return 2.0f * x; }};
}
auto left_half_strategy(std::uint32_t m) {
    return restir::SourceStrategy{m, [](Pcg32& rng) { return 0.5f * next_float(rng); },
                                  [](float x) { return x < 0.5f ? 2.0f : 0.0f; }};
}

TEST(RisMis, UnbiasedWithTwoTechniques) {
    RunningStats stats;
    for (std::uint32_t trial = 0; trial < trials; ++trial) {
        Pcg32 rng = restir::make_pixel_rng(trial, 0u, 0u, 31u);
        const auto r =
            restir::resample_ris_mis(rng, rough_target, uniform_strategy(3u), linear_strategy(5u));
        EXPECT_EQ(r.candidate_count, 8u);
        stats.add(integrand(r.sample) * static_cast<double>(r.contribution_weight));
    }
    EXPECT_TRUE(restir::test::agrees_with(stats, integrand_integral));
}

TEST(RisMis, UnbiasedWhenOnlyTheUnionOfTechniquesCoversTheSupport) {
    // The left-half technique misses (0.5, 1] and the linear one has p(0) = 0, yet their
    // union covers [0, 1]; the balance heuristic over both keeps the estimate unbiased.
    RunningStats stats;
    for (std::uint32_t trial = 0; trial < trials; ++trial) {
        Pcg32 rng = restir::make_pixel_rng(trial, 0u, 0u, 32u);
        const auto r = restir::resample_ris_mis(rng, rough_target, left_half_strategy(4u),
                                                linear_strategy(4u));
        stats.add(integrand(r.sample) * static_cast<double>(r.contribution_weight));
    }
    EXPECT_TRUE(restir::test::agrees_with(stats, integrand_integral));
}

TEST(RisMis, TechniquesThatMissPartOfTheSupportAreBiased) {
    // Only the left half is ever sampled: the estimate converges to the integral over
    // [0, 0.5], which shows why some technique must cover the support.
    RunningStats stats;
    for (std::uint32_t trial = 0; trial < trials; ++trial) {
        Pcg32 rng = restir::make_pixel_rng(trial, 0u, 0u, 33u);
        const auto r = restir::resample_ris_mis(rng, rough_target, left_half_strategy(8u));
        stats.add(integrand(r.sample) * static_cast<double>(r.contribution_weight));
    }
    EXPECT_TRUE(restir::test::differs_from(stats, integrand_integral));
    const double half_integral = 0.5 + 1.0 / 24.0 + 0.5 * (1.0 - std::cos(3.0)) / 6.0;
    EXPECT_TRUE(restir::test::agrees_with(stats, half_integral));
}

} // namespace

namespace {

// The reuse passes' two-argument target at a surface selects exactly what the same target bound
// to that surface selects.
struct Height {
    float y = 0.0f;
};
[[maybe_unused]] glm::vec3 surface_position(const Height& h) { return {0.0f, h.y, 0.0f}; }
[[maybe_unused]] glm::vec3 surface_normal(const Height&) { return {0.0f, 1.0f, 0.0f}; }
[[maybe_unused]] float surface_depth(const Height&) { return 1.0f; }
[[maybe_unused]] bool is_valid_surface(const Height&) { return true; }

TEST(Ris, TargetAtASurfaceEqualsTheBoundTarget) {
    const auto target_at = [](float x, const Height& h) { return 1.0f + x * h.y; };
    for (std::uint32_t seed = 0; seed < 100; ++seed) {
        const Height h{0.1f * static_cast<float>(seed)};
        Pcg32 a = restir::make_pixel_rng(seed, 0u, 0u);
        Pcg32 b = a;
        const auto bound =
            restir::resample_ris(a, 8u, draw_uniform, [&](float x) { return target_at(x, h); });
        const auto at_surface = restir::resample_ris(b, 8u, draw_uniform, target_at, h);
        EXPECT_EQ(bound.sample, at_surface.sample);
        EXPECT_EQ(bound.contribution_weight, at_surface.contribution_weight);
        EXPECT_EQ(bound.candidate_count, at_surface.candidate_count);
    }
}

} // namespace
