// Distant lights beside a light BVH, a power sampler and a light grid
// (sampling/infinite_lights.hpp). For one and two distant lights placed at the start, middle and
// end of the id space, these tests check five things. The mixture's pmf sums to P plus 1 - P
// times the local sampler's sum, which is 1 where the BVH's is. Draws follow the pmf
// (chi-square). A draw's pmf is `pmf(at, id)`. P = 0 gives the local sampler's draws bit for
// bit. Grid tiles with distant entries are unbiased, and each entry is a distant light with
// probability P.
#include "restir/sampling/infinite_lights.hpp"

#include "restir/core/rng.hpp"
#include "restir/light/light_bvh.hpp"
#include "restir/sampling/alias_table.hpp"
#include "restir/sampling/light_grid.hpp"
#include "restir/sampling/light_sampler.hpp"

#include "support/chi2.hpp"
#include "support/statistics.hpp"

#include <glm/geometric.hpp>
#include <gtest/gtest.h>

#include <algorithm>
#include <bit>
#include <cmath>
#include <cstdint>
#include <limits>
#include <vector>

namespace {

using restir::DiscreteSample;
using restir::LightBounds;
using restir::ShadingPoint;

constexpr std::uint32_t local_count = 300u;

glm::vec3 random_direction(restir::Pcg32& rng) {
    const float z = 2.0f * next_float(rng) - 1.0f;
    const float phi = 6.2831853f * next_float(rng);
    const float r = std::sqrt(std::max(0.0f, 1.0f - z * z));
    return {r * std::cos(phi), r * std::sin(phi), z};
}

// `count` local lights in [0, 10]^3, powers over three decades. Mixed: a third each small area
// lights, cosine points and isotropic points, facing random directions. Otherwise all
// isotropic points, whose BVH bounds are positive everywhere: the BVH's pmf then sums to 1 at
// points without a normal.
std::vector<LightBounds> local_lights(std::uint32_t count, bool mixed, std::uint64_t seed) {
    restir::Pcg32 rng = restir::make_pixel_rng(0u, 0u, 0u, seed);
    std::vector<LightBounds> lights;
    for (std::uint32_t i = 0; i < count; ++i) {
        const glm::vec3 p = 10.0f * glm::vec3(next_float(rng), next_float(rng), next_float(rng));
        const glm::vec3 n = random_direction(rng);
        const float power = std::exp(6.9f * (next_float(rng) - 0.5f));
        if (mixed && i % 3u == 0u)
            lights.push_back(
                restir::area_light_bounds(p - glm::vec3(0.1f), p + glm::vec3(0.1f), n, power));
        else
            lights.push_back(
                restir::point_light_bounds(p, mixed && i % 3u == 1u ? n : glm::vec3(0.0f), power));
    }
    return lights;
}

ShadingPoint random_point(restir::Pcg32& rng, bool with_normal) {
    const glm::vec3 p(next_float(rng), next_float(rng), next_float(rng));
    const glm::vec3 n = random_direction(rng);
    return {-2.0f + 14.0f * p, with_normal ? n : glm::vec3(0.0f)};
}

// Where the distant lights sit in the application's ids: count 1 and 2, at the start, the
// middle and the end.
struct Placement {
    std::uint32_t first, count;
};
const Placement placements[] = {{0u, 1u}, {local_count / 2u, 1u}, {local_count, 1u},
                                {0u, 2u}, {local_count / 2u, 2u}, {local_count, 2u}};

// A light BVH over the local lights, which lives as long as the test.
struct Bvh {
    std::vector<LightBounds> bounds;
    restir::LightBvh bvh;
    explicit Bvh(bool mixed) : bounds(local_lights(local_count, mixed, 11u)), bvh(bounds) {}
};

// The sum over every id of the mixture's pmf at `at` (in double, over float pmfs).
template <class Sampler>
double pmf_sum(const Sampler& s, const ShadingPoint& at) {
    double sum = 0.0;
    for (std::uint32_t id = 0; id < s.light_count(); ++id)
        sum += static_cast<double>(s.pmf(at, id));
    return sum;
}

// Where the BVH's pmf sums to one (isotropic points, no receiver normal), so does the mixture's;
// elsewhere the mixture's sum is P + (1 - P) times the BVH's, the rest being "no light". Ids past
// the end have pmf 0.
TEST(DistantLights, PmfSumsToOne) {
    const Bvh isotropic(false), mixed(true);
    restir::Pcg32 rng = restir::make_pixel_rng(1u, 0u, 0u, 3u);
    for (const Placement& place : placements) {
        for (const float p : {0.3f, restir::distant_light_probability(2.0f, 7.0f), 1.0f}) {
            const auto iso =
                restir::with_distant_lights(isotropic.bvh.view(), place.first, place.count, p);
            const auto mix =
                restir::with_distant_lights(mixed.bvh.view(), place.first, place.count, p);
            ASSERT_EQ(iso.light_count(), local_count + place.count);
            for (int k = 0; k < 8; ++k) {
                const ShadingPoint at = random_point(rng, false);
                EXPECT_NEAR(pmf_sum(iso, at), 1.0, 1e-5) << "first " << place.first;
                const ShadingPoint lit = random_point(rng, true);
                double local_sum = 0.0;
                for (std::uint32_t id = 0; id < local_count; ++id)
                    local_sum += static_cast<double>(mixed.bvh.view().pmf(lit, id));
                const auto share = static_cast<double>(p);
                EXPECT_NEAR(pmf_sum(mix, lit), share + (1.0 - share) * local_sum, 1e-5);
                for (const std::uint32_t past : {mix.light_count(), mix.light_count() + 7u, ~0u})
                    EXPECT_EQ(mix.pmf(lit, past), 0.0f);
            }
        }
    }
}

// Draws at `at` against the pmf, with "no light" as one more cell; every draw's pmf is that of
// `pmf(at, id)`.
template <class Sampler>
restir::test::Chi2Result chi2_of_draws(const Sampler& s, const ShadingPoint& at,
                                       std::uint32_t draws, restir::Pcg32& rng) {
    const std::uint32_t n = s.light_count();
    std::vector<double> expected(n + 1u), observed(n + 1u, 0.0);
    double total = 0.0;
    for (std::uint32_t id = 0; id < n; ++id) {
        expected[id] = static_cast<double>(s.pmf(at, id)) * draws;
        total += static_cast<double>(s.pmf(at, id));
    }
    expected[n] = std::max(0.0, 1.0 - total) * draws;
    for (std::uint32_t i = 0; i < draws; ++i) {
        const DiscreteSample d = restir::sample_light(s, at, rng);
        if (!(d.pmf > 0.0f)) {
            observed[n] += 1.0;
            continue;
        }
        EXPECT_LT(d.index, n);
        if (d.index >= n)
            return {};
        EXPECT_FLOAT_EQ(d.pmf, s.pmf(at, d.index)) << "light " << d.index;
        observed[d.index] += 1.0;
    }
    return restir::test::pearson_chi2(observed, expected);
}

TEST(DistantLights, DrawsFollowThePmfBesideALightBvh) {
    const Bvh mixed(true);
    restir::Pcg32 rng = restir::make_pixel_rng(2u, 0u, 0u, 5u);
    constexpr int points = 3;
    const double significance =
        restir::test::sidak_significance(0.01, points * static_cast<int>(std::size(placements)));
    for (const Placement& place : placements) {
        const auto s =
            restir::with_distant_lights(mixed.bvh.view(), place.first, place.count, 0.3f);
        for (int k = 0; k < points; ++k) {
            const ShadingPoint at = random_point(rng, true);
            const restir::test::Chi2Result chi2 = chi2_of_draws(s, at, 200000u, rng);
            EXPECT_GT(chi2.p_value, significance)
                << "first " << place.first << ", count " << place.count << ": chi2 "
                << chi2.statistic << ", dof " << chi2.degrees_of_freedom;
        }
    }
}

// The plain `LightSampler` form over a power sampler, with two distant lights chosen by weight
// (1 : 3) among themselves: the pmf sums to one and draws follow it.
TEST(DistantLights, DrawsFollowThePmfBesideAPowerSampler) {
    std::vector<float> powers;
    for (const LightBounds& b : local_lights(local_count, true, 13u))
        powers.push_back(b.power);
    const restir::AliasTable table(powers);
    const std::vector<float> distant_powers = {1.0f, 3.0f};
    const restir::AliasTable distant_table(distant_powers);
    const restir::PowerLightSampler distant{distant_table.view()};
    restir::Pcg32 rng = restir::make_pixel_rng(3u, 0u, 0u, 7u);
    const double significance =
        restir::test::sidak_significance(0.01, static_cast<int>(std::size(placements)));
    for (const Placement& place : placements) {
        const auto s = restir::with_distant_lights(restir::PowerLightSampler{table.view()},
                                                   place.first, distant, 0.25f);
        double sum = 0.0;
        for (std::uint32_t id = 0; id < s.light_count(); ++id)
            sum += static_cast<double>(s.pmf(id));
        EXPECT_NEAR(sum, 1.0, 1e-5);
        EXPECT_FLOAT_EQ(s.pmf(place.first), 0.25f * 0.25f);
        EXPECT_FLOAT_EQ(s.pmf(place.first + 1u), 0.25f * 0.75f);
        std::vector<double> pmf(s.light_count()), observed(s.light_count(), 0.0);
        for (std::uint32_t id = 0; id < s.light_count(); ++id)
            pmf[id] = static_cast<double>(s.pmf(id));
        for (int i = 0; i < 200000; ++i) {
            const DiscreteSample d = restir::sample_light(s, rng);
            ASSERT_LT(d.index, s.light_count());
            ASSERT_EQ(d.pmf, s.pmf(d.index));
            observed[d.index] += 1.0;
        }
        EXPECT_TRUE(restir::test::fits_distribution(observed, pmf, significance))
            << "first " << place.first;
    }
}

// With P = 0 the wrapper is the BVH: the same draws from the same numbers, bit for bit, under
// the application's ids, and the same pmfs; with no distant light, the very same ids.
TEST(DistantLights, ProbabilityZeroGivesTheBvhsOwnDraws) {
    const Bvh mixed(true);
    const restir::LightBvhView view = mixed.bvh.view();
    restir::Pcg32 rng = restir::make_pixel_rng(4u, 0u, 0u, 9u);
    const auto expect_same = [&](const auto& s, std::uint32_t first, std::uint32_t count) {
        for (int k = 0; k < 2000; ++k) {
            const ShadingPoint at = random_point(rng, true);
            const float u0 = next_float(rng), u1 = next_float(rng);
            const DiscreteSample own = view.sample(at, u0, u1);
            const DiscreteSample wrapped = s.sample(at, u0, u1);
            const std::uint32_t id = own.index < first ? own.index : own.index + count;
            ASSERT_EQ(std::bit_cast<std::uint32_t>(wrapped.pmf),
                      std::bit_cast<std::uint32_t>(own.pmf));
            if (own.pmf > 0.0f) {
                ASSERT_EQ(wrapped.index, id);
            }
            const auto local = restir::uniform_index(next_float(rng), local_count);
            const std::uint32_t app = local < first ? local : local + count;
            ASSERT_EQ(std::bit_cast<std::uint32_t>(s.pmf(at, app)),
                      std::bit_cast<std::uint32_t>(view.pmf(at, local)));
            for (std::uint32_t d = first; d < first + count; ++d)
                ASSERT_EQ(s.pmf(at, d), 0.0f);
        }
    };
    for (const Placement& place : placements)
        expect_same(restir::with_distant_lights(view, place.first, place.count, 0.0f), place.first,
                    place.count);
    // No distant light: P is forced to 0.
    expect_same(restir::with_distant_lights(view, 7u, 0u, 0.5f), 7u, 0u);
}

TEST(DistantLights, DefaultProbabilityFollowsPower) {
    EXPECT_FLOAT_EQ(restir::distant_light_probability(1.0f, 3.0f), 0.25f);
    EXPECT_EQ(restir::distant_light_probability(0.0f, 3.0f), 0.0f);
    EXPECT_EQ(restir::distant_light_probability(5.0f, 0.0f), 1.0f);
    EXPECT_EQ(restir::distant_light_probability(0.0f, 0.0f), 0.0f);
    EXPECT_FLOAT_EQ(restir::distant_light_probability(3e38f, 3e38f), 0.5f); // no overflow
    const float nan = std::numeric_limits<float>::quiet_NaN();
    const float inf = std::numeric_limits<float>::infinity();
    EXPECT_EQ(restir::distant_light_probability(nan, 1.0f), 0.0f);
    EXPECT_EQ(restir::distant_light_probability(-1.0f, 1.0f), 0.0f);
    EXPECT_EQ(restir::distant_light_probability(1.0f, nan), 1.0f);
    EXPECT_EQ(restir::distant_light_probability(inf, 1.0f), 0.0f);
    // `with_distant_lights` keeps P in [0, 1] and `first` within the local lights.
    const restir::UniformLightSampler local{10u};
    EXPECT_EQ(restir::with_distant_lights(local, 0u, 1u, 1.5f).distant.probability, 1.0f);
    EXPECT_EQ(restir::with_distant_lights(local, 0u, 1u, -0.5f).distant.probability, 0.0f);
    EXPECT_EQ(restir::with_distant_lights(local, 0u, 1u, nan).distant.probability, 0.0f);
    EXPECT_EQ(restir::with_distant_lights(local, 0u, 0u, 0.5f).distant.probability, 0.0f);
    // P = 1: only distant lights.
    const auto all_distant = restir::with_distant_lights(local, 4u, 2u, 1.0f);
    EXPECT_EQ(all_distant.pmf(3u), 0.0f);
    EXPECT_EQ(all_distant.pmf(5u), 0.5f);
    for (const float u : {0.0f, 0.5f, 0x1.fffffep-1f})
        EXPECT_TRUE(all_distant.distant.contains(all_distant.sample(u, 0.3f).index));
}

// Point lights in [0, 10] x [0, 4] x [0, 10] with the distant lights at `first` of the ids: a
// `LightSet` over the application's ids and each local light's bounds.
struct GridLights {
    std::uint32_t first, count;
    std::vector<LightBounds> bounds;               // local ids
    std::vector<restir::LightBvhNode> local_nodes; // local ids
    std::vector<float> powers;                     // local ids

