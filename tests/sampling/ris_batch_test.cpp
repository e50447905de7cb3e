// Batch resampled importance sampling: the candidate it keeps has exactly the distribution of
// streaming RIS, w_i / sum_j w_j (Pearson chi-square), f(Y) W is unbiased (|mean - truth| < 4
// standard errors), groups enter a reservoir with the right count and probability, and the
// structure-of-arrays light tiles give the target values of `unshadowed_irradiance`.
#include <restir/sampling/ris_batch.hpp>

#include <restir/core/reservoir.hpp>
#include <restir/light/irradiance.hpp>
#include <restir/sampling/alias_table.hpp>
#include <restir/sampling/light_sampler.hpp>
#include <restir/sampling/light_tile_arrays.hpp>

#include "support/chi2.hpp"
#include "support/discrete_lights.hpp"
#include "support/statistics.hpp"

#include <gtest/gtest.h>

#include <glm/geometric.hpp>
#include <glm/vec3.hpp>

#include <array>
#include <cmath>
#include <cstddef>
#include <cstdint>
#include <limits>
#include <vector>

namespace {

using restir::CandidateBlock;
using restir::Pcg32;
using restir::test::RunningStats;

constexpr float nan = std::numeric_limits<float>::quiet_NaN();
constexpr float inf = std::numeric_limits<float>::infinity();

// The chi-square tests of this file (three candidate sets, two blocks) share a family-wise
// significance of 1%.
const double alpha = restir::test::sidak_significance(0.01, 5);

// The resampling weight of streaming RIS: target / pdf, or 0 where that is not finite and
// non-negative.
double valid_weight(float target, float inverse_pdf) {
    const float w = target * inverse_pdf;
    return std::isfinite(w) && w > 0.0f ? static_cast<double>(w) : 0.0;
}

// 32 candidates: ordinary ones, and ones of weight 0 (zero target, zero inverse pdf) or of an
// invalid weight (NaN, negative, infinite) that count as weight 0. Entries 29 to 31 have huge
// weights but lie beyond every candidate count used here: they fall in the ignored lanes of a
// partial last block.
struct CandidateSet {
    std::array<float, 32> target{};
    std::array<float, 32> inverse_pdf{};
};

CandidateSet make_candidates() {
    CandidateSet c;
    for (std::uint32_t i = 0; i < 32u; ++i) {
        c.target[i] = 0.25f + 0.5f * static_cast<float>((i * 7u) % 11u);
        c.inverse_pdf[i] = 0.5f + 0.25f * static_cast<float>((i * 5u) % 7u);
    }
    c.target[0] = 0.0f;
    c.inverse_pdf[3] = 0.0f;
    c.target[6] = nan;
    c.target[9] = -1.5f;
    c.inverse_pdf[12] = inf;
    c.target[15] = inf;
    c.target[17] = 0.0f;
    c.target[21] = 1e6f;
    c.inverse_pdf[21] = 0.0f;
    c.inverse_pdf[26] = -2.0f;
    for (std::uint32_t i = 29u; i < 32u; ++i)
        c.target[i] = 1e6f;
    return c;
}

// w_i / sum_j w_j over the first `n` candidates.
std::vector<double> streaming_pmf(const CandidateSet& c, std::uint32_t n, double& weight_sum) {
    std::vector<double> pmf(n);
    weight_sum = 0.0;
    for (std::uint32_t i = 0; i < n; ++i) {
        pmf[i] = valid_weight(c.target[i], c.inverse_pdf[i]);
        weight_sum += pmf[i];
    }
    for (double& p : pmf)
        p /= weight_sum;
    return pmf;
}

// Batch RIS over the first `n` candidates, many times: the kept handle follows w_i / sum w,
// M is n, and W = w_sum / (M p-hat(y)).
template <std::uint32_t BlockSize>
void expect_streaming_distribution(std::uint32_t n, std::uint64_t seed) {
    const CandidateSet c = make_candidates();
    double weight_sum = 0.0;
    const std::vector<double> pmf = streaming_pmf(c, n, weight_sum);
    const std::uint32_t block_count = (n + BlockSize - 1u) / BlockSize;
    std::vector<double> histogram(n, 0.0);
    for (std::uint32_t trial = 0; trial < 100'000u; ++trial) {
        Pcg32 rng = restir::make_pixel_rng(trial, 0u, 0u, seed);
        std::uint32_t calls = 0u;
        const restir::Reservoir<std::uint32_t> r = restir::resample_ris_batch<BlockSize>(
            rng, n, [&](std::uint32_t b, CandidateBlock<BlockSize>& block) -> std::uint32_t {
                ++calls;
                for (std::uint32_t i = 0; i < BlockSize; ++i) {
                    block.target[i] = c.target[b * BlockSize + i];
                    block.inverse_pdf[i] = c.inverse_pdf[b * BlockSize + i];
                }
                return b * BlockSize;
            });
        ASSERT_EQ(calls, block_count);
        ASSERT_EQ(r.candidate_count, n);
        ASSERT_LT(r.sample, n);
        ASSERT_GT(pmf[r.sample], 0.0) << "kept candidate " << r.sample << " of weight 0";
        ASSERT_EQ(r.target_value, c.target[r.sample]);
        ASSERT_NEAR(static_cast<double>(r.weight_sum), weight_sum, 1e-5 * weight_sum);
        const double w = weight_sum / (n * static_cast<double>(c.target[r.sample]));
        ASSERT_NEAR(static_cast<double>(r.contribution_weight), w, 1e-5 * w);
        histogram[r.sample] += 1.0;
    }
    EXPECT_TRUE(restir::test::fits_distribution(histogram, pmf, alpha))
        << "block size " << BlockSize << ", " << n << " candidates";
}

TEST(RisBatch, KeepsCandidatesWithTheStreamingDistribution) {
    expect_streaming_distribution<8>(24u, 1u); // whole blocks
    expect_streaming_distribution<8>(29u, 2u); // a last block of 5 lanes
}

TEST(RisBatch, KeepsCandidatesWithTheStreamingDistributionInBlocksOf16) {
    expect_streaming_distribution<16>(29u, 3u); // a last block of 13 lanes
}

TEST(RisBatch, AllZeroWeightsKeepNothingButCountEveryCandidate) {
    Pcg32 rng = restir::make_pixel_rng(0u, 0u, 0u, 4u);
    const restir::Reservoir<std::uint32_t> r = restir::resample_ris_batch<8>(
        rng, 13u, [](std::uint32_t b, CandidateBlock<8>& block) -> std::uint32_t {
            for (std::uint32_t i = 0; i < 8u; ++i) {
                block.target[i] = i % 2u == 0u ? 0.0f : -1.0f;
                block.inverse_pdf[i] = i % 3u == 0u ? nan : 1.0f;
            }
            return b * 8u;
        });
    EXPECT_EQ(r.candidate_count, 13u);
    EXPECT_EQ(r.weight_sum, 0.0f);
    EXPECT_EQ(r.contribution_weight, 0.0f);
    EXPECT_FALSE(r.has_sample());
}

TEST(RisBatch, BlockWhoseWeightOverflowsTheSumIsDropped) {
    // Two blocks of weight 2e38 each: their sum is not a float, so the second block is dropped
    // (as Reservoir::stream drops such a candidate) and the first one's weight sum stays.
    for (std::uint32_t seed = 0; seed < 64u; ++seed) {
        Pcg32 rng = restir::make_pixel_rng(seed, 0u, 0u, 8u);
        const restir::Reservoir<std::uint32_t> r = restir::resample_ris_batch<8>(
            rng, 16u, [](std::uint32_t b, CandidateBlock<8>& block) -> std::uint32_t {
                for (std::uint32_t i = 0; i < 8u; ++i) {
                    block.target[i] = i == 3u * b ? 1e37f : 0.0f;
                    block.inverse_pdf[i] = 20.0f;
                }
                return b * 8u;
            });
        ASSERT_EQ(r.candidate_count, 16u);
        ASSERT_EQ(r.sample, 0u);
        ASSERT_EQ(r.weight_sum, 2e38f);
        ASSERT_EQ(r.target_value, 1e37f);
        ASSERT_FLOAT_EQ(r.contribution_weight, 1.25f);
    }
}

// Blocks taken from the candidate set: the first holds a zero target (lane 0), a zero inverse
// pdf and a NaN target; the second a negative target, infinite target and inverse pdf, a zero
// target and a zero inverse pdf times a large target.
template <std::uint32_t Size>
CandidateBlock<Size> block_of_candidates(std::uint32_t first) {
    const CandidateSet c = make_candidates();
    CandidateBlock<Size> block;
    for (std::uint32_t i = 0; i < Size; ++i) {
        block.target[i] = c.target[first + i];
        block.inverse_pdf[i] = c.inverse_pdf[first + i];
    }
    return block;
}

template <std::uint32_t Size>
void expect_lanes_follow_weights(const CandidateBlock<Size>& block, std::uint64_t seed) {
    std::vector<double> pmf(Size);
    double total = 0.0;
    float sum = 0.0f; // summed in lane order, as the block is
    for (std::uint32_t i = 0; i < Size; ++i) {
        pmf[i] = valid_weight(block.target[i], block.inverse_pdf[i]);
        total += pmf[i];
        sum += static_cast<float>(pmf[i]);
    }
    for (double& p : pmf)
        p /= total;
    std::vector<double> histogram(Size, 0.0);
    Pcg32 rng = restir::make_pixel_rng(0u, 0u, 0u, seed);
    for (int draw = 0; draw < 200'000; ++draw) {
        const restir::BlockSelection s = restir::select_in_block(block, next_float(rng));
        ASSERT_FLOAT_EQ(s.weight_sum, sum);
        ASSERT_LT(s.lane, Size);
        ASSERT_GT(pmf[s.lane], 0.0) << "chose lane " << s.lane << " of weight 0";
        ASSERT_EQ(s.target, block.target[s.lane]);
        histogram[s.lane] += 1.0;
    }
    EXPECT_TRUE(restir::test::fits_distribution(histogram, pmf, alpha)) << "block of " << Size;
}

TEST(RisBatch, BlockSelectionFollowsTheWeights) {
    expect_lanes_follow_weights(block_of_candidates<8>(0u), 5u);
    expect_lanes_follow_weights(block_of_candidates<16>(8u), 6u);
}

TEST(RisBatch, BlockSelectionInvertsTheCdfExactly) {
    // Weights 0, 6, 0, 10, 0, 8, 8, 0 (S = 32) and u = k / 1024: every threshold u S is exact
    // and many land exactly on a prefix sum. Lane i is chosen for exactly 1024 w_i / S of the
    // u values, and a lane of weight 0 never, whether it comes first, between others or last.
    CandidateBlock<8> block;
    const std::array<float, 8> target = {0.0f, 3.0f, 5.0f, 2.5f, nan, 4.0f, 8.0f, inf};
    const std::array<float, 8> inverse_pdf = {1.0f, 2.0f, 0.0f, 4.0f, 1.0f, 2.0f, 1.0f, 0.0f};
    const std::array<std::uint32_t, 8> expected = {0u, 192u, 0u, 320u, 0u, 256u, 256u, 0u};
    for (std::uint32_t i = 0; i < 8u; ++i) {
        block.target[i] = target[i];
        block.inverse_pdf[i] = inverse_pdf[i];
    }
    std::array<std::uint32_t, 8> chosen{};
    for (std::uint32_t k = 0; k < 1024u; ++k) {
        const restir::BlockSelection s =
            restir::select_in_block(block, static_cast<float>(k) * 0x1p-10f);
        ASSERT_LT(s.lane, 8u);
        EXPECT_EQ(s.weight_sum, 32.0f);
        ++chosen[s.lane];
    }
    for (std::uint32_t i = 0; i < 8u; ++i)
        EXPECT_EQ(chosen[i], expected[i]) << "lane " << i;
}

constexpr std::uint32_t trials = 40'000u;

// Integrand on [0, 1] with a closed-form integral, and a target that only approximates it.
double integrand(float x) {
    const auto xd = static_cast<double>(x);
    return 1.0 + xd * xd + 0.5 * std::sin(6.0 * xd);
}
const double integrand_integral = 4.0 / 3.0 + 0.5 * (1.0 - std::cos(6.0)) / 6.0;
float rough_target(float x) { return 1.0f + x * x; }

TEST(RisBatch, UnbiasedFromAUniformSource) {
    for (std::uint32_t m : {1u, 5u, 13u, 32u}) {
        RunningStats stats;
        for (std::uint32_t trial = 0; trial < trials; ++trial) {
            Pcg32 rng = restir::make_pixel_rng(trial, 0u, 0u, 100u + m);
            Pcg32 source = restir::make_pixel_rng(trial, 0u, 1u, 100u + m);
            std::array<float, 32> x{};
            const restir::Reservoir<std::uint32_t> r = restir::resample_ris_batch<8>(
                rng, m, [&](std::uint32_t b, CandidateBlock<8>& block) -> std::uint32_t {
                    for (std::uint32_t i = 0; i < 8u; ++i) {
                        x[b * 8u + i] = next_float(source);
                        block.target[i] = rough_target(x[b * 8u + i]);
                        block.inverse_pdf[i] = 1.0f;
                    }
                    return b * 8u;
                });
            ASSERT_EQ(r.candidate_count, m);
            ASSERT_LT(r.sample, m);
            stats.add(integrand(x[r.sample]) * static_cast<double>(r.contribution_weight));
        }
        EXPECT_TRUE(restir::test::agrees_with(stats, integrand_integral)) << "M = " << m;
    }
}

TEST(RisBatch, UnbiasedOverDiscreteLights) {
    // Sum of 64 light contributions, candidates from a power sampler whose weights only
    // roughly follow the contributions, kept with a target that follows them less still.
    const restir::test::DiscreteLights lights(77u);
    const std::vector<double>& contribution = lights.contribution;
    const double truth = lights.truth;
    const restir::AliasTable table(lights.power);
    const restir::PowerLightSampler by_power{table.view()};
    const auto target = [&](std::uint32_t light) { return lights.target(light); };
    for (std::uint32_t m : {8u, 13u, 32u}) {
        RunningStats stats;
        for (std::uint32_t trial = 0; trial < trials; ++trial) {
            Pcg32 rng = restir::make_pixel_rng(trial, 0u, 0u, 200u + m);
            Pcg32 source = restir::make_pixel_rng(trial, 0u, 1u, 200u + m);
            std::array<std::uint32_t, 32> drawn{}; // light of each candidate, by handle
            const restir::Reservoir<std::uint32_t> r = restir::resample_ris_batch<8>(
                rng, m, [&](std::uint32_t b, CandidateBlock<8>& block) -> std::uint32_t {
                    for (std::uint32_t i = 0; i < 8u; ++i) {
                        const restir::DiscreteSample c = restir::sample_light(by_power, source);
                        drawn[b * 8u + i] = c.index;
                        block.target[i] = target(c.index);
                        block.inverse_pdf[i] = c.pmf > 0.0f ? 1.0f / c.pmf : 0.0f;
                    }
                    return b * 8u;
                });
            ASSERT_EQ(r.candidate_count, m);
            ASSERT_LT(r.sample, m);
            stats.add(contribution[drawn[r.sample]] * static_cast<double>(r.contribution_weight));
        }
        EXPECT_TRUE(restir::test::agrees_with(stats, truth)) << "M = " << m;
    }
}

// A presampled area light (one-sided, area density `area_pdf`).
restir::PresampledLight area_light(std::uint32_t id, float pdf, glm::vec3 position,
                                   glm::vec3 normal, glm::vec3 radiance, float area_pdf) {
    restir::PresampledLight e;
    e.reference = {id, glm::vec2(0.25f, 0.75f)};
    e.pdf = pdf;
    e.point.position = position;
    e.point.normal = normal;
    e.point.radiance = radiance;
    e.point.area_pdf = area_pdf;
    e.point.is_delta = false;
    return e;
}

// A presampled delta light: a VPL (oriented `normal`) or an isotropic point light (zero
// normal).
restir::PresampledLight delta_light(std::uint32_t id, float pdf, glm::vec3 position,
                                    glm::vec3 normal, glm::vec3 intensity) {
    restir::PresampledLight e = area_light(id, pdf, position, normal, intensity, 1.0f);
    e.point.is_delta = true;
    return e;
}

// 24 entries cycling through area lights, VPLs and isotropic point lights at pseudo-random
// places above and below y = 2, facing every way; entry 5 has source pdf 0, entry 10 is an
// area light of area density 0.
std::vector<restir::PresampledLight> tile_entries() {
    std::vector<restir::PresampledLight> entries;
    Pcg32 rng = restir::make_pixel_rng(0u, 0u, 0u, 99u);
    const auto uniform = [&](float lo, float hi) { return lo + (hi - lo) * next_float(rng); };
    for (std::uint32_t i = 0; i < 24u; ++i) {
        const glm::vec3 position(uniform(-2.0f, 2.0f), uniform(1.0f, 3.0f), uniform(-2.0f, 2.0f));
        const glm::vec3 normal = glm::normalize(
            glm::vec3(uniform(-1.0f, 1.0f), uniform(-1.0f, 1.0f), uniform(-1.0f, 1.0f)));
        const glm::vec3 radiance(uniform(0.5f, 5.0f), uniform(0.5f, 5.0f), uniform(0.5f, 5.0f));
        const float pdf = i == 5u ? 0.0f : uniform(0.01f, 1.0f);
        switch (i % 3u) {
        case 0u:
            entries.push_back(area_light(i, pdf, position, normal, radiance,
                                         i == 10u       ? 0.0f
                                         : i % 2u == 0u ? 0.25f
                                                        : 2.0f));
            break;
        case 1u:
            entries.push_back(delta_light(i, pdf, position, normal, radiance));
            break;
        default:
            entries.push_back(delta_light(i, pdf, position, glm::vec3(0.0f), radiance));
            break;
        }
    }
    return entries;
}

struct Receiver {
    glm::vec3 position;
    glm::vec3 normal;
};

std::vector<Receiver> receivers(const std::vector<restir::PresampledLight>& entries) {
    return {
        {{0.0f, 0.0f, 0.0f}, {0.0f, 1.0f, 0.0f}},  // below every light, facing them
        {{0.5f, 4.0f, -0.3f}, {0.0f, 1.0f, 0.0f}}, // above every light, facing away from them
        {{0.3f, 4.0f, 0.2f}, {0.0f, -1.0f, 0.0f}}, // above every light, facing them
        {{1.0f, 2.0f, 0.5f}, glm::normalize(glm::vec3(1.0f, 1.0f, -1.0f))},
        {{-0.7f, 1.8f, 0.4f}, glm::normalize(glm::vec3(-0.3f, -1.0f, 0.2f))},
        // Nearer to a VPL than the falloff distance, and at an isotropic light itself.
        {entries[1].point.position + glm::vec3(0.05f, -0.1f, 0.02f), {0.0f, 1.0f, 0.0f}},
        {entries[2].point.position, {0.0f, 1.0f, 0.0f}},
    };
}

TEST(LightTileArrays, BlockTargetsMatchUnshadowedIrradiance) {
    const std::vector<restir::PresampledLight> entries = tile_entries();
    const glm::vec3 channel_weights(0.2f, 0.7f, 0.1f);
    const std::array<restir::Falloff, 3> falloffs = {
        restir::Falloff{restir::FalloffKind::yuksel, 0.3f},
        restir::Falloff{restir::FalloffKind::clamped_inverse_square, 0.3f},
        restir::Falloff{restir::FalloffKind::inverse_square, 0.3f}};
    for (const restir::Falloff& falloff : falloffs) {
        // Tile 1 of three; the other two hold NaN, so reading outside tile 1 shows.
        restir::LightTileArrays tiles{nullptr, nullptr, 3u, 24u};
        std::vector<float> planes(tiles.plane_float_count(), nan);
        std::vector<restir::LightSampleRef> references(3u * 24u);
        tiles.planes = planes.data();
        tiles.references = references.data();
        for (std::uint32_t i = 0; i < 24u; ++i)
            tiles.store(1u, i, entries[i], falloff);
        int zero = 0, positive = 0;
        const auto check = [&](const auto& block, std::uint32_t first, const Receiver& at) {
            for (std::uint32_t i = 0; i < block.size; ++i) {
                const restir::PresampledLight& e = entries[first + i];
                const float target = block.target[i];
                SCOPED_TRACE(::testing::Message()
                             << "entry " << first + i << ", receiver (" << at.position.x << ", "
                             << at.position.y << ", " << at.position.z << "), falloff kind "
                             << static_cast<int>(falloff.kind));
                if (!(e.pdf > 0.0f)) {
                    EXPECT_EQ(block.inverse_pdf[i], 0.0f);
                    EXPECT_TRUE(std::isfinite(target) && target >= 0.0f);
                    continue;
                }
                EXPECT_FLOAT_EQ(block.inverse_pdf[i], 1.0f / e.pdf);
                const auto expected = static_cast<double>(
                    glm::dot(channel_weights, restir::unshadowed_irradiance(e.point, at.position,
                                                                            at.normal, falloff)));
                EXPECT_NEAR(static_cast<double>(target), expected,
                            1e-5 * std::abs(expected) + 1e-7);
                if (expected == 0.0 && target == 0.0f)
                    ++zero;
                else if (expected > 0.0 && target > 0.0f)
                    ++positive;
            }
        };
        for (const Receiver& at : receivers(entries)) {
            for (std::uint32_t first : {0u, 8u, 16u}) {
                CandidateBlock<8> block;
                EXPECT_EQ(restir::evaluate_tile_block(tiles, 1u, first, at.position, at.normal,
                                                      channel_weights, block),
                          24u + first);
                check(block, first, at);
            }
            CandidateBlock<16> wide;
            EXPECT_EQ(restir::evaluate_tile_block(tiles, 1u, 8u, at.position, at.normal,
                                                  channel_weights, wide),
                      32u);
            check(wide, 8u, at);
            // Parts of a group (4, 2 or 1 of its 8 entries): the whole group's lanes, exactly.
            CandidateBlock<8> whole;
            restir::evaluate_tile_block(tiles, 1u, 16u, at.position, at.normal, channel_weights,
                                        whole);
            const auto check_parts = [&]<std::uint32_t Lanes>() {
                for (std::uint32_t lane = 0; lane < 8u; lane += Lanes) {
                    CandidateBlock<Lanes> part;
                    EXPECT_EQ(restir::evaluate_tile_block(tiles, 1u, 16u + lane, at.position,
                                                          at.normal, channel_weights, part),
                              40u + lane);
                    for (std::uint32_t k = 0; k < Lanes; ++k) {
                        EXPECT_EQ(part.target[k], whole.target[lane + k]) << Lanes << " " << lane;
                        EXPECT_EQ(part.inverse_pdf[k], whole.inverse_pdf[lane + k]);
                    }
                    check(part, 16u + lane, at);
                }
            };
            check_parts.template operator()<4u>();
            check_parts.template operator()<2u>();
            check_parts.template operator()<1u>();
        }
        // The receivers see lights from the front and from behind, and lights facing away.
        EXPECT_GT(zero, 40);
        EXPECT_GT(positive, 40);
        // The Euclidean fold: |channel_weights * E| per entry.
        for (const Receiver& at : receivers(entries)) {
            CandidateBlock<8> block;
            restir::evaluate_tile_block<8, restir::ChannelNorm::euclidean>(
                tiles, 1u, 8u, at.position, at.normal, channel_weights, block);
            for (std::uint32_t i = 0; i < block.size; ++i) {
                const restir::PresampledLight& e = entries[8u + i];
                if (!(e.pdf > 0.0f))
                    continue;
                const glm::vec3 f = channel_weights * restir::unshadowed_irradiance(
                                                          e.point, at.position, at.normal, falloff);
                const double expected = std::sqrt(static_cast<double>(glm::dot(f, f)));
                EXPECT_NEAR(static_cast<double>(block.target[i]), expected, 1e-5 * expected + 1e-7);
            }
        }
    }
}

TEST(ReservoirStreamGroup, CountsEveryCandidateOfTheGroup) {
    restir::Reservoir<std::uint32_t> r;
    EXPECT_TRUE(r.stream_group(7u, 2.0f, 0.5f, 8u, 0.9f)); // the first weighted group is kept
    EXPECT_EQ(r.candidate_count, 8u);
    EXPECT_EQ(r.sample, 7u);
    EXPECT_EQ(r.target_value, 0.5f);
    EXPECT_EQ(r.weight_sum, 2.0f);
    // Groups of weight 0 or of an invalid weight count, but are never kept.
    EXPECT_FALSE(r.stream_group(9u, 0.0f, 1.0f, 5u, 0.0f));
    EXPECT_FALSE(r.stream_group(9u, nan, 1.0f, 3u, 0.0f));
    EXPECT_FALSE(r.stream_group(9u, inf, 1.0f, 2u, 0.0f));
    EXPECT_FALSE(r.stream_group(9u, -4.0f, 1.0f, 1u, 0.0f));
    EXPECT_EQ(r.candidate_count, 19u);
    EXPECT_EQ(r.weight_sum, 2.0f);
    EXPECT_EQ(r.sample, 7u);
    // Weight 6 after 2: kept for u < 6 / 8.
    EXPECT_FALSE(r.stream_group(11u, 6.0f, 3.0f, 13u, 0.75f));
    EXPECT_EQ(r.candidate_count, 32u);
    EXPECT_EQ(r.weight_sum, 8.0f);
    EXPECT_EQ(r.sample, 7u);
    r.finalize();
    EXPECT_EQ(r.contribution_weight, 8.0f / (32.0f * 0.5f));
}

TEST(ReservoirStreamGroup, CountsAsManyAsStreamingTheGroupOneByOne) {
    restir::Reservoir<std::uint32_t> grouped, streamed;
    const std::array<float, 5> weights = {1.0f, 0.0f, 2.5f, nan, 0.5f};
    float group_sum = 0.0f;
    for (std::uint32_t i = 0; i < 5u; ++i) {
        streamed.stream(i, weights[i], 1.0f, 0.5f);
        group_sum += restir::is_valid_weight(weights[i]) ? weights[i] : 0.0f;
    }
    grouped.stream_group(2u, group_sum, 1.0f, 5u, 0.5f);
    EXPECT_EQ(grouped.candidate_count, streamed.candidate_count);
    EXPECT_EQ(grouped.weight_sum, streamed.weight_sum);
}

// Offers a group of weight `weight` to copies of a reservoir whose weight sum is `before`,
// once for each of `n` evenly spaced u in [0, 1), and counts how often it is kept.
std::uint32_t times_kept(float before, float weight, std::uint32_t n) {
    restir::Reservoir<std::uint32_t> base;
    base.stream_group(1u, before, 1.0f, 4u, 0.0f);
    std::uint32_t kept = 0u;
    for (std::uint32_t k = 0; k < n; ++k) {
        restir::Reservoir<std::uint32_t> r = base;
        const float u = static_cast<float>(k) / static_cast<float>(n);
        const bool selected = r.stream_group(2u, weight, 2.0f, 4u, u);
        EXPECT_EQ(r.candidate_count, 8u);
        EXPECT_EQ(r.sample, selected ? 2u : 1u);
        EXPECT_EQ(r.target_value, selected ? 2.0f : 1.0f);
        kept += selected ? 1u : 0u;
    }
    return kept;
}

TEST(ReservoirStreamGroup, KeepsTheGroupWithProbabilityWeightOverSum) {
    // With n evenly spaced u, the group is kept for the u below weight / w_sum: exactly
    // n weight / w_sum of them when that is a whole number, and within one otherwise.
    EXPECT_EQ(times_kept(5.0f, 3.0f, 1024u), 384u);
    EXPECT_EQ(times_kept(1.0f, 15.0f, 1024u), 960u);
    EXPECT_EQ(times_kept(0.75f, 0.25f, 1024u), 256u);
    EXPECT_NEAR(static_cast<double>(times_kept(2.3f, 0.7f, 1000u)), 1000.0 * 0.7 / 3.0, 1.0);
    EXPECT_NEAR(static_cast<double>(times_kept(0.1f, 9.9f, 1000u)), 990.0, 1.0);
}

} // namespace
