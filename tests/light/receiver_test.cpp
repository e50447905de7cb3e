// Receivers: the unshadowed radiance of a light point at any receiver, one by one and in the
// batch loop, against the folded diffuse formulas and direct evaluation.
#include <restir/restir.hpp>

#include <gtest/gtest.h>

#include <array>
#include <cmath>
#include <cstdint>
#include <vector>

namespace {

// A Lambertian receiver that the library does not recognise: it takes the general path.
struct PlainDiffuse {
    glm::vec3 position{0.0f};
    glm::vec3 normal{0.0f, 1.0f, 0.0f};
    glm::vec3 albedo{0.0f};
    glm::vec3 reflected(glm::vec3 wi) const {
        return albedo * (restir::inv_pi * std::max(0.0f, glm::dot(normal, wi)));
    }
};

// A receiver that reflects only light from straight above (a caricature of a glossy lobe), and
// counts nothing from elsewhere: the general path must hand it the unit direction to the light.
struct FromAbove {
    glm::vec3 position{0.0f};
    glm::vec3 reflected(glm::vec3 wi) const {
        return glm::vec3(wi.y > 0.99f ? 1.0f : 0.0f, std::max(0.0f, wi.y), wi.y * wi.y);
    }
};

// An area light point, VPLs under each falloff, and an isotropic point light, at varied places.
std::vector<restir::LightPointSample> light_points() {
    std::vector<restir::LightPointSample> points;
    const restir::Falloff falloffs[] = {restir::Falloff::exact(), restir::Falloff::yuksel(0.3f),
                                        restir::Falloff::clamped(0.2f)};
    for (int i = 0; i < 12; ++i) {
        const float t = static_cast<float>(i);
        restir::LightSample p;
        p.position = {0.3f * t - 1.5f, 0.5f + 0.2f * t, 0.1f * t * t - 0.7f};
        p.normal = glm::normalize(glm::vec3(0.2f * std::sin(t), -1.0f, 0.3f * std::cos(t)));
        p.radiance = {1.0f + t, 0.5f, 2.0f - 0.1f * t};
        p.area_pdf = i % 4 == 0 ? 0.25f + 0.1f * t : 1.0f;
        p.is_delta = i % 4 != 0;
        if (i % 4 == 3)
            p.normal = glm::vec3(0.0f); // isotropic
        points.push_back(
            restir::make_light_point_sample(static_cast<std::uint32_t>(i), p, falloffs[i % 3]));
    }
    return points;
}

TEST(Receiver, LambertianIsTheFoldedDiffuseFormula) {
    const restir::LambertianReceiver lambert{
        {0.1f, 0.0f, 0.2f}, {0.0f, 1.0f, 0.0f}, {0.8f, 0.5f, 0.2f}};
    for (const restir::LightPointSample& s : light_points()) {
        const glm::vec3 expected =
            lambert.albedo * restir::inv_pi *
            restir::unshadowed_irradiance(s, lambert.position, lambert.normal);
        const glm::vec3 got = restir::unshadowed_radiance(s, lambert);
        EXPECT_EQ(got.x, expected.x);
        EXPECT_EQ(got.y, expected.y);
        EXPECT_EQ(got.z, expected.z);
    }
}

TEST(Receiver, GeneralPathAgreesWithTheFoldedFormulaForADiffuseReceiver) {
    const PlainDiffuse plain{{0.1f, 0.0f, 0.2f}, {0.0f, 1.0f, 0.0f}, {0.8f, 0.5f, 0.2f}};
    const restir::LambertianReceiver lambert{plain.position, plain.normal, plain.albedo};
    int lit = 0;
    for (const restir::LightPointSample& s : light_points()) {
        const glm::vec3 expected = restir::unshadowed_radiance(s, lambert);
        const glm::vec3 got = restir::unshadowed_radiance(s, plain);
        for (int c = 0; c < 3; ++c)
            EXPECT_NEAR(got[c], expected[c], 1e-5f * expected[c] + 1e-12f);
        lit += expected.x > 0.0f ? 1 : 0;
    }
    EXPECT_GE(lit, 6); // the comparison saw lit points, not only zeros
}

TEST(Receiver, GeneralPathPassesTheUnitDirectionToTheLight) {
    restir::LightSample above;
    above.position = {0.0f, 2.0f, 0.0f};
    above.normal = {0.0f, -1.0f, 0.0f};
    above.radiance = glm::vec3(3.0f);
    above.area_pdf = 1.0f;
    above.is_delta = true;
    const restir::LightPointSample s =
        restir::make_light_point_sample(0u, above, restir::Falloff::exact());
    // I cos(theta_light) / d^2 times the receiver's (1, 1, 1) straight up: 3 / 4.
    const glm::vec3 got = restir::unshadowed_radiance(s, FromAbove{});
    EXPECT_FLOAT_EQ(got.x, 0.75f);
    EXPECT_FLOAT_EQ(got.y, 0.75f);
    EXPECT_FLOAT_EQ(got.z, 0.75f);
    // From the side the direction is oblique: wi.y = 2 / sqrt(5), the light's cosine too.
    const glm::vec3 side = restir::unshadowed_radiance(s, FromAbove{{1.0f, 0.0f, 0.0f}});
    const float cosine = 2.0f / std::sqrt(5.0f);
    EXPECT_EQ(side.x, 0.0f);
    EXPECT_NEAR(side.y, 3.0f * cosine / 5.0f * cosine, 1e-6f);
    EXPECT_NEAR(side.z, 3.0f * cosine / 5.0f * cosine * cosine, 1e-6f);
}

TEST(Receiver, LightAtTheReceiverGivesZeroNotNaN) {
    restir::LightSample at;
    at.position = glm::vec3(0.0f);
    at.normal = {0.0f, -1.0f, 0.0f};
    at.radiance = glm::vec3(1.0f);
    at.area_pdf = 1.0f;
    for (const restir::Falloff f : {restir::Falloff::exact(), restir::Falloff::yuksel(0.1f)}) {
        const restir::LightPointSample s = restir::make_light_point_sample(0u, at, f);
        const glm::vec3 got = restir::unshadowed_radiance(s, PlainDiffuse{{}, {}, glm::vec3(1)});
        EXPECT_EQ(got.x, 0.0f);
        EXPECT_EQ(got.y, 0.0f);
        EXPECT_EQ(got.z, 0.0f);
    }
}

// The batch loop at a receiver gives each entry's folded unshadowed radiance.
template <class R>
void expect_batch_matches_points(const R& receiver, float tolerance) {
    constexpr std::uint32_t size = 16u;
    std::vector<float> planes(size * restir::tile_plane_count);
    std::vector<restir::LightSampleRef> references(size);
    const restir::LightTileArrays tiles{planes.data(), references.data(), 1u, size};
    const std::vector<restir::LightPointSample> points = light_points();
    for (std::uint32_t i = 0; i < size; ++i) {
        const restir::LightPointSample& s = points[i % points.size()];
        restir::LightSample p;
        p.position = s.position;
        p.normal = s.normal;
        p.radiance = s.intensity; // an area pdf of 1 keeps the intensity as it is
        p.area_pdf = 1.0f;
        p.is_delta = s.falloff != 0.0f;
        const restir::Falloff falloff =
            s.falloff > 0.0f   ? restir::Falloff::yuksel(std::sqrt(s.falloff))
            : s.falloff < 0.0f ? restir::Falloff::clamped(std::sqrt(-s.falloff))
                               : restir::Falloff::exact();
        tiles.store(0u, i, {{i, {0.0f, 0.0f}}, 0.5f, p}, falloff);
    }
    restir::CandidateBlock<size> block;
    EXPECT_EQ((restir::evaluate_tile_block<size, restir::ChannelNorm::euclidean>(tiles, 0u, 0u,
                                                                                 receiver, block)),
              0u);
    int lit = 0;
    for (std::uint32_t i = 0; i < size; ++i) {
        const float expected = restir::fold_channels<restir::ChannelNorm::euclidean>(
            restir::unshadowed_radiance(tiles.point_sample(i), receiver));
        EXPECT_NEAR(block.target[i], expected, tolerance * expected + 1e-12f) << "entry " << i;
        EXPECT_EQ(block.inverse_pdf[i], 2.0f);
        lit += expected > 0.0f ? 1 : 0;
    }
    EXPECT_GE(lit, 4);
}

TEST(Receiver, BatchTargetsAreEachEntrysRadiance) {
    expect_batch_matches_points(
        restir::LambertianReceiver{{0.1f, 0.0f, 0.2f}, {0.0f, 1.0f, 0.0f}, {0.8f, 0.5f, 0.2f}},
        1e-6f);
    expect_batch_matches_points(
        PlainDiffuse{{0.1f, 0.0f, 0.2f}, {0.0f, 1.0f, 0.0f}, {0.8f, 0.5f, 0.2f}}, 1e-5f);
    expect_batch_matches_points(FromAbove{{-0.3f, 0.0f, 0.1f}}, 1e-5f);
    // A glossy receiver that sees a VplPartition's VPLs (the clamped points) through its diffuse
    // lobe alone does so in the batch as at each point.
    const restir::GlossyBsdf bsdf =
        restir::GlossyBsdf::from_metallic_roughness({0.8f, 0.5f, 0.2f}, 0.0f, 0.3f, 0.04f);
    const glm::vec3 wo = glm::normalize(glm::vec3(0.3f, 1.0f, 0.1f));
    for (const bool diffuse_only : {false, true})
        expect_batch_matches_points(
            restir::GlossyReceiver{
                {0.1f, 0.0f, 0.2f}, {0.0f, 1.0f, 0.0f}, wo, bsdf, 0.0f, diffuse_only},
            1e-5f);
}

} // namespace

