// The light grid (ReGIR): its cells, the regions that cover every point that can look a cell
// up, and tiles whose entries are unbiased RIS samples at every point of their region.
#include <restir/restir.hpp>

#include "support/statistics.hpp"

#include <gtest/gtest.h>

#include <cmath>
#include <cstdint>
#include <limits>
#include <vector>

namespace {

TEST(LightGrid, CellsAreAboutCubic) {
    const auto flat =
        restir::LightGridLayout::over({-50.0f, 0.0f, -50.0f}, {50.0f, 3.0f, 50.0f}, 32u);
    EXPECT_EQ(flat.cells, glm::uvec3(32u, 1u, 32u));
    EXPECT_FLOAT_EQ(flat.cell_size.x, 3.125f);
    EXPECT_FLOAT_EQ(flat.cell_size.y, 3.0f);
    EXPECT_EQ(flat.cell_count(), 1024u);
    const auto box = restir::LightGridLayout::over({0.0f, 0.0f, 0.0f}, {1.0f, 2.0f, 4.0f}, 8u);
    EXPECT_EQ(box.cells, glm::uvec3(2u, 4u, 8u));
    // A point, or nothing: one cell, which every point belongs to.
    for (const glm::vec3 upper : {glm::vec3(1.0f), glm::vec3(0.0f)}) {
        const auto point = restir::LightGridLayout::over(glm::vec3(1.0f), upper, 16u);
        EXPECT_EQ(point.cell_count(), 1u);
        EXPECT_EQ(point.cell_of(glm::vec3(-7.0f, 3.0f, 1e30f)), 0u);
    }
}

TEST(LightGrid, EachCellHoldsItsCentreAndOutsidePointsClamp) {
    const auto grid = restir::LightGridLayout::over({-1.0f, 2.0f, 0.0f}, {3.0f, 3.0f, 6.0f}, 12u);
    ASSERT_GT(grid.cell_count(), 12u);
    for (std::uint32_t cell = 0; cell < grid.cell_count(); ++cell)
        EXPECT_EQ(grid.cell_of(grid.cell_centre(cell)), cell);
    EXPECT_EQ(grid.cell_of(glm::vec3(-1e30f)), 0u);
    EXPECT_EQ(grid.cell_of(glm::vec3(1e30f)), grid.cell_count() - 1u);
    EXPECT_EQ(grid.cell_of(glm::vec3(std::numeric_limits<float>::quiet_NaN())), 0u);
}

// Every point of the box lies within the region of any cell its jittered lookup lands in.
TEST(LightGrid, RegionsCoverEveryPointThatCanLookThemUp) {
    const glm::vec3 lower(-2.0f, 0.0f, 1.0f), upper(5.0f, 1.0f, 4.0f);
    const auto grid = restir::LightGridLayout::over(lower, upper, 7u);
    restir::Pcg32 rng = restir::make_pixel_rng(3u, 0u, 0u, 5u);
    const auto uniform3 = [&] {
        const float x = next_float(rng), y = next_float(rng);
        return glm::vec3(x, y, next_float(rng));
    };
    for (int trial = 0; trial < 200000; ++trial) {
        const glm::vec3 p = lower + uniform3() * (upper - lower);
        const std::uint32_t cell = grid.jittered_cell_of(p, uniform3());
        const restir::ShadingPoint region = grid.cell_region(cell);
        ASSERT_LE(glm::length(p - region.position), region.radius) << trial;
    }
}

// Point lights in a box, cosine emitters in all directions, powers over two decades.
struct Lights {
    std::vector<glm::vec3> positions, normals;
    std::vector<float> powers;
    std::vector<restir::LightBvhNode> nodes;

