// unshadowed_irradiance: VPLs with each falloff, area light samples, isotropic point lights.
#include <restir/restir.hpp>

#include <gtest/gtest.h>

#include <cmath>

namespace {

constexpr float pi = 3.14159265358979f;

// A VPL of reflected flux Phi at the origin facing up, and a receiver straight above facing down.
restir::Vpl vpl_at_origin(float flux) {
    return {glm::vec3(0.0f), {0.0f, 1.0f, 0.0f}, glm::vec3(flux), glm::vec3(0.5f)};
}

float irradiance_above(const restir::Vpl& vpl, float height, restir::Falloff falloff) {
    return restir::unshadowed_irradiance(restir::vpl_light_sample(vpl), {0.0f, height, 0.0f},
                                         {0.0f, -1.0f, 0.0f}, falloff)
        .x;
}

TEST(VplIrradiance, YukselIsFiniteAtTheVplAndExactFarAway) {
    const restir::Vpl vpl = vpl_at_origin(2.0f);
    const float radius = 0.1f;
    const restir::Falloff yuksel{restir::FalloffKind::yuksel, radius};
    const restir::Falloff exact{restir::FalloffKind::inverse_square, 0.0f};
    // At distance -> 0: Phi / pi * 2 / r^2, finite; the exact 1/d^2 grows without bound.
    const float near_value = irradiance_above(vpl, 1e-6f, yuksel);
    EXPECT_TRUE(std::isfinite(near_value));
    EXPECT_NEAR(near_value, 2.0f / pi * 2.0f / (radius * radius), 1e-3f * near_value);
    EXPECT_GT(irradiance_above(vpl, 1e-3f, exact), 100.0f * near_value);
    // Far away (d = 100 r) the two agree to (3/4) r^2 / d^2 = 7.5e-5.
    const float far = 100.0f * radius;
    EXPECT_NEAR(irradiance_above(vpl, far, yuksel) / irradiance_above(vpl, far, exact), 1.0f,
                1e-4f);
    EXPECT_FLOAT_EQ(irradiance_above(vpl, far, exact), 2.0f / pi / (far * far));
}

TEST(VplIrradiance, ClampedGeometryTermIsBounded) {
    const restir::Vpl vpl = vpl_at_origin(1.0f);
    const restir::Falloff clamped{restir::FalloffKind::clamped_inverse_square, 0.2f};
    EXPECT_FLOAT_EQ(irradiance_above(vpl, 0.0001f, clamped), 1.0f / pi / 0.04f);
    EXPECT_FLOAT_EQ(irradiance_above(vpl, 0.5f, clamped), 1.0f / pi / 0.25f);
}

TEST(VplIrradiance, CosineLobesOnBothSides) {
    const restir::Vpl vpl = vpl_at_origin(1.0f);
    const restir::Falloff exact{restir::FalloffKind::inverse_square, 0.0f};
    const restir::LightSample light = restir::vpl_light_sample(vpl);
    // Receiver at 60 degrees from the VPL normal, facing the VPL: one cosine of 1/2.
    const glm::vec3 receiver(std::sqrt(3.0f), 1.0f, 0.0f); // distance 2
    const glm::vec3 facing = -glm::normalize(receiver);
    EXPECT_NEAR(restir::unshadowed_irradiance(light, receiver, facing, exact).x,
                1.0f / pi * 0.5f / 4.0f, 1e-6f);
    // Behind the VPL, or a receiver facing away: nothing.
    EXPECT_EQ(
        restir::unshadowed_irradiance(light, {0.0f, -1.0f, 0.0f}, {0.0f, 1.0f, 0.0f}, exact).x,
        0.0f);
    EXPECT_EQ(restir::unshadowed_irradiance(light, {0.0f, 1.0f, 0.0f}, {0.0f, 1.0f, 0.0f}, exact).x,
              0.0f);
    // At the VPL's own position: zero, not NaN.
    EXPECT_EQ(restir::unshadowed_irradiance(light, glm::vec3(0.0f), {0.0f, 1.0f, 0.0f}, exact).x,
              0.0f);
}

TEST(LightIrradiance, AreaSamplesDivideByTheirDensityAndPointLightsAreIsotropic) {
    restir::LightSample area;
    area.position = {0.0f, 2.0f, 0.0f};
    area.normal = {0.0f, -1.0f, 0.0f};
    area.radiance = glm::vec3(3.0f);
    area.area_pdf = 4.0f; // a quarter of a unit square
    const restir::Falloff ignored{restir::FalloffKind::yuksel, 10.0f};
    EXPECT_FLOAT_EQ(
        restir::unshadowed_irradiance(area, glm::vec3(0.0f), {0.0f, 1.0f, 0.0f}, ignored).x,
        3.0f / (4.0f * 4.0f));

    restir::LightSample point;
    point.position = {0.0f, 0.0f, 2.0f};
    point.normal = glm::vec3(0.0f); // isotropic
    point.radiance = glm::vec3(5.0f);
    point.area_pdf = 1.0f;
    point.is_delta = true;
    const restir::Falloff exact{restir::FalloffKind::inverse_square, 0.0f};
    EXPECT_FLOAT_EQ(
        restir::unshadowed_irradiance(point, glm::vec3(0.0f), {0.0f, 0.0f, 1.0f}, exact).x,
        5.0f / 4.0f);
    EXPECT_FLOAT_EQ(
        restir::unshadowed_irradiance(point, glm::vec3(0.0f), {0.0f, 0.0f, -1.0f}, exact).x, 0.0f);
}

// The default falloff is the exact one; the bounded ones are asked for by name.
TEST(Falloff, DefaultIsExactAndTheBoundedOnesAreNamed) {
    EXPECT_EQ(restir::Falloff{}.kind, restir::FalloffKind::inverse_square);
    EXPECT_EQ(restir::Falloff::exact().kind, restir::FalloffKind::inverse_square);
    EXPECT_EQ(restir::Falloff::yuksel(0.2f).kind, restir::FalloffKind::yuksel);
    EXPECT_EQ(restir::Falloff::yuksel(0.2f).parameter, 0.2f);
    EXPECT_EQ(restir::Falloff::clamped(0.3f).kind, restir::FalloffKind::clamped_inverse_square);
    EXPECT_EQ(restir::Falloff::clamped(0.3f).parameter, 0.3f);
}

} // namespace
