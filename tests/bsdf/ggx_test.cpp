// The GGX building blocks: the shading frame, Schlick's Fresnel, the distribution's
// normalisation, the Smith terms, and the visible-normal sampler against its density.
#include "bsdf/hemisphere_chi2.hpp"
#include "support/chi2.hpp"

#include <restir/bsdf/fresnel.hpp>
#include <restir/bsdf/ggx.hpp>
#include <restir/bsdf/shading_frame.hpp>
#include <restir/core/math.hpp>
#include <restir/core/rng.hpp>

#include <glm/geometric.hpp>
#include <glm/vec3.hpp>

#include <gtest/gtest.h>

#include <cmath>
#include <limits>
#include <numbers>
#include <optional>
#include <vector>

namespace {

using restir::Pcg32;
using restir::test::random_unit;
using restir::test::roughnesses;
using restir::test::view_at;
using restir::test::view_degrees;

TEST(BsdfShadingFrame, IsOrthonormalRightHandedAndInvertible) {
    Pcg32 rng;
    rng.seed(11u, 3u);
    std::vector<glm::vec3> normals = {{0, 0, 1},
                                      {0, 0, -1},
                                      {1, 0, 0},
                                      {0, -1, 0},
                                      glm::normalize(glm::vec3(1e-7f, 0.0f, -1.0f))};
    for (int i = 0; i < 1000; ++i)
        normals.push_back(random_unit(rng));
    for (const glm::vec3 n : normals) {
        const restir::ShadingFrame f = restir::ShadingFrame::from_normal(n);
        EXPECT_NEAR(glm::length(f.tangent), 1.0f, 1e-6f);
        EXPECT_NEAR(glm::length(f.bitangent), 1.0f, 1e-6f);
        EXPECT_NEAR(glm::dot(f.tangent, f.bitangent), 0.0f, 1e-6f);
        EXPECT_NEAR(glm::dot(f.tangent, n), 0.0f, 1e-6f);
        EXPECT_NEAR(glm::dot(f.bitangent, n), 0.0f, 1e-6f);
        EXPECT_LT(glm::length(glm::cross(f.tangent, f.bitangent) - n), 1e-6f) << "left-handed";
        const glm::vec3 v = random_unit(rng);
        EXPECT_LT(glm::length(f.to_world(f.to_local(v)) - v), 1e-6f);
        EXPECT_NEAR(f.to_local(n).z, 1.0f, 1e-6f);
    }
}

TEST(BsdfFresnel, SchlickEndsAndTheGrazingValue) {
    const glm::vec3 f0(0.04f, 0.5f, 0.9f);
    EXPECT_EQ(restir::fresnel_schlick(f0, 1.0f), f0);
    // f90 = min(1, 50 average(F0)) = 1 here: the grazing value.
    EXPECT_EQ(restir::fresnel_schlick(f0, 0.0f), glm::vec3(1.0f));
    EXPECT_EQ(restir::fresnel_schlick(f0, -0.5f), glm::vec3(1.0f)) << "cos clamped to 0";
    // Below 2 % the grazing value falls with F0 (pre-shadowed): 0.01 -> 0.5, 0 -> 0.
    EXPECT_FLOAT_EQ(restir::fresnel_f90(glm::vec3(0.01f)), 0.5f);
    for (const float c : {0.0f, 0.3f, 1.0f}) {
        EXPECT_EQ(restir::fresnel_schlick(glm::vec3(0.0f), c), glm::vec3(0.0f));
        EXPECT_EQ(restir::fresnel_schlick(glm::vec3(1.0f), c), glm::vec3(1.0f));
    }
    // (1 - c)^5 by multiplications, and monotone towards grazing.
    EXPECT_FLOAT_EQ(restir::schlick_weight(0.5f), 0.03125f);
    float previous = 0.0f;
    for (int i = 100; i >= 0; --i) {
        const float f = restir::fresnel_schlick(glm::vec3(0.04f), 0.01f * static_cast<float>(i)).x;
        EXPECT_GE(f, previous);
        previous = f;
    }
    EXPECT_NEAR(restir::dielectric_f0(1.5f), 0.04f, 1e-7f);
    EXPECT_EQ(restir::dielectric_f0(1.0f), 0.0f);
}

TEST(BsdfGgx, AlphaIsRoughnessSquaredAboveTheMinimum) {
    EXPECT_EQ(restir::ggx_alpha(0.5f), 0.25f);
    EXPECT_EQ(restir::ggx_alpha(1.0f), 1.0f);
    EXPECT_EQ(restir::ggx_alpha(2.0f), 1.0f);
    EXPECT_EQ(restir::ggx_alpha(0.0f), restir::ggx_min_alpha);
    EXPECT_EQ(restir::ggx_alpha(0.02f), restir::ggx_min_alpha);
    EXPECT_EQ(restir::ggx_alpha(-1.0f), restir::ggx_min_alpha);
    EXPECT_EQ(restir::ggx_alpha(std::numeric_limits<float>::quiet_NaN()), restir::ggx_min_alpha);
}

// Integral of D(m) cos(theta_m) over the hemisphere is 1 (the projected microfacet area equals
// the macro surface's). Quadrature accurate to about 1e-5 (its per-cell tolerance), float
// evaluation of D to about 1e-6: 1e-4 tells a wrong normalisation (a missing pi, alpha^2 for
// alpha) apart by orders of magnitude.
TEST(BsdfGgx, DistributionIsNormalised) {
    for (const float alpha : {restir::ggx_min_alpha, 0.0025f, 0.04f, 0.25f, 1.0f}) {
        // ggx_ndf from cos theta, and from the tangential components as the BSDF uses it.
        const auto from_cos = [alpha](glm::vec3 m) { return restir::ggx_ndf(m.z, alpha) * m.z; };
        const auto from_squares = [alpha](glm::vec3 m) {
            return restir::ggx_ndf_from_squares(m.z * m.z, m.x * m.x + m.y * m.y, alpha) * m.z;
        };
        const restir::test::HemisphereCell all{0.0, 1.0, 0.0, 2.0 * std::numbers::pi};
        const restir::test::HemisphereQuadrature q1(from_cos, {0, 0, 1}, alpha);
        const restir::test::HemisphereQuadrature q2(from_squares, {0, 0, 1}, alpha);
        EXPECT_NEAR(q2.integrate(all), 1.0, 1e-4) << "alpha " << alpha;
        // From a float cosine, D is a step function on steps of 6e-8 in cos theta, too
        // coarse for the narrowest lobe: only from roughness 0.05 up.
        if (alpha >= 0.0025f) {
            EXPECT_NEAR(q1.integrate(all), 1.0, 1e-4) << "alpha " << alpha;
        }
    }
}

// The weak white furnace (Heitz 2014, eq. 18 with G1): integral of G1(wo) max(0, wo.m) D(m) /
// wo.z over the hemisphere is 1 for every view: the visible normals' density is normalised.
TEST(BsdfGgx, WeakWhiteFurnace) {
    for (const float roughness : roughnesses)
        for (const float degrees : {0.0f, 45.0f, 80.0f, 89.0f}) {
            const float alpha = restir::ggx_alpha(roughness);
            const glm::vec3 wo = view_at(degrees);
            const auto density = [&](glm::vec3 m) { return restir::ggx_vndf_pdf(wo, m, alpha); };
            const restir::test::HemisphereQuadrature q(density, {0, 0, 1}, alpha);
            EXPECT_NEAR(q.integrate({0.0, 1.0, 0.0, 2.0 * std::numbers::pi}), 1.0, 1e-4)
                << "roughness " << roughness << ", view " << degrees << " degrees";
        }
}

TEST(BsdfGgx, SmithTermsAreTheirLambdaForms) {
    for (const float alpha : {restir::ggx_min_alpha, 0.04f, 0.25f, 1.0f}) {
        EXPECT_EQ(restir::smith_lambda(1.0f, alpha), 0.0f);
        EXPECT_EQ(restir::smith_g1(1.0f, alpha), 1.0f);
        EXPECT_EQ(restir::smith_g1(0.0f, alpha), 0.0f);
        EXPECT_EQ(restir::smith_g2(0.5f, -0.1f, alpha), 0.0f);
        for (int i = 1; i <= 20; ++i) {
            const float co = 0.05f * static_cast<float>(i);
            const float lo = restir::smith_lambda(co, alpha);
            EXPECT_NEAR(restir::smith_g1(co, alpha), 1.0f / (1.0f + lo), 1e-6f);
            // Lambda = (sqrt(1 + alpha^2 tan^2) - 1) / 2, in double.
            const double c = static_cast<double>(co), a = static_cast<double>(alpha);
            const double tan2 = (1.0 - c * c) / (c * c);
            EXPECT_NEAR(static_cast<double>(lo), 0.5 * (std::sqrt(1.0 + a * a * tan2) - 1.0),
                        1e-6 * (1.0 + static_cast<double>(lo)));
            for (int j = 1; j <= 20; ++j) {
                const float ci = 0.05f * static_cast<float>(j);
                const float li = restir::smith_lambda(ci, alpha);
                const float g2 = restir::smith_g2(co, ci, alpha);
                EXPECT_NEAR(g2, 1.0f / (1.0f + lo + li), 1e-6f);
                EXPECT_FLOAT_EQ(g2, restir::smith_g2(ci, co, alpha)); // up to fused multiply-adds
                EXPECT_LE(g2, restir::smith_g1(co, alpha) * (1.0f + 1e-6f));
            }
        }
    }
}

// Visible normals drawn by sample_ggx_vndf against ggx_vndf_pdf, chi-square on a (cos theta,
// phi) grid, 12 tests at a family-wise significance of 1 %.
TEST(BsdfGgx, VisibleNormalSamplesFitTheirDensity) {
    const double alpha_test = restir::test::sidak_significance(0.01, 12);
    Pcg32 rng;
    rng.seed(2018u, 7u);
    for (const float roughness : roughnesses)
        for (const float degrees : view_degrees) {
            const float alpha = restir::ggx_alpha(roughness);
            const glm::vec3 wo = view_at(degrees);
            const auto draw = [&]() -> std::optional<glm::vec3> {
                const float u0 = next_float(rng);
                const float u1 = next_float(rng);
                return restir::sample_ggx_vndf(wo, alpha, u0, u1);
            };
            const auto density = [&](glm::vec3 m) { return restir::ggx_vndf_pdf(wo, m, alpha); };
            EXPECT_TRUE(restir::test::samples_fit_density(draw, density, {0, 0, 1}, alpha, 200000,
                                                          alpha_test))
                << "roughness " << roughness << ", view " << degrees << " degrees";
        }
}

TEST(BsdfGgx, FiniteForHostileInputs) {
    const float cosines[] = {-1.0f, -1e-30f, 0.0f, 1e-30f, 1e-7f, 0.5f, 1.0f, 1.0000001f};
    const float us[] = {0.0f, 0.5f, 0x1.fffffep-1f};
    for (const float roughness : {0.0f, 0.02f, 1.0f}) {
        const float alpha = restir::ggx_alpha(roughness);
        for (const float c : cosines) {
            EXPECT_TRUE(restir::is_valid_weight(restir::ggx_ndf(c, alpha)) ||
                        restir::ggx_ndf(c, alpha) == 0.0f);
            EXPECT_TRUE(restir::is_finite(restir::smith_lambda(c, alpha)));
            EXPECT_TRUE(restir::is_finite(restir::smith_g1(c, alpha)));
            for (const float c2 : cosines)
                EXPECT_TRUE(restir::is_finite(restir::smith_g2(c, c2, alpha)));
        }
        // Views from the normal to the horizon's first float above it.
        for (const glm::vec3 wo : {glm::vec3(0, 0, 1), glm::normalize(glm::vec3(1, 1e-3f, 1e-6f)),
                                   glm::vec3(1.0f, 0.0f, 1e-30f), glm::vec3(0.6f, 0.0f, 0.8f)})
            for (const float u0 : us)
                for (const float u1 : us) {
                    const glm::vec3 m = restir::sample_ggx_vndf(wo, alpha, u0, u1);
                    EXPECT_NEAR(glm::length(m), 1.0f, 1e-5f);
                    EXPECT_GE(m.z, 0.0f);
                    EXPECT_TRUE(restir::is_finite(restir::ggx_vndf_pdf(wo, m, alpha)));
                    EXPECT_GE(restir::ggx_vndf_pdf(wo, m, alpha), 0.0f);
                }
        EXPECT_EQ(restir::ggx_vndf_pdf({0.6f, 0.0f, -0.8f}, {0, 0, 1}, alpha), 0.0f);
        EXPECT_EQ(restir::ggx_vndf_pdf({0, 0, 1}, {1, 0, 0}, alpha), 0.0f);
    }
}

} // namespace
