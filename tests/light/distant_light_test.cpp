// Distant lights (an environment's directions) as light samples: the same direction and value
// from every receiver, in the folded formulas, in tiles and batch RIS, and in shadow segments
// that run past the scene instead of ending at a point.
#include <restir/restir.hpp>

#include <gtest/gtest.h>

#include <glm/geometric.hpp>

#include <cmath>
#include <cstdint>
#include <vector>

namespace {

const glm::vec3 sky_direction = glm::normalize(glm::vec3(0.3f, 0.9f, -0.2f));
const glm::vec3 sky_radiance{2.0f, 1.5f, 0.5f};
constexpr float sky_pdf = 0.25f; // per steradian

restir::LightSample sky_point() {
    restir::LightSample p;
    p.position = sky_direction;
    p.normal = glm::vec3(0.0f);
    p.radiance = sky_radiance;
    p.area_pdf = sky_pdf;
    p.is_distant = true;
    return p;
}

// L cos(theta) / pdf times the receiver's f: one sample of the reflected radiance.
glm::vec3 expected_lambertian(glm::vec3 normal, glm::vec3 albedo) {
    return sky_radiance * albedo *
           (restir::inv_pi * std::max(0.0f, glm::dot(normal, sky_direction)) / sky_pdf);
}

TEST(DistantLight, FoldsToRadianceOverPdfWithNoPosition) {
    const restir::LightPointSample s =
        restir::make_light_point_sample(3u, sky_point(), restir::Falloff::yuksel(0.5f));
    EXPECT_TRUE(s.is_distant());
    EXPECT_EQ(s.positional, 0.0f);
    EXPECT_EQ(s.falloff, 0.0f); // a falloff is for delta lights, not directions
    EXPECT_EQ(s.normal, glm::vec3(0.0f));
    EXPECT_EQ(s.intensity, sky_radiance / sky_pdf);
    const glm::vec3 albedo{0.8f, 0.5f, 0.2f};
    for (const glm::vec3 position :
         {glm::vec3(0.0f), glm::vec3(10.0f, -3.0f, 7.0f), glm::vec3(-1e4f, 2e4f, 5.0f)})
        for (const glm::vec3 normal :
             {glm::vec3(0.0f, 1.0f, 0.0f), glm::normalize(glm::vec3(1.0f, 0.2f, -0.4f)),
              glm::vec3(0.0f, -1.0f, 0.0f)}) {
            const glm::vec3 expected = expected_lambertian(normal, albedo);
            const glm::vec3 got = restir::unshadowed_radiance(
                s, restir::LambertianReceiver{position, normal, albedo});
            const glm::vec3 generic =
                albedo * restir::inv_pi *
                restir::unshadowed_irradiance(sky_point(), position, normal, restir::Falloff{});
            for (int c = 0; c < 3; ++c) {
                EXPECT_NEAR(got[c], expected[c], 1e-5f * expected[c] + 1e-7f);
                EXPECT_NEAR(generic[c], expected[c], 1e-5f * expected[c] + 1e-7f);
            }
        }
}

TEST(DistantLight, GlossyReceiverReflectsTheDirectionItself) {
    const restir::LightPointSample s =
        restir::make_light_point_sample(0u, sky_point(), restir::Falloff::exact());
    restir::GlossyReceiver receiver{
        {5.0f, 1.0f, -2.0f},
        {0.0f, 1.0f, 0.0f},
        glm::normalize(glm::vec3(-0.3f, 1.0f, 0.2f)),
        restir::GlossyBsdf::from_metallic_roughness({0.9f, 0.8f, 0.6f}, 1.0f, 0.2f)};
    const glm::vec3 expected = sky_radiance * receiver.reflected(sky_direction) / sky_pdf;
    const glm::vec3 got = restir::unshadowed_radiance(s, receiver);
    EXPECT_GT(expected.x, 0.0f);
    for (int c = 0; c < 3; ++c)
        EXPECT_NEAR(got[c], expected[c], 1e-5f * expected[c]);
}

// Tile entries alternate between the sky's direction and a point light: the batch loop gives
// each its own value at receivers far from the origin, and the entries read back as stored.
TEST(DistantLight, TileBatchEvaluatesDirectionsAndPointsAlike) {
    constexpr std::uint32_t size = 16u;
    std::vector<float> planes(size * restir::tile_plane_count);
    std::vector<restir::LightSampleRef> references(size);
    const restir::LightTileArrays tiles{planes.data(), references.data(), 1u, size};
    restir::LightSample point;
    point.position = {0.0f, 4.0f, 0.0f};
    point.normal = glm::vec3(0.0f);
    point.radiance = glm::vec3(3.0f);
    point.area_pdf = 1.0f;
    point.is_delta = true;
    for (std::uint32_t i = 0; i < size; ++i)
        tiles.store(0u, i, {{i, {0.0f, 0.0f}}, 0.5f, i % 2u == 0u ? sky_point() : point},
                    restir::Falloff::exact());
    const glm::vec3 albedo{0.6f, 0.6f, 0.6f};
    for (const glm::vec3 position : {glm::vec3(0.0f), glm::vec3(50.0f, 1.0f, -20.0f)}) {
        const restir::LambertianReceiver receiver{position, {0.0f, 1.0f, 0.0f}, albedo};
        restir::CandidateBlock<size> block;
        restir::evaluate_tile_block<size, restir::ChannelNorm::sum>(tiles, 0u, 0u, receiver, block);
        for (std::uint32_t i = 0; i < size; ++i) {
            const restir::LightPointSample s = tiles.point_sample(i);
            EXPECT_EQ(s.is_distant(), i % 2u == 0u);
            glm::vec3 expected;
            if (i % 2u == 0u) {
                expected = expected_lambertian(receiver.normal, albedo);
            } else {
                const glm::vec3 x = point.position - position;
                const float d2 = glm::dot(x, x);
                expected = point.radiance * albedo * restir::inv_pi *
                           std::max(0.0f, glm::dot(receiver.normal, x) / std::sqrt(d2)) / d2;
            }
            const float folded = expected.x + expected.y + expected.z;
            EXPECT_NEAR(block.target[i], folded, 1e-5f * folded + 1e-9f) << "entry " << i;
        }
    }
}

struct Surface {
    glm::vec3 position;
    glm::vec3 normal;
};
glm::vec3 surface_position(const Surface& s) { return s.position; }
glm::vec3 surface_normal(const Surface& s) { return s.normal; }
[[maybe_unused]] float surface_depth(const Surface&) { return 1.0f; }
[[maybe_unused]] bool is_valid_surface(const Surface&) { return true; }

// Remembers the last segment it was asked about; a wall at y = 5 blocks everything above it.
struct RecordingQuery {
    mutable glm::vec3 from{0.0f}, to{0.0f};
    bool occluded(glm::vec3 a, glm::vec3 b) const {
        from = a;
        to = b;
        return std::max(a.y, b.y) > 5.0f;
    }
};

// One sky light, for LightVisibility.
struct SkyOnly {
    std::uint32_t light_count() const { return 1u; }
    restir::LightSample sample_point(std::uint32_t, glm::vec2) const { return sky_point(); }
};

TEST(DistantLight, ShadowRaysRunPastTheSceneAlongTheDirection) {
    const Surface surface{{1.0f, 2.0f, 3.0f}, {0.0f, 1.0f, 0.0f}};
    const float extent = 10.0f;
    const RecordingQuery query;
    const auto visibility = restir::LightPointVisibility<RecordingQuery>::for_scene(query, extent);
    const restir::LightPointSample s =
        restir::make_light_point_sample(0u, sky_point(), restir::Falloff::exact());
    EXPECT_FALSE(visibility(s, surface)); // the wall at y = 5 is in the way
    const glm::vec3 start = surface.position + surface.normal * (1e-4f * extent);
    for (int c = 0; c < 3; ++c) {
        EXPECT_FLOAT_EQ(query.from[c], start[c]);
        EXPECT_FLOAT_EQ(query.to[c], start[c] + sky_direction[c] * 2.0f * extent);
    }
    const SkyOnly lights;
    const auto by_reference =
        restir::LightVisibility<SkyOnly, RecordingQuery>::for_scene(lights, query, extent);
    EXPECT_FALSE(by_reference(restir::LightSampleRef{0u, {0.5f, 0.5f}}, surface));
    for (int c = 0; c < 3; ++c)
        EXPECT_FLOAT_EQ(query.to[c], start[c] + sky_direction[c] * 2.0f * extent);
    // Below the wall, looking down and sideways, nothing blocks: the start leaves the surface
    // on the side the direction goes.
    const Surface under{{1.0f, 2.0f, 3.0f}, {0.0f, -1.0f, 0.0f}};
    restir::LightPointSample down = s;
    down.position = glm::normalize(glm::vec3(1.0f, -0.2f, 0.0f));
    EXPECT_TRUE(visibility(down, under));
    EXPECT_FLOAT_EQ(query.from.y, 2.0f - 1e-4f * extent);
}

TEST(DistantLight, PhotonEmitterPointsLeaveDistantLightsOut) {
    const SkyOnly lights;
    EXPECT_TRUE(restir::make_emitter_points(lights, 16u, 1u).empty());
}

} // namespace
