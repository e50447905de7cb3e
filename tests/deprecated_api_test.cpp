// The names of version 0.1 that were renamed, kept deprecated until at least 0.3: each still
// compiles and means what its new name means. This file is compiled with
// -Wno-deprecated-declarations (tests/CMakeLists.txt); that the warning fires everywhere else
// is checked by the `deprecation.warns` test (tests/deprecated/).
#include <restir/light/falloff.hpp>
#include <restir/light/irradiance.hpp>

#include <gtest/gtest.h>

#include <type_traits>

namespace {

TEST(DeprecatedApi, AttenuationIsFalloffKind) {
    static_assert(std::is_same_v<restir::Attenuation, restir::FalloffKind>);
    EXPECT_EQ(restir::Attenuation::yuksel, restir::FalloffKind::yuksel);
    EXPECT_EQ(restir::Attenuation::clamped_inverse_square,
              restir::FalloffKind::clamped_inverse_square);
    EXPECT_EQ(restir::Attenuation::inverse_square, restir::FalloffKind::inverse_square);
    // A 0.1 client built its falloff from the enum by its old name.
    const restir::Falloff falloff{restir::Attenuation::yuksel, 0.25f};
    EXPECT_EQ(falloff.kind, restir::Falloff::yuksel(0.25f).kind);
    EXPECT_EQ(falloff.parameter, restir::Falloff::yuksel(0.25f).parameter);
}

TEST(DeprecatedApi, OldFalloffFunctionsGiveTheNewOnesResults) {
    EXPECT_EQ(restir::smallest_attenuation_divisor, restir::smallest_falloff_divisor);
    const float distances[] = {0.0f, 1e-3f, 0.5f, 1.0f, 7.0f, 1e4f};
    const float parameters[] = {0.0f, 0.05f, 1.0f};
    for (const float d : distances) {
        for (const float p : parameters) {
            EXPECT_EQ(restir::yuksel_attenuation(d, p), restir::yuksel_falloff(d, p));
            EXPECT_EQ(restir::attenuate(restir::Attenuation::yuksel, d, p),
                      restir::evaluate_falloff(restir::FalloffKind::yuksel, d, p));
            if (p > 0.0f) {
                EXPECT_EQ(restir::attenuate(restir::Attenuation::clamped_inverse_square, d, p),
                          restir::clamped_inverse_square(d, p));
            }
            if (d > 0.0f) {
                EXPECT_EQ(restir::attenuate(restir::Attenuation::inverse_square, d, p),
                          restir::evaluate_falloff(restir::FalloffKind::inverse_square, d, p));
            }
        }
    }
}

} // namespace