    GridLights(std::uint32_t first_id, std::uint32_t distant_count)
        : first(first_id), count(distant_count) {
        restir::Pcg32 rng = restir::make_pixel_rng(7u, 0u, 0u, 11u);
        for (std::uint32_t i = 0; i < local_count; ++i) {
            const float x = next_float(rng), y = next_float(rng), z = next_float(rng);
            const glm::vec3 n = random_direction(rng);
            powers.push_back(1.0f + 99.0f * next_float(rng));
            bounds.push_back(restir::point_light_bounds(glm::vec3(10.0f * x, 4.0f * y, 10.0f * z),
                                                        n, powers.back()));
            local_nodes.push_back(restir::light_bvh_node(bounds.back()));
        }
    }
    bool is_distant(std::uint32_t id) const { return id >= first && id < first + count; }
    bool is_local(std::uint32_t id) const { return !is_distant(id) && id < light_count(); }
    std::uint32_t local_of(std::uint32_t id) const { return id < first ? id : id - count; }
    std::uint32_t light_count() const { return local_count + count; }
    // What light `id` gives a point (the importance bound, exact for a point light), and a
    // distant light 3 + its index: any positive value does for the test.
    double contribution(std::uint32_t id, const ShadingPoint& at) const {
        if (is_distant(id))
            return 3.0 + (id - first);
        if (!is_local(id))
            return 0.0;
        return static_cast<double>(restir::light_importance(local_nodes[local_of(id)], at));
    }
    restir::LightSample sample_point(std::uint32_t id, glm::vec2) const {
        restir::LightSample p;
        p.position = is_local(id) ? bounds[local_of(id)].lower : glm::vec3(1e6f);
        p.radiance = glm::vec3(1.0f);
        p.area_pdf = 1.0f;
        p.is_delta = true;
        return p;
    }
};

struct GridFixture {
    GridLights lights;
    restir::AliasTable table;
    restir::LightGridLayout grid =
        restir::LightGridLayout::over({0.0f, 0.0f, 0.0f}, {10.0f, 4.0f, 10.0f}, 5u);

