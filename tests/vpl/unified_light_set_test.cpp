// Emitters and VPLs in one light set: ids, powers, and RIS over both at once.
#include <restir/restir.hpp>

#include "support/quadrature.hpp"
#include "support/statistics.hpp"
#include "vpl/box_scene.hpp"

#include <gtest/gtest.h>

#include <cstdint>
#include <vector>

namespace {

using restir::test::RectangleLights;
using Unified = restir::UnifiedLightSet<RectangleLights>;

static_assert(restir::LightSet<Unified>);

RectangleLights two_rectangles() {
    return {{restir::test::ceiling_light(0.9f, 0.4f, glm::vec3(2.0f, 1.0f, 0.5f)),
             {{0.3f, 0.7f, -0.6f}, {0.2f, 0.0f, 0.0f}, {0.0f, 0.0f, 0.3f}, glm::vec3(0.5f)}}};
}

std::vector<restir::Vpl> some_vpls() {
    restir::PhotonParams params = restir::default_photon_params();
    params.photon_count = 300u;
    params.max_bounces = 3u;
    return restir::shoot_photons(two_rectangles(), restir::test::ClosedBox{},
                                 restir::test::Lambertian{glm::vec3(0.6f, 0.5f, 0.4f)}, params);
}

float channel_sum(glm::vec3 v) { return v.x + v.y + v.z; }

TEST(UnifiedLightSet, EmittersFirstThenVpls) {
    const RectangleLights emitters = two_rectangles();
    const std::vector<restir::Vpl> vpls = some_vpls();
    ASSERT_FALSE(vpls.empty());
    const Unified lights{&emitters, vpls.data(), static_cast<std::uint32_t>(vpls.size())};
    EXPECT_EQ(lights.light_count(), 2u + vpls.size());
    EXPECT_FALSE(lights.is_vpl(1u));
    EXPECT_TRUE(lights.is_vpl(2u));
    const restir::LightSample v = lights.sample_point(2u + 5u, glm::vec2(0.3f));
    EXPECT_TRUE(v.is_delta);
    EXPECT_EQ(v.position, vpls[5].position);
    const restir::LightSample e = lights.sample_point(1u, glm::vec2(0.5f));
    EXPECT_FALSE(e.is_delta);
    EXPECT_FLOAT_EQ(e.area_pdf, 1.0f / (0.2f * 0.3f));

    const std::vector<float> powers = restir::unified_light_powers(lights);
    EXPECT_FLOAT_EQ(powers[0], channel_sum(emitters.rectangles[0].radiance) * 3.14159265f * 0.16f);
    EXPECT_FLOAT_EQ(powers[1], 1.5f * 3.14159265f * 0.06f);
    for (std::size_t i = 0; i < vpls.size(); ++i)
        EXPECT_NEAR(powers[2 + i], channel_sum(vpls[i].flux), 1e-6f * channel_sum(vpls[i].flux));
}

// A prefetch is asked for the VPL that a VPL id reads; emitters that say nothing of their data,
// and ids out of range, give the set itself (a harmless address).
TEST(UnifiedLightSet, PrefetchAddressIsTheVplRead) {
    const RectangleLights emitters = two_rectangles();
    const std::vector<restir::Vpl> vpls = some_vpls();
    ASSERT_GT(vpls.size(), 5u);
    const Unified lights{&emitters, vpls.data(), static_cast<std::uint32_t>(vpls.size())};
    EXPECT_EQ(lights.prefetch_address(2u + 5u), &vpls[5]);
    EXPECT_EQ(lights.prefetch_address(lights.light_count() - 1u), &vpls.back());
    EXPECT_EQ(lights.prefetch_address(1u), &lights);
    EXPECT_EQ(lights.prefetch_address(lights.light_count()), &lights);
}

// RIS with candidates from one power-proportional distribution over emitters and VPLs
// estimates the total unshadowed irradiance, direct (emitters) plus indirect (VPLs).
TEST(UnifiedLightSet, RisOverEmittersAndVplsIsUnbiased) {
    const RectangleLights emitters = two_rectangles();
    const std::vector<restir::Vpl> vpls = some_vpls();
    const Unified lights{&emitters, vpls.data(), static_cast<std::uint32_t>(vpls.size())};
    const restir::AliasTable table(restir::unified_light_powers(lights));
    const restir::PowerLightSampler sampler{table.view()};
    const glm::vec3 receiver(0.1f, -0.6f, 0.2f);
    const glm::vec3 normal(0.0f, 1.0f, 0.0f);
    const restir::Falloff falloff{restir::FalloffKind::yuksel, 0.05f};
    const auto irradiance = [&](const restir::LightSampleRef& ref) {
        return channel_sum(restir::unshadowed_irradiance(lights.sample_point(ref.light_id, ref.uv),
                                                         receiver, normal, falloff));
    };

    // Truth: VPLs exactly, emitters by a 1000 x 1000 midpoint rule in uv.
    double truth = 0.0;
    for (std::uint32_t id = 2u; id < lights.light_count(); ++id)
        truth += static_cast<double>(irradiance({id, glm::vec2(0.5f)}));
    for (std::uint32_t id = 0; id < 2u; ++id)
        truth += restir::test::mean_over_unit_square<double>(1000, [&](glm::vec2 uv) {
            return static_cast<double>(irradiance({id, uv}));
        });

    restir::test::RunningStats estimate;
    for (std::uint32_t trial = 0; trial < 40'000u; ++trial) {
        restir::Pcg32 rng = restir::make_pixel_rng(trial, 0u, 0u, 11u);
        const auto draw = [&](restir::Pcg32& g) {
            const restir::DiscreteSample c = restir::sample_light(sampler, g);
            const float u = next_float(g);
            const float v = next_float(g);
            return restir::SourceSample<restir::LightSampleRef>{{c.index, {u, v}}, c.pmf};
        };
        const auto r = restir::resample_ris(rng, 8u, draw, irradiance);
        estimate.add(static_cast<double>(irradiance(r.sample) * r.contribution_weight));
    }
    EXPECT_TRUE(restir::test::agrees_with(estimate, truth));
}

} // namespace