    explicit Lights(std::uint32_t count) {
        restir::Pcg32 rng = restir::make_pixel_rng(7u, 0u, 0u, 11u);
        for (std::uint32_t i = 0; i < count; ++i) {
            const float x = next_float(rng), y = next_float(rng), z = next_float(rng);
            positions.emplace_back(10.0f * x, 4.0f * y, 10.0f * z);
            const float a = next_float(rng), b = next_float(rng), c = next_float(rng);
            normals.push_back(glm::normalize(glm::vec3(a - 0.5f, b - 0.5f, c - 0.5f)));
            powers.push_back(1.0f + 99.0f * next_float(rng));
            nodes.push_back(restir::light_bvh_node(
                restir::point_light_bounds(positions.back(), normals.back(), powers.back())));
        }
    }
    std::uint32_t light_count() const { return static_cast<std::uint32_t>(positions.size()); }
    restir::LightSample sample_point(std::uint32_t id, glm::vec2) const {
        restir::LightSample p;
        p.position = positions[id];
        p.normal = normals[id];
        p.radiance = glm::vec3(powers[id]);
        p.area_pdf = 1.0f;
        p.is_delta = true;
        return p;
    }
};

// What a light gives a point x with normal n, by the same bound (exact for a point light but
// for the falloff's clamp): positive only where the region's bound is.
double contribution(const Lights& lights, std::uint32_t id, glm::vec3 x, glm::vec3 n) {
    return static_cast<double>(
        restir::light_importance(lights.nodes[id], restir::ShadingPoint{x, n}));
}

// An entry's 1 / pdf is an unbiased contribution weight at every point that can look its cell
// up: the mean of f(Y) / pdf over fresh tiles is the sum of f over the lights, within 4
// standard errors measured over the trials.
TEST(LightGrid, EntriesAreUnbiasedAtEveryPointOfTheirRegion) {
    const Lights lights(200u);
    const restir::AliasTable table(lights.powers);
    const restir::PowerLightSampler sampler{table.view()};
    const auto grid = restir::LightGridLayout::over({0.0f, 0.0f, 0.0f}, {10.0f, 4.0f, 10.0f}, 5u);
    const auto node_of = [&](std::uint32_t id) -> const restir::LightBvhNode& {
        return lights.nodes[id];
    };
    constexpr std::uint32_t entries = 4, per_entry = 8;
    std::vector<restir::GridCandidate> scratch(entries * per_entry);
    const struct {
        glm::vec3 point, normal;
    } cases[] = {{{0.2f, 0.1f, 0.3f}, {0.0f, 1.0f, 0.0f}},
                 {{5.0f, 2.0f, 5.0f}, {0.0f, 0.0f, 0.0f}},
                 {{9.9f, 3.9f, 0.1f}, {0.0f, -1.0f, 0.0f}},
                 {{3.0f, 1.0f, 7.0f}, {0.6f, 0.0f, 0.8f}}};
    for (const auto& c : cases) {
        restir::Pcg32 jitter = restir::make_pixel_rng(13u, 0u, 0u, 17u);
        for (int look_up = 0; look_up < 3; ++look_up) {
            const float u = next_float(jitter), v = next_float(jitter);
            const std::uint32_t cell =
                grid.jittered_cell_of(c.point, glm::vec3(u, v, next_float(jitter)));
            double truth = 0.0;
            for (std::uint32_t id = 0; id < lights.light_count(); ++id)
                truth += contribution(lights, id, c.point, c.normal);
            ASSERT_GT(truth, 0.0);
            restir::test::RunningStats estimate;
            for (std::uint32_t trial = 0; trial < 20000u; ++trial) {
                restir::Pcg32 rng = restir::make_pixel_rng(trial, cell, 1u, 19u);
                double sum = 0.0;
                restir::resample_grid_tile(
                    sampler, grid.cell_region(cell), node_of, lights, rng, entries, per_entry,
                    scratch.data(), [&](std::uint32_t, const restir::PresampledLight& e) {
                        if (e.pdf > 0.0f)
                            sum += contribution(lights, e.reference.light_id, c.point, c.normal) /
                                   static_cast<double>(e.pdf);
                    });
                estimate.add(sum / entries);
            }
            EXPECT_LT(std::abs(estimate.mean() - truth), 4.0 * estimate.standard_error())
                << "cell " << cell << ": " << estimate.mean() << " against " << truth;
            EXPECT_LT(estimate.standard_error(), 0.05 * truth); // the test can see a bias
        }
    }
}

// Without candidates, or with no light that can reach the region, the entries are empty.
TEST(LightGrid, EntriesWithoutLightsAreEmpty) {
    const Lights lights(10u);
    const restir::AliasTable table(lights.powers);
    const restir::PowerLightSampler sampler{table.view()};
    const auto node_of = [&](std::uint32_t id) -> const restir::LightBvhNode& {
        return lights.nodes[id];
    };
    // Every light faces +x with a narrow cone; the region lies far behind them.
    Lights facing(10u);
    for (std::uint32_t id = 0; id < facing.light_count(); ++id) {
        restir::LightBounds b =
            restir::point_light_bounds(facing.positions[id], {1.0f, 0.0f, 0.0f}, facing.powers[id]);
        facing.nodes[id] = restir::light_bvh_node(b);
    }
    const auto facing_node = [&](std::uint32_t id) -> const restir::LightBvhNode& {
        return facing.nodes[id];
    };
    const restir::ShadingPoint behind{{-100.0f, 2.0f, 5.0f}, glm::vec3(0.0f), 1.0f};
    std::vector<restir::GridCandidate> scratch(8u * 4u);
    restir::Pcg32 rng = restir::make_pixel_rng(31u, 0u, 0u, 37u);
    int stored = 0;
    const auto expect_empty = [&](std::uint32_t, const restir::PresampledLight& e) {
        EXPECT_EQ(e.pdf, 0.0f);
        ++stored;
    };
    restir::resample_grid_tile(sampler, behind, facing_node, facing, rng, 8u, 4u, scratch.data(),
                               expect_empty);
    restir::resample_grid_tile(sampler, behind, node_of, lights, rng, 8u, 0u, nullptr,
                               expect_empty);
    EXPECT_EQ(stored, 16);
}

// Entries take lights that matter at the region: far more often than power alone would.
TEST(LightGrid, EntriesFavourTheRegionsLights) {
    const Lights lights(200u);
    const restir::AliasTable table(lights.powers);
    const restir::PowerLightSampler sampler{table.view()};
    const auto grid = restir::LightGridLayout::over({0.0f, 0.0f, 0.0f}, {10.0f, 4.0f, 10.0f}, 10u);
    const std::uint32_t cell = grid.cell_of({1.0f, 1.0f, 1.0f});
    const restir::ShadingPoint region = grid.cell_region(cell);
    const auto node_of = [&](std::uint32_t id) -> const restir::LightBvhNode& {
        return lights.nodes[id];
    };
    // The lights within the region's radius of its centre, and how often power draws them.
    std::vector<bool> near(lights.light_count());
    double near_by_power = 0.0;
    for (std::uint32_t id = 0; id < lights.light_count(); ++id) {
        near[id] = glm::length(lights.positions[id] - region.position) < region.radius;
        near_by_power += near[id] ? static_cast<double>(table.pmf(id)) : 0.0;
    }
    ASSERT_GT(near_by_power, 0.0);
    constexpr std::uint32_t entries = 64, per_entry = 32;
    std::vector<restir::GridCandidate> scratch(entries * per_entry);
    restir::Pcg32 rng = restir::make_pixel_rng(23u, 0u, 0u, 29u);
    std::uint32_t near_entries = 0;
    for (int tile = 0; tile < 20; ++tile)
        restir::resample_grid_tile(sampler, region, node_of, lights, rng, entries, per_entry,
                                   scratch.data(),
                                   [&](std::uint32_t, const restir::PresampledLight& e) {
                                       near_entries += near[e.reference.light_id] ? 1u : 0u;
                                   });
    EXPECT_GT(near_entries / (20.0 * entries), 3.0 * near_by_power);
}

} // namespace