    explicit GridFixture(const Placement& place)
        : lights(place.first, place.count), table(lights.powers) {}
    restir::PowerLightSampler sampler() const { return {table.view()}; }
    // Bounds by the application's id; never asked for a distant light (nor past the end).
    auto node_of() const {
        return [this](std::uint32_t id) -> const restir::LightBvhNode& {
            static const restir::LightBvhNode none{};
            const bool local = lights.is_local(id);
            EXPECT_TRUE(local) << "bounds asked for light " << id;
            return local ? lights.local_nodes[lights.local_of(id)] : none;
        };
    }
};

// Each entry's 1 / pdf is an unbiased contribution weight of all the lights at a point of the
// cell: the mean of f / pdf over the entries of fresh tiles is the sum of f over the local and
// the distant lights, within 4 standard errors.
TEST(DistantLights, GridEntriesAreUnbiasedWithDistantLights) {
    constexpr std::uint32_t entries = 40, per_entry = 8; // 40: two blocks of coins
    std::vector<restir::GridCandidate> scratch(entries * per_entry);
    for (const Placement& place : {placements[1], placements[5]}) {
        const GridFixture f(place);
        const ShadingPoint at{{3.0f, 1.0f, 7.0f}, {0.6f, 0.0f, 0.8f}};
        const std::uint32_t cell = f.grid.cell_of(at.position);
        double truth = 0.0;
        for (std::uint32_t id = 0; id < f.lights.light_count(); ++id)
            truth += f.lights.contribution(id, at);
        for (const float p : {0.2f, 0.7f}) {
            const restir::DistantLights<> distant{place.first, p,
                                                  restir::UniformLightSampler{place.count}};
            restir::test::RunningStats estimate;
            for (std::uint32_t trial = 0; trial < 20000u; ++trial) {
                restir::Pcg32 rng = restir::make_pixel_rng(trial, cell, 1u, 19u);
                double sum = 0.0;
                restir::resample_grid_tile_with_distant(
                    f.sampler(), distant, f.grid.cell_region(cell), f.node_of(), f.lights, rng,
                    entries, per_entry, scratch.data(),
                    [&](std::uint32_t, const restir::PresampledLight& e) {
                        if (e.pdf > 0.0f)
                            sum += f.lights.contribution(e.reference.light_id, at) /
                                   static_cast<double>(e.pdf);
                    });
                estimate.add(sum / entries);
            }
            EXPECT_TRUE(restir::test::agrees_with(estimate, truth))
                << "first " << place.first << ", P " << p;
            EXPECT_LT(estimate.standard_error(), 0.02 * truth); // the test can see a bias
        }
    }
}

// Entry j of a tile is distant light d with probability P / count on its own, whatever j
// (chi-square over the cells (entry, local or which distant light)), and a distant entry's pdf
// is P / count exactly.
TEST(DistantLights, EachGridEntryIsDistantWithProbabilityP) {
    constexpr std::uint32_t entries = 40, per_entry = 4;
    std::vector<restir::GridCandidate> scratch(entries * per_entry);
    const double significance = restir::test::sidak_significance(0.01, 2);
    for (const Placement& place : {placements[3], placements[4]}) {
        const GridFixture f(place);
        const std::uint32_t cell = f.grid.cell_of({5.0f, 2.0f, 5.0f});
        constexpr float p = 0.3f;
        const restir::DistantLights<> distant{place.first, p,
                                              restir::UniformLightSampler{place.count}};
        const std::uint32_t kinds = place.count + 1u; // local, then each distant light
        std::vector<double> observed(entries * kinds, 0.0), expected(entries * kinds);
        for (std::uint32_t j = 0; j < entries; ++j) {
            expected[j * kinds] = (1.0 - static_cast<double>(p)) / entries;
            for (std::uint32_t d = 1; d < kinds; ++d)
                expected[j * kinds + d] = static_cast<double>(p) / place.count / entries;
        }
        restir::Pcg32 rng = restir::make_pixel_rng(5u, cell, 1u, 23u);
        for (int tile = 0; tile < 5000; ++tile)
            restir::resample_grid_tile_with_distant(
                f.sampler(), distant, f.grid.cell_region(cell), f.node_of(), f.lights, rng, entries,
                per_entry, scratch.data(), [&](std::uint32_t j, const restir::PresampledLight& e) {
                    const std::uint32_t id = e.reference.light_id;
                    const bool is_distant = f.lights.is_distant(id);
                    if (is_distant) {
                        EXPECT_EQ(e.pdf, p / static_cast<float>(place.count));
                    }
                    observed[j * kinds + (is_distant ? 1u + id - place.first : 0u)] += 1.0;
                });
        EXPECT_TRUE(restir::test::fits_distribution(observed, expected, significance))
            << "first " << place.first;
    }
}

// With P = 0 the tile is `resample_grid_tile`'s over the local sampler, bit for bit, with the
// local ids mapped to the application's; with no distant light, the very same tile.
TEST(DistantLights, GridProbabilityZeroGivesThePlainTile) {
    constexpr std::uint32_t entries = 40, per_entry = 8;
    std::vector<restir::GridCandidate> scratch(entries * per_entry);
    std::vector<Placement> cases(std::begin(placements), std::end(placements));
    cases.push_back({local_count / 2u, 0u});
    for (const Placement& place : cases) {
        const GridFixture f(place);
        const std::uint32_t cell = f.grid.cell_of({2.0f, 1.0f, 8.0f});
        // The plain tile sees local ids: its bounds and points by local id.
        const auto local_node = [&](std::uint32_t id) -> const restir::LightBvhNode& {
            return f.lights.local_nodes[id];
        };
        struct LocalLights {
            const GridLights* lights;
            std::uint32_t light_count() const { return local_count; }
            restir::LightSample sample_point(std::uint32_t id, glm::vec2 uv) const {
                const std::uint32_t app = id < lights->first ? id : id + lights->count;
                return lights->sample_point(app, uv);
            }
        } local_lights{&f.lights};
        std::vector<restir::PresampledLight> plain(entries), mixed(entries);
        restir::Pcg32 rng = restir::make_pixel_rng(6u, cell, 1u, 29u);
        restir::Pcg32 same = rng;
        restir::resample_grid_tile(
            f.sampler(), f.grid.cell_region(cell), local_node, local_lights, rng, entries,
            per_entry, scratch.data(),
            [&](std::uint32_t j, const restir::PresampledLight& e) { plain[j] = e; });
        const restir::DistantLights<> none{place.first, 0.0f,
                                           restir::UniformLightSampler{place.count}};
        restir::resample_grid_tile_with_distant(
            f.sampler(), none, f.grid.cell_region(cell), f.node_of(), f.lights, same, entries,
            per_entry, scratch.data(),
            [&](std::uint32_t j, const restir::PresampledLight& e) { mixed[j] = e; });
        for (std::uint32_t j = 0; j < entries; ++j) {
            const std::uint32_t local = plain[j].reference.light_id;
            EXPECT_EQ(mixed[j].reference.light_id,
                      local < place.first ? local : local + place.count)
                << j;
            EXPECT_EQ(mixed[j].reference.uv, plain[j].reference.uv) << j;
            EXPECT_EQ(std::bit_cast<std::uint32_t>(mixed[j].pdf),
                      std::bit_cast<std::uint32_t>(plain[j].pdf))
                << j;
            EXPECT_EQ(mixed[j].point.position, plain[j].point.position) << j;
        }
    }
}

} // namespace
