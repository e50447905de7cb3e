// The environment light: a chi-square of its directions against its pdf over sub-cells of the
// texels (a gradient with a sun, non-square and rotated maps, a 1x1 map), the pdf's and the
// radiance's integrals over the sphere by quadrature, sample against pdf and radiance / pdf per
// texel, the equirectangular mapping and the rotation, black texels, invalid input, and a white
// furnace and a sky's irradiance estimated within 4 standard errors.
#include <restir/core/rng.hpp>
#include <restir/light/environment_map.hpp>

#include "support/chi2.hpp"

#include <gtest/gtest.h>

#include <glm/geometric.hpp>

#include <algorithm>
#include <array>
#include <cmath>
#include <cstdint>
#include <functional>
#include <limits>
#include <map>
#include <numbers>
#include <stdexcept>
#include <string>
#include <vector>

namespace {

constexpr double kPi = std::numbers::pi;

double luminance(glm::vec3 c) {
    return 0.2126 * static_cast<double>(c.x) + 0.7152 * static_cast<double>(c.y) +
           0.0722 * static_cast<double>(c.z);
}

/// A sky: a gradient from a bright zenith to a dim nadir with a colour change along u, a small
/// bright "sun" of three texels, and, when asked, black texels: a block and the bottom row.
std::vector<glm::vec3> gradient_sun_map(std::uint32_t width, std::uint32_t height,
                                        bool with_black = false) {
    std::vector<glm::vec3> texels(std::size_t{width} * height);
    const std::uint32_t sun_x = width * 3u / 10u, sun_y = height / 4u;
    for (std::uint32_t y = 0; y < height; ++y) {
        for (std::uint32_t x = 0; x < width; ++x) {
            const float u = (static_cast<float>(x) + 0.5f) / static_cast<float>(width);
            const float v = (static_cast<float>(y) + 0.5f) / static_cast<float>(height);
            glm::vec3 c(0.2f + 0.8f * (1.0f - v), 0.3f + 0.5f * u, 0.1f + 0.6f * (1.0f - v));
            if (y == sun_y && x + 1u >= sun_x && x <= sun_x + 1u)
                c += glm::vec3(250.0f, 220.0f, 180.0f);
            texels[std::size_t{y} * width + x] = c;
        }
    }
    if (with_black && height >= 4u) {
        for (std::uint32_t x = 0; x < width; ++x)
            texels[std::size_t{height - 1u} * width + x] = glm::vec3(0.0f);
        for (std::uint32_t y = height / 2u; y < height / 2u + 2u; ++y)
            for (std::uint32_t x = width / 2u; x < std::min(width, width / 2u + 3u); ++x)
                texels[std::size_t{y} * width + x] = glm::vec3(0.0f);
    }
    return texels;
}

/// The map's direction d seen at world R d, R the rotation by `angle` about +Y, in double.
glm::dvec3 rotate_y(glm::dvec3 d, double angle) {
    const double c = std::cos(angle), s = std::sin(angle);
    return {c * d.x + s * d.z, d.y, -s * d.x + c * d.z};
}

/// Where a map-frame direction falls, computed here in double from the documented mapping.
struct Location {
    std::uint32_t x = 0, y = 0;   // texel
    double along_phi = 0.0;       // position inside the texel in [0, 1) along phi
    double along_cos = 0.0;       // and along cos theta (0 at the texel's top)
    double border_distance = 0.0; // radians to the nearest texel border
    double sin_theta = 0.0;
};

Location locate(glm::dvec3 d, std::uint32_t width, std::uint32_t height) {
    d = glm::normalize(d);
    double u = 0.5 + std::atan2(d.x, -d.z) / (2.0 * kPi);
    u = u >= 1.0 ? u - 1.0 : u;
    const double theta = std::acos(std::clamp(d.y, -1.0, 1.0));
    const double fx = u * width, fy = theta / kPi * height;
    Location at;
    at.x = std::min(static_cast<std::uint32_t>(fx), width - 1u);
    at.y = std::min(static_cast<std::uint32_t>(fy), height - 1u);
    const double cos_top = std::cos(kPi * at.y / height);
    const double cos_bottom = std::cos(kPi * (at.y + 1.0) / height);
    at.along_phi = std::clamp(fx - at.x, 0.0, 1.0);
    at.along_cos = std::clamp((cos_top - d.y) / (cos_top - cos_bottom), 0.0, 1.0);
    at.sin_theta = std::sin(theta);
    // A border in phi is a meridian, one in theta a parallel; a 1x1 map has neither inside.
    const double phi_gap = std::min(fx - at.x, at.x + 1.0 - fx) * 2.0 * kPi / width;
    const double theta_gap = std::min(fy - at.y, at.y + 1.0 - fy) * kPi / height;
    at.border_distance =
        std::min(width > 1u ? phi_gap * at.sin_theta : 10.0, height > 1u ? theta_gap : 10.0);
    return at;
}

/// Near enough to a texel border that float rounding of a direction may cross it: a few float
/// ulps of an angle, and of phi where sin theta is small (near the poles).
bool near_border(const Location& at) { return at.border_distance < 1e-5; }

double texel_solid_angle(std::uint32_t y, std::uint32_t width, std::uint32_t height) {
    return 2.0 * kPi / width * (std::cos(kPi * y / height) - std::cos(kPi * (y + 1.0) / height));
}

/// The density per steradian in each texel that the sampling rule prescribes: luminance over
/// the integral of luminance over the sphere.
std::vector<double> texel_density(const std::vector<glm::vec3>& texels, std::uint32_t width,
                                  std::uint32_t height) {
    double integral = 0.0;
    for (std::uint32_t y = 0; y < height; ++y)
        for (std::uint32_t x = 0; x < width; ++x)
            integral +=
                luminance(texels[std::size_t{y} * width + x]) * texel_solid_angle(y, width, height);
    std::vector<double> density(texels.size());
    for (std::size_t i = 0; i < texels.size(); ++i)
        density[i] = luminance(texels[i]) / integral;
    return density;
}

glm::dvec3 to_double(glm::vec3 v) { return glm::dvec3(v); }

struct MapCase {
    const char* name;
    std::uint32_t width, height;
    float scale, rotation;
    std::uint32_t subdivisions; // chi-square cells per texel side
};

const std::array<MapCase, 3> map_cases = {{
    {"64x32", 64u, 32u, 1.0f, 0.0f, 2u},
    {"37x19 rotated", 37u, 19u, 2.5f, 1.1f, 2u},
    {"1x1", 1u, 1u, 0.5f, -2.5f, 8u},
}};

restir::EnvironmentMap make_map(const MapCase& c, const std::vector<glm::vec3>& texels) {
    return restir::EnvironmentMap(texels, c.width, c.height, c.scale, c.rotation);
}

TEST(EnvironmentMap, DirectionsFollowThePdf) {
    constexpr int count = 1000000;
    const double alpha = restir::test::sidak_significance(0.01, map_cases.size());
    for (const MapCase& c : map_cases) {
        const std::vector<glm::vec3> texels = gradient_sun_map(c.width, c.height, true);
        const restir::EnvironmentMap map = make_map(c, texels);
        const restir::EnvironmentMapView view = map.view();
        const std::vector<double> density = texel_density(texels, c.width, c.height);
        const std::uint32_t s = c.subdivisions;
        // Cells: s x s per texel, equal in phi and in cos theta, so equal in solid angle.
        std::vector<double> expected_pmf(texels.size() * s * s);
        for (std::uint32_t y = 0; y < c.height; ++y)
            for (std::uint32_t x = 0; x < c.width; ++x)
                for (std::uint32_t k = 0; k < s * s; ++k)
                    expected_pmf[(std::size_t{y} * c.width + x) * s * s + k] =
                        density[std::size_t{y} * c.width + x] *
                        texel_solid_angle(y, c.width, c.height) / (s * s);
        std::vector<double> observed(expected_pmf.size(), 0.0);
        restir::Pcg32 rng = restir::make_pixel_rng(11u, 0u, 1u);
        int strays = 0;
        for (int k = 0; k < count; ++k) {
            const float u0 = restir::next_float(rng);
            const float u1 = restir::next_float(rng);
            const restir::EnvironmentSample sample = view.sample({u0, u1});
            const Location at =
                locate(rotate_y(to_double(sample.direction), -static_cast<double>(c.rotation)),
                       c.width, c.height);
            const std::size_t texel = std::size_t{at.y} * c.width + at.x;
            // A direction rounded across the border into a black texel: counted, not binned.
            if (density[texel] == 0.0) {
                EXPECT_TRUE(near_border(at)) << c.name << ": texel " << at.x << ", " << at.y;
                ++strays;
                continue;
            }
            const auto i = std::min(static_cast<std::uint32_t>(at.along_phi * s), s - 1u);
            const auto j = std::min(static_cast<std::uint32_t>(at.along_cos * s), s - 1u);
            observed[texel * s * s + j * s + i] += 1.0;
        }
        EXPECT_LT(strays, count / 100000) << c.name;
        EXPECT_TRUE(restir::test::fits_distribution(observed, expected_pmf, alpha)) << c.name;
    }
}

// Midpoint quadrature over cells that subdivide the texels (3 x 3 in phi and theta, each
// weighted by its exact solid angle): the pdf integrates to 1, and the radiance to
// radiance_integral(), itself the sum of L * solid angle * scale.
TEST(EnvironmentMap, PdfIntegratesToOneAndRadianceToItsIntegral) {
    for (const MapCase& c : map_cases) {
        const std::vector<glm::vec3> texels = gradient_sun_map(c.width, c.height, true);
        const restir::EnvironmentMap map = make_map(c, texels);
        const restir::EnvironmentMapView view = map.view();
        constexpr int n = 3;
        const std::uint32_t columns = c.width * n, rows = c.height * n;
        double pdf_integral = 0.0;
        glm::dvec3 radiance_quadrature(0.0), radiance_sum(0.0);
        for (std::uint32_t row = 0; row < rows; ++row) {
            const double top = kPi * row / rows, bottom = kPi * (row + 1.0) / rows;
            const double solid_angle = 2.0 * kPi / columns * (std::cos(top) - std::cos(bottom));
            for (std::uint32_t column = 0; column < columns; ++column) {
                const double theta = 0.5 * (top + bottom);
                const double phi = 2.0 * kPi * ((column + 0.5) / columns - 0.5);
                const glm::dvec3 d(std::sin(theta) * std::sin(phi), std::cos(theta),
                                   -std::sin(theta) * std::cos(phi));
                const glm::vec3 world(rotate_y(d, static_cast<double>(c.rotation)));
                pdf_integral += static_cast<double>(view.pdf(world)) * solid_angle;
                radiance_quadrature += to_double(view.radiance(world)) * solid_angle;
            }
        }
        for (std::uint32_t y = 0; y < c.height; ++y)
            for (std::uint32_t x = 0; x < c.width; ++x)
                radiance_sum += to_double(texels[std::size_t{y} * c.width + x]) *
                                texel_solid_angle(y, c.width, c.height) *
                                static_cast<double>(c.scale);
        EXPECT_NEAR(pdf_integral, 1.0, 1e-5) << c.name;
        const glm::dvec3 reported = to_double(map.radiance_integral());
        for (int k = 0; k < 3; ++k) {
            EXPECT_NEAR(radiance_quadrature[k] / radiance_sum[k], 1.0, 1e-5) << c.name;
            EXPECT_NEAR(reported[k] / radiance_sum[k], 1.0, 1e-6) << c.name;
        }
    }
}

// The sample's pdf is pdf(direction) and L / pdf is one value per texel, L * scale over the
// prescribed density; a sample's radiance is radiance(direction). Away from texel borders these
// hold bit for bit; across a border rounding may pick the neighbour.
TEST(EnvironmentMap, SampleAgreesWithPdfAndRadianceOfItsDirection) {
    constexpr int count = 200000;
    for (const MapCase& c : map_cases) {
        const std::vector<glm::vec3> texels = gradient_sun_map(c.width, c.height, true);
        const restir::EnvironmentMap map = make_map(c, texels);
        const restir::EnvironmentMapView view = map.view();
        const std::vector<double> density = texel_density(texels, c.width, c.height);
        std::map<std::size_t, glm::vec3> ratio_of_texel;
        restir::Pcg32 rng = restir::make_pixel_rng(12u, 0u, 1u);
        int mismatches = 0, ratio_changes = 0, wrong_ratio = 0, not_unit = 0;
        for (int k = 0; k < count; ++k) {
            const float u0 = restir::next_float(rng);
            const float u1 = restir::next_float(rng);
            const restir::EnvironmentSample sample = view.sample({u0, u1});
            not_unit += std::abs(glm::length(sample.direction) - 1.0f) > 1e-6f;
            const Location at =
                locate(rotate_y(to_double(sample.direction), -static_cast<double>(c.rotation)),
                       c.width, c.height);
            if (near_border(at))
                continue;
            mismatches += sample.pdf != view.pdf(sample.direction) ||
                          sample.radiance != view.radiance(sample.direction);
            const std::size_t texel = std::size_t{at.y} * c.width + at.x;
            const glm::vec3 ratio = sample.radiance / sample.pdf;
            const auto [it, inserted] = ratio_of_texel.emplace(texel, ratio);
            ratio_changes += !inserted && it->second != ratio;
            const glm::dvec3 expected =
                to_double(texels[texel]) * static_cast<double>(c.scale) / density[texel];
            for (int i = 0; i < 3; ++i)
                wrong_ratio +=
                    std::abs(static_cast<double>(ratio[i]) - expected[i]) > 1e-5 * expected[i];
        }
        EXPECT_EQ(mismatches, 0) << c.name;
        EXPECT_EQ(ratio_changes, 0) << c.name;
        EXPECT_EQ(wrong_ratio, 0) << c.name;
        EXPECT_EQ(not_unit, 0) << c.name;
    }
}

TEST(EnvironmentMap, EquirectMappingAndItsInverse) {
    const auto expect_uv = [](glm::vec3 d, float u, float v) {
        const glm::vec2 uv = restir::equirect_uv(d);
        EXPECT_NEAR(uv.x, u, 1e-6f) << d.x << " " << d.y << " " << d.z;
        EXPECT_NEAR(uv.y, v, 1e-6f) << d.x << " " << d.y << " " << d.z;
    };
    expect_uv({0.0f, 0.0f, -1.0f}, 0.5f, 0.5f);
    expect_uv({1.0f, 0.0f, 0.0f}, 0.75f, 0.5f);
    expect_uv({-1.0f, 0.0f, 0.0f}, 0.25f, 0.5f);
    EXPECT_NEAR(restir::equirect_uv({0.0f, 1.0f, 0.0f}).y, 0.0f, 1e-7f);
    EXPECT_NEAR(restir::equirect_uv({0.0f, -1.0f, 0.0f}).y, 1.0f, 1e-7f);
    const float behind = restir::equirect_uv({0.0f, 0.0f, 1.0f}).x;
    EXPECT_TRUE(behind < 1e-6f || behind > 1.0f - 1e-6f) << behind;
    // uv -> direction -> uv over the interior (phi is undefined at the poles).
    int worst_uv = 0;
    for (int i = 1; i < 200; ++i) {
        for (int j = 1; j < 100; ++j) {
            const glm::vec2 uv(static_cast<float>(i) / 200.0f, static_cast<float>(j) / 100.0f);
            const glm::vec3 d = restir::equirect_direction(uv);
            EXPECT_NEAR(glm::length(d), 1.0f, 1e-6f);
            const glm::vec2 back = restir::equirect_uv(d);
            worst_uv += std::abs(back.x - uv.x) > 2e-6f || std::abs(back.y - uv.y) > 2e-6f;
        }
    }
    EXPECT_EQ(worst_uv, 0);
    // direction -> uv -> direction for random unit directions.
    restir::Pcg32 rng = restir::make_pixel_rng(13u, 0u, 1u);
    int worst_direction = 0;
    for (int k = 0; k < 100000; ++k) {
        const float z = 1.0f - 2.0f * restir::next_float(rng);
        const float phi = 2.0f * restir::pi * restir::next_float(rng);
        const float r = std::sqrt(std::max(0.0f, 1.0f - z * z));
        const glm::vec3 d(r * std::cos(phi), z, r * std::sin(phi));
        const glm::vec3 back = restir::equirect_direction(restir::equirect_uv(d));
        worst_direction += glm::length(back - d) > 2e-6f;
    }
    EXPECT_EQ(worst_direction, 0);
}

// The inline sin and cos that place a direction inside its texel: within 1.5e-7 (2 ulps at 1)
// of the double-precision values over [-pi, pi], the range sample() gives them.
TEST(EnvironmentMap, InlineSinCosIsAccurateOverAHalfTurn) {
    double worst = 0.0;
    for (int i = -2000000; i <= 2000000; ++i) {
        const float x = static_cast<float>(i) * (restir::pi / 2000000.0f);
        const restir::detail::SinCos sc = restir::detail::sin_cos_half_turn(x);
        worst = std::max(
            {worst, std::abs(static_cast<double>(sc.sin) - std::sin(static_cast<double>(x))),
             std::abs(static_cast<double>(sc.cos) - std::cos(static_cast<double>(x)))});
    }
    EXPECT_LT(worst, 1.5e-7);
}

// A dim map with a sun at the map's +X (u = 0.75, v = 0.5): rotated by +pi/2 about +Y it shines
// from world -Z, by -pi/2 from +Z, and its samples gather there.
TEST(EnvironmentMap, RotationMovesTheSun) {
    constexpr std::uint32_t width = 18u, height = 9u;
    std::vector<glm::vec3> texels(width * height, glm::vec3(0.01f));
    const glm::vec3 sun(500.0f, 400.0f, 300.0f);
    texels[4u * width + 13u] = sun; // centred on u = 13.5 / 18 = 0.75, v = 0.5
    struct Turn {
        float angle;
        glm::vec3 where;
    };
    for (const Turn turn : {Turn{0.0f, {1.0f, 0.0f, 0.0f}}, Turn{0.5f * restir::pi, {0, 0, -1}},
                            Turn{-0.5f * restir::pi, {0, 0, 1}}, Turn{restir::pi, {-1, 0, 0}}}) {
        const restir::EnvironmentMap map(texels, width, height, 1.0f, turn.angle);
        const restir::EnvironmentMapView view = map.view();
        EXPECT_EQ(view.radiance(turn.where), sun) << turn.angle;
        EXPECT_EQ(view.radiance(-turn.where), glm::vec3(0.01f)) << turn.angle;
        EXPECT_GT(view.pdf(turn.where), 1000.0f * view.pdf(-turn.where)) << turn.angle;
        restir::Pcg32 rng = restir::make_pixel_rng(14u, 0u, 1u);
        int near_sun = 0;
        constexpr int count = 10000;
        for (int k = 0; k < count; ++k) {
            const float u0 = restir::next_float(rng);
            const float u1 = restir::next_float(rng);
            // The sun texel spans 2 pi / 18 in phi and pi / 9 in theta: within 0.3 rad.
            near_sun += glm::dot(view.sample({u0, u1}).direction, turn.where) > std::cos(0.3f);
        }
        EXPECT_GT(near_sun, count * 95 / 100) << turn.angle;
    }
}

TEST(EnvironmentMap, BlackTexelsAreNeverDrawn) {
    for (const MapCase& c : map_cases) {
        std::vector<glm::vec3> texels = gradient_sun_map(c.width, c.height, true);
        // Every other texel black as well (the 1x1 map keeps its single texel).
        for (std::size_t i = 1; i < texels.size(); i += 2)
            texels[i] = glm::vec3(0.0f);
        const restir::EnvironmentMap map = make_map(c, texels);
        const restir::EnvironmentMapView view = map.view();
        restir::Pcg32 rng = restir::make_pixel_rng(15u, 0u, 1u);
        int black = 0, black_away_from_border = 0;
        for (int k = 0; k < 500000; ++k) {
            const float u0 = restir::next_float(rng);
            const float u1 = restir::next_float(rng);
            const restir::EnvironmentSample sample = view.sample({u0, u1});
            black += !(sample.pdf > 0.0f) || !(luminance(sample.radiance) > 0.0);
            const Location at =
                locate(rotate_y(to_double(sample.direction), -static_cast<double>(c.rotation)),
                       c.width, c.height);
            black_away_from_border +=
                luminance(texels[std::size_t{at.y} * c.width + at.x]) == 0.0 && !near_border(at);
        }
        EXPECT_EQ(black, 0) << c.name;
        EXPECT_EQ(black_away_from_border, 0) << c.name;
    }
}

// Each rejected input throws std::invalid_argument with a one-line message naming the problem.
TEST(EnvironmentMap, InvalidInputThrowsWithAMessage) {
    const std::vector<glm::vec3> good = gradient_sun_map(8u, 4u);
    const auto expect_rejected = [](const std::function<void()>& build, const std::string& reason) {
        try {
            build();
            ADD_FAILURE() << "accepted, expected: " << reason;
        } catch (const std::invalid_argument& error) {
            const std::string message = error.what();
            EXPECT_NE(message.find(reason), std::string::npos) << message;
            EXPECT_EQ(message.find('\n'), std::string::npos) << message;
        }
    };
    const auto with_texel = [&](std::size_t index, glm::vec3 value) {
        std::vector<glm::vec3> texels = good;
        texels[index] = value;
        return texels;
    };
    const float nan = std::numeric_limits<float>::quiet_NaN();
    const float inf = std::numeric_limits<float>::infinity();
    const auto build = [](std::vector<glm::vec3> texels, std::uint32_t w, std::uint32_t h,
                          float scale = 1.0f, float rotation = 0.0f) {
        return [=] { restir::EnvironmentMap map(texels, w, h, scale, rotation); };
    };
    expect_rejected(build(with_texel(13u, {nan, 1.0f, 1.0f}), 8u, 4u), "texel (5, 1)");
    expect_rejected(build(with_texel(13u, {1.0f, inf, 1.0f}), 8u, 4u), "texel (5, 1)");
    expect_rejected(build(with_texel(31u, {1.0f, 1.0f, -inf}), 8u, 4u), "texel (7, 3)");
    expect_rejected(build(with_texel(0u, {1.0f, -0.5f, 1.0f}), 8u, 4u), "texel (0, 0)");
    expect_rejected(build(with_texel(8u, {-1e-30f, 1.0f, 1.0f}), 8u, 4u), "texel (0, 1)");
    expect_rejected(build(std::vector<glm::vec3>(32u, glm::vec3(0.0f)), 8u, 4u), "zero everywhere");
    expect_rejected(build({}, 0u, 4u), "width and height");
    expect_rejected(build({}, 8u, 0u), "width and height");
    expect_rejected(build(good, 8u, 5u), "32 texels given for 8 x 5");
    expect_rejected(build(good, 4u, 4u), "32 texels given for 4 x 4");
    expect_rejected(build(good, 65536u, 4096u), "more than 2^27");
    expect_rejected(build(good, 8u, 4u, 0.0f), "scale");
    expect_rejected(build(good, 8u, 4u, -1.0f), "scale");
    expect_rejected(build(good, 8u, 4u, nan), "scale");
    expect_rejected(build(good, 8u, 4u, inf), "scale");
    expect_rejected(build(good, 8u, 4u, 1.0f, nan), "rotation");
    expect_rejected(build(good, 8u, 4u, 1.0f, -inf), "rotation");
    // Valid extremes: the largest finite channel, and the tiniest positive one.
    EXPECT_NO_THROW(build(with_texel(3u, glm::vec3(std::numeric_limits<float>::max())), 8u, 4u)());
    EXPECT_NO_THROW(build(with_texel(3u, glm::vec3(1e-30f)), 8u, 4u)());
}

TEST(EnvironmentMap, EmptyViewIsBlack) {
    const restir::EnvironmentMapView view = restir::EnvironmentMap().view();
    EXPECT_TRUE(view.empty());
    EXPECT_EQ(view.pdf({0.0f, 1.0f, 0.0f}), 0.0f);
    EXPECT_EQ(view.radiance({0.0f, 1.0f, 0.0f}), glm::vec3(0.0f));
    EXPECT_EQ(view.sample({0.5f, 0.5f}).pdf, 0.0f);
    EXPECT_EQ(restir::EnvironmentMap().table_bytes(), 0u);
}

struct MeanAndError {
    double mean, standard_error;
};

/// Mean and standard error of the estimator L f cos / pdf of the light that a +Y plane receives
/// (Lambertian, albedo `albedo`, f = albedo / pi), with `count` samples of the map.
MeanAndError reflected_radiance(const restir::EnvironmentMapView& view, double albedo, int count,
                                std::uint32_t seed) {
    restir::Pcg32 rng = restir::make_pixel_rng(seed, 0u, 1u);
    double sum = 0.0, sum_squares = 0.0;
    for (int k = 0; k < count; ++k) {
        const float u0 = restir::next_float(rng);
        const float u1 = restir::next_float(rng);
        const restir::EnvironmentSample sample = view.sample({u0, u1});
        const double cos_theta = std::max(0.0, static_cast<double>(sample.direction.y));
        const double value = sample.pdf > 0.0f ? luminance(sample.radiance) * albedo / kPi *
                                                     cos_theta / static_cast<double>(sample.pdf)
                                               : 0.0;
        sum += value;
        sum_squares += value * value;
    }
    const double mean = sum / count;
    const double variance = (sum_squares / count - mean * mean) * count / (count - 1.0);
    return {mean, std::sqrt(variance / count)};
}

// A uniform white sky (radiance 1) over an unoccluded Lambertian plane of albedo a reflects
// exactly a, for any map size and rotation.
TEST(EnvironmentMap, WhiteFurnaceReflectsTheAlbedo) {
    constexpr double albedo = 0.6;
    for (const MapCase& c : map_cases) {
        const std::vector<glm::vec3> white(std::size_t{c.width} * c.height, glm::vec3(1.0f));
        const restir::EnvironmentMap map(white, c.width, c.height, 1.0f, c.rotation);
        const MeanAndError estimate = reflected_radiance(map.view(), albedo, 200000, 16u);
        EXPECT_LT(std::abs(estimate.mean - albedo), 4.0 * estimate.standard_error)
            << c.name << ": " << estimate.mean << " +- " << estimate.standard_error;
        EXPECT_GT(estimate.standard_error, 0.0) << c.name;
    }
}

// The same estimator under the gradient-and-sun sky against the exact answer, the sum over
// texels of luminance * scale * (a / pi) * integral of cos+ over the texel (rotation about +Y
// does not change it; with an even height the horizon is a row border).
TEST(EnvironmentMap, SkyIrradianceIsUnbiased) {
    constexpr double albedo = 0.6;
    const MapCase c{"64x32", 64u, 32u, 1.5f, 0.4f, 2u};
    const std::vector<glm::vec3> texels = gradient_sun_map(c.width, c.height, true);
    const restir::EnvironmentMap map = make_map(c, texels);
    double exact = 0.0;
    for (std::uint32_t y = 0; y < c.height / 2u; ++y) {
        const double cos_top = std::cos(kPi * y / c.height);
        const double cos_bottom = std::cos(kPi * (y + 1.0) / c.height);
        // Integral of cos theta d omega over a texel: (2 pi / w) (cos^2 top - cos^2 bottom) / 2.
        const double cosine_integral =
            kPi / c.width * (cos_top * cos_top - cos_bottom * cos_bottom);
        for (std::uint32_t x = 0; x < c.width; ++x)
            exact += luminance(texels[std::size_t{y} * c.width + x]) * cosine_integral;
    }
    exact *= static_cast<double>(c.scale) * albedo / kPi;
    const MeanAndError estimate = reflected_radiance(map.view(), albedo, 400000, 17u);
    EXPECT_LT(std::abs(estimate.mean - exact), 4.0 * estimate.standard_error)
        << estimate.mean << " +- " << estimate.standard_error << " against " << exact;
}

} // namespace
