// Unbiasedness of solid-angle light sampling: the irradiance from a uniformly emitting triangle
// and rectangle estimated with L max(0, n.w) max(0, -n_l.w) / (d^2 pdf_area) from solid-angle
// samples (and, as the check of the exact value's sign convention, from area samples) against
// Lambert's polygon formula; and the firefly fix measured: next to the light, the solid-angle
// estimator's standard error against area sampling's.
#include <restir/core/rng.hpp>
#include <restir/light/solid_angle.hpp>
#include <restir/light/spherical_rectangle.hpp>
#include <restir/light/spherical_triangle.hpp>
#include <restir/light/triangle_light.hpp>

#include "support/statistics.hpp"

#include <gtest/gtest.h>

#include <glm/geometric.hpp>

#include <cmath>
#include <cstddef>
#include <cstdio>
#include <vector>

namespace {

using restir::test::RunningStats;

constexpr double radiance = 2.0;

// Lambert's formula for a polygon of vertices `v` (in order; the emitting normal is that of
// the right-hand rule, cross(v1 - v0, v2 - v0)) wholly above the receiver's horizon and facing
// it: E = -L / 2 sum_i theta_i n.normalize(v_i x v_{i+1}), v relative to the receiver. The
// sign is the one that the area-sampling estimate below agrees with.
double polygon_irradiance(const std::vector<glm::vec3>& vertices, glm::vec3 receiver,
                          glm::vec3 normal) {
    double sum = 0.0;
    for (std::size_t i = 0; i < vertices.size(); ++i) {
        const glm::dvec3 v0 = glm::dvec3(vertices[i]) - glm::dvec3(receiver);
        const glm::dvec3 v1 =
            glm::dvec3(vertices[(i + 1) % vertices.size()]) - glm::dvec3(receiver);
        const double theta = std::atan2(glm::length(glm::cross(v0, v1)), glm::dot(v0, v1));
        sum += theta * glm::dot(glm::dvec3(normal), glm::normalize(glm::cross(v0, v1)));
    }
    return -0.5 * radiance * sum;
}

// One sample's irradiance estimate from a point with area density `area_pdf`.
double estimate(glm::vec3 point, double area_pdf, glm::vec3 receiver, glm::vec3 normal,
                glm::vec3 light_normal) {
    if (!(area_pdf > 0.0))
        return 0.0;
    const glm::dvec3 offset = glm::dvec3(point) - glm::dvec3(receiver);
    const double d2 = glm::dot(offset, offset);
    const glm::dvec3 w = offset / std::sqrt(d2);
    return radiance * std::fmax(0.0, glm::dot(glm::dvec3(normal), w)) *
           std::fmax(0.0, -glm::dot(glm::dvec3(light_normal), w)) / (d2 * area_pdf);
}

struct TriangleLight {
    glm::vec3 a, b, c;
    glm::vec3 normal() const { return glm::normalize(glm::cross(b - a, c - a)); }
    float area() const { return 0.5f * glm::length(glm::cross(b - a, c - a)); }
};

// Solid-angle (front end) and area estimates of the irradiance at (receiver, n).
void triangle_estimates(const TriangleLight& light, glm::vec3 receiver, glm::vec3 n, int count,
                        RunningStats& solid, RunningStats& area) {
    restir::Pcg32 rng = restir::make_pixel_rng(4u, 2u, 6u);
    for (int i = 0; i < count; ++i) {
        const glm::vec2 u(restir::next_float(rng), restir::next_float(rng));
        const restir::SolidAngleSample s =
            restir::sample_triangle_from(receiver, light.a, light.b, light.c, u);
        const float pdf = restir::solid_angle_to_area_pdf(s.pdf, receiver, s.point, light.normal());
        solid.add(estimate(s.point, static_cast<double>(pdf), receiver, n, light.normal()));
        const glm::vec3 p = restir::sample_triangle_area(light.a, light.b, light.c, u);
        area.add(estimate(p, 1.0 / static_cast<double>(light.area()), receiver, n, light.normal()));
    }
}

TEST(SolidAngleIrradiance, TriangleMatchesLambertsFormula) {
    // The light at z = 1 facing down; a tilted receiver below that sees it whole.
    const TriangleLight light{{-0.5f, -0.4f, 1.0f}, {0.2f, 0.9f, 1.0f}, {0.8f, -0.3f, 1.0f}};
    ASSERT_LT(light.normal().z, 0.0f);
    const glm::vec3 receiver(0.1f, 0.0f, 0.0f), n = glm::normalize(glm::vec3(0.3f, 0.2f, 1.0f));
    const double exact = polygon_irradiance({light.a, light.b, light.c}, receiver, n);
    RunningStats solid, area;
    triangle_estimates(light, receiver, n, 200000, solid, area);
    EXPECT_GT(exact, 0.0);
    EXPECT_TRUE(restir::test::agrees_with(area, exact));
    EXPECT_TRUE(restir::test::agrees_with(solid, exact));
}

TEST(SolidAngleIrradiance, RectangleMatchesLambertsFormula) {
    const glm::vec3 corner(-0.6f, -0.5f, 1.0f), e0(0.0f, 1.2f, 0.0f), e1(1.1f, 0.0f, 0.0f);
    const glm::vec3 light_normal = glm::normalize(glm::cross(e0, e1));
    ASSERT_LT(light_normal.z, 0.0f);
    const glm::vec3 receiver(0.0f, 0.1f, 0.2f), n = glm::normalize(glm::vec3(-0.2f, 0.1f, 1.0f));
    const double exact =
        polygon_irradiance({corner, corner + e0, corner + e0 + e1, corner + e1}, receiver, n);
    const double area_pdf = 1.0 / (1.2 * 1.1);
    RunningStats solid, area;
    restir::Pcg32 rng = restir::make_pixel_rng(8u, 2u, 6u);
    for (int i = 0; i < 200000; ++i) {
        const glm::vec2 u(restir::next_float(rng), restir::next_float(rng));
        const restir::SolidAngleSample s =
            restir::sample_spherical_rectangle(receiver, corner, e0, e1, u);
        const float pdf = restir::solid_angle_to_area_pdf(s.pdf, receiver, s.point, light_normal);
        solid.add(estimate(s.point, static_cast<double>(pdf), receiver, n, light_normal));
        area.add(estimate(corner + u.x * e0 + u.y * e1, area_pdf, receiver, n, light_normal));
    }
    EXPECT_GT(exact, 0.0);
    EXPECT_TRUE(restir::test::agrees_with(area, exact));
    EXPECT_TRUE(restir::test::agrees_with(solid, exact));
}

TEST(SolidAngleIrradiance, NextToTheLightTheErrorIsTenTimesLowerThanAreaSampling) {
    // A triangle of size 1 and a receiver 1e-3 below its centroid, facing it.
    const TriangleLight light{{0.0f, 0.0f, 1e-3f}, {0.0f, 1.0f, 1e-3f}, {1.0f, 0.0f, 1e-3f}};
    ASSERT_LT(light.normal().z, 0.0f);
    const glm::vec3 receiver(1.0f / 3.0f, 1.0f / 3.0f, 0.0f), n(0.0f, 0.0f, 1.0f);
    const double exact = polygon_irradiance({light.a, light.b, light.c}, receiver, n);
    // Area sampling's error comes from the rare points within a few d of the receiver's foot
    // (probability ~ 9 pi d^2 / area each within 3 d): enough samples that some land there.
    RunningStats solid, area;
    triangle_estimates(light, receiver, n, 1000000, solid, area);
    EXPECT_TRUE(restir::test::agrees_with(solid, exact));
    EXPECT_GE(area.standard_error(), 10.0 * solid.standard_error())
        << "area " << area.standard_error() << ", solid angle " << solid.standard_error();
    std::printf("next to the light: standard error %.3g (area) vs %.3g (solid angle)\n",
                area.standard_error(), solid.standard_error());
}

} // namespace
