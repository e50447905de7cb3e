// Solid-angle sampling of triangles: the solid angle against known values, Arvo's directions
// against a chi-square over midpoint-subdivided sub-triangles, the points on the triangle with
// pdf 1 / solid angle, the area/solid-angle conversions, the front end's switch and its pdf,
// and degenerate input.
#include <restir/core/rng.hpp>
#include <restir/light/solid_angle.hpp>
#include <restir/light/spherical_triangle.hpp>
#include <restir/light/triangle_light.hpp>

#include "support/chi2.hpp"

#include <gtest/gtest.h>

#include <glm/geometric.hpp>

#include <array>
#include <cmath>
#include <vector>

namespace {

using restir::SolidAngleSample;

struct Triangle {
    glm::vec3 a, b, c;
};

struct Configuration {
    const char* name;
    glm::vec3 from;
    Triangle triangle;
};

// Close and large, far and small, grazing, obtuse, a sliver, very far (3e-12 sr: below the
// front end's switch, where its area sampling is uniform in solid angle to within 1e-5).
const std::array<Configuration, 6> configurations = {{
    {"close and large",
     {0.2f, 0.1f, 0.15f},
     {{-1.0f, -1.0f, 0.0f}, {1.5f, -0.8f, 0.0f}, {0.1f, 1.2f, 0.0f}}},
    {"far and small",
     {3.0f, -2.0f, 40.0f},
     {{0.0f, 0.0f, 0.0f}, {0.3f, 0.05f, 0.1f}, {0.1f, 0.25f, 0.0f}}},
    {"grazing", {6.0f, 0.3f, 0.05f}, {{0.0f, 0.0f, 0.0f}, {1.0f, 0.2f, 0.0f}, {0.3f, 0.9f, 0.0f}}},
    {"obtuse", {0.4f, 0.3f, 0.7f}, {{-2.0f, 0.0f, 0.0f}, {2.0f, 0.0f, 0.0f}, {0.3f, 0.15f, 0.0f}}},
    {"sliver", {0.5f, -0.3f, 3.0f}, {{0.0f, 0.0f, 0.0f}, {1.0f, 0.0f, 0.0f}, {0.5f, 0.05f, 0.0f}}},
    {"very far",
     {0.4f, -0.3f, 4.0e5f},
     {{0.0f, 0.0f, 0.0f}, {1.0f, 0.2f, 0.0f}, {0.3f, 0.9f, 0.0f}}},
}};

// Barycentrics of `p` (projected on the triangle's plane), in double.
std::array<double, 3> barycentrics(const Triangle& t, glm::vec3 p) {
    const glm::dvec3 a(t.a), b(t.b), c(t.c), x(p);
    const glm::dvec3 n = glm::cross(b - a, c - a);
    const double nn = glm::dot(n, n);
    const double lb = glm::dot(glm::cross(x - a, c - a), n) / nn;
    const double lc = glm::dot(glm::cross(b - a, x - a), n) / nn;
    return {1.0 - lb - lc, lb, lc};
}

// The sub-triangles of `levels` midpoint subdivisions, in the order of `cell_of`: the corner
// children at a, b, c, then the middle one.
void subdivide(const Triangle& t, int levels, std::vector<Triangle>& out) {
    if (levels == 0) {
        out.push_back(t);
        return;
    }
    const glm::vec3 ab = 0.5f * (t.a + t.b), ac = 0.5f * (t.a + t.c), bc = 0.5f * (t.b + t.c);
    subdivide({t.a, ab, ac}, levels - 1, out);
    subdivide({ab, t.b, bc}, levels - 1, out);
    subdivide({ac, bc, t.c}, levels - 1, out);
    subdivide({bc, ac, ab}, levels - 1, out);
}

// The sub-triangle that holds the point of barycentrics `l`.
std::size_t cell_of(std::array<double, 3> l, int levels) {
    std::size_t index = 0;
    for (int level = 0; level < levels; ++level) {
        std::size_t child = 3;
        for (std::size_t i = 0; i < 3; ++i)
            if (l[i] >= 0.5)
                child = i;
        for (std::size_t i = 0; i < 3; ++i)
            l[i] = child == 3 ? 1.0 - 2.0 * l[i] : i == child ? 2.0 * l[i] - 1.0 : 2.0 * l[i];
        index = index * 4 + child;
    }
    return index;
}

constexpr int levels = 3; // 64 sub-triangles
constexpr int sample_count = 200000;

// Draws from `sampler` and checks the points, their pdf and the chi-square of the sub-triangles.
template <class Sampler>
void check_uniform_in_solid_angle(const Configuration& config, Sampler sampler, double alpha) {
    const Triangle& t = config.triangle;
    const float total = restir::spherical_triangle_solid_angle(config.from, t.a, t.b, t.c);
    ASSERT_GT(total, 0.0f) << config.name;
    std::vector<Triangle> cells;
    subdivide(t, levels, cells);
    std::vector<double> pmf;
    for (const Triangle& cell : cells)
        pmf.push_back(static_cast<double>(restir::spherical_triangle_solid_angle(
                          config.from, cell.a, cell.b, cell.c)) /
                      static_cast<double>(total));
    std::vector<double> observed(cells.size(), 0.0);
    restir::Pcg32 rng = restir::make_pixel_rng(7u, 3u, 11u);
    int off_triangle = 0, wrong_pdf = 0;
    for (int i = 0; i < sample_count; ++i) {
        const float u0 = restir::next_float(rng);
        const float u1 = restir::next_float(rng);
        const SolidAngleSample s = sampler(config.from, t, glm::vec2(u0, u1));
        wrong_pdf += std::fabs(s.pdf * total - 1.0f) > 1e-5f;
        const std::array<double, 3> l = barycentrics(t, s.point);
        off_triangle += l[0] < -1e-4 || l[1] < -1e-4 || l[2] < -1e-4;
        observed[cell_of(l, levels)] += 1.0;
    }
    EXPECT_EQ(off_triangle, 0) << config.name;
    EXPECT_EQ(wrong_pdf, 0) << config.name;
    EXPECT_TRUE(restir::test::fits_distribution(observed, pmf, alpha)) << config.name;
}

TEST(SphericalTriangle, SolidAngleOfKnownShapes) {
    // An octant's face triangle: pi / 2; either winding.
    const glm::vec3 o(0.0f), x(1.0f, 0.0f, 0.0f), y(0.0f, 1.0f, 0.0f), z(0.0f, 0.0f, 1.0f);
    EXPECT_NEAR(restir::spherical_triangle_solid_angle(o, x, y, z), restir::pi / 2.0f, 1e-6f);
    EXPECT_NEAR(restir::spherical_triangle_solid_angle(o, x, z, y), restir::pi / 2.0f, 1e-6f);
    // A small triangle far away: area cos / d^2 to first order.
    const float far = restir::spherical_triangle_solid_angle(glm::vec3(0.0f, 0.0f, 1000.0f), o,
                                                             0.01f * x, 0.01f * y);
    EXPECT_NEAR(far, 0.5e-4f / 1e6f, 1e-4f * 0.5e-10f);
    // Four sub-triangles sum to the whole.
    for (const Configuration& config : configurations) {
        std::vector<Triangle> cells;
        subdivide(config.triangle, 1, cells);
        double sum = 0.0;
        for (const Triangle& cell : cells)
            sum += static_cast<double>(
                restir::spherical_triangle_solid_angle(config.from, cell.a, cell.b, cell.c));
        const Triangle& t = config.triangle;
        const double total =
            static_cast<double>(restir::spherical_triangle_solid_angle(config.from, t.a, t.b, t.c));
        EXPECT_NEAR(sum / total, 1.0, 1e-4) << config.name;
    }
}

TEST(SphericalTriangle, DirectionsAreUniformInTheSolidAngle) {
    const double alpha = restir::test::sidak_significance(0.01, 2 * configurations.size());
    for (const Configuration& config : configurations)
        check_uniform_in_solid_angle(
            config,
            [](glm::vec3 from, const Triangle& t, glm::vec2 u) {
                return restir::sample_spherical_triangle(from, t.a, t.b, t.c, u);
            },
            alpha);
}

TEST(TriangleFrom, IsUniformInSolidAngleAndAgreesWithItsPdf) {
    const double alpha = restir::test::sidak_significance(0.01, 2 * configurations.size());
    const Triangle& last = configurations.back().triangle;
    EXPECT_LT(
        restir::spherical_triangle_solid_angle(configurations.back().from, last.a, last.b, last.c),
        restir::min_solid_angle_for_arvo);
    for (const Configuration& config : configurations) {
        check_uniform_in_solid_angle(
            config,
            [](glm::vec3 from, const Triangle& tri, glm::vec2 u) {
                const SolidAngleSample s =
                    restir::sample_triangle_from(from, tri.a, tri.b, tri.c, u);
                EXPECT_FLOAT_EQ(restir::triangle_pdf_from(from, tri.a, tri.b, tri.c, s.point),
                                s.pdf);
                return s;
            },
            alpha);
    }
}

TEST(TriangleFrom, SamplesByAreaBelowTheSwitchWithTheConvertedPdf) {
    // 1e-14 sr: below the switch, where the area density converted by d^2 / |cos| is returned.
    const Triangle t{{0.0f, 0.0f, 0.0f}, {1.0f, 0.2f, 0.0f}, {0.3f, 0.9f, 0.0f}};
    const glm::vec3 from(2.0e6f, 1.0e6f, 4.0e6f);
    ASSERT_LT(restir::spherical_triangle_solid_angle(from, t.a, t.b, t.c),
              restir::min_solid_angle_for_arvo);
    const glm::vec3 normal = glm::normalize(glm::cross(t.b - t.a, t.c - t.a));
    const float area = 0.5f * glm::length(glm::cross(t.b - t.a, t.c - t.a));
    restir::Pcg32 rng = restir::make_pixel_rng(1u, 2u, 3u);
    std::vector<double> observed(4, 0.0);
    constexpr int count = 20000;
    for (int i = 0; i < count; ++i) {
        const float u0 = restir::next_float(rng);
        const float u1 = restir::next_float(rng);
        const SolidAngleSample s = restir::sample_triangle_from(from, t.a, t.b, t.c, {u0, u1});
        const glm::vec3 offset = s.point - from;
        const float expected =
            glm::dot(offset, offset) / (area * std::fabs(glm::dot(normal, glm::normalize(offset))));
        ASSERT_NEAR(s.pdf / expected, 1.0f, 1e-4f);
        ASSERT_FLOAT_EQ(restir::triangle_pdf_from(from, t.a, t.b, t.c, s.point), s.pdf);
        const std::array<double, 3> l = barycentrics(t, s.point);
        ASSERT_GE(std::fmin(l[0], std::fmin(l[1], l[2])), -1e-5);
        observed[cell_of(l, 1)] += 1.0;
    }
    // Uniform in area: each midpoint sub-triangle a quarter.
    EXPECT_TRUE(restir::test::fits_distribution(observed, {0.25, 0.25, 0.25, 0.25}, 0.01));
}

TEST(SolidAnglePdf, ConvertsBetweenAreaAndSolidAngle) {
    const glm::vec3 from(0.0f), point(0.0f, 3.0f, 4.0f); // d = 5
    const glm::vec3 normal(0.0f, 0.0f, -1.0f);           // |cos| = 4 / 5
    EXPECT_FLOAT_EQ(restir::solid_angle_to_area_pdf(2.0f, from, point, normal),
                    2.0f * 0.8f / 25.0f);
    EXPECT_FLOAT_EQ(restir::area_to_solid_angle_pdf(2.0f, from, point, normal),
                    2.0f * 25.0f / 0.8f);
    EXPECT_FLOAT_EQ(
        restir::area_to_solid_angle_pdf(restir::solid_angle_to_area_pdf(0.7f, from, point, normal),
                                        from, point, normal),
        0.7f);
    // Degenerate: at the point, or grazing.
    EXPECT_EQ(restir::solid_angle_to_area_pdf(1.0f, point, point, normal), 0.0f);
    EXPECT_EQ(restir::area_to_solid_angle_pdf(1.0f, point, point, normal), 0.0f);
    EXPECT_EQ(restir::area_to_solid_angle_pdf(1.0f, from, point, glm::vec3(1.0f, 0.0f, 0.0f)),
              0.0f);
}

TEST(SphericalTriangle, DegenerateInputGivesZeroPdfAndNoNaN) {
    const Triangle t{{0.0f, 0.0f, 0.0f}, {1.0f, 0.0f, 0.0f}, {0.0f, 1.0f, 0.0f}};
    struct Case {
        glm::vec3 from;
        Triangle triangle;
    };
    const std::array<Case, 7> cases = {{
        {{0.2f, 0.2f, 0.0f}, t},                      // in the plane, inside
        {{3.0f, 2.0f, 0.0f}, t},                      // in the plane, beside
        {t.b, t},                                     // at a vertex
        {{0.5f, 0.0f, 0.0f}, t},                      // on an edge
        {{0.2f, 0.2f, 1.0f}, {t.a, t.a, t.c}},        // two equal vertices
        {{0.2f, 0.2f, 1.0f}, {t.a, t.b, 2.0f * t.b}}, // collinear
        {{0.2f, 0.2f, 1.0f}, {t.a, t.a, t.a}},        // a point
    }};
    restir::Pcg32 rng = restir::make_pixel_rng(5u, 0u, 1u);
    for (const Case& c : cases) {
        const Triangle& d = c.triangle;
        EXPECT_EQ(restir::spherical_triangle_solid_angle(c.from, d.a, d.b, d.c), 0.0f);
        for (int i = 0; i < 64; ++i) {
            const glm::vec2 u(restir::next_float(rng), restir::next_float(rng));
            const SolidAngleSample arvo =
                restir::sample_spherical_triangle(c.from, d.a, d.b, d.c, u);
            const SolidAngleSample front = restir::sample_triangle_from(c.from, d.a, d.b, d.c, u);
            EXPECT_EQ(arvo.pdf, 0.0f);
            EXPECT_EQ(front.pdf, 0.0f);
            EXPECT_TRUE(std::isfinite(front.point.x) && std::isfinite(front.point.y) &&
                        std::isfinite(front.point.z));
            EXPECT_EQ(restir::triangle_pdf_from(c.from, d.a, d.b, d.c, front.point), 0.0f);
        }
    }
}

} // namespace
