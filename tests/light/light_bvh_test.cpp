// The light BVH (light/light_bvh.hpp): the pmf sums to one at every shading point, the descent
// draws lights with exactly that pmf (chi-square), the pmf is positive for every light that
// lights the point, and RIS with BVH candidates is unbiased; at 1k and at 1M lights.
#include "restir/light/light_bvh.hpp"

#include "restir/core/rng.hpp"
#include "restir/sampling/alias_table.hpp"
#include "restir/sampling/light_candidates.hpp"
#include "restir/sampling/light_sampler.hpp"
#include "restir/sampling/light_tiles.hpp"
#include "restir/sampling/ris.hpp"

#include "support/chi2.hpp"
#include "support/statistics.hpp"

#include <glm/geometric.hpp>
#include <gtest/gtest.h>

#include <algorithm>
#include <cmath>
#include <cstdint>
#include <stdexcept>
#include <vector>

namespace {

using restir::LightBounds;
using restir::ShadingPoint;

glm::vec3 random_direction(restir::Pcg32& rng) {
    const float z = 2.0f * next_float(rng) - 1.0f;
    const float phi = 6.2831853f * next_float(rng);
    const float r = std::sqrt(std::max(0.0f, 1.0f - z * z));
    return {r * std::cos(phi), r * std::sin(phi), z};
}

// The lights of a test scene: `count` lights in [0, 10]^3, a third each small area lights
// (random facing), cosine point emitters (VPLs) and isotropic points, powers over three orders
// of magnitude. With `points_only`, no area lights.
struct TestLight {
    glm::vec3 position;
    glm::vec3 normal; // zero: isotropic
    float power;
};
std::vector<TestLight> test_lights(std::uint32_t count, std::uint64_t seed) {
    restir::Pcg32 rng = restir::make_pixel_rng(0u, 0u, 0u, seed);
    std::vector<TestLight> lights(count);
    for (std::uint32_t i = 0; i < count; ++i) {
        lights[i].position = 10.0f * glm::vec3(next_float(rng), next_float(rng), next_float(rng));
        lights[i].normal = i % 3u == 2u ? glm::vec3(0.0f) : random_direction(rng);
        lights[i].power = std::exp(6.9f * (next_float(rng) - 0.5f));
    }
    return lights;
}
std::vector<LightBounds> bounds_of(const std::vector<TestLight>& lights) {
    std::vector<LightBounds> bounds;
    bounds.reserve(lights.size());
    for (std::uint32_t i = 0; i < lights.size(); ++i) {
        const TestLight& l = lights[i];
        if (i % 3u == 0u) { // a 0.2-wide quad in the plane facing `normal`
            const glm::vec3 half(0.1f);
            bounds.push_back(
                restir::area_light_bounds(l.position - half, l.position + half, l.normal, l.power));
        } else {
            bounds.push_back(restir::point_light_bounds(l.position, l.normal, l.power));
        }
    }
    return bounds;
}

// Every light as a point light (the area lights' quads left out of their bounds).
std::vector<LightBounds> point_bounds_of(const std::vector<TestLight>& lights) {
    std::vector<LightBounds> bounds;
    for (const TestLight& l : lights)
        bounds.push_back(restir::point_light_bounds(l.position, l.normal, l.power));
    return bounds;
}

// A fixed direction for index i (the VPLs' normals in the grazing test).
glm::vec3 random_direction_of(std::uint32_t i) {
    restir::Pcg32 rng = restir::make_pixel_rng(i, 1u, 0u, 103u);
    return random_direction(rng);
}

ShadingPoint random_point(restir::Pcg32& rng) {
    const glm::vec3 p(next_float(rng), next_float(rng), next_float(rng));
    return {-2.0f + 14.0f * p, random_direction(rng)};
}

// Irradiance at `at` from a point light (the integrand RIS estimates in the unbiasedness test).
float point_irradiance(const TestLight& l, const ShadingPoint& at) {
    const glm::vec3 d = l.position - at.position;
    const float d2 = glm::dot(d, d);
    const glm::vec3 w = d / std::sqrt(d2);
    const float receiver = std::max(0.0f, glm::dot(at.normal, w));
    const bool isotropic = l.normal == glm::vec3(0.0f);
    const float emitter = isotropic ? 0.25f : std::max(0.0f, -glm::dot(l.normal, w)) / 3.1415927f;
    return l.power * receiver * emitter / d2;
}

// The grid each group's boxes are stored on (its parent's box's), by a walk from the root: a
// group comes after its parent.
std::vector<restir::LightBvhGrid> group_grids(const restir::LightBvh& bvh) {
    std::vector<restir::LightBvhGrid> grids(bvh.groups().size());
    if (grids.empty())
        return grids;
    grids[0] = bvh.view().root_grid();
    for (std::size_t index = 0u; index < grids.size(); ++index) {
        const restir::LightBvhGroup& group = bvh.groups()[index];
        for (std::uint32_t c = 0u; c < restir::LightBvhGroup::lanes; ++c)
            if (!group.is_leaf(c))
                grids[group.child_or_light[c]] = group.child_grid(c, grids[index]);
    }
    return grids;
}

// The pmf is positive wherever a point light lights the point, sums to at most one (the rest
// is the chance that the descent reaches a node none of whose lights reach the point: no
// light), and the descent's histogram, with "no light" as one more cell, matches it. With the
// default near-field length (0 for these lights, mostly points) or `near_length`.
void check_distribution(std::uint32_t light_count, std::uint32_t points, std::uint32_t draws,
                        float near_length = -1.0f) {
    const std::vector<TestLight> lights = test_lights(light_count, 11u);
    const std::vector<LightBounds> bounds = bounds_of(lights);
    const restir::LightBvh bvh =
        near_length < 0.0f ? restir::LightBvh(bounds) : restir::LightBvh(bounds, near_length);
    const restir::LightBvhView view = bvh.view();
    ASSERT_EQ(view.light_count(), light_count);
    restir::Pcg32 rng = restir::make_pixel_rng(1u, 0u, 0u, 12u);
    const double significance = restir::test::sidak_significance(0.01, static_cast<int>(points));
    for (std::uint32_t k = 0; k < points; ++k) {
        const ShadingPoint at = random_point(rng);
        std::vector<double> expected(light_count + 1u);
        double total = 0.0;
        for (std::uint32_t id = 0; id < light_count; ++id) {
            const float pmf = view.pmf(at, id);
            total += static_cast<double>(pmf);
            expected[id] = static_cast<double>(pmf) * draws;
            if (id % 3u != 0u && point_irradiance(lights[id], at) > 0.0f) {
                ASSERT_GT(pmf, 0.0f) << "light " << id << " lights point " << k;
            }
        }
        ASSERT_LE(total, 1.0 + 1e-4) << "point " << k;
        expected[light_count] = std::max(0.0, 1.0 - total) * draws;
        std::vector<double> observed(light_count + 1u, 0.0);
        for (std::uint32_t i = 0; i < draws; ++i) {
            const restir::DiscreteSample s = restir::sample_light(view, at, rng);
            if (!(s.pmf > 0.0f)) {
                observed[light_count] += 1.0;
                continue;
            }
            ASSERT_LT(s.index, light_count);
            ASSERT_FLOAT_EQ(s.pmf, view.pmf(at, s.index));
            observed[s.index] += 1.0;
        }
        const restir::test::Chi2Result chi2 = restir::test::pearson_chi2(observed, expected);
        EXPECT_GT(chi2.p_value, significance)
            << "point " << k << ": chi2 " << chi2.statistic << ", dof " << chi2.degrees_of_freedom;
    }
}

TEST(LightBvh, DrawsLightsWithItsPmfAt1kLights) { check_distribution(1000u, 8u, 200000u); }

TEST(LightBvh, DrawsLightsWithItsPmfWithANearFieldLength) {
    check_distribution(1000u, 8u, 200000u, 1.0f);
}

TEST(LightBvh, DrawsLightsWithItsPmfAt1MLights) { check_distribution(1u << 20u, 2u, 400000u); }

// Light counts that leave interior nodes with unused (powerless) children, which no draw may
// take, and nodes whose children are all leaves.
TEST(LightBvh, DrawsLightsWithItsPmfWhereNodesHaveUnusedChildren) {
    for (const std::uint32_t count : {2u, 3u, 5u, 6u, 7u, 17u})
        check_distribution(count, 4u, 20000u);
}

// RIS with BVH candidates: the mean of f(Y) W over trials is the irradiance summed over all
// lights, within 4 measured standard errors, at points inside, beside and far from the lights.
void check_ris_unbiased(std::uint32_t light_count) {
    std::vector<TestLight> lights = test_lights(light_count, 21u);
    for (TestLight& l : lights) // point lights only: the truth is a plain sum
        l.normal = l.normal == glm::vec3(0.0f) ? l.normal : glm::normalize(l.normal);
    const restir::LightBvh bvh(point_bounds_of(lights));
    const restir::LightBvhView view = bvh.view();
    const ShadingPoint points[3] = {{glm::vec3(5.0f), glm::normalize(glm::vec3(1.0f, 2.0f, 3.0f))},
                                    {glm::vec3(-1.0f, 5.0f, 5.0f), glm::vec3(1.0f, 0.0f, 0.0f)},
                                    {glm::vec3(40.0f, 3.0f, 2.0f), glm::vec3(-1.0f, 0.0f, 0.0f)}};
    for (const ShadingPoint& at : points) {
        double truth = 0.0;
        for (const TestLight& l : lights)
            truth += static_cast<double>(point_irradiance(l, at));
        restir::Pcg32 rng = restir::make_pixel_rng(2u, 0u, 0u, 22u);
        restir::test::RunningStats estimate;
        for (std::uint32_t trial = 0; trial < 20000u; ++trial) {
            const auto r = restir::resample_ris(
                rng, 8u,
                [&](restir::Pcg32& g) { return restir::draw_light_candidate(view, at, g); },
                [&](const restir::LightSampleRef& x) {
                    return point_irradiance(lights[x.light_id], at);
                });
            const float f = r.has_sample() ? point_irradiance(lights[r.sample.light_id], at) : 0.0f;
            estimate.add(static_cast<double>(f * r.contribution_weight));
        }
        EXPECT_TRUE(restir::test::agrees_with(estimate, truth));
    }
}

TEST(LightBvh, RisWithBvhCandidatesIsUnbiasedAt1kLights) { check_ris_unbiased(1000u); }

TEST(LightBvh, RisWithBvhCandidatesIsUnbiasedAt1MLights) { check_ris_unbiased(1u << 20u); }

// Every light's bounds hold within the quantised bounds of each node on its path (the lanes
// its descent weighs): its box inside the lane's box, its cone of normals inside the lane's
// cone, its emission spread within the lane's, a positive power wherever it has one; and each
// corner on a grid comes out exactly (the same in float and in double).
void check_quantised_bounds(const std::vector<LightBounds>& bounds) {
    const restir::LightBvh bvh(bounds);
    const restir::LightBvhView view = bvh.view();
    const auto angle_between = [](glm::vec3 a, glm::vec3 b) {
        const glm::dvec3 x(a), y(b);
        return std::atan2(glm::length(glm::cross(x, y)), glm::dot(x, y));
    };
    for (std::uint32_t id = 0; id < bounds.size(); ++id) {
        const LightBounds& light = bounds[id];
        const std::uint64_t path = view.paths[id];
        const auto depth = static_cast<std::uint32_t>(path >> restir::LightBvhView::depth_shift);
        ASSERT_LE(depth, restir::LightBvhView::max_depth);
        std::uint32_t group = 0u;
        restir::LightBvhGrid grid = view.root_grid();
        for (std::uint32_t level = 0; level < depth; ++level) {
            const auto lane =
                static_cast<std::uint32_t>(path >> (restir::LightBvhGroup::lane_bits * level) &
                                           (restir::LightBvhGroup::lanes - 1u));
            const restir::LightBvhGroup& g = view.groups[group];
            const restir::LightBvhBox box = g.box(lane, grid);
            const restir::LightBvhNode node = g.node(lane, grid);
            for (int a = 0; a < 3; ++a) {
                ASSERT_LE(box.lower[a], light.lower[a]) << "light " << id << ", level " << level;
                ASSERT_GE(box.upper[a], light.upper[a]) << "light " << id << ", level " << level;
                const auto exact = [&](std::uint32_t code, float corner) {
                    return static_cast<double>(grid.origin[a]) +
                               code * static_cast<double>(grid.step[a]) ==
                           static_cast<double>(corner);
                };
                ASSERT_TRUE(exact(g.lower[a][lane], box.lower[a]));
                ASSERT_TRUE(exact(g.upper[a][lane], box.upper[a]));
            }
            if (node.cos_theta_o > -1.0f) { // else the lane's cone is the sphere
                const double light_theta = std::acos(static_cast<double>(light.cos_theta_o));
                ASSERT_LE(angle_between(node.axis, light.axis) + light_theta,
                          std::acos(static_cast<double>(node.cos_theta_o)))
                    << "light " << id << ", level " << level;
            }
            ASSERT_LE(node.cos_theta_e, light.cos_theta_e) << "light " << id;
            ASSERT_GE(node.power, light.power) << "light " << id;
            if (level + 1u == depth) {
                ASSERT_TRUE(g.is_leaf(lane));
                ASSERT_EQ(g.child_or_light[lane], restir::LightBvhNode::leaf_bit | id);
            }
            grid = g.child_grid(lane, grid);
            group = g.child_or_light[lane];
        }
    }
}

TEST(LightBvh, QuantisedBoundsHoldEveryLight) {
    check_quantised_bounds(bounds_of(test_lights(20000u, 61u)));
    // A cluster of small lights far from the origin, 10 ulps of its coordinates wide, where the
    // grid steps are finer than those ulps, and lights whose normals lie on the octahedron's
    // folds.
    std::vector<TestLight> far = test_lights(3000u, 62u);
    for (std::uint32_t i = 0; i < far.size(); ++i) {
        far[i].position = glm::vec3(1.0e4f, -3.0e4f, 5.0e3f) + 1.0e-3f * far[i].position;
        if (i % 7u == 0u)
            far[i].normal = glm::normalize(glm::vec3(1.0f, i % 2u == 0u ? -1.0f : 1.0f, 0.0f));
    }
    check_quantised_bounds(bounds_of(far));
    check_quantised_bounds(point_bounds_of(test_lights(5u, 63u)));
}

// Coplanar lights away from the origin (a ceiling of panels, or the two triangles of the
// Cornell box's light at y = 548.8 in millimetres): their box is flat along y, where a grid step
// of FLT_MIN made lower / step overflow, the root's box infinite and every pmf 0 (a black image
// from restir-render --source bvh). Every light must keep a positive pmf below the ceiling, the
// pmfs sum to one there, and the quantised bounds hold.
TEST(LightBvh, CoplanarLightsFarFromTheOriginAreDrawn) {
    for (const float height : {2.0f, 5.0f, 548.8f, -3.0e4f}) {
        std::vector<LightBounds> ceiling;
        for (int i = 0; i < 8; ++i)
            for (int j = 0; j < 8; ++j) {
                const glm::vec3 corner(-4.0f + static_cast<float>(i), height,
                                       -4.0f + static_cast<float>(j));
                ceiling.push_back(restir::area_light_bounds(
                    corner, corner + glm::vec3(0.5f, 0.0f, 0.5f), {0.0f, -1.0f, 0.0f},
                    1.0f + static_cast<float>(i + j)));
            }
        check_quantised_bounds(ceiling);
        const restir::LightBvh bvh(ceiling);
        const restir::LightBvhView view = bvh.view();
        for (const glm::vec3 position :
             {glm::vec3(0.0f, height - 1.0f, 0.0f), glm::vec3(3.0f, height - 50.0f, -2.0f)}) {
            const ShadingPoint at{position, {0.0f, 1.0f, 0.0f}};
            double total = 0.0;
            for (std::uint32_t id = 0; id < ceiling.size(); ++id) {
                const float pmf = view.pmf(at, id);
                EXPECT_GT(pmf, 0.0f) << "height " << height << ", light " << id;
                total += static_cast<double>(pmf);
            }
            EXPECT_NEAR(total, 1.0, 1e-5) << "height " << height;
            restir::Pcg32 rng = restir::make_pixel_rng(3u, 0u, 0u, 64u);
            const restir::DiscreteSample s = restir::sample_light(view, at, rng);
            EXPECT_GT(s.pmf, 0.0f) << "height " << height;
        }
    }
}

// Lights in a few tight clusters of very different powers: the cost splits them unevenly, so
// paths are longer than log8 n; the draws still follow the pmf.
TEST(LightBvh, DrawsLightsWithItsPmfInClusters) {
    std::vector<TestLight> lights = test_lights(3000u, 71u);
    for (std::uint32_t i = 0; i < lights.size(); ++i) {
        const float cluster = static_cast<float>(i % 5u);
        lights[i].position = glm::vec3(2.0f * cluster, 5.0f, 5.0f) + 0.05f * lights[i].position;
        lights[i].power *= std::exp(2.0f * cluster);
    }
    const restir::LightBvh bvh(bounds_of(lights));
    const restir::LightBvhView view = bvh.view();
    restir::Pcg32 rng = restir::make_pixel_rng(7u, 0u, 0u, 72u);
    for (int k = 0; k < 3; ++k) {
        const ShadingPoint at = random_point(rng);
        std::vector<double> expected(lights.size() + 1u), observed(lights.size() + 1u, 0.0);
        double total = 0.0;
        constexpr std::uint32_t draws = 200000u;
        for (std::uint32_t id = 0; id < lights.size(); ++id) {
            const double pmf = static_cast<double>(view.pmf(at, id));
            total += pmf;
            expected[id] = pmf * draws;
        }
        expected[lights.size()] = std::max(0.0, 1.0 - total) * draws;
        for (std::uint32_t i = 0; i < draws; ++i) {
            const restir::DiscreteSample s = restir::sample_light(view, at, rng);
            observed[s.pmf > 0.0f ? s.index : lights.size()] += 1.0;
        }
        const restir::test::Chi2Result chi2 = restir::test::pearson_chi2(observed, expected);
        EXPECT_GT(chi2.p_value, restir::test::sidak_significance(0.01, 3)) << "point " << k;
    }
}

// A line of point lights whose powers grow geometrically: the cost would isolate the
// brightest few at every level, making paths longer than their bits hold; the builder falls
// back to medians before that, so every path fits and every draw's pmf is `pmf`'s.
TEST(LightBvh, PathsFitTheirBitsWhereTheCostIsolatesLights) {
    std::vector<LightBounds> bounds;
    for (int i = 0; i < 2000; ++i)
        bounds.push_back(restir::point_light_bounds(glm::vec3(static_cast<float>(i), 0.0f, 0.0f),
                                                    glm::vec3(0.0f, 0.0f, 1.0f),
                                                    std::exp(0.2f * static_cast<float>(i % 400))));
    const restir::LightBvh bvh(bounds);
    const restir::LightBvhView view = bvh.view();
    std::uint32_t deepest = 0u;
    for (const std::uint64_t path : bvh.paths())
        deepest = std::max(deepest,
                           static_cast<std::uint32_t>(path >> restir::LightBvhView::depth_shift));
    ASSERT_LE(deepest, restir::LightBvhView::max_depth);
    EXPECT_GT(deepest, 8u); // deeper than a balanced tree: the fallback was needed
    restir::Pcg32 rng = restir::make_pixel_rng(8u, 0u, 0u, 81u);
    for (int k = 0; k < 20; ++k) {
        const ShadingPoint at{glm::vec3(2000.0f * next_float(rng), 3.0f, 10.0f),
                              glm::vec3(0.0f, 0.0f, -1.0f)};
        double total = 0.0;
        for (std::uint32_t id = 0; id < bounds.size(); ++id)
            total += static_cast<double>(view.pmf(at, id));
        EXPECT_NEAR(total, 1.0, 1e-4);
        for (int i = 0; i < 1000; ++i) {
            const restir::DiscreteSample s = restir::sample_light(view, at, rng);
            ASSERT_GT(s.pmf, 0.0f);
            ASSERT_EQ(s.pmf, view.pmf(at, s.index));
        }
    }
}

// The pmf sums to one over the lights: exactly (to float rounding) where every node's bound is
// positive (isotropic lights seen without a receiver normal), and elsewhere to one less the
// probability of the draws that end where no child can light the point, found by a walk of
// the tree in double precision.
double dead_end_mass(const restir::LightBvhView& view, std::uint32_t group,
                     const restir::LightBvhGrid& grid, const ShadingPoint& at, double reach) {
    const restir::LightBvhGroup& g = view.groups[group];
    float importance[restir::LightBvhGroup::lanes];
    const float total = g.importance(at, grid, importance);
    if (!(total > 0.0f))
        return reach;
    double dead = 0.0;
    for (std::uint32_t c = 0u; c < restir::LightBvhGroup::lanes; ++c)
        if (!g.is_leaf(c) && importance[c] > 0.0f)
            dead += dead_end_mass(view, g.child_or_light[c], g.child_grid(c, grid), at,
                                  reach * static_cast<double>(importance[c]) /
                                      static_cast<double>(total));
    return dead;
}

TEST(LightBvh, PmfSumsToOneOverTheLightsThatCanContribute) {
    std::vector<TestLight> lights = test_lights(5000u, 91u);
    const restir::LightBvh mixed(bounds_of(lights));
    for (TestLight& l : lights)
        l.normal = glm::vec3(0.0f);
    const restir::LightBvh isotropic(point_bounds_of(lights));
    restir::Pcg32 rng = restir::make_pixel_rng(9u, 0u, 0u, 92u);
    for (int k = 0; k < 10; ++k) {
        ShadingPoint at = random_point(rng);
        const auto sum = [&](const restir::LightBvhView& view) {
            double total = 0.0;
            for (std::uint32_t id = 0; id < lights.size(); ++id)
                total += static_cast<double>(view.pmf(at, id));
            return total;
        };
        const restir::LightBvhView view = mixed.view();
        const double dead = dead_end_mass(view, 0u, view.root_grid(), at, 1.0);
        EXPECT_NEAR(sum(view), 1.0 - dead, 1e-5) << "point " << k;
        at.normal = glm::vec3(0.0f);
        EXPECT_NEAR(sum(isotropic.view()), 1.0, 1e-5) << "point " << k;
    }
}

// A light that lights a point always has a positive pmf there, however near the edge of its
// emission or of the receiver's hemisphere the point lies: a tenth of a degree inside either,
// where bounds rounded inward (a box or a cone a step too small) would give it none.
TEST(LightBvh, GrazingLightsKeepAPositivePmf) {
    std::vector<TestLight> lights = test_lights(2000u, 101u);
    for (std::uint32_t i = 0; i < lights.size(); i += 2u) // half of them VPLs, the rest isotropic
        lights[i].normal = random_direction_of(i);
    const restir::LightBvh bvh(point_bounds_of(lights));
    const restir::LightBvhView view = bvh.view();
    const float grazing = std::sin(0.1f * 3.14159265f / 180.0f);
    restir::Pcg32 rng = restir::make_pixel_rng(10u, 0u, 0u, 102u);
    std::uint32_t checked = 0u;
    for (std::uint32_t id = 0; id < lights.size(); ++id) {
        const TestLight& l = lights[id];
        const glm::vec3 normal = l.normal == glm::vec3(0.0f) ? random_direction(rng) : l.normal;
        for (int k = 0; k < 4; ++k) {
            // A direction `grazing` above the emitter's horizon (or any, for an isotropic one).
            const glm::vec3 side = glm::normalize(glm::cross(normal, random_direction(rng)));
            const glm::vec3 out = l.normal == glm::vec3(0.0f)
                                      ? random_direction(rng)
                                      : glm::normalize(side + grazing * normal);
            const glm::vec3 position = l.position + (0.5f + 3.0f * next_float(rng)) * out;
            // A receiver normal `grazing` above the plane that holds the light, or facing it.
            const glm::vec3 across = glm::normalize(glm::cross(out, random_direction(rng)));
            const glm::vec3 receiver = k % 2 == 0 ? glm::normalize(across - grazing * out) : -out;
            const ShadingPoint at{position, receiver};
            if (!(point_irradiance(l, at) > 0.0f))
                continue;
            ++checked;
            ASSERT_GT(view.pmf(at, id), 0.0f) << "light " << id << ", case " << k;
        }
    }
    EXPECT_GT(checked, 4000u);
}

// A region (ShadingPoint::radius, a grid cell) gets a positive pmf for every point light that
// lights any point of it, whatever that point's normal.
TEST(LightBvh, RegionPmfCoversEveryPointOfTheRegion) {
    const std::vector<TestLight> lights = test_lights(3000u, 31u);
    const restir::LightBvh bvh(point_bounds_of(lights));
    const restir::LightBvhView view = bvh.view();
    restir::Pcg32 rng = restir::make_pixel_rng(4u, 0u, 0u, 32u);
    for (int cell = 0; cell < 20; ++cell) {
        const ShadingPoint region{
            12.0f * glm::vec3(next_float(rng), next_float(rng), next_float(rng)) - glm::vec3(1.0f),
            glm::vec3(0.0f), 0.25f + next_float(rng)};
        std::vector<float> pmf(lights.size());
        for (std::uint32_t id = 0; id < lights.size(); ++id)
            pmf[id] = view.pmf(region, id);
        for (int k = 0; k < 50; ++k) {
            const glm::vec3 offset = random_direction(rng) * (region.radius * next_float(rng));
            const ShadingPoint at{region.position + offset, random_direction(rng)};
            for (std::uint32_t id = 0; id < lights.size(); ++id)
                if (point_irradiance(lights[id], at) > 0.0f) {
                    ASSERT_GT(pmf[id], 0.0f) << "cell " << cell << ", light " << id;
                }
        }
    }
}

TEST(LightBvh, PointsNoLightReachesDrawNothing) {
    // Every light faces +z from z = 0: a point below them, or one facing away, sees none.
    std::vector<LightBounds> bounds;
    for (int i = 0; i < 64; ++i)
        bounds.push_back(restir::point_light_bounds(
            glm::vec3(static_cast<float>(i % 8), static_cast<float>(i / 8), 0.0f),
            glm::vec3(0.0f, 0.0f, 1.0f), 1.0f));
    const restir::LightBvh bvh(bounds);
    const restir::LightBvhView view = bvh.view();
    const ShadingPoint below{glm::vec3(3.5f, 3.5f, -5.0f), glm::vec3(0.0f, 0.0f, 1.0f)};
    const ShadingPoint facing_away{glm::vec3(3.5f, 3.5f, 5.0f), glm::vec3(0.0f, 0.0f, 1.0f)};
    for (const ShadingPoint& at : {below, facing_away}) {
        EXPECT_EQ(view.sample(at, 0.3f, 0.7f).pmf, 0.0f);
        for (std::uint32_t id = 0; id < 64u; ++id)
            EXPECT_EQ(view.pmf(at, id), 0.0f);
    }
    const ShadingPoint above{glm::vec3(3.5f, 3.5f, 5.0f), glm::vec3(0.0f, 0.0f, -1.0f)};
    EXPECT_GT(view.sample(above, 0.3f, 0.7f).pmf, 0.0f);
}

// A group's eight bounds, computed side by side (the host's loop, in vector registers), equal
// each lane's bound as device code evaluates it (`LightBvhGroup::bound`), bit for bit (this file
// is compiled without contraction into fused multiply-adds, which a vectorised and a scalar
// evaluation could apply differently): at points, at regions, without a normal, inside the
// children's spheres, and at a child's centre. The lanes weigh their cone axes unnormalised; the
// bound differs from `light_importance` of the child as `node` reads it back (a unit axis) by
// rounding alone, at most 1e-5 of power / d^2 (the largest the bound can be; some 170 float
// ulps of it, where the worst seen is six). With the paper's distance term and with a
// near-field length (`LightBvhView::near_length`).
TEST(LightBvh, GroupBoundsEqualEachChildsBound) {
    const std::vector<TestLight> lights = test_lights(5000u, 51u);
    const restir::LightBvh bvh(bounds_of(lights));
    const std::vector<restir::LightBvhGrid> grids = group_grids(bvh);
    restir::Pcg32 rng = restir::make_pixel_rng(6u, 0u, 0u, 52u);
    std::uint32_t positive = 0u;
    for (std::size_t index = 0u; index < bvh.groups().size(); ++index) {
        const restir::LightBvhGroup& group = bvh.groups()[index];
        const restir::LightBvhGrid& grid = grids[index];
        for (int k = 0; k < 8; ++k) {
            ShadingPoint at = random_point(rng);
            if (k == 1)
                at.normal = glm::vec3(0.0f);
            if (k == 2)
                at.radius = 2.0f * next_float(rng);
            if (k == 3)
                at.position = group.node(0u, grid).centre;
            for (const float near : {0.0f, 0.5f}) {
                float bounds[restir::LightBvhGroup::lanes];
                const float total = group.importance(at, grid, bounds, near);
                float sum = 0.0f;
                for (std::uint32_t c = 0u; c < restir::LightBvhGroup::lanes; ++c) {
                    const float expected = group.bound(c, grid, at, near);
                    ASSERT_EQ(bounds[c], expected) << "lane " << c << ", point " << k;
                    positive += expected > 0.0f ? 1u : 0u;
                    sum += expected;
                    const restir::LightBvhNode node = group.node(c, grid);
                    const float node_bound = restir::light_importance(node, at, near);
                    const glm::vec3 to = at.position - node.centre;
                    const double radius = double(node.radius) + double(std::max(at.radius, 0.0f));
                    const double near_squared =
                        near > 0.0f ? radius * double(near) : radius * radius;
                    const double scale =
                        double(node.power) / std::max(double(glm::dot(to, to)), near_squared);
                    // An unused lane has no power: both bounds are 0.
                    ASSERT_LE(std::abs(double(node_bound) - double(expected)), 1e-5 * scale)
                        << "lane " << c << ", point " << k << ", near " << near;
                }
                ASSERT_EQ(total, sum);
            }
        }
    }
    EXPECT_GT(positive, bvh.groups().size()); // most cases have something to compare
}

// The batch overload's draws are the single draws, bit for bit, including "no light" at points
// no light reaches and light counts whose trees end at different depths.
TEST(LightBvh, BatchDrawsEqualSingleDraws) {
    for (const std::uint32_t light_count : {1u, 5u, 1000u, 20000u}) {
        const std::vector<TestLight> lights = test_lights(light_count, 41u);
        const restir::LightBvh bvh(bounds_of(lights));
        const restir::LightBvhView view = bvh.view();
        restir::Pcg32 rng = restir::make_pixel_rng(5u, 0u, 0u, 42u);
        for (int point = 0; point < 200; ++point) {
            const ShadingPoint at = random_point(rng);
            float u0[8], u1[8];
            for (int k = 0; k < 8; ++k) {
                u0[k] = next_float(rng);
                u1[k] = next_float(rng);
            }
            restir::DiscreteSample batch[8];
            view.sample(at, u0, u1, batch);
            for (int k = 0; k < 8; ++k) {
                const restir::DiscreteSample single = view.sample(at, u0[k], u1[k]);
                ASSERT_EQ(batch[k].pmf, single.pmf) << light_count << " lights, draw " << k;
                if (single.pmf > 0.0f) {
                    ASSERT_EQ(batch[k].index, single.index) << light_count << " lights, draw " << k;
                }
            }
        }
    }
    const restir::LightBvh none(std::vector<LightBounds>{});
    const float u[2] = {0.5f, 0.25f};
    restir::DiscreteSample out[2] = {{3u, 1.0f}, {3u, 1.0f}};
    none.view().sample(ShadingPoint{}, u, u, out);
    EXPECT_EQ(out[0].pmf, 0.0f);
    EXPECT_EQ(out[1].pmf, 0.0f);
}

TEST(LightBvh, OneLightAndNoLights) {
    const std::vector<LightBounds> one = {
        restir::point_light_bounds(glm::vec3(0.0f), glm::vec3(0.0f, 0.0f, 1.0f), 2.0f)};
    const restir::LightBvh single(one);
    const ShadingPoint lit{glm::vec3(0.0f, 0.0f, 1.0f), glm::vec3(0.0f, 0.0f, -1.0f)};
    const ShadingPoint unlit{glm::vec3(0.0f, 0.0f, -1.0f), glm::vec3(0.0f, 0.0f, 1.0f)};
    EXPECT_EQ(single.view().sample(lit, 0.5f, 0.5f).pmf, 1.0f);
    EXPECT_EQ(single.view().pmf(lit, 0u), 1.0f);
    EXPECT_EQ(single.view().sample(unlit, 0.5f, 0.5f).pmf, 0.0f);
    EXPECT_EQ(single.view().pmf(unlit, 0u), 0.0f);
    const restir::LightBvh none(std::vector<LightBounds>{});
    EXPECT_EQ(none.view().sample(lit, 0.5f, 0.5f).pmf, 0.0f);
    EXPECT_EQ(none.view().pmf(lit, 0u), 0.0f);
}

TEST(LightBvh, RejectsLightsWithBadPowerOrPosition) {
    for (const float bad : {-1.0f, std::nanf(""), INFINITY}) {
        std::vector<LightBounds> bounds = {
            restir::point_light_bounds(glm::vec3(0.0f), glm::vec3(0.0f, 0.0f, 1.0f), 1.0f),
            restir::point_light_bounds(glm::vec3(1.0f), glm::vec3(0.0f, 0.0f, 1.0f), bad)};
        EXPECT_THROW(restir::LightBvh{bounds}, std::invalid_argument);
        if (bad != -1.0f) { // a position may be negative
            bounds[1] =
                restir::point_light_bounds(glm::vec3(bad), glm::vec3(0.0f, 0.0f, 1.0f), 1.0f);
            EXPECT_THROW(restir::LightBvh{bounds}, std::invalid_argument);
        }
    }
}

// Positions whose squared distances would overflow a float (and whose boxes' extents could) are
// rejected too.
TEST(LightBvh, RejectsPositionsBeyond2To64) {
    const std::vector<LightBounds> far = {
        restir::point_light_bounds(glm::vec3(0.0f), glm::vec3(0.0f, 0.0f, 1.0f), 1.0f),
        restir::point_light_bounds(glm::vec3(0.0f, -3.0e38f, 0.0f), glm::vec3(0.0f, 0.0f, 1.0f),
                                   1.0f)};
    EXPECT_THROW(restir::LightBvh{far}, std::invalid_argument);
    const std::vector<LightBounds> near = {
        restir::point_light_bounds(glm::vec3(0x1p64f), glm::vec3(0.0f, 0.0f, 1.0f), 1.0f),
        restir::point_light_bounds(glm::vec3(-0x1p64f), glm::vec3(0.0f, 0.0f, 1.0f), 1.0f)};
    const restir::LightBvh bvh(near);
    EXPECT_EQ(bvh.view().light_count(), 2u);
}

TEST(LightBvh, PowerAndUniformSamplersIgnoreTheShadingPoint) {
    const std::vector<float> powers = {1.0f, 3.0f, 0.5f, 2.0f};
    const restir::AliasTable table(powers);
    const restir::PowerLightSampler power{table.view()};
    const restir::UniformLightSampler uniform{10u};
    const ShadingPoint at{glm::vec3(1.0f), glm::vec3(0.0f, 1.0f, 0.0f)};
    for (const float u : {0.0f, 0.25f, 0.6f, 0.99f}) {
        EXPECT_EQ(uniform.sample(at, u, 0.5f).index, uniform.sample(u, 0.5f).index);
        EXPECT_EQ(power.sample(at, u, 0.5f).index, power.sample(u, 0.5f).index);
        EXPECT_EQ(power.sample(at, u, 0.5f).pmf, power.sample(u, 0.5f).pmf);
    }
    EXPECT_EQ(uniform.pmf(at, 3u), uniform.pmf(3u));
    EXPECT_EQ(power.pmf(at, 1u), power.pmf(1u));
}

// A tile entry presampled for a region (ReGIR) carries the light the BVH drew with its pmf at
// that region, and the light's evaluated point.
TEST(LightBvh, PresampledEntriesCarryThePmfAtTheirRegion) {
    const std::vector<TestLight> lights = test_lights(500u, 41u);
    const restir::LightBvh bvh(point_bounds_of(lights));
    const restir::LightBvhView view = bvh.view();
    struct Points { // restir::LightSet over the test lights
        const std::vector<TestLight>* lights;
        std::uint32_t light_count() const { return static_cast<std::uint32_t>(lights->size()); }
        restir::LightSample sample_point(std::uint32_t id, glm::vec2) const {
            restir::LightSample s;
            s.position = (*lights)[id].position;
            s.normal = (*lights)[id].normal;
            s.radiance = glm::vec3((*lights)[id].power);
            s.is_delta = true;
            return s;
        }
    };
    const Points set{&lights};
    const ShadingPoint region{glm::vec3(5.0f), glm::vec3(0.0f), 1.5f};
    restir::Pcg32 rng = restir::make_pixel_rng(5u, 0u, 0u, 42u);
    for (int i = 0; i < 200; ++i) {
        const restir::PresampledLight entry = restir::presample_light(view, region, set, rng);
        if (!(entry.pdf > 0.0f))
            continue;
        const std::uint32_t id = entry.reference.light_id;
        ASSERT_EQ(entry.pdf, view.pmf(region, id));
        ASSERT_EQ(entry.point.position, lights[id].position);
    }
}

} // namespace