namespace {

// A 4 x 2 sky: a bright texel in the upper half, dimmer elsewhere.
restir::EnvironmentMap small_sky() {
    std::vector<glm::vec3> texels(8u, glm::vec3(0.2f, 0.3f, 0.5f));
    texels[1] = glm::vec3(5.0f, 4.0f, 3.0f);
    return restir::EnvironmentMap(texels, 4u, 2u);
}

TEST(UnifiedLightSet, EnvironmentSitsBetweenEmittersAndVplsAsADistantLight) {
    const RectangleLights emitters = two_rectangles();
    const std::vector<restir::Vpl> vpls = some_vpls();
    const restir::EnvironmentMap sky = small_sky();
    const Unified lights{&emitters, vpls.data(), static_cast<std::uint32_t>(vpls.size()),
                         sky.view()};
    EXPECT_EQ(lights.light_count(), 3u + vpls.size());
    EXPECT_EQ(lights.environment_id(), 2u);
    EXPECT_TRUE(lights.is_environment(2u));
    EXPECT_FALSE(lights.is_vpl(2u));
    EXPECT_TRUE(lights.is_vpl(3u));
    EXPECT_EQ(lights.sample_point(3u + 5u, glm::vec2(0.3f)).position, vpls[5].position);
    const restir::LightSample d = lights.sample_point(2u, glm::vec2(0.3f, 0.6f));
    const restir::EnvironmentSample expected = sky.view().sample(glm::vec2(0.3f, 0.6f));
    EXPECT_TRUE(d.is_distant);
    EXPECT_FALSE(d.is_delta);
    EXPECT_EQ(d.position, expected.direction);
    EXPECT_EQ(d.radiance, expected.radiance);
    EXPECT_EQ(d.area_pdf, expected.pdf);

    EXPECT_THROW(restir::unified_light_powers(lights), std::invalid_argument);
    const float radius = 2.0f;
    const std::vector<float> powers =
        restir::unified_light_powers(lights, restir::environment_power(sky, radius));
    const glm::vec3 integral = sky.radiance_integral();
    EXPECT_FLOAT_EQ(powers[2], 3.14159265f * radius * radius * channel_sum(integral));
    EXPECT_FLOAT_EQ(powers[3], channel_sum(vpls[0].flux));
    // Without an environment nothing moves.
    const Unified plain{&emitters, vpls.data(), static_cast<std::uint32_t>(vpls.size())};
    EXPECT_EQ(plain.first_vpl(), 2u);
    EXPECT_FALSE(plain.is_environment(2u));
}

// RIS over emitters and the sky, by power, estimates the irradiance of both: the sky's part by
// quadrature over the map's texels (the part above the receiver's horizon).
TEST(UnifiedLightSet, RisOverEmittersAndTheSkyIsUnbiased) {
    const RectangleLights emitters = two_rectangles();
    const restir::EnvironmentMap sky = small_sky();
    const Unified lights{&emitters, nullptr, 0u, sky.view()};
    const restir::AliasTable table(
        restir::unified_light_powers(lights, restir::environment_power(sky, 1.0f)));
    const restir::PowerLightSampler sampler{table.view()};
    const glm::vec3 receiver(0.1f, -0.6f, 0.2f);
    const glm::vec3 normal = glm::normalize(glm::vec3(0.2f, 1.0f, 0.1f));
    const auto irradiance = [&](const restir::LightSampleRef& ref) {
        return channel_sum(restir::unshadowed_irradiance(lights.sample_point(ref.light_id, ref.uv),
                                                         receiver, normal, restir::Falloff{}));
    };
    double truth = 0.0;
    for (std::uint32_t id = 0; id < 2u; ++id)
        truth += restir::test::mean_over_unit_square<double>(1000, [&](glm::vec2 uv) {
            return static_cast<double>(irradiance({id, uv}));
        });
    // The sky: L cos over the sphere.
    const restir::EnvironmentMapView view = sky.view();
    truth += restir::test::integrate_over_sphere<double>(1000, [&](glm::vec3 w) {
        return static_cast<double>(channel_sum(view.radiance(w))) *
               std::max(0.0, static_cast<double>(glm::dot(normal, w)));
    });

    restir::test::RunningStats stats;
    for (std::uint32_t trial = 0; trial < 20000u; ++trial) {
        restir::Pcg32 rng = restir::make_pixel_rng(trial, 0u, 0u, 5u);
        const auto reservoir = restir::resample_ris(
            rng, 8u,
            [&](restir::Pcg32& g) {
                const restir::DiscreteSample c = restir::sample_light(sampler, g);
                const float u = restir::next_float(g);
                const float v = restir::next_float(g);
                return restir::SourceSample<restir::LightSampleRef>{{c.index, {u, v}}, c.pmf};
            },
            irradiance);
        stats.add(reservoir.has_sample() ? static_cast<double>(irradiance(reservoir.sample) *
                                                               reservoir.contribution_weight)
                                         : 0.0);
    }
    EXPECT_TRUE(restir::test::agrees_with(stats, truth));
}

} // namespace

