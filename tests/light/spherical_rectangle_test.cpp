// Solid-angle sampling of rectangles (Urena et al. 2013, and the front end that switches to
// Arvo's triangles where Urena's mapping loses precision): a chi-square over a grid of
// sub-rectangles weighted by their solid angles, the points on the rectangle with pdf
// 1 / solid angle, the front end's pdf function, and degenerate input.
#include <restir/core/rng.hpp>
#include <restir/light/rectangle_light.hpp>
#include <restir/light/spherical_rectangle.hpp>

#include "support/chi2.hpp"

#include <gtest/gtest.h>

#include <glm/geometric.hpp>

#include <array>
#include <cmath>
#include <vector>

namespace {

struct RectangleCase {
    const char* name;
    glm::vec3 from, corner, edge0, edge1;
};

// "very far" (6e-12 sr) lies below the front end's switch to area sampling.
const std::array<RectangleCase, 6> rectangle_cases = {{
    {"close and large",
     {0.3f, 0.2f, 0.1f},
     {-1.0f, -1.0f, 0.0f},
     {2.5f, 0.0f, 0.0f},
     {0.0f, 1.8f, 0.0f}},
    {"far and small",
     {2.0f, -3.0f, -30.0f},
     {0.0f, 0.0f, 0.0f},
     {0.2f, 0.1f, 0.0f},
     {-0.05f, 0.1f, 0.3f}},
    {"grazing", {5.0f, 0.4f, 0.05f}, {0.0f, 0.0f, 0.0f}, {1.0f, 0.0f, 0.0f}, {0.0f, 1.0f, 0.0f}},
    {"beside", {-0.5f, 1.5f, 0.4f}, {0.0f, 0.0f, 0.0f}, {0.0f, 2.0f, 0.0f}, {1.0f, 0.0f, 0.0f}},
    {"very far", {0.3f, 0.2f, 4.0e5f}, {0.0f, 0.0f, 0.0f}, {1.0f, 0.0f, 0.0f}, {0.0f, 1.0f, 0.0f}},
    {"above a corner",
     {0.0f, 0.0f, 1.0f},
     {0.0f, 0.0f, 0.0f},
     {1.0f, 0.0f, 0.0f},
     {0.0f, 3.0f, 0.0f}},
}};

TEST(SphericalRectangle, SolidAngleOfKnownShapes) {
    // A unit square seen from height 1 above a corner: a quarter of a cube's face seen from the
    // cube's centre, (4 pi / 6) / 4.
    const float quarter = restir::spherical_rectangle_solid_angle(
        glm::vec3(0.0f, 0.0f, 1.0f), glm::vec3(0.0f), glm::vec3(1.0f, 0.0f, 0.0f),
        glm::vec3(0.0f, 1.0f, 0.0f));
    EXPECT_NEAR(quarter, 4.0f * restir::pi / 24.0f, 1e-6f);
}

// Draws from `sampler` and checks the points, their pdf and the chi-square of the grid cells.
template <class Sampler>
void check_uniform_in_solid_angle(const RectangleCase& r, Sampler sampler, double alpha) {
    constexpr int grid = 8, count = 200000;
    const float total = restir::spherical_rectangle_solid_angle(r.from, r.corner, r.edge0, r.edge1);
    ASSERT_GT(total, 0.0f) << r.name;
    std::vector<double> pmf;
    for (int j = 0; j < grid; ++j)
        for (int i = 0; i < grid; ++i) {
            const glm::vec3 corner = r.corner + (static_cast<float>(i) / grid) * r.edge0 +
                                     (static_cast<float>(j) / grid) * r.edge1;
            const float cell = restir::spherical_rectangle_solid_angle(
                r.from, corner, r.edge0 / static_cast<float>(grid),
                r.edge1 / static_cast<float>(grid));
            pmf.push_back(static_cast<double>(cell) / static_cast<double>(total));
        }
    std::vector<double> observed(pmf.size(), 0.0);
    restir::Pcg32 rng = restir::make_pixel_rng(3u, 1u, 4u);
    int off_rectangle = 0, wrong_pdf = 0;
    for (int k = 0; k < count; ++k) {
        const float u0 = restir::next_float(rng);
        const float u1 = restir::next_float(rng);
        const restir::SolidAngleSample s = sampler(r, glm::vec2(u0, u1));
        wrong_pdf += std::fabs(s.pdf * total - 1.0f) > 1e-5f;
        const glm::dvec3 offset = glm::dvec3(s.point) - glm::dvec3(r.corner);
        const glm::dvec3 e0(r.edge0), e1(r.edge1);
        const double along0 = glm::dot(offset, e0) / glm::dot(e0, e0);
        const double along1 = glm::dot(offset, e1) / glm::dot(e1, e1);
        const glm::dvec3 normal = glm::normalize(glm::cross(e0, e1));
        off_rectangle += along0 < -1e-5 || along0 > 1.0 + 1e-5 || along1 < -1e-5 ||
                         along1 > 1.0 + 1e-5 ||
                         std::fabs(glm::dot(offset, normal)) > 1e-5 * glm::length(e0);
        const int i = std::min(grid - 1, std::max(0, static_cast<int>(along0 * grid)));
        const int j = std::min(grid - 1, std::max(0, static_cast<int>(along1 * grid)));
        observed[static_cast<std::size_t>(j * grid + i)] += 1.0;
    }
    EXPECT_EQ(off_rectangle, 0) << r.name;
    EXPECT_EQ(wrong_pdf, 0) << r.name;
    EXPECT_TRUE(restir::test::fits_distribution(observed, pmf, alpha)) << r.name;
}

TEST(SphericalRectangle, DirectionsAreUniformInTheSolidAngle) {
    // Urena et al.'s mapping on its own, where the front end uses it.
    const double alpha = restir::test::sidak_significance(0.01, 2 * rectangle_cases.size());
    int checked = 0;
    for (const RectangleCase& r : rectangle_cases) {
        if (restir::spherical_rectangle_solid_angle(r.from, r.corner, r.edge0, r.edge1) <
            restir::min_solid_angle_for_urena)
            continue;
        ++checked;
        check_uniform_in_solid_angle(
            r,
            [](const RectangleCase& c, glm::vec2 u) {
                return restir::sample_spherical_rectangle(c.from, c.corner, c.edge0, c.edge1, u);
            },
            alpha);
    }
    EXPECT_EQ(checked, 3);
}

TEST(RectangleFrom, IsUniformInSolidAngleAndAgreesWithItsPdf) {
    // Every case: the small and the grazing ones below Urena's switch, on Arvo's triangles.
    const double alpha = restir::test::sidak_significance(0.01, 2 * rectangle_cases.size());
    for (const RectangleCase& r : rectangle_cases)
        check_uniform_in_solid_angle(
            r,
            [](const RectangleCase& c, glm::vec2 u) {
                const restir::SolidAngleSample s =
                    restir::sample_rectangle_from(c.from, c.corner, c.edge0, c.edge1, u);
                EXPECT_FLOAT_EQ(
                    restir::rectangle_pdf_from(c.from, c.corner, c.edge0, c.edge1, s.point), s.pdf);
                return s;
            },
            alpha);
}

TEST(SphericalRectangle, DegenerateInputGivesZeroPdfAndNoNaN) {
    const glm::vec3 corner(0.0f), e0(1.0f, 0.0f, 0.0f), e1(0.0f, 1.0f, 0.0f);
    struct Case {
        glm::vec3 from, edge0, edge1;
    };
    const std::array<Case, 5> cases = {{
        {{0.5f, 0.5f, 0.0f}, e0, e1},              // in the plane, inside
        {{3.0f, -2.0f, 0.0f}, e0, e1},             // in the plane, beside
        {corner, e0, e1},                          // at a corner
        {{0.5f, 0.5f, 1.0f}, glm::vec3(0.0f), e1}, // a zero edge
        {{0.5f, 0.5f, 1.0f}, e0, 2.0f * e0},       // parallel edges
    }};
    restir::Pcg32 rng = restir::make_pixel_rng(9u, 0u, 1u);
    for (const Case& c : cases) {
        EXPECT_EQ(restir::spherical_rectangle_solid_angle(c.from, corner, c.edge0, c.edge1), 0.0f);
        for (int i = 0; i < 64; ++i) {
            const glm::vec2 u(restir::next_float(rng), restir::next_float(rng));
            const restir::SolidAngleSample s =
                restir::sample_spherical_rectangle(c.from, corner, c.edge0, c.edge1, u);
            const restir::SolidAngleSample front =
                restir::sample_rectangle_from(c.from, corner, c.edge0, c.edge1, u);
            EXPECT_EQ(s.pdf, 0.0f);
            EXPECT_EQ(front.pdf, 0.0f);
            EXPECT_EQ(restir::rectangle_pdf_from(c.from, corner, c.edge0, c.edge1, front.point),
                      0.0f);
            EXPECT_TRUE(std::isfinite(s.point.x) && std::isfinite(s.point.y) &&
                        std::isfinite(s.point.z));
            EXPECT_TRUE(std::isfinite(front.point.x) && std::isfinite(front.point.y) &&
                        std::isfinite(front.point.z));
        }
    }
}

} // namespace
