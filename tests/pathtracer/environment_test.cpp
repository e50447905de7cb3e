// The renderer's environment light: the generated sun and sky reach their stated irradiances,
// bad maps are refused with one-line messages, escaped camera rays show the sky in every
// method, and the reference path tracer's sky is unbiased: a diffuse or glossy plane under a
// uniform sky reads its directional albedo, and the image is the same with and without the
// sky's next-event estimation.
#include "environment.hpp"
#include "image_io.hpp"
#include "renderer.hpp"
#include "scene.hpp"
#include "scene_quad.hpp"

#include "pathtracer/directional_albedo.hpp"
#include "support/statistics.hpp"

#include <glm/geometric.hpp>
#include <gtest/gtest.h>

#include <cmath>
#include <cstdio>
#include <limits>
#include <memory>
#include <numbers>
#include <string>
#include <vector>

namespace {

using pt::GlobalIllumination;
using pt::Method;

constexpr double pi = std::numbers::pi;

// An environment of `texels` (through pt::make_environment, as --env builds one).
std::shared_ptr<const pt::Environment> map_of(const std::vector<glm::vec3>& texels,
                                              std::uint32_t width, std::uint32_t height,
                                              const std::string& name, float scale = 1.0f,
                                              float rotate_degrees = 0.0f) {
    return pt::make_environment(texels, width, height, name, scale, rotate_degrees);
}

double luminance(glm::vec3 c) {
    return 0.2126 * static_cast<double>(c.x) + 0.7152 * static_cast<double>(c.y) +
           0.0722 * static_cast<double>(c.z);
}

// The horizontal irradiance (luminance) of `environment`, estimated from its own sampler:
// E = integral of L max(0, cos theta), L / pdf per draw.
restir::test::RunningStats horizontal_irradiance(const pt::Environment& environment,
                                                 std::uint64_t seed) {
    const restir::EnvironmentMapView view = environment.view();
    restir::Pcg32 rng = restir::make_pixel_rng(0u, 0u, 0u, seed);
    restir::test::RunningStats irradiance;
    for (int i = 0; i < 1 << 20; ++i) {
        const float u0 = next_float(rng);
        const float u1 = next_float(rng);
        const restir::EnvironmentSample s = view.sample({u0, u1});
        irradiance.add(s.pdf > 0.0f ? luminance(s.radiance) *
                                          std::max(0.0, static_cast<double>(s.direction.y)) /
                                          static_cast<double>(s.pdf)
                                    : 0.0);
    }
    return irradiance;
}

// The sky alone lights a horizontal plane with E = pi, the sun with four times that (the
// defaults of SunSkyParams), measured by sampling the map rather than from the builder's sums.
TEST(Environment, SunAndSkyReachTheirStatedIrradiance) {
    pt::SunSkyParams params;
    params.width = 1024;
    params.height = 512;
    pt::SunSkyFigures figures;
    const std::vector<glm::vec3> texels = pt::make_sun_sky_texels(params, &figures);
    EXPECT_NEAR(figures.sky_irradiance, pi, 1e-3 * pi);
    EXPECT_NEAR(figures.sun_irradiance, 4.0 * pi, 4e-3 * pi);
    const auto sun_sky = pt::make_environment(texels, params.width, params.height, "test", 1, 0);
    EXPECT_TRUE(restir::test::agrees_with(horizontal_irradiance(*sun_sky, 1u), 5.0 * pi));
    params.sun_to_sky_ratio = 0.0f;
    const auto sky = pt::make_sun_sky_environment(params);
    EXPECT_TRUE(restir::test::agrees_with(horizontal_irradiance(*sky, 2u), pi));
}

// The sun lies where its elevation and azimuth say (through restir::equirect_uv), the sky is
// bluer at the zenith and brighter at the horizon, and the ground below is dim.
TEST(Environment, SunSkyHasItsSunWhereStatedAndAGradient) {
    const pt::SunSkyParams params; // elevation 35, azimuth -50 degrees from -Z towards +X
    pt::SunSkyFigures figures;
    const std::vector<glm::vec3> texels = pt::make_sun_sky_texels(params, &figures);
    const auto environment =
        pt::make_environment(texels, params.width, params.height, "sun-sky", 1, 0);
    const float elevation = 35.0f * std::numbers::pi_v<float> / 180.0f;
    const float azimuth = -50.0f * std::numbers::pi_v<float> / 180.0f;
    const glm::vec3 sun{std::sin(azimuth) * std::cos(elevation), std::sin(elevation),
                        -std::cos(azimuth) * std::cos(elevation)};
    const auto sun_radiance = static_cast<double>(figures.sun_radiance);
    EXPECT_NEAR(luminance(environment->radiance(sun)), sun_radiance, 1e-4 * sun_radiance);
    EXPECT_GT(figures.sun_radiance, 1e5f); // a 0.5 degree disc four times as bright as the sky
    EXPECT_GE(figures.sun_texels, 2u);
    EXPECT_LE(figures.sun_texels, 12u); // about 0.5 / 0.176 texels across
    // Away from the sun: the mirror image of its direction about the vertical plane x = 0.
    EXPECT_LT(luminance(environment->radiance({-sun.x, sun.y, sun.z})), 10.0);
    const glm::vec3 zenith = environment->radiance({0.0f, 1.0f, 0.0f});
    const glm::vec3 horizon = environment->radiance(glm::normalize(glm::vec3{0.0f, 0.02f, 1.0f}));
    const glm::vec3 ground = environment->radiance(glm::normalize(glm::vec3{0.3f, -1.0f, 0.2f}));
    std::printf("sun-sky %ux%u: sky E %.4f, sun E %.4f, %u sun texels of luminance %.4g; "
                "zenith (%.3f %.3f %.3f), horizon (%.3f %.3f %.3f), ground (%.3f %.3f %.3f)\n",
                params.width, params.height, static_cast<double>(figures.sky_irradiance),
                static_cast<double>(figures.sun_irradiance), figures.sun_texels, sun_radiance,
                static_cast<double>(zenith.x), static_cast<double>(zenith.y),
                static_cast<double>(zenith.z), static_cast<double>(horizon.x),
                static_cast<double>(horizon.y), static_cast<double>(horizon.z),
                static_cast<double>(ground.x), static_cast<double>(ground.y),
                static_cast<double>(ground.z));
    EXPECT_GT(zenith.z / zenith.x, 2.0f * horizon.z / horizon.x); // bluer above
    EXPECT_GT(luminance(horizon), 2.0 * luminance(zenith));       // brighter low
    EXPECT_LT(luminance(ground), luminance(zenith));              // dim below
}

// Every map the library refuses is an ImageError with a one-line message naming the map.
TEST(Environment, BadMapsAreOneLineImageErrors) {
    const float nan = std::numeric_limits<float>::quiet_NaN();
    const float inf = std::numeric_limits<float>::infinity();
    const auto refused = [](std::vector<glm::vec3> texels, std::uint32_t w, std::uint32_t h,
                            float scale, float rotate, const char* needle) {
        try {
            pt::make_environment(texels, w, h, "map.pfm", scale, rotate);
            ADD_FAILURE() << needle << ": accepted";
        } catch (const pt::ImageError& e) {
            const std::string what = e.what();
            EXPECT_NE(what.find("map.pfm"), std::string::npos) << what;
            EXPECT_NE(what.find(needle), std::string::npos) << what;
            EXPECT_EQ(what.find('\n'), std::string::npos) << what;
        }
    };
    const glm::vec3 one(1.0f);
    refused({one, glm::vec3(nan, 1, 1)}, 2, 1, 1, 0, "texel (1, 0)");
    refused({glm::vec3(1, -1, 1), one}, 2, 1, 1, 0, "texel (0, 0)");
    refused({one, glm::vec3(1, inf, 1)}, 1, 2, 1, 0, "texel (0, 1)");
    refused({glm::vec3(0.0f), glm::vec3(0.0f)}, 2, 1, 1, 0, "zero everywhere");
    refused({one}, 2, 1, 1, 0, "texels given");
    refused({}, 0, 0, 1, 0, "must be > 0");
    refused({one}, 1, 1, 0, 0, "scale");
    refused({one}, 1, 1, nan, 0, "scale");
    refused({one}, 1, 1, 1, inf, "rotation");
    refused({glm::vec3(1e20f)}, 1, 1, 1e20f, 0, "1e30");
    // A 1 x 1 map is a constant sky.
    const auto constant = map_of({glm::vec3(0.5f)}, 1, 1, "one.pfm", 2.0f, 30.0f);
    EXPECT_EQ(constant->radiance({0.0f, -1.0f, 0.0f}), glm::vec3(1.0f));
    EXPECT_NEAR(constant->view().pdf({1.0f, 0.0f, 0.0f}), 1.0 / (4.0 * pi), 1e-6);
}

// A ground plane of `material` (normal +Y, 100 x 100) under `environment`, with one small
// emitter beneath it facing down (the renderer needs an emitter; it lights nothing above), and
// a camera looking down at the plane: every pixel sees it.
pt::Scene plane_under(std::shared_ptr<const pt::Environment> environment,
                      const pt::Material& material) {
    pt::Scene scene;
    scene.name = "plane under the sky";
    scene.materials = {material, {.name = "hidden lamp", .emission = glm::vec3(1.0f)}};
    pt::add_quad(scene, {{{-50, 0, -50}, {50, 0, -50}, {50, 0, 50}, {-50, 0, 50}}}, {0, 1, 0}, 0);
    pt::add_quad(scene, {{{-1, -2, -1}, {1, -2, -1}, {1, -2, 1}, {-1, -2, 1}}}, {0, -1, 0}, 1);
    scene.environment = std::move(environment);
    scene.camera = pt::CameraSetup{{0.0f, 2.0f, 0.0f}, {0.6f, 0.0f, -0.4f}, {0, 1, 0}, 40.0f};
    return scene;
}

pt::RenderSettings reference_settings(const pt::Scene& scene, std::uint32_t size) {
    pt::RenderSettings s;
    s.width = size;
    s.height = size;
    s.camera = *scene.camera;
    s.method = Method::reference;
    s.threads = 2;
    return s;
}

// The sky furnace: an unoccluded Lambertian plane of albedo a under a uniform sky of radiance 1
// reflects a (irradiance pi, times a / pi), with direct light only and with paths, the sky
// sampled with MIS against the BSDF.
TEST(Environment, ReferenceReadsTheAlbedoUnderAUniformSky) {
    const float albedo = 0.6f;
    const pt::Scene scene = plane_under(map_of({glm::vec3(1.0f)}, 1, 1, "white"),
                                        {.name = "grey", .albedo = glm::vec3(albedo)});
    for (GlobalIllumination gi : {GlobalIllumination::none, GlobalIllumination::path}) {
        pt::RenderSettings s = reference_settings(scene, 16);
        s.gi = gi;
        pt::Renderer renderer(scene, s);
        const restir::test::RunningStats radiance = pt::test::pixel_means(renderer, 8);
        std::printf("plane under a white sky, gi %d: %.5f +- %.5f, expected %.5f\n",
                    static_cast<int>(gi), radiance.mean(), radiance.standard_error(),
                    static_cast<double>(albedo));
        EXPECT_TRUE(restir::test::agrees_with(radiance, static_cast<double>(albedo)))
            << static_cast<int>(gi);
    }
}

// The same for glossy planes: L = A(wo), the directional albedo, integral of f cos over the
// hemisphere, here from BSDF sampling alone (the mean of GlossyBsdf::sample's weights) while
// the renderer also samples the sky, so that a wrong density in either MIS weight or a wrong
// f cos in the sky's NEE shows.
TEST(Environment, ReferenceReadsTheDirectionalAlbedoOfGlossyPlanesUnderAUniformSky) {
    const pt::Material materials[] = {
        {.name = "dielectric", .albedo = glm::vec3(0.5f), .specular = 0.04f, .roughness = 0.2f},
        {.name = "copper", .albedo = {0.95f, 0.64f, 0.54f}, .roughness = 0.3f, .metallic = 1.0f}};
    const glm::vec3 eye{0.0f, 1.0f, 2.0f}, seen{0.0f, 0.0f, 0.0f}, normal{0.0f, 1.0f, 0.0f};
    const glm::vec3 wo = glm::normalize(eye - seen);
    for (const pt::Material& material : materials) {
        const pt::test::ChannelStats albedo = pt::test::directional_albedo(
            material.bsdf(), normal, wo, 1 << 21, restir::make_pixel_rng(0u, 0u, 0u, 9u));
        pt::Scene scene = plane_under(map_of({glm::vec3(1.0f)}, 1, 1, "white"), material);
        scene.camera = pt::CameraSetup{eye, seen, {0.0f, 1.0f, 0.0f}, 30.0f};
        pt::RenderSettings s = reference_settings(scene, 1);
        s.gi = GlobalIllumination::none;
        s.spp = 64;
        pt::Renderer renderer(scene, s);
        const pt::test::ChannelStats radiance = pt::test::pixel_radiance(renderer, 400);
        for (int c = 0; c < 3; ++c) {
            const double error = std::abs(radiance[c].mean() - albedo[c].mean());
            const double se = std::hypot(radiance[c].standard_error(), albedo[c].standard_error());
            std::printf("%s under a white sky, channel %d: %.5f, expected %.5f +- %.5f\n",
                        material.name.c_str(), c, radiance[c].mean(), albedo[c].mean(), se);
            EXPECT_LT(error, 4.0 * se) << material.name << ", channel " << c;
        }
    }
}

// The sun-sky scene under a sun of 8 degrees (so that BSDF rays alone find it often enough):
// the reference path tracer with the sky's NEE (MIS) and without it (escaped BSDF rays alone)
// estimate the same image; the mean brightness over 8 seeds agrees within 4 standard errors.
TEST(Environment, SkyNeeAndBsdfRaysEstimateTheSameImage) {
    pt::SunSkyParams sky;
    sky.width = 256;
    sky.height = 128;
    sky.sun_diameter_degrees = 8.0f;
    const pt::Scene scene = pt::make_sun_sky_scene(pt::make_sun_sky_environment(sky));
    pt::RenderSettings s = reference_settings(scene, 24);
    s.gi = GlobalIllumination::path;
    s.spp = 16;
    restir::test::RunningStats brightness[2];
    for (std::uint64_t seed = 1; seed <= 8; ++seed)
        for (int k = 0; k < 2; ++k) {
            s.environment_nee = k == 0;
            s.seed = seed;
            pt::Renderer renderer(scene, s);
            for (int frame = 0; frame < 4; ++frame)
                renderer.render_frame();
            double sum = 0.0;
            for (const glm::vec3& p : renderer.accumulated().pixels)
                sum += static_cast<double>(p.x + p.y + p.z);
            brightness[k].add(sum);
        }
    const double difference = std::abs(brightness[0].mean() - brightness[1].mean());
    const double error = std::hypot(brightness[0].standard_error(), brightness[1].standard_error());
    std::printf("sun-sky: with the sky's NEE %.2f +- %.2f, BSDF rays alone %.2f +- %.2f\n",
                brightness[0].mean(), brightness[0].standard_error(), brightness[1].mean(),
                brightness[1].standard_error());
    EXPECT_LT(difference, 4.0 * error);
}

// Pixels whose camera ray leaves the scene show the sky in its direction, in every method: a
// map of two rows (the upper hemisphere blue, the lower brown) seen by a camera looking up.
TEST(Environment, EscapedCameraRaysShowTheSkyInEveryMethod) {
    const glm::vec3 blue{0.2f, 0.4f, 0.9f}, brown{0.5f, 0.3f, 0.1f};
    const pt::Scene base = plane_under(map_of({blue, brown}, 1, 2, "two rows"),
                                       {.name = "grey", .albedo = glm::vec3(0.5f)});
    pt::Scene scene = base;
    scene.camera = pt::CameraSetup{{0.0f, 1.0f, 0.0f}, {0.0f, 3.0f, -2.0f}, {0, 1, 0}, 30.0f};
    for (Method method : {Method::uniform, Method::ris, Method::restir, Method::reference}) {
        pt::RenderSettings s = reference_settings(scene, 8);
        s.method = method;
        s.gi = GlobalIllumination::none;
        pt::Renderer renderer(scene, s);
        renderer.render_frame();
        EXPECT_EQ(renderer.surface_pixel_count(), 0u);
        for (const glm::vec3& p : renderer.accumulated().pixels)
            ASSERT_EQ(p, blue) << static_cast<int>(method);
    }
}

} // namespace
