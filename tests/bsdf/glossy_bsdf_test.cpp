// GlossyBsdf: its sampler against its density (chi-square), the white furnace, reciprocity,
// sample weights, world-space frames, F0 = 0 as a Lambertian surface, and hostile inputs.
#include "bsdf/hemisphere_chi2.hpp"
#include "support/chi2.hpp"
#include "support/statistics.hpp"

#include <restir/bsdf/glossy_bsdf.hpp>
#include <restir/core/math.hpp>
#include <restir/core/rng.hpp>
#include <restir/sampling/diffuse_direction.hpp>

#include <glm/geometric.hpp>
#include <glm/vec3.hpp>

#include <gtest/gtest.h>

#include <cmath>
#include <numbers>
#include <optional>
#include <string>
#include <vector>

namespace {

using restir::BsdfSample;
using restir::GlossyBsdf;
using restir::Pcg32;
using restir::test::random_unit;
using restir::test::roughnesses;
using restir::test::view_at;
using restir::test::view_degrees;

constexpr glm::vec3 up{0.0f, 0.0f, 1.0f};

glm::vec3 random_upper(Pcg32& rng) {
    const glm::vec3 d = random_unit(rng);
    return {d.x, d.y, std::fabs(d.z)};
}

struct Material {
    std::string name;
    GlossyBsdf (*make)(float roughness);
};

const Material materials[] = {
    {"metal",
     [](float r) {
         return GlossyBsdf::from_metallic_roughness(glm::vec3(0.9f, 0.6f, 0.3f), 1.0f, r);
     }},
    {"dielectric",
     [](float r) {
         return GlossyBsdf::from_metallic_roughness(glm::vec3(0.2f, 0.5f, 0.8f), 0.0f, r);
     }},
    {"diffuse",
     [](float r) {
         return GlossyBsdf{glm::vec3(0.7f), glm::vec3(0.0f), r};
     }},
};

/// Rotation about the unit `axis` by `angle` (Rodrigues), independent of ShadingFrame.
struct Rotation {
    glm::vec3 axis;
    float angle;
    glm::vec3 operator()(glm::vec3 v) const {
        const float c = std::cos(angle), s = std::sin(angle);
        return v * c + glm::cross(axis, v) * s + axis * (glm::dot(axis, v) * (1.0f - c));
    }
    Rotation inverse() const { return {axis, -angle}; }
};

/// The largest relative difference of two colours, against a floor for values near 0.
float relative_difference(glm::vec3 a, glm::vec3 b) {
    const glm::vec3 d = glm::abs(a - b) / glm::max(glm::max(glm::abs(a), glm::abs(b)), 1e-6f);
    return std::fmax(d.x, std::fmax(d.y, d.z));
}

// sample() against pdf() for 3 materials, 4 roughnesses and 3 views, plus one rotated normal:
// 37 tests at a family-wise significance of 1 %. A draw with pdf 0 counts in the cell of
// "no direction", whose expected mass is what pdf leaves of 1 (reflections below the surface).
constexpr int chi2_tests = 37;

TEST(BsdfGlossy, SamplesFitPdf) {
    const double alpha_test = restir::test::sidak_significance(0.01, chi2_tests);
    Pcg32 rng;
    rng.seed(1997u, 5u);
    for (const Material& material : materials)
        for (const float roughness : roughnesses)
            for (const float degrees : view_degrees) {
                const GlossyBsdf bsdf = material.make(roughness);
                const glm::vec3 wo = view_at(degrees);
                const auto draw = [&]() -> std::optional<glm::vec3> {
                    const float u_lobe = next_float(rng);
                    const float u0 = next_float(rng);
                    const float u1 = next_float(rng);
                    const BsdfSample s = bsdf.sample(up, wo, u_lobe, u0, u1);
                    if (s.pdf == 0.0f)
                        return std::nullopt;
                    return s.wi;
                };
                const auto density = [&](glm::vec3 wi) { return bsdf.pdf(up, wo, wi); };
                const glm::vec3 mirror(-wo.x, -wo.y, wo.z);
                EXPECT_TRUE(restir::test::samples_fit_density(
                    draw, density, mirror, restir::ggx_alpha(roughness), 200000, alpha_test))
                    << material.name << ", roughness " << roughness << ", view " << degrees
                    << " degrees";
            }
}

// The same with a tilted normal: samples drawn about R z, rotated back by R^-1, fit the z-up
// density (sampling in world space puts the lobe where pdf says).
TEST(BsdfGlossy, SamplesAboutARotatedNormalFitTheZUpPdf) {
    const double alpha_test = restir::test::sidak_significance(0.01, chi2_tests);
    Pcg32 rng;
    rng.seed(2017u, 9u);
    const Rotation rotate{glm::normalize(glm::vec3(0.3f, -0.8f, 0.5f)), 2.1f};
    const GlossyBsdf bsdf = materials[1].make(0.2f);
    const glm::vec3 wo = view_at(45.0f);
    const glm::vec3 n_world = rotate(up), wo_world = rotate(wo);
    const auto draw = [&]() -> std::optional<glm::vec3> {
        const float u_lobe = next_float(rng);
        const float u0 = next_float(rng);
        const float u1 = next_float(rng);
        const BsdfSample s = bsdf.sample(n_world, wo_world, u_lobe, u0, u1);
        if (s.pdf == 0.0f)
            return std::nullopt;
        return rotate.inverse()(s.wi);
    };
    const auto density = [&](glm::vec3 wi) { return bsdf.pdf(up, wo, wi); };
    EXPECT_TRUE(restir::test::samples_fit_density(draw, density, {-wo.x, -wo.y, wo.z},
                                                  restir::ggx_alpha(0.2f), 200000, alpha_test));
}

/// The directional albedo of `bsdf` at `wo` by quadrature of evaluate_cos (channel x).
double quadrature_albedo(const GlossyBsdf& bsdf, glm::vec3 wo) {
    const auto f = [&](glm::vec3 wi) { return bsdf.evaluate_cos(up, wo, wi).x; };
    const restir::test::HemisphereQuadrature q(f, {-wo.x, -wo.y, wo.z},
                                               restir::ggx_alpha(bsdf.roughness));
    double sum = 0.0;
    const restir::test::HemisphereGrid grid;
    for (int c = 0; c < grid.cell_count(); ++c)
        sum += q.integrate(grid.cell(c));
    return sum;
}

// The white furnace: with diffuse_albedo 1 the directional albedo, integral of f cos over the
// hemisphere, is at most 1, for F0 of 0, 0.04 and 1, every roughness and view. Monte Carlo
// with the sampler (mean of the weights; bound 1 + 4 standard errors + 1e-5 for the float
// rounding of each weight f cos / pdf) and quadrature of evaluate_cos (bound 1 + 1e-4, the
// quadrature's accuracy); the two agree within 4 standard errors + 1e-4 (unbiased weights).
TEST(BsdfGlossy, WhiteFurnaceAlbedoIsAtMostOne) {
    Pcg32 rng;
    rng.seed(1994u, 1u);
    for (const float f0 : {0.0f, 0.04f, 1.0f})
        for (const float roughness : roughnesses)
            for (const float degrees : view_degrees) {
                const GlossyBsdf bsdf{glm::vec3(1.0f), glm::vec3(f0), roughness};
                const glm::vec3 wo = view_at(degrees);
                restir::test::RunningStats albedo;
                for (int i = 0; i < 50000; ++i) {
                    const float u_lobe = next_float(rng);
                    const float u0 = next_float(rng);
                    const float u1 = next_float(rng);
                    albedo.add(static_cast<double>(bsdf.sample(up, wo, u_lobe, u0, u1).weight.x));
                }
                const double quadrature = quadrature_albedo(bsdf, wo);
                const std::string at = "F0 " + std::to_string(f0) + ", roughness " +
                                       std::to_string(roughness) + ", view " +
                                       std::to_string(degrees);
                EXPECT_LE(albedo.mean(), 1.0 + 4.0 * albedo.standard_error() + 1e-5) << at;
                EXPECT_LE(quadrature, 1.0 + 1e-4) << at;
                EXPECT_LE(std::abs(albedo.mean() - quadrature),
                          4.0 * albedo.standard_error() + 1e-4)
                    << at << ": Monte Carlo " << albedo.mean() << ", quadrature " << quadrature;
            }
}

// A mirror-like metal with F0 = 1 (F = 1 exactly) loses little: single scattering loses the
// masked energy, 1 - G2 / G1(wo) <= Lambda(wi) ~ alpha^2 tan^2 / 4 < 1e-4 at alpha = 0.0025 and
// 80 degrees, and the reflections that leave the hemisphere: the visible normals more than 5
// degrees from n at an 80-degree view, a fraction of about (alpha / 0.087)^2 ~ 1e-3. So the
// albedo is above 0.99 at every view (the bound leaves 10 times the estimated loss).
TEST(BsdfGlossy, WhiteFurnaceOfASmoothMetalIsNearlyOne) {
    Pcg32 rng;
    rng.seed(2014u, 2u);
    const GlossyBsdf metal = GlossyBsdf::from_metallic_roughness(glm::vec3(1.0f), 1.0f, 0.05f);
    for (const float degrees : view_degrees) {
        const glm::vec3 wo = view_at(degrees);
        restir::test::RunningStats albedo;
        for (int i = 0; i < 50000; ++i) {
            const float u_lobe = next_float(rng);
            const float u0 = next_float(rng);
            const float u1 = next_float(rng);
            albedo.add(static_cast<double>(metal.sample(up, wo, u_lobe, u0, u1).weight.x));
        }
        EXPECT_GE(albedo.mean() + 4.0 * albedo.standard_error(), 0.99) << degrees;
        EXPECT_LE(albedo.mean(), 1.0 + 4.0 * albedo.standard_error() + 1e-5) << degrees;
    }
}

// f(wo, wi) = f(wi, wo) for f = evaluate_cos / n.wi: the formula is symmetric term by term,
// so only roundings differ (fused multiply-adds, the divisions by the cosines): 1e-5
// relative, a few dozen ulps.
TEST(BsdfGlossy, IsReciprocal) {
    Pcg32 rng;
    rng.seed(1967u, 4u);
    for (const Material& material : materials)
        for (const float roughness : {0.0f, 0.05f, 0.2f, 0.5f, 1.0f})
            for (int i = 0; i < 2000; ++i) {
                const GlossyBsdf bsdf = material.make(roughness);
                const glm::vec3 wo = random_upper(rng), wi = random_upper(rng);
                const glm::vec3 forward = bsdf.evaluate_cos(up, wo, wi) / wi.z;
                const glm::vec3 backward = bsdf.evaluate_cos(up, wi, wo) / wo.z;
                ASSERT_LE(relative_difference(forward, backward), 1e-5f)
                    << material.name << " " << roughness;
            }
}

TEST(BsdfGlossy, SampleWeightIsEvaluateCosOverPdf) {
    Pcg32 rng;
    rng.seed(2000u, 6u);
    int valid = 0;
    for (const Material& material : materials)
        for (const float roughness : {0.0f, 0.05f, 0.5f, 1.0f})
            for (int i = 0; i < 5000; ++i) {
                const GlossyBsdf bsdf = material.make(roughness);
                const glm::vec3 n = random_unit(rng);
                const glm::vec3 wo = random_unit(rng);
                const float u_lobe = next_float(rng);
                const float u0 = next_float(rng);
                const float u1 = next_float(rng);
                const BsdfSample s = bsdf.sample(n, wo, u_lobe, u0, u1);
                if (s.pdf == 0.0f) {
                    EXPECT_EQ(s.weight, glm::vec3(0.0f));
                    continue;
                }
                ++valid;
                EXPECT_GT(glm::dot(n, wo), 0.0f);
                EXPECT_GT(glm::dot(n, s.wi), 0.0f);
                EXPECT_NEAR(glm::length(s.wi), 1.0f, 1e-5f);
                EXPECT_EQ(bsdf.pdf(n, wo, s.wi), s.pdf);
                EXPECT_EQ(s.weight, bsdf.evaluate_cos(n, wo, s.wi) / s.pdf);
            }
    // Half the views face the normal; most of their samples are valid.
    EXPECT_GT(valid, 20000);
}

/// How far rounding may move evaluate_cos and pdf when n, wo and wi are rotated: each rotated
/// unit vector is off by a few ulps (taken as 1e-6 together), which moves a cosine by 1e-6 (a
/// relative 1e-6 / cos) and the half vector h = (wo + wi) / |wo + wi| by 1e-6 / |wo + wi| rad;
/// D moves by at most 2 / alpha per radian (d ln D / d theta_h = -4 theta / (alpha^2 +
/// theta^2)). Grazing pairs (small |wo + wi|) and narrow lobes are ill-conditioned, not wrong.
float rotation_tolerance(float roughness, glm::vec3 wo, glm::vec3 wi) {
    const float shift = 1e-6f;
    const float cosine = shift / std::fmax(std::fmin(wo.z, wi.z), 1e-6f);
    const float half_vector = shift / glm::length(wo + wi);
    return 1e-4f + 2.0f * (cosine + 2.0f / restir::ggx_alpha(roughness) * half_vector);
}

// World-space correctness: rotating n, wo and wi together changes nothing but rounding.
TEST(BsdfGlossy, RotatedNormalGivesTheZUpValues) {
    Pcg32 rng;
    rng.seed(1234u, 8u);
    for (const Material& material : materials)
        for (const float roughness : roughnesses)
            for (int i = 0; i < 1000; ++i) {
                const GlossyBsdf bsdf = material.make(roughness);
                const Rotation rotate{random_unit(rng), restir::two_pi * next_float(rng)};
                const glm::vec3 wo = random_upper(rng);
                // Half of the directions near the mirror direction, where the lobe is.
                const glm::vec3 wi =
                    i % 2 == 0
                        ? random_upper(rng)
                        : glm::normalize(glm::vec3(-wo.x, -wo.y, wo.z) +
                                         0.5f * restir::ggx_alpha(roughness) * random_unit(rng));
                const glm::vec3 n_r = rotate(up), wo_r = rotate(wo), wi_r = rotate(wi);
                const float tolerance = rotation_tolerance(roughness, wo, wi);
                EXPECT_LE(relative_difference(bsdf.evaluate_cos(n_r, wo_r, wi_r),
                                              bsdf.evaluate_cos(up, wo, wi)),
                          tolerance);
                EXPECT_LE(relative_difference(glm::vec3(bsdf.pdf(n_r, wo_r, wi_r)),
                                              glm::vec3(bsdf.pdf(up, wo, wi))),
                          tolerance);
                EXPECT_NEAR(bsdf.specular_probability(n_r, wo_r), bsdf.specular_probability(up, wo),
                            1e-5f);
                // A sample drawn about the rotated normal has the z-up density once rotated back.
                const BsdfSample s =
                    bsdf.sample(n_r, wo_r, next_float(rng), next_float(rng), next_float(rng));
                const glm::vec3 wi_back = rotate.inverse()(s.wi);
                if (s.pdf > 0.0f) {
                    EXPECT_LE(
                        relative_difference(glm::vec3(bsdf.pdf(up, wo, wi_back)), glm::vec3(s.pdf)),
                        rotation_tolerance(roughness, wo, wi_back));
                }
            }
}

// F0 = 0 is a Lambertian surface: evaluate_cos is albedo * (1 / pi) * cos bit for bit, the
// sampler is sample_diffuse_direction and its pdf diffuse_direction_pdf, exactly.
TEST(BsdfGlossy, ZeroF0IsExactlyLambertian) {
    Pcg32 rng;
    rng.seed(1760u, 10u);
    const glm::vec3 albedo(0.3f, 0.55f, 0.9f);
    for (const float roughness : {0.0f, 0.05f, 0.5f, 1.0f}) {
        const GlossyBsdf bsdf{albedo, glm::vec3(0.0f), roughness};
        for (int i = 0; i < 2000; ++i) {
            const glm::vec3 n = random_unit(rng), wo = random_unit(rng), wi = random_unit(rng);
            const float cos_i = glm::dot(n, wi);
            const glm::vec3 lambert = albedo * (1.0f / restir::pi) * cos_i;
            if (glm::dot(n, wo) > 0.0f && cos_i > 0.0f) {
                ASSERT_EQ(bsdf.evaluate_cos(n, wo, wi), lambert);
            } else {
                ASSERT_EQ(bsdf.evaluate_cos(n, wo, wi), glm::vec3(0.0f));
            }
            if (!(glm::dot(n, wo) > 0.0f))
                continue;
            EXPECT_EQ(bsdf.specular_probability(n, wo), 0.0f);
            EXPECT_EQ(bsdf.pdf(n, wo, wi), restir::diffuse_direction_pdf(n, wi));
            const float u_lobe = next_float(rng), u0 = next_float(rng), u1 = next_float(rng);
            const BsdfSample s = bsdf.sample(n, wo, u_lobe, u0, u1);
            const glm::vec3 cosine = restir::sample_diffuse_direction(n, u0, u1);
            if (s.pdf > 0.0f) {
                EXPECT_EQ(s.wi, cosine);
                EXPECT_EQ(s.pdf, restir::diffuse_direction_pdf(n, cosine));
            } else {
                EXPECT_LE(glm::dot(n, cosine), 0.0f);
            }
        }
    }
}

TEST(BsdfGlossy, LobeChoiceAndMetallicRoughness) {
    const GlossyBsdf metal =
        GlossyBsdf::from_metallic_roughness(glm::vec3(0.9f, 0.6f, 0.3f), 1.0f, 0.3f);
    EXPECT_EQ(metal.diffuse_albedo, glm::vec3(0.0f));
    EXPECT_EQ(metal.specular_f0, glm::vec3(0.9f, 0.6f, 0.3f));
    EXPECT_EQ(metal.roughness, 0.3f);
    const GlossyBsdf plastic =
        GlossyBsdf::from_metallic_roughness(glm::vec3(0.9f, 0.6f, 0.3f), 0.0f, 0.3f);
    EXPECT_EQ(plastic.diffuse_albedo, glm::vec3(0.9f, 0.6f, 0.3f));
    EXPECT_EQ(plastic.specular_f0, glm::vec3(0.04f));
    EXPECT_EQ(GlossyBsdf::from_metallic_roughness(glm::vec3(0.5f), 0.0f, 0.3f, 0.08f).specular_f0,
              glm::vec3(0.08f));
    // White F0 leaves the diffuse lobe nothing (1 - F = 0): only the specular one is sampled.
    const GlossyBsdf mirror{glm::vec3(0.8f), glm::vec3(1.0f), 0.3f};
    for (const float degrees : view_degrees) {
        const glm::vec3 wo = view_at(degrees);
        EXPECT_EQ(metal.specular_probability(up, wo), 1.0f);
        EXPECT_EQ(mirror.specular_probability(up, wo), 1.0f);
        const float p = plastic.specular_probability(up, wo);
        EXPECT_GE(p, restir::glossy_lobe_probability_floor);
        EXPECT_LE(p, 1.0f - restir::glossy_lobe_probability_floor);
    }
    // Towards grazing the dielectric's Fresnel grows, and the specular lobe with it.
    EXPECT_LT(plastic.specular_probability(up, view_at(0.0f)),
              plastic.specular_probability(up, view_at(80.0f)));
}

// No NaN or infinity for grazing and below-surface directions, wi = -wo, wi = wo, roughness 0
// and 1 (and out of range), uniform numbers at both ends.
TEST(BsdfGlossy, FiniteForHostileInputs) {
    const std::vector<glm::vec3> directions = {{0, 0, 1},
                                               {0, 0, -1},
                                               {1, 0, 0},
                                               {-1, 0, 0},
                                               {1.0f, 0.0f, 1e-30f},
                                               glm::normalize(glm::vec3(1.0f, 0.0f, 1e-7f)),
                                               glm::normalize(glm::vec3(0.6f, 0.0f, -0.8f)),
                                               glm::normalize(glm::vec3(-0.6f, 0.0f, 0.8f)),
                                               glm::normalize(glm::vec3(0.6f, 0.0f, 0.8f)),
                                               {0.0f, 0.0f, 0.0f}};
    const float us[] = {0.0f, 0.5f, 0x1.fffffep-1f};
    const auto finite = [](glm::vec3 v) {
        return restir::is_finite(v.x) && restir::is_finite(v.y) && restir::is_finite(v.z);
    };
    for (const Material& material : materials)
        for (const float roughness : {-1.0f, 0.0f, 0.02f, 1.0f, 3.0f}) {
            const GlossyBsdf bsdf = material.make(roughness);
            for (const glm::vec3 wo : directions) {
                const float p = bsdf.specular_probability(up, wo);
                EXPECT_TRUE(p >= 0.0f && p <= 1.0f) << p;
                for (const glm::vec3 wi : directions) {
                    EXPECT_TRUE(finite(bsdf.evaluate_cos(up, wo, wi)));
                    EXPECT_TRUE(restir::is_finite(bsdf.pdf(up, wo, wi)));
                    EXPECT_GE(bsdf.pdf(up, wo, wi), 0.0f);
                }
                EXPECT_EQ(bsdf.evaluate_cos(up, wo, -wo), glm::vec3(0.0f));
                EXPECT_EQ(bsdf.pdf(up, wo, -wo), 0.0f);
                for (const float u_lobe : us)
                    for (const float u0 : us)
                        for (const float u1 : us) {
                            const BsdfSample s = bsdf.sample(up, wo, u_lobe, u0, u1);
                            EXPECT_TRUE(finite(s.wi) && finite(s.weight) &&
                                        restir::is_finite(s.pdf));
                            EXPECT_GE(s.pdf, 0.0f);
                        }
            }
        }
}

} // namespace
