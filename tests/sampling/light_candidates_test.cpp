// Light candidates: `draw_light_candidate` follows the light sampler, and its pdf convention
// (the light's pmf alone, in the (light, uv) measure) with `unshadowed_irradiance` as target
// gives unbiased irradiance from area and point lights together.
#include <restir/restir.hpp>

#include "support/chi2.hpp"
#include "support/statistics.hpp"

#include <gtest/gtest.h>

#include <cmath>
#include <cstdint>
#include <vector>

namespace {

// Light 0: a 2 x 2 square at height 1 facing down, radiance 1 (area pdf 1/4).
// Light 1: an isotropic point light of intensity 1 at (0.5, 2, 0).
struct SquareAndPoint {
    std::uint32_t light_count() const { return 2u; }
    restir::LightSample sample_point(std::uint32_t id, glm::vec2 uv) const {
        restir::LightSample p;
        if (id == 0u) {
            p.position = {2.0f * uv.x - 1.0f, 1.0f, 2.0f * uv.y - 1.0f};
            p.normal = {0.0f, -1.0f, 0.0f};
            p.area_pdf = 0.25f;
        } else {
            p.position = {0.5f, 2.0f, 0.0f};
            p.normal = glm::vec3(0.0f); // isotropic
            p.area_pdf = 1.0f;
            p.is_delta = true;
        }
        p.radiance = glm::vec3(1.0f);
        return p;
    }
};

TEST(LightCandidates, FollowTheSamplerAndCarryItsPmf) {
    const std::vector<float> powers{1.0f, 4.0f, 2.0f, 0.5f, 8.0f};
    const restir::AliasTable table(powers);
    const restir::PowerLightSampler sampler{table.view()};
    restir::Pcg32 rng = restir::make_pixel_rng(1u, 2u, 3u, 4u);
    std::vector<double> histogram(powers.size(), 0.0);
    for (int i = 0; i < 200'000; ++i) {
        const restir::SourceSample<restir::LightSampleRef> c =
            restir::draw_light_candidate(sampler, rng);
        ASSERT_LT(c.sample.light_id, powers.size());
        ASSERT_EQ(c.pdf, table.pmf(c.sample.light_id));
        ASSERT_GE(c.sample.uv.x, 0.0f);
        ASSERT_LT(c.sample.uv.x, 1.0f);
        ASSERT_GE(c.sample.uv.y, 0.0f);
        ASSERT_LT(c.sample.uv.y, 1.0f);
        histogram[c.sample.light_id] += 1.0;
    }
    std::vector<double> pmf;
    for (std::uint32_t i = 0; i < powers.size(); ++i)
        pmf.push_back(static_cast<double>(table.pmf(i)));
    EXPECT_TRUE(restir::test::fits_distribution(histogram, pmf, 0.01));
}

// Had the pdf included the area density (pmf * area_pdf), the square's share would come out
// 4x too large; had the target left out 1 / area_pdf, 4x too small.
TEST(LightCandidates, RisWithTheIrradianceTargetIsUnbiasedForAreaAndPointLights) {
    // The square's irradiance at the origin (normal up), h^2 / (x^2 + z^2 + h^2)^2 over it,
    // by a fine midpoint rule; the point light's in closed form.
    constexpr int grid = 2000;
    double square = 0.0;
    for (int i = 0; i < grid; ++i)
        for (int j = 0; j < grid; ++j) {
            const double x = -1.0 + (i + 0.5) * 2.0 / grid;
            const double z = -1.0 + (j + 0.5) * 2.0 / grid;
            const double r2 = x * x + z * z + 1.0;
            square += 1.0 / (r2 * r2) * (4.0 / (grid * static_cast<double>(grid)));
        }
    const double point = 2.0 / std::pow(4.25, 1.5);
    const double truth = square + point;

    const SquareAndPoint lights;
    const restir::UniformLightSampler sampler{2u};
    const glm::vec3 position(0.0f);
    const glm::vec3 normal(0.0f, 1.0f, 0.0f);
    const auto target = [&](const restir::LightSampleRef& ref) {
        return restir::unshadowed_irradiance(lights.sample_point(ref.light_id, ref.uv), position,
                                             normal, restir::Falloff::exact())
            .x;
    };
    restir::test::RunningStats estimate;
    for (std::uint32_t trial = 0; trial < 40'000u; ++trial) {
        restir::Pcg32 rng = restir::make_pixel_rng(trial, 0u, 0u, 21u);
        const auto r = restir::resample_ris(
            rng, 4u, [&](restir::Pcg32& g) { return restir::draw_light_candidate(sampler, g); },
            target);
        estimate.add(static_cast<double>(target(r.sample) * r.contribution_weight));
    }
    EXPECT_TRUE(restir::test::agrees_with(estimate, truth));
}

} // namespace
