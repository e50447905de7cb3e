// Sampling of a spherical light's visible cap uniformly in its cone: a chi-square over cells in
// (cos theta, phi) of the cone, the points on the visible side of the sphere, the pdf, and a
// receiver inside or on the sphere.
#include <restir/core/rng.hpp>
#include <restir/light/sphere_light.hpp>

#include "support/chi2.hpp"

#include <gtest/gtest.h>

#include <glm/geometric.hpp>

#include <array>
#include <cmath>
#include <vector>

namespace {

struct SphereCase {
    const char* name;
    glm::vec3 from, centre;
    float radius;
};

TEST(SphereCone, DirectionsAreUniformInTheCone) {
    const std::array<SphereCase, 3> cases = {{
        {"close", {0.0f, 0.0f, 0.0f}, {0.3f, 1.0f, -0.2f}, 1.0f},
        {"far", {1.0f, 2.0f, 3.0f}, {-40.0f, 7.0f, 30.0f}, 0.5f},
        {"tiny", {0.0f, 0.0f, 0.0f}, {0.0f, 0.0f, -100.0f}, 1e-3f},
    }};
    constexpr int bins = 8, count = 200000;
    const double alpha = restir::test::sidak_significance(0.01, cases.size());
    for (const SphereCase& c : cases) {
        const glm::dvec3 axis = glm::dvec3(c.centre) - glm::dvec3(c.from);
        const double distance = glm::length(axis);
        const glm::dvec3 w = axis / distance;
        const double radius = static_cast<double>(c.radius);
        const double sin_max = radius / distance;
        const double one_minus_cos_max =
            sin_max * sin_max / (1.0 + std::sqrt(1.0 - sin_max * sin_max));
        const glm::dvec3 t = glm::normalize(
            glm::cross(w, std::fabs(w.x) < 0.5 ? glm::dvec3(1, 0, 0) : glm::dvec3(0, 1, 0)));
        const glm::dvec3 s = glm::cross(w, t);
        const float pdf = restir::sphere_cone_pdf(c.from, c.centre, c.radius);
        EXPECT_NEAR(static_cast<double>(pdf) * 2.0 * M_PI * one_minus_cos_max, 1.0, 1e-5) << c.name;
        std::vector<double> observed(bins * bins, 0.0);
        restir::Pcg32 rng = restir::make_pixel_rng(2u, 8u, 1u);
        int off_sphere = 0, wrong_pdf = 0;
        for (int k = 0; k < count; ++k) {
            const float u0 = restir::next_float(rng);
            const float u1 = restir::next_float(rng);
            const restir::SolidAngleSample sample =
                restir::sample_sphere_cone(c.from, c.centre, c.radius, {u0, u1});
            wrong_pdf += sample.pdf != pdf;
            const glm::dvec3 on = glm::dvec3(sample.point) - glm::dvec3(c.centre);
            const glm::dvec3 to_receiver = glm::dvec3(c.from) - glm::dvec3(sample.point);
            // On the sphere, and on the side that faces the receiver, within the rounding of
            // float coordinates of the size of the centre's.
            const double tolerance =
                1e-5 * radius + 5e-7 * static_cast<double>(glm::length(c.centre));
            off_sphere += std::fabs(glm::length(on) - radius) > tolerance ||
                          glm::dot(on, to_receiver) < -tolerance * glm::length(to_receiver);
            const glm::dvec3 d = glm::normalize(glm::dvec3(sample.point) - glm::dvec3(c.from));
            // 1 - cos theta, accurate for small angles: |d - w|^2 / 2.
            const double fraction = 0.5 * glm::dot(d - w, d - w) / one_minus_cos_max;
            const double phi = std::atan2(glm::dot(d, s), glm::dot(d, t)) + M_PI;
            const int i = std::min(bins - 1, std::max(0, static_cast<int>(fraction * bins)));
            const int j =
                std::min(bins - 1, std::max(0, static_cast<int>(phi / (2.0 * M_PI) * bins)));
            observed[static_cast<std::size_t>(j * bins + i)] += 1.0;
        }
        EXPECT_EQ(off_sphere, 0) << c.name;
        EXPECT_EQ(wrong_pdf, 0) << c.name;
        const std::vector<double> pmf(bins * bins, 1.0 / (bins * bins));
        EXPECT_TRUE(restir::test::fits_distribution(observed, pmf, alpha)) << c.name;
    }
}

TEST(SphereCone, InsideOrOnTheSphereGivesZeroPdf) {
    const glm::vec3 centre(1.0f, 2.0f, 3.0f);
    for (const glm::vec3 from :
         {centre, centre + glm::vec3(0.5f, 0.0f, 0.0f), centre + glm::vec3(0.0f, 1.0f, 0.0f)}) {
        EXPECT_EQ(restir::sphere_cone_pdf(from, centre, 1.0f), 0.0f);
        const restir::SolidAngleSample s =
            restir::sample_sphere_cone(from, centre, 1.0f, {0.3f, 0.6f});
        EXPECT_EQ(s.pdf, 0.0f);
        EXPECT_TRUE(std::isfinite(s.point.x) && std::isfinite(s.point.y) &&
                    std::isfinite(s.point.z));
    }
    EXPECT_EQ(restir::sphere_cone_pdf(glm::vec3(0.0f), centre, 0.0f), 0.0f);
}

} // namespace
