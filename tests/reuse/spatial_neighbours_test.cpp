// The spatial pass's neighbours: the offset table, its random rotation, the rounding of a
// rotated offset to a pixel (defined for any radius, rotation and pixel), and the isotropy of
// the neighbours found.
#include <restir/restir.hpp>

#include <gtest/gtest.h>

#include <algorithm>
#include <cmath>
#include <cstdint>
#include <limits>
#include <set>
#include <utility>
#include <vector>

namespace {

using restir::PixelCoord;

TEST(NeighbourOffsets, LieInTheUnitDiskAndAreDistinctAndSpread) {
    constexpr restir::NeighbourOffsets table = restir::make_neighbour_offsets();
    std::set<std::pair<float, float>> distinct;
    int quadrant[4] = {0, 0, 0, 0};
    for (std::uint32_t i = 0; i < restir::neighbour_offset_count; ++i) {
        const restir::DiskOffset o = table[i];
        EXPECT_LE(o.x * o.x + o.y * o.y, 1.0f);
        distinct.insert({o.x, o.y});
        ++quadrant[(o.x < 0.0f ? 0 : 1) + (o.y < 0.0f ? 0 : 2)];
    }
    EXPECT_EQ(distinct.size(), restir::neighbour_offset_count);
    // A low-discrepancy set puts close to a quarter of the points in each quadrant.
    for (int q : quadrant) {
        EXPECT_GE(q, 12);
        EXPECT_LE(q, 20);
    }
    EXPECT_EQ(table[restir::neighbour_offset_count + 5u].x, table[5u].x);
}

TEST(SpatialReuse, NeighbourRotationIsCosineAndSineOfTwoPiU) {
    double worst = 0.0;
    for (std::uint32_t k = 0; k < 100'000u; ++k) {
        const float u = static_cast<float>(k) / 100'000.0f;
        const restir::DiskOffset r = restir::neighbour_rotation(u);
        const double angle = 6.283185307179586 * static_cast<double>(u);
        worst = std::max({worst, std::abs(static_cast<double>(r.x) - std::cos(angle)),
                          std::abs(static_cast<double>(r.y) - std::sin(angle))});
    }
    EXPECT_LT(worst, 4e-7);
    for (const float u : {-0.25f, 1.25f, 1e30f, -1e-30f, std::numeric_limits<float>::infinity(),
                          std::numeric_limits<float>::quiet_NaN()}) {
        const restir::DiskOffset r = restir::neighbour_rotation(u);
        EXPECT_NEAR(static_cast<double>(r.x * r.x + r.y * r.y), 1.0, 1e-6) << u;
    }
    EXPECT_NEAR(static_cast<double>(restir::neighbour_rotation(-0.25f).y), -1.0, 1e-6); // 3/4 turn
}

// A radius that no int offset can hold (or NaN) is clamped, not converted with undefined
// behaviour (caught by the sanitised build); the history cap saturates instead of wrapping.
TEST(SpatialReuse, HugeOrNanRadiusIsClamped) {
    const restir::NeighbourOffsets offsets = restir::make_neighbour_offsets();
    for (float radius : {1e10f, std::numeric_limits<float>::infinity(),
                         std::numeric_limits<float>::quiet_NaN(), -5.0f})
        for (std::uint32_t i = 0; i < 8u; ++i) {
            const PixelCoord n = restir::spatial_neighbour({3, 4}, 5u, i, radius, offsets,
                                                           restir::neighbour_rotation(0.3f));
            EXPECT_LE(std::abs(static_cast<double>(n.x)), 16777216.0 + 4.0) << radius;
            EXPECT_LE(std::abs(static_cast<double>(n.y)), 16777216.0 + 5.0) << radius;
            if (!(radius > 0.0f)) {
                EXPECT_EQ(n.x, 3);
                EXPECT_EQ(n.y, 4);
            }
        }
    // Any rotation (NaN, huge) and any pixel (at the ends of the int range) give a defined,
    // saturated result.
    const float nan = std::numeric_limits<float>::quiet_NaN();
    constexpr std::int32_t lowest = std::numeric_limits<std::int32_t>::min();
    constexpr std::int32_t highest = std::numeric_limits<std::int32_t>::max();
    for (const restir::DiskOffset rotation :
         {restir::DiskOffset{nan, nan}, restir::DiskOffset{1e30f, -1e30f},
          restir::neighbour_rotation(nan)})
        for (std::uint32_t i = 0; i < 8u; ++i) {
            const PixelCoord n =
                restir::spatial_neighbour({highest, lowest}, 5u, i, 1e6f, offsets, rotation);
            EXPECT_GE(n.x, highest - 16777217);
            EXPECT_LE(n.y, lowest + 16777217);
        }
    EXPECT_EQ(restir::offset_coordinate(highest, 3.0f), highest);
    EXPECT_EQ(restir::offset_coordinate(lowest, -3.0f), lowest);
    EXPECT_EQ(restir::offset_coordinate(10, -2.6f), 7);
    EXPECT_EQ(restir::offset_coordinate(10, 2.4f), 12);
    EXPECT_EQ(restir::offset_coordinate(10, nan), 10);
    // Rounded half away from zero after clamping to 2^24, as the formula with branches on the
    // sign rounds (the library's is without branches), at the halves and the clamp's ends and for
    // random offsets of either sign.
    const auto rounded = [](std::int32_t c, float offset) {
        const float clamped = offset > 0.0f   ? std::min(offset, 16777216.0f) + 0.5f
                              : offset < 0.0f ? std::max(offset, -16777216.0f) - 0.5f
                                              : 0.0f;
        return static_cast<std::int32_t>(std::int64_t{c} + static_cast<std::int64_t>(clamped));
    };
    const float infinity = std::numeric_limits<float>::infinity();
    std::vector<float> cases = {0.0f, 0.49999997f, 0.5f,        0.50000006f, 1.5f,     2.5f,
                                1e7f, 16777216.0f, 16777218.0f, 3e7f,        infinity, 1e-30f};
    restir::Pcg32 numbers = restir::make_pixel_rng(5u, 0u, 0u);
    for (int i = 0; i < 1000; ++i)
        cases.push_back(200.0f * next_float(numbers) - 100.0f);
    for (const float offset : cases)
        for (const float sign : {1.0f, -1.0f}) {
            EXPECT_EQ(restir::offset_coordinate(10, sign * offset), rounded(10, sign * offset))
                << sign * offset;
            EXPECT_EQ(restir::offset_coordinate(-7, sign * offset), rounded(-7, sign * offset))
                << sign * offset;
        }
    EXPECT_EQ(restir::offset_coordinate(10, -0.5f), 9);
    EXPECT_EQ(restir::offset_coordinate(10, 0.5f), 11);
    EXPECT_EQ(restir::offset_coordinate(10, -infinity), 10 - 16777216);

    restir::TemporalParams params = restir::default_temporal_params();
    params.history_cap_multiplier = 3'000'000'000u;
    EXPECT_EQ(restir::history_cap(2u, params), 0xffffffffu); // 6e9 saturates, no wrap to 1.7e9
    params.history_cap_multiplier = 0u;
    EXPECT_EQ(restir::history_cap(2u, params), restir::no_candidate_cap);
}

// The offset table is rotated by a random angle per pixel: over many pixels the neighbours
// spread alike along x and y, stay inside the radius (plus rounding), and their mean is 0.
TEST(SpatialReuse, RotatedNeighboursAreIsotropic) {
    const restir::NeighbourOffsets offsets = restir::make_neighbour_offsets();
    restir::Pcg32 rng = restir::make_pixel_rng(0u, 0u, 0u, 42u);
    constexpr int trials = 20000;
    constexpr float radius = 10.0f;
    double sum_x = 0, sum_y = 0, sum_xx = 0, sum_yy = 0, sum_d = 0, sum_dd = 0;
    for (int t = 0; t < trials; ++t) {
        const restir::NeighbourDraw draw = restir::draw_neighbours(rng);
        const restir::DiskOffset rotation = draw.rotation;
        EXPECT_NEAR(rotation.x * rotation.x + rotation.y * rotation.y, 1.0f, 1e-5f);
        const PixelCoord n =
            restir::spatial_neighbour({0, 0}, draw.start, 0u, radius, offsets, rotation);
        const double x = n.x, y = n.y;
        EXPECT_LE(std::hypot(x, y), static_cast<double>(radius) + 1.0);
        sum_x += x;
        sum_y += y;
        sum_xx += x * x;
        sum_yy += y * y;
        const double d = x * x - y * y; // mean 0 when x and y spread alike
        sum_d += d;
        sum_dd += d * d;
    }
    const double n = trials;
    const double se_x = std::sqrt(sum_xx / n / n), se_y = std::sqrt(sum_yy / n / n);
    EXPECT_LT(std::abs(sum_x / n), 4.0 * se_x);
    EXPECT_LT(std::abs(sum_y / n), 4.0 * se_y);
    const double mean_d = sum_d / n;
    const double se_d = std::sqrt((sum_dd / n - mean_d * mean_d) / n);
    EXPECT_LT(std::abs(mean_d), 4.0 * se_d) << "E[x^2] " << sum_xx / n << ", E[y^2] " << sum_yy / n;
    // Without rotation a pixel sees only the table's 64 offsets.
    std::set<std::pair<int, int>> fixed, rotated;
    for (std::uint32_t start = 0; start < restir::neighbour_offset_count; ++start) {
        const PixelCoord f = restir::spatial_neighbour({0, 0}, start, 0u, radius, offsets);
        fixed.insert({f.x, f.y});
    }
    for (int t = 0; t < 2000; ++t) {
        const PixelCoord r = restir::spatial_neighbour(
            {0, 0}, static_cast<std::uint32_t>(t) % restir::neighbour_offset_count, 0u, radius,
            offsets, restir::neighbour_rotation(restir::next_float(rng)));
        rotated.insert({r.x, r.y});
    }
    EXPECT_LE(fixed.size(), restir::neighbour_offset_count);
    EXPECT_GT(rotated.size(), 3u * fixed.size()); // a disk of radius 10 holds ~300 pixels
}

// Asking for a drawn neighbourhood's data ahead touches only pixels inside the image, at every
// pixel and for any radius (the views assert it in debug builds, which the sanitizer build is).
TEST(SpatialReuse, PrefetchingNeighboursStaysInsideTheImage) {
    constexpr std::uint32_t width = 7u, height = 5u;
    const std::vector<restir::Reservoir<std::uint32_t>> reservoirs(width * height);
    const std::vector<float> surfaces(width * height);
    const restir::ImageView<const restir::Reservoir<std::uint32_t>> reservoir_view{
        reservoirs.data(), width, height};
    const restir::ImageView<const float> surface_view{surfaces.data(), width, height};
    const restir::NeighbourOffsets offsets = restir::make_neighbour_offsets();
    restir::Pcg32 rng = restir::make_pixel_rng(3u, 0u, 0u);
    std::uint32_t outside = 0u;
    for (const float radius : {0.0f, 2.0f, 30.0f, 1e9f, std::numeric_limits<float>::quiet_NaN()}) {
        restir::SpatialParams params = restir::default_spatial_params();
        params.radius = radius;
        params.neighbour_count = 15u;
        for (std::int32_t y = 0; y < static_cast<std::int32_t>(height); ++y)
            for (std::int32_t x = 0; x < static_cast<std::int32_t>(width); ++x) {
                const restir::NeighbourDraw draw = restir::draw_neighbours(rng);
                restir::prefetch_spatial_neighbours({x, y}, reservoir_view, surface_view, params,
                                                    offsets, draw);
                for (std::uint32_t i = 0; i < params.neighbour_count; ++i)
                    outside += reservoir_view.contains(restir::spatial_neighbour(
                                   {x, y}, draw.start, i, radius, offsets, draw.rotation))
                                   ? 0u
                                   : 1u;
            }
    }
    EXPECT_GT(outside, 1000u) << "most neighbours at the larger radii should fall outside";
}

} // namespace