namespace {

// Flat rectangles of one radiance: a point's normal, radiance and density are the rectangle's
// wherever it lies, so the position gives the point back (restir::LightPointLookup).
struct FlatRectangles : RectangleLights {
    restir::LightSample point_at(std::uint32_t id, glm::vec3 position) const {
        restir::LightSample s = sample_point(id, glm::vec2(0.0f));
        s.position = position;
        return s;
    }
};
static_assert(restir::LightPointLookup<FlatRectangles>);
static_assert(restir::LightPointLookup<restir::UnifiedLightSet<FlatRectangles>>);
static_assert(
    restir::LightPointDecoder<restir::LightSetDecoder<restir::UnifiedLightSet<FlatRectangles>>>);

// Every light's sample (emitters, the sky, VPLs) comes back from its id and position exactly,
// through a packed history too; an id past the set is a removed light.
TEST(UnifiedLightSet, PointsComeBackFromTheirPositions) {
    const FlatRectangles emitters{two_rectangles()};
    const std::vector<restir::Vpl> vpls = some_vpls();
    const restir::EnvironmentMap sky = small_sky();
    const restir::UnifiedLightSet<FlatRectangles> lights{
        &emitters, vpls.data(), static_cast<std::uint32_t>(vpls.size()), sky.view()};
    const restir::Falloff falloff{restir::FalloffKind::yuksel, 0.1f};
    const restir::LightSetDecoder<restir::UnifiedLightSet<FlatRectangles>> decode{lights, falloff};
    restir::Pcg32 rng{17u};
    for (std::uint32_t id = 0; id < lights.light_count(); ++id) {
        const glm::vec2 uv(next_float(rng), next_float(rng));
        const restir::LightPointSample x =
            restir::make_light_point_sample(id, lights.sample_point(id, uv), falloff);
        restir::Reservoir<restir::LightPointSample> r;
        r.stream(x, 2.0f, 0.5f, 0.0f);
        r.finalize();
        const restir::PackedPointReservoir stored = restir::pack_reservoir(r);
        const restir::PackedPointHistory<decltype(decode)> history{{&stored, 1u, 1u}, decode};
        for (const restir::LightPointSample& y :
             {decode(id, x.position), history.load({0, 0}).sample}) {
            EXPECT_EQ(y.light_id, id);
            EXPECT_EQ(y.position, x.position) << "light " << id;
            EXPECT_EQ(y.normal, x.normal) << "light " << id;
            EXPECT_EQ(y.intensity, x.intensity) << "light " << id;
            EXPECT_EQ(y.falloff, x.falloff) << "light " << id;
            EXPECT_EQ(y.positional, x.positional) << "light " << id;
        }
    }
    EXPECT_EQ(decode(lights.light_count(), glm::vec3(0.0f)).light_id, restir::removed_light);
}

} // namespace
