// The partition of indirect light between VPLs and path samples (vpl/vpl_partition.hpp): the
// VPLs' falloff is their share over the squared distance, and at every receiver the VPL part
// (through the library's light-point evaluation and its batch form) plus the path part of a
// path sample is the exact integrand.
#include <restir/bsdf/glossy_receiver.hpp>
#include <restir/core/rng.hpp>
#include <restir/light/light_point_sample.hpp>
#include <restir/vpl/vpl_partition.hpp>

#include <gtest/gtest.h>

#include <glm/geometric.hpp>

#include <cmath>
#include <cstdint>
#include <vector>

namespace {

using restir::GlossyReceiver;
using restir::LambertianReceiver;
using restir::PathSample;
using restir::VplPartition;

TEST(VplPartition, FalloffIsTheVplShareOverTheSquaredDistance) {
    const VplPartition partition{0.3f};
    for (float d = 0.01f; d < 2.0f; d *= 1.07f) {
        const float falloff = restir::evaluate_falloff(partition.vpl_falloff().kind, d,
                                                       partition.vpl_falloff().parameter);
        EXPECT_NEAR(falloff * d * d, partition.vpl_share(d), 1e-6f) << d;
        EXPECT_LE(falloff, 1.0f / (0.3f * 0.3f) * (1.0f + 1e-6f)) << d; // bounded by 1 / r^2
    }
    EXPECT_FLOAT_EQ(partition.vpl_share(0.0f), 0.0f);
    EXPECT_FLOAT_EQ(partition.vpl_share(0.3f), 1.0f);
    EXPECT_FLOAT_EQ(partition.vpl_share(5.0f), 1.0f);
}

TEST(VplPartition, OnlyLambertianSamplePointsHoldVpls) {
    PathSample x;
    x.sample_roughness = 1.0f;
    EXPECT_TRUE(restir::holds_vpls(x));
    x.sample_roughness = 0.99999994f;
    EXPECT_FALSE(restir::holds_vpls(x));
}

// A random unit vector in the hemisphere about `n`.
glm::vec3 random_direction(restir::Pcg32& rng, glm::vec3 n) {
    for (;;) {
        const glm::vec3 v{2.0f * next_float(rng) - 1.0f, 2.0f * next_float(rng) - 1.0f,
                          2.0f * next_float(rng) - 1.0f};
        const float l2 = glm::dot(v, v);
        if (l2 > 1e-4f && l2 <= 1.0f)
            return glm::dot(v, n) < 0.0f ? -v / std::sqrt(l2) : v / std::sqrt(l2);
    }
}

// At receiver `r`: a VPL of intensity Lr at y (the light y reflects, per unit area) through the
// library's light point, plus the path part of the path sample (x -> y, Lo = Lr) in the area
// measure (times cos_y / d^2), against the exact f Lr cos_x cos_y / d^2. `holds` is whether y
// holds VPLs: where it does not, no VPL is there.
template <class R>
void expect_parts_sum_to_exact(const R& r, glm::vec3 y, glm::vec3 n_y, glm::vec3 lr, bool holds,
                               const VplPartition& partition) {
    PathSample x;
    x.visible_point = r.position;
    x.sample_point = y;
    x.sample_normal = n_y;
    x.radiance = lr;
    x.source_pdf = 1.0f;
    x.sample_roughness = holds ? 1.0f : 0.5f;
    const glm::vec3 to_y = y - r.position;
    const float d2 = glm::dot(to_y, to_y);
    const float cos_y = std::max(0.0f, -glm::dot(n_y, to_y) / std::sqrt(d2));
    const glm::vec3 exact = restir::path_sample_radiance(x, r) * (cos_y / d2);
    const glm::vec3 path = restir::partitioned_path_radiance(x, r, partition) * (cos_y / d2);

    restir::LightSample vpl;
    vpl.position = y;
    vpl.normal = n_y;
    vpl.radiance = lr;
    vpl.area_pdf = 1.0f;
    vpl.is_delta = true;
    const restir::LightPointSample point =
        restir::make_light_point_sample(0u, vpl, partition.vpl_falloff());
    const glm::vec3 vpl_part = holds ? restir::unshadowed_radiance(point, r) : glm::vec3(0.0f);
    for (int c = 0; c < 3; ++c)
        EXPECT_NEAR(vpl_part[c] + path[c], exact[c], 2e-5f * exact[c] + 1e-7f)
            << "channel " << c << ", distance " << std::sqrt(d2) << ", holds " << holds;
}

TEST(VplPartition, TheTwoPartsSumToTheExactIntegrandAtEveryReceiver) {
    restir::Pcg32 rng = restir::make_pixel_rng(3u, 0u, 0u, 50u);
    const VplPartition partition{0.25f};
    for (int trial = 0; trial < 2000; ++trial) {
        const glm::vec3 n = random_direction(rng, {0.0f, 0.0f, 1.0f});
        const glm::vec3 p{next_float(rng), next_float(rng), next_float(rng)};
        const float distance = 0.02f + 0.6f * next_float(rng); // within and beyond r
        const glm::vec3 y = p + distance * random_direction(rng, n);
        const glm::vec3 n_y = random_direction(rng, glm::normalize(p - y));
        const glm::vec3 lr{next_float(rng), next_float(rng), next_float(rng)};
        const bool holds = trial % 3 != 0;
        expect_parts_sum_to_exact(LambertianReceiver{p, n, {0.7f, 0.5f, 0.3f}}, y, n_y, lr, holds,
                                  partition);
        const float roughness = 0.05f + 0.95f * next_float(rng);
        const restir::GlossyBsdf bsdf = restir::GlossyBsdf::from_metallic_roughness(
            {0.8f, 0.6f, 0.2f}, trial % 2 == 0 ? 0.0f : 1.0f, roughness, 0.04f);
        const glm::vec3 wo = random_direction(rng, n);
        for (const bool diffuse_only : {true, false})
            expect_parts_sum_to_exact(GlossyReceiver{p, n, wo, bsdf, 0.25f, diffuse_only}, y, n_y,
                                      lr, holds, partition);
        if (::testing::Test::HasFailure())
            return;
    }
}

// A glossy receiver's VPL light is its diffuse lobe alone: the whole BSDF less its specular
// lobe (the model with no diffuse albedo), in the light point's evaluation and the batch's.
TEST(VplPartition, GlossyReceiversSeeVplsThroughTheirDiffuseLobe) {
    restir::Pcg32 rng = restir::make_pixel_rng(4u, 0u, 0u, 50u);
    for (int trial = 0; trial < 500; ++trial) {
        const glm::vec3 n{0.0f, 0.0f, 1.0f};
        const glm::vec3 wo = random_direction(rng, n);
        const glm::vec3 wi = random_direction(rng, n);
        const restir::GlossyBsdf bsdf = restir::GlossyBsdf::from_metallic_roughness(
            {0.8f, 0.6f, 0.2f}, 0.3f, 0.05f + 0.9f * next_float(rng), 0.04f);
        restir::GlossyBsdf specular_alone = bsdf;
        specular_alone.diffuse_albedo = glm::vec3(0.0f);
        const GlossyReceiver r{glm::vec3(0.0f), n, wo, bsdf, 0.25f, true};
        const glm::vec3 whole = r.reflected(wi);
        const glm::vec3 diffuse = r.reflected(wi, 0.0f, true);
        const glm::vec3 specular = specular_alone.evaluate_cos(n, wo, wi);
        for (int c = 0; c < 3; ++c) {
            EXPECT_NEAR(diffuse[c] + specular[c], whole[c], 1e-5f * whole[c] + 1e-7f);
            EXPECT_LE(diffuse[c], whole[c] * (1.0f + 1e-6f));
        }
        // Other lights, and every light where the flag is off, see the whole BSDF.
        EXPECT_EQ(r.reflected(wi, 0.0f, false), whole);
        const GlossyReceiver plain{glm::vec3(0.0f), n, wo, bsdf, 0.25f, false};
        EXPECT_EQ(plain.reflected(wi, 0.0f, true), whole);
    }
}

} // namespace
