#include <restir/light/falloff.hpp>

#include <gtest/gtest.h>

#include <cmath>
#include <limits>

namespace {

using restir::clamped_inverse_square;
using restir::yuksel_falloff;

TEST(YukselFalloff, IsFiniteAtZeroDistance) {
    for (float r : {0.01f, 0.1f, 1.0f, 5.0f})
        EXPECT_FLOAT_EQ(yuksel_falloff(0.0f, r), 2.0f / (r * r)) << r;
}

TEST(YukselFalloff, StaysBelowInverseSquare) {
    const float r = 0.5f;
    for (float d = 0.01f; d < 100.0f; d *= 1.3f)
        EXPECT_LT(yuksel_falloff(d, r), 1.0f / (d * d)) << d;
}

TEST(YukselFalloff, ConvergesToInverseSquareFarAway) {
    // f(d) d^2 = 2 / (1 + s + sqrt(1 + s)) with s = r^2 / d^2, so 1 - f d^2 ~ 3s/4.
    const float r = 0.2f;
    for (float d : {10.0f, 100.0f}) {
        const double s = static_cast<double>(r * r) / static_cast<double>(d * d);
        const double ratio = static_cast<double>(yuksel_falloff(d, r) * d * d);
        EXPECT_NEAR(1.0 - ratio, 0.75 * s, 0.5 * s) << d;
    }
    EXPECT_NEAR(yuksel_falloff(1000.0f, r) * 1e6f, 1.0f, 1e-6f);
}

TEST(YukselFalloff, DecreasesWithDistance) {
    float previous = yuksel_falloff(0.0f, 0.3f);
    for (float d = 0.001f; d < 50.0f; d *= 1.1f) {
        const float current = yuksel_falloff(d, 0.3f);
        EXPECT_LT(current, previous) << d;
        previous = current;
    }
}

TEST(YukselFalloff, ZeroRadiusIsInverseSquare) {
    for (float d : {0.5f, 1.0f, 3.0f})
        EXPECT_FLOAT_EQ(yuksel_falloff(d, 0.0f), 1.0f / (d * d));
}

TEST(ClampedInverseSquare, ClampsBelowTheMinimumDistance) {
    EXPECT_FLOAT_EQ(clamped_inverse_square(0.0f, 0.5f), 4.0f);
    EXPECT_FLOAT_EQ(clamped_inverse_square(0.25f, 0.5f), 4.0f);
    EXPECT_FLOAT_EQ(clamped_inverse_square(2.0f, 0.5f), 0.25f);
}

TEST(FalloffKind, DispatchesOnTheKind) {
    EXPECT_EQ(restir::evaluate_falloff(restir::FalloffKind::yuksel, 1.0f, 0.3f),
              yuksel_falloff(1.0f, 0.3f));
    EXPECT_EQ(restir::evaluate_falloff(restir::FalloffKind::clamped_inverse_square, 0.1f, 0.3f),
              clamped_inverse_square(0.1f, 0.3f));
}

// At the light's own position with no radius (a VPL evaluated on itself), and for radii too
// small to square, the falloff is large and finite, not infinity.
TEST(YukselFalloff, IsFiniteForAnyNonNegativeInput) {
    for (float r : {0.0f, 1e-30f, 1e-20f})
        for (float d : {0.0f, 1e-30f}) {
            const float f = yuksel_falloff(d, r);
            EXPECT_TRUE(std::isfinite(f)) << d << " " << r;
            EXPECT_GE(f, 2e37f) << d << " " << r;
        }
    EXPECT_TRUE(std::isfinite(clamped_inverse_square(0.0f, 1e-30f)));
    EXPECT_EQ(yuksel_falloff(std::numeric_limits<float>::infinity(), 1.0f), 0.0f);
}

} // namespace
