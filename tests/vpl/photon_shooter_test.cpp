// The photon shooter: energy conservation in a closed box, one-bounce indirect irradiance
// against direct Monte Carlo integration, determinism across threads, bad input, and photons
// from the sky: the flux a floor reflects under a sky, alone and beside an emitter.
#include <restir/restir.hpp>

#include "support/statistics.hpp"
#include "vpl/box_scene.hpp"

#include <gtest/gtest.h>

#include <array>
#include <cmath>
#include <cstdint>
#include <numbers>
#include <optional>
#include <stdexcept>
#include <string>
#include <thread>
#include <vector>

namespace {

using restir::PhotonParams;
using restir::Vpl;
using restir::test::ClosedBox;
using restir::test::FloorOnly;
using restir::test::Lambertian;
using restir::test::RectangleLights;
using restir::test::RunningStats;

glm::dvec3 total_flux(const std::vector<Vpl>& vpls) {
    glm::dvec3 sum(0.0);
    for (const Vpl& v : vpls)
        sum += glm::dvec3(v.flux);
    return sum;
}

RectangleLights box_light() {
    return {{restir::test::ceiling_light(0.9f, 0.4f, glm::vec3(2.0f, 1.0f, 0.5f))}};
}

// First bounce: every photon leaves with Phi / N (the emitter points share the flux equally,
// and are chosen in proportion to it) and hits a wall of albedo a, so the deposited reflected
// flux is exactly Phi * a: the estimator has no variance here, and only float rounding of the
// per-photon sums separates it from the truth.
TEST(PhotonShooter, FirstBounceDepositsThePhotonFluxTimesTheAlbedo) {
    const RectangleLights lights = box_light();
    const glm::vec3 albedo(0.3f, 0.5f, 0.7f);
    PhotonParams params = restir::default_photon_params();
    params.photon_count = 20'000u;
    params.max_bounces = 1u;
    const std::vector<Vpl> vpls =
        restir::shoot_photons(lights, ClosedBox{}, Lambertian{albedo}, params);
    ASSERT_EQ(vpls.size(), params.photon_count);
    const glm::dvec3 expected = glm::dvec3(lights.flux()) * glm::dvec3(albedo);
    const glm::dvec3 sum = total_flux(vpls);
    for (int c = 0; c < 3; ++c)
        EXPECT_NEAR(sum[c], expected[c], 1e-5 * expected[c]) << "channel " << c;
}

// All bounces: Russian roulette (survival = the largest channel of the albedo) makes the
// number of VPLs per photon random; the expected reflected flux per channel is
// Phi a (1 + a + ... + a^(L-1)) = Phi a (1 - a^L) / (1 - a) for a bounce limit L.
TEST(PhotonShooter, AllBouncesDepositTheGeometricSeriesOfReflectedFlux) {
    const RectangleLights lights = box_light();
    const glm::vec3 albedo(0.3f, 0.5f, 0.7f);
    PhotonParams params = restir::default_photon_params();
    params.photon_count = 2'000u;
    params.max_bounces = 8u;
    RunningStats channel[3];
    for (std::uint32_t trial = 0; trial < 400u; ++trial) {
        params.seed = trial;
        const glm::dvec3 sum =
            total_flux(restir::shoot_photons(lights, ClosedBox{}, Lambertian{albedo}, params));
        for (int c = 0; c < 3; ++c)
            channel[c].add(sum[c]);
    }
    for (int c = 0; c < 3; ++c) {
        const auto a = static_cast<double>(albedo[c]);
        const double expected = static_cast<double>(lights.flux()[c]) * a *
                                (1.0 - std::pow(a, params.max_bounces)) / (1.0 - a);
        EXPECT_TRUE(restir::test::agrees_with(channel[c], expected)) << "channel " << c;
    }
}

// One-bounce indirect irradiance at a sensor facing a lit floor, from the VPLs (exact 1/d^2, no
// clamping) and from a direct Monte Carlo estimate of the same double integral
//   E(r) = int_floor int_emitter (rho / pi) L G(e, y) G(y, r) dA_e dA_y.
TEST(PhotonShooter, VplIndirectIrradianceMatchesDirectIntegration) {
    const float floor_half = 2.0f;
    const float rho = 0.6f;
    const RectangleLights lights{{restir::test::ceiling_light(1.0f, 0.5f, glm::vec3(1.0f))}};
    const glm::vec3 sensor(0.8f, 0.3f, 0.1f);
    const glm::vec3 sensor_normal(0.0f, -1.0f, 0.0f);
    const restir::Falloff exact{restir::FalloffKind::inverse_square, 0.0f};

    PhotonParams params = restir::default_photon_params();
    params.photon_count = 4'000u;
    params.max_bounces = 1u;
    RunningStats from_vpls;
    for (std::uint32_t trial = 0; trial < 300u; ++trial) {
        params.seed = 1000u + trial;
        double e = 0.0;
        for (const Vpl& v : restir::shoot_photons(lights, FloorOnly{floor_half},
                                                  Lambertian{glm::vec3(rho)}, params))
            e += static_cast<double>(restir::unshadowed_irradiance(restir::vpl_light_sample(v),
                                                                   sensor, sensor_normal, exact)
                                         .x);
        from_vpls.add(e);
    }

    // Direct integration: y uniform on the floor, e uniform on the emitter.
    const restir::test::Rectangle& emitter = lights.rectangles[0];
    const double floor_area = 4.0 * static_cast<double>(floor_half * floor_half);
    const auto emitter_area = static_cast<double>(emitter.area());
    restir::Pcg32 rng = restir::make_pixel_rng(0u, 0u, 0u, 77u);
    RunningStats direct;
    for (int i = 0; i < 2'000'000; ++i) {
        const glm::vec3 y{floor_half * (2.0f * next_float(rng) - 1.0f), 0.0f,
                          floor_half * (2.0f * next_float(rng) - 1.0f)};
        const restir::LightSample e = lights.sample_point(0u, {next_float(rng), next_float(rng)});
        const glm::vec3 up(0.0f, 1.0f, 0.0f);
        const glm::vec3 to_emitter = e.position - y;
        const float d1 = glm::length(to_emitter);
        const float g1 = std::fmax(0.0f, glm::dot(up, to_emitter / d1)) *
                         std::fmax(0.0f, glm::dot(e.normal, -to_emitter / d1)) / (d1 * d1);
        const glm::vec3 to_sensor = sensor - y;
        const float d2 = glm::length(to_sensor);
        const float g2 = std::fmax(0.0f, glm::dot(up, to_sensor / d2)) *
                         std::fmax(0.0f, glm::dot(sensor_normal, -to_sensor / d2)) / (d2 * d2);
        direct.add(floor_area * emitter_area * static_cast<double>(rho / 3.14159265f * g1 * g2));
    }

    const double difference = std::abs(from_vpls.mean() - direct.mean());
    const double combined = std::sqrt(from_vpls.standard_error() * from_vpls.standard_error() +
                                      direct.standard_error() * direct.standard_error());
    EXPECT_LT(difference, 4.0 * combined)
        << "VPLs " << from_vpls.mean() << " +- " << from_vpls.standard_error() << ", direct "
        << direct.mean() << " +- " << direct.standard_error();
}

// Four threads interleaving photons give exactly the VPLs of one thread.
TEST(PhotonShooter, ResultDoesNotDependOnThreading) {
    const RectangleLights lights = box_light();
    PhotonParams params = restir::default_photon_params();
    params.photon_count = 40'000u; // more than one batch
    params.max_bounces = 3u;
    params.seed = 5u;
    const auto four_threads = [](std::uint32_t count, auto&& body) {
        std::vector<std::thread> threads;
        for (std::uint32_t t = 0; t < 4u; ++t)
            threads.emplace_back([&, t] {
                for (std::uint32_t i = t; i < count; i += 4u)
                    body(i);
            });
        for (std::thread& thread : threads)
            thread.join();
    };
    const std::vector<Vpl> one = restir::shoot_photons(lights, ClosedBox{}, Lambertian{}, params);
    const std::vector<Vpl> many =
        restir::shoot_photons(lights, ClosedBox{}, Lambertian{}, params, four_threads);
    ASSERT_EQ(one.size(), many.size());
    for (std::size_t i = 0; i < one.size(); ++i) {
        ASSERT_EQ(one[i].position, many[i].position) << i;
        ASSERT_EQ(one[i].flux, many[i].flux) << i;
    }
    params.seed = 6u;
    const std::vector<Vpl> other = restir::shoot_photons(lights, ClosedBox{}, Lambertian{}, params);
    EXPECT_NE(other.front().position, one.front().position);
}

TEST(PhotonShooter, BadInputGivesAnEmptySetAndNeverNaN) {
    PhotonParams params = restir::default_photon_params();
    params.photon_count = 1000u;
    EXPECT_TRUE(restir::shoot_photons(RectangleLights{}, ClosedBox{}, Lambertian{}, params).empty())
        << "no emitters";
    RectangleLights dark = box_light();
    dark.rectangles[0].radiance = glm::vec3(0.0f);
    EXPECT_TRUE(restir::shoot_photons(dark, ClosedBox{}, Lambertian{}, params).empty())
        << "zero flux";
    RectangleLights broken = box_light();
    broken.rectangles[0].radiance = glm::vec3(std::nanf(""));
    EXPECT_TRUE(restir::shoot_photons(broken, ClosedBox{}, Lambertian{}, params).empty())
        << "NaN radiance";
    PhotonParams no_budget = params;
    no_budget.photon_count = 0u;
    EXPECT_TRUE(restir::shoot_photons(box_light(), ClosedBox{}, Lambertian{}, no_budget).empty());
    PhotonParams no_points = params;
    no_points.points_per_emitter = 0u;
    EXPECT_TRUE(restir::shoot_photons(box_light(), ClosedBox{}, Lambertian{}, no_points).empty());
    // Photons that leave the scene (a floor of no extent) deposit nothing; black surfaces
    // deposit nothing.
    EXPECT_TRUE(restir::shoot_photons(box_light(), FloorOnly{0.0f}, Lambertian{}, params).empty());
    EXPECT_TRUE(restir::shoot_photons(box_light(), ClosedBox{}, Lambertian{glm::vec3(0.0f)}, params)
                    .empty());
    for (const Vpl& v : restir::shoot_photons(box_light(), ClosedBox{}, Lambertian{}, params))
        for (int c = 0; c < 3; ++c) {
            ASSERT_TRUE(std::isfinite(v.flux[c]));
            ASSERT_TRUE(std::isfinite(v.position[c]));
            ASSERT_TRUE(std::isfinite(v.normal[c]));
        }
}

TEST(EmitterPoints, ShareTheEmittedFluxAndStratifyTheEmitter) {
    const RectangleLights lights = box_light();
    const std::vector<restir::EmitterPoint> points = restir::make_emitter_points(lights, 16u, 3u);
    ASSERT_EQ(points.size(), 16u);
    glm::dvec3 sum(0.0);
    int quadrant[4] = {0, 0, 0, 0};
    for (const restir::EmitterPoint& p : points) {
        sum += glm::dvec3(p.flux);
        EXPECT_EQ(p.normal, glm::vec3(0.0f, -1.0f, 0.0f));
        ++quadrant[(p.position.x < 0.0f ? 0 : 1) + (p.position.z < 0.0f ? 0 : 2)];
    }
    for (int c = 0; c < 3; ++c)
        EXPECT_NEAR(sum[c], static_cast<double>(lights.flux()[c]),
                    1e-5 * static_cast<double>(lights.flux()[c]));
    for (int q : quadrant)
        EXPECT_EQ(q, 4) << "a 4 x 4 grid puts 4 points in each quadrant";
}

TEST(EmissionDirections, CosineAndSphereDensities) {
    // Mean cosine about the normal: 2/3 for the cosine density, 0 for the sphere.
    restir::Pcg32 rng = restir::make_pixel_rng(0u, 0u, 0u, 9u);
    const glm::vec3 normal = glm::normalize(glm::vec3(0.3f, -1.0f, 0.2f));
    RunningStats cosine, sphere;
    for (int i = 0; i < 200'000; ++i) {
        const float u0 = next_float(rng), u1 = next_float(rng);
        const glm::vec3 d = restir::sample_diffuse_direction(normal, u0, u1);
        ASSERT_NEAR(glm::length(d), 1.0f, 1e-5f);
        ASSERT_GE(glm::dot(d, normal), -1e-6f);
        cosine.add(static_cast<double>(glm::dot(d, normal)));
        sphere.add(static_cast<double>(
            glm::dot(restir::sample_diffuse_direction(glm::vec3(0.0f), u0, u1), normal)));
    }
    EXPECT_TRUE(restir::test::agrees_with(cosine, 2.0 / 3.0));
    EXPECT_TRUE(restir::test::agrees_with(sphere, 0.0));
}

// The floor square [-half, half]^2 at y = 0, seen from above only: photons travelling up from
// below the horizon pass it (as if its underside were black), so a sky lights one side.
struct SkyFloor {
    float half = 1.5f;
    restir::test::SceneHit closest_hit(glm::vec3 origin, glm::vec3 direction) const {
        if (!(direction.y < 0.0f) || !(origin.y > 0.0f))
            return {};
        const float t = -origin.y / direction.y;
        const glm::vec3 p = origin + t * direction;
        if (std::abs(p.x) > half || std::abs(p.z) > half)
            return {};
        return {{p.x, 0.0f, p.z}, {0.0f, 1.0f, 0.0f}, true};
    }
    double area() const { return 4.0 * static_cast<double>(half) * static_cast<double>(half); }
    // The bounding sphere about the origin (a margin over the square's half-diagonal).
    float radius() const { return 1.01f * std::sqrt(2.0f) * half; }
};

// A gradient sky with a sun above the horizon and a dark ground.
std::vector<glm::vec3> sunny_sky(std::uint32_t width, std::uint32_t height) {
    std::vector<glm::vec3> texels(std::size_t{width} * height);
    for (std::uint32_t y = 0; y < height; ++y)
        for (std::uint32_t x = 0; x < width; ++x) {
            const float v = (static_cast<float>(y) + 0.5f) / static_cast<float>(height);
            glm::vec3 c = v < 0.5f ? glm::vec3(0.3f + v, 0.6f, 1.0f - v) : glm::vec3(0.05f);
            if (y == height / 5u && x == width / 3u)
                c = glm::vec3(400.0f, 350.0f, 300.0f);
            texels[std::size_t{y} * width + x] = c;
        }
    return texels;
}

// Irradiance of the +Y side under a map, per channel: the sum over texels above the horizon of
// L (2 pi / w) (cos^2 theta_top - cos^2 theta_bottom) / 2 (the integral of cos over the texel),
// times scale. The height must be even (the horizon a row border).
glm::dvec3 upper_irradiance(const std::vector<glm::vec3>& texels, std::uint32_t width,
                            std::uint32_t height, double scale) {
    constexpr double pi = std::numbers::pi;
    glm::dvec3 sum(0.0);
    for (std::uint32_t y = 0; y < height / 2u; ++y) {
        const double top = std::cos(pi * y / height), bottom = std::cos(pi * (y + 1.0) / height);
        for (std::uint32_t x = 0; x < width; ++x)
            sum += glm::dvec3(texels[std::size_t{y} * width + x]) *
                   (pi / width * (top * top - bottom * bottom));
    }
    return sum * scale;
}

// Form factor from a point at height h above the centre of a parallel square of half-side s:
// four times that to an s x s rectangle with a corner below the point,
// (1 / 2 pi) (X / sqrt(1 + X^2) atan(Y / sqrt(1 + X^2)) + Y / sqrt(1 + Y^2) atan(X / ...)),
// X = Y = s / h (Howell's catalogue of configuration factors, B-3).
double centred_square_form_factor(double half, double height) {
    const double x = half / height;
    const double root = std::sqrt(1.0 + x * x);
    return 4.0 * (2.0 * x / root * std::atan(x / root)) / (2.0 * std::numbers::pi);
}

struct SkyRun {
    glm::vec3 albedo{0.3f, 0.5f, 0.7f};
    std::uint32_t photons = 4'000u;
    std::uint32_t trials = 300u;
};

// Total first-bounce VPL flux per channel, one RunningStats per channel over independent runs.
template <class Configure>
std::array<RunningStats, 3> first_bounce_flux(const RectangleLights& lights, const SkyFloor& floor,
                                              const SkyRun& run, Configure&& configure) {
    std::array<RunningStats, 3> stats;
    PhotonParams params = restir::default_photon_params();
    params.photon_count = run.photons;
    params.max_bounces = 1u;
    for (std::uint32_t trial = 0; trial < run.trials; ++trial) {
        params.seed = 7000u + trial;
        restir::PhotonEmitters emitters(lights, params.points_per_emitter, params.seed);
        configure(emitters);
        const glm::dvec3 sum =
            total_flux(restir::shoot_photons(emitters, floor, Lambertian{run.albedo}, params));
        for (int c = 0; c < 3; ++c)
            stats[static_cast<std::size_t>(c)].add(sum[c]);
    }
    return stats;
}

// A floor of albedo a and area A under a sky, no emitters: the first-bounce VPLs carry the flux
// the floor reflects, a A E with E the sky's irradiance: pi L for a uniform sky of radiance L,
// the texel sum `upper_irradiance` for a gradient with a sun (rotated, scaled).
TEST(SkyPhotons, FloorReflectsTheSkysIrradiance) {
    const SkyFloor floor;
    const SkyRun run;
    struct SkyCase {
        const char* name;
        std::uint32_t width, height;
        std::vector<glm::vec3> texels;
        float scale, rotation;
    };
    const std::vector<SkyCase> cases = {
        {"uniform", 8u, 4u, std::vector<glm::vec3>(32u, glm::vec3(0.5f, 1.0f, 1.5f)), 1.0f, 0.0f},
        {"sunny", 48u, 24u, sunny_sky(48u, 24u), 2.0f, 0.7f},
    };
    for (const SkyCase& c : cases) {
        const restir::EnvironmentMap sky(c.texels, c.width, c.height, c.scale, c.rotation);
        const std::array<RunningStats, 3> stats =
            first_bounce_flux(RectangleLights{}, floor, run, [&](restir::PhotonEmitters& e) {
                e.set_environment(sky, glm::vec3(0.0f), floor.radius());
                ASSERT_EQ(e.sky_probability(), 1.0f) << "no emitters: every photon from the sky";
            });
        const glm::dvec3 irradiance =
            upper_irradiance(c.texels, c.width, c.height, static_cast<double>(c.scale));
        if (std::string(c.name) == "uniform") {
            EXPECT_NEAR(irradiance.y, std::numbers::pi, 1e-9);
        }
        for (int k = 0; k < 3; ++k) {
            const double expected =
                static_cast<double>(run.albedo[k]) * floor.area() * irradiance[k];
            EXPECT_TRUE(restir::test::agrees_with(stats[static_cast<std::size_t>(k)], expected))
                << c.name << ", channel " << k;
        }
    }
}

// A sky and a small emitter above the floor's centre together: the expectation is the sum of
// the sky's share, a A pi L, and the emitter's, a Phi_e F (F the point-to-square form factor),
// whether the sky's probability follows the flux or is set by hand.
TEST(SkyPhotons, SkyAndEmitterKeepBothExpectations) {
    const SkyFloor floor;
    const SkyRun run;
    const glm::vec3 sky_radiance(0.8f, 1.0f, 1.2f);
    const restir::EnvironmentMap sky(std::vector<glm::vec3>(64u * 32u, sky_radiance), 64u, 32u);
    const RectangleLights lights{{restir::test::ceiling_light(1.0f, 0.01f, glm::vec3(3e5f))}};
    const double form_factor = centred_square_form_factor(static_cast<double>(floor.half), 1.0);
    for (const std::optional<float> probability : {std::optional<float>{}, std::optional{0.25f}}) {
        float used = 0.0f;
        const std::array<RunningStats, 3> stats =
            first_bounce_flux(lights, floor, run, [&](restir::PhotonEmitters& e) {
                e.set_environment(sky, glm::vec3(0.0f), floor.radius(), probability);
                used = e.sky_probability();
            });
        if (!probability) {
            // In proportion to flux: pi R^2 * 4 pi L (summed over channels) against Phi_e.
            const double radius = static_cast<double>(floor.radius());
            const double sky_flux =
                std::numbers::pi * radius * radius * 4.0 * std::numbers::pi *
                static_cast<double>(sky_radiance.x + sky_radiance.y + sky_radiance.z);
            const glm::vec3 phi = lights.flux();
            const double emitter_flux = static_cast<double>(phi.x + phi.y + phi.z);
            EXPECT_NEAR(static_cast<double>(used), sky_flux / (sky_flux + emitter_flux), 1e-4);
        } else {
            EXPECT_EQ(used, 0.25f);
        }
        for (int k = 0; k < 3; ++k) {
            const double a = static_cast<double>(run.albedo[k]);
            const double expected =
                a * floor.area() * std::numbers::pi * static_cast<double>(sky_radiance[k]) +
                a * static_cast<double>(lights.flux()[k]) * form_factor;
            EXPECT_TRUE(restir::test::agrees_with(stats[static_cast<std::size_t>(k)], expected))
                << "probability " << used << ", channel " << k;
        }
    }
}

// Without a sky, or with a sky of probability 0, the emitters shoot exactly the VPLs that
// shoot_photons(lights, ...) does.
TEST(SkyPhotons, NoSkyLeavesTheEmittersUnchanged) {
    const RectangleLights lights = box_light();
    PhotonParams params = restir::default_photon_params();
    params.photon_count = 5'000u;
    params.max_bounces = 3u;
    params.seed = 9u;
    const std::vector<Vpl> reference =
        restir::shoot_photons(lights, ClosedBox{}, Lambertian{}, params);
    const restir::EnvironmentMap sky(std::vector<glm::vec3>(8u, glm::vec3(1.0f)), 4u, 2u);
    restir::PhotonEmitters plain(lights, params.points_per_emitter, params.seed);
    restir::PhotonEmitters zero_sky(lights, params.points_per_emitter, params.seed);
    zero_sky.set_environment(sky, glm::vec3(0.0f), 2.0f, 0.0f);
    for (const restir::PhotonEmitters* emitters : {&plain, &zero_sky}) {
        const std::vector<Vpl> vpls =
            restir::shoot_photons(*emitters, ClosedBox{}, Lambertian{}, params);
        ASSERT_EQ(vpls.size(), reference.size());
        for (std::size_t i = 0; i < vpls.size(); ++i) {
            ASSERT_EQ(vpls[i].position, reference[i].position) << i;
            ASSERT_EQ(vpls[i].normal, reference[i].normal) << i;
            ASSERT_EQ(vpls[i].flux, reference[i].flux) << i;
        }
    }
}

TEST(SkyPhotons, BadSkySettingsThrow) {
    const restir::EnvironmentMap sky(std::vector<glm::vec3>(8u, glm::vec3(1.0f)), 4u, 2u);
    restir::PhotonEmitters emitters(box_light(), 4u, 0u);
    const glm::vec3 origin(0.0f);
    const float nan = std::nanf("");
    EXPECT_THROW(emitters.set_environment(restir::EnvironmentMap{}, origin, 1.0f),
                 std::invalid_argument);
    EXPECT_THROW(emitters.set_environment(sky, origin, 0.0f), std::invalid_argument);
    EXPECT_THROW(emitters.set_environment(sky, origin, nan), std::invalid_argument);
    EXPECT_THROW(emitters.set_environment(sky, glm::vec3(nan), 1.0f), std::invalid_argument);
    EXPECT_THROW(emitters.set_environment(sky, origin, 1.0f, 1.5f), std::invalid_argument);
    EXPECT_THROW(emitters.set_environment(sky, origin, 1.0f, -0.1f), std::invalid_argument);
    EXPECT_THROW(emitters.set_environment(sky, origin, 1.0f, nan), std::invalid_argument);
    EXPECT_FALSE(emitters.source().has_sky());
}

} // namespace