namespace {

// A glossy receiver widens its lobe for lights with a sphere radius (VPLs with Yuksel's falloff)
// and for nothing else: an area light's point and an exact point light see the BSDF itself.
TEST(Receiver, GlossyLobeWidensForSpheresOnly) {
    restir::GlossyReceiver receiver{
        {0.0f, 0.0f, 0.0f},
        {0.0f, 1.0f, 0.0f},
        glm::normalize(glm::vec3(-1.0f, 1.0f, 0.0f)),
        restir::GlossyBsdf::from_metallic_roughness(glm::vec3(0.9f), 1.0f, 0.1f),
        0.25f};
    const glm::vec3 mirror = glm::normalize(glm::vec3(1.0f, 1.0f, 0.0f)); // the lobe's peak
    const glm::vec3 peak = receiver.reflected(mirror);
    EXPECT_EQ(receiver.reflected(mirror, 0.0f), peak);
    // alpha 0.01 widened to at least 0.25: the peak falls by far.
    EXPECT_LT(receiver.reflected(mirror, 0.01f).x, 0.1f * peak.x);
    receiver.sphere_min_alpha = 0.0f; // Karis's widening alone: alpha + 0.5 * 0.02
    const glm::vec3 widened = receiver.reflected(mirror, 0.02f);
    EXPECT_LT(widened.x, peak.x);
    EXPECT_GT(widened.x, 0.1f * peak.x);

    restir::LightSample light;
    light.position = 2.0f * mirror;
    light.normal = -mirror;
    light.radiance = glm::vec3(1.0f);
    light.area_pdf = 1.0f;
    light.is_delta = true;
    receiver.sphere_min_alpha = 0.25f;
    const float sharp =
        restir::unshadowed_radiance(
            restir::make_light_point_sample(0u, light, restir::Falloff::exact()), receiver)
            .x;
    EXPECT_NEAR(sharp, peak.x * 0.25f, 1e-5f * sharp); // cos 1, 1 / d^2
    const float sphere =
        restir::unshadowed_radiance(
            restir::make_light_point_sample(0u, light, restir::Falloff::yuksel(0.1f)), receiver)
            .x;
    EXPECT_LT(sphere, 0.1f * sharp);
}

} // namespace
