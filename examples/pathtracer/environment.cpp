// Environment maps: checked construction from texels or a file, and the generated sun and sky.
#include "environment.hpp"

#include "image_io.hpp"
#include "scene.hpp"

#include <glm/common.hpp>
#include <glm/geometric.hpp>
#include <glm/vec2.hpp>

#include <algorithm>
#include <cmath>
#include <cstddef>
#include <numbers>
#include <stdexcept>
#include <utility>

namespace pt {
namespace {

constexpr float pi = std::numbers::pi_v<float>;

// The largest radiance (texel times scale) an environment may have.
constexpr double max_environment_radiance = 1e30;

using restir::environment_luminance;

float radians(float degrees) { return degrees * (pi / 180.0f); }

// The rotation in radians, reduced to (-360, 360) degrees first so that a large angle keeps its
// precision.
float rotation_radians(float degrees) { return radians(std::fmod(degrees, 360.0f)); }

// The sky's colours before normalisation: bluer at the zenith, whiter and brighter at the
// horizon (blended by (1 - cos theta)^3); the ground's radiance below the horizon is absolute.
constexpr glm::vec3 zenith_colour{0.22f, 0.38f, 0.85f};
constexpr glm::vec3 horizon_colour{0.95f, 0.97f, 1.0f};
constexpr glm::vec3 ground_radiance{0.45f, 0.40f, 0.33f};
constexpr glm::vec3 sun_colour{1.0f, 0.94f, 0.86f}; // normalised to unit luminance below

// The unnormalised sky radiance towards a direction with cos theta = `up` > 0.
glm::vec3 sky_gradient(float up) {
    const float t = 1.0f - up;
    return glm::mix(zenith_colour, horizon_colour, t * t * t);
}

// Integral of max(0, cos theta) over one texel of row `row` (of `height` rows, `width` texels
// each): (2 pi / width) (sin^2 theta_bottom - sin^2 theta_top) / 2 with theta clamped to the
// upper hemisphere, exact for the piecewise-constant map.
double texel_cosine_solid_angle(std::uint32_t row, std::uint32_t width, std::uint32_t height) {
    constexpr double half_pi = std::numbers::pi / 2.0;
    const double rows = static_cast<double>(height);
    const double top = std::min(std::numbers::pi * static_cast<double>(row) / rows, half_pi);
    const double bottom =
        std::min(std::numbers::pi * (static_cast<double>(row) + 1.0) / rows, half_pi);
    const double s_top = std::sin(top), s_bottom = std::sin(bottom);
    return std::numbers::pi / static_cast<double>(width) * (s_bottom * s_bottom - s_top * s_top);
}

// The direction towards the centre of texel (x, y).
glm::vec3 texel_direction(std::uint32_t x, std::uint32_t y, std::uint32_t width,
                          std::uint32_t height) {
    return restir::equirect_direction(
        {(static_cast<float>(x) + 0.5f) / static_cast<float>(width),
         (static_cast<float>(y) + 0.5f) / static_cast<float>(height)});
}

// Fills `texels` with the sky gradient scaled to `sky_irradiance` above the horizon and the
// ground below it; returns the horizontal irradiance of the map (luminance).
float fill_sky(std::vector<glm::vec3>& texels, std::uint32_t width, std::uint32_t height,
               float sky_irradiance) {
    const auto for_each_texel = [&](auto&& visit) {
        for (std::uint32_t y = 0; y < height; ++y) {
            const double cosine_solid_angle = texel_cosine_solid_angle(y, width, height);
            for (std::uint32_t x = 0; x < width; ++x)
                visit(texels[x + std::size_t{width} * y], texel_direction(x, y, width, height).y,
                      cosine_solid_angle);
        }
    };
    double gradient_irradiance = 0.0;
    for_each_texel([&](glm::vec3& texel, float up, double cosine_solid_angle) {
        texel = up > 0.0f ? sky_gradient(up) : glm::vec3(0.0f);
        gradient_irradiance +=
            cosine_solid_angle * static_cast<double>(environment_luminance(texel));
    });
    const auto normalise =
        static_cast<float>(static_cast<double>(sky_irradiance) / gradient_irradiance);
    double irradiance = 0.0;
    for_each_texel([&](glm::vec3& texel, float up, double cosine_solid_angle) {
        texel = up > 0.0f ? texel * normalise : ground_radiance;
        irradiance += cosine_solid_angle * static_cast<double>(environment_luminance(texel));
    });
    return static_cast<float>(irradiance);
}

// The texels of the sun's disc: those whose centre lies within its angular radius of
// `sun`, and always the one `sun` itself falls in.
std::vector<std::size_t> sun_texels(glm::vec3 sun, float radius, std::uint32_t width,
                                    std::uint32_t height) {
    const glm::vec2 uv = restir::equirect_uv(sun);
    const auto column = [&](float u) {
        return std::min(static_cast<std::uint32_t>(u * static_cast<float>(width)), width - 1u);
    };
    const auto row = [&](float v) {
        return std::min(static_cast<std::uint32_t>(v * static_cast<float>(height)), height - 1u);
    };
    const std::size_t centre = column(uv.x) + std::size_t{width} * row(uv.y);
    std::vector<std::size_t> texels{centre};
    // Only rows within the radius (and one texel) of the sun's row can hold the disc.
    const float margin = radius / pi + 1.0f / static_cast<float>(height);
    const std::uint32_t first = row(std::max(uv.y - margin, 0.0f));
    const std::uint32_t last = row(std::min(uv.y + margin, 1.0f));
    const float cos_radius = std::cos(radius);
    for (std::uint32_t y = first; y <= last; ++y)
        for (std::uint32_t x = 0; x < width; ++x) {
            const std::size_t i = x + std::size_t{width} * y;
            if (i != centre && glm::dot(texel_direction(x, y, width, height), sun) >= cos_radius)
                texels.push_back(i);
        }
    return texels;
}

void check_sun_sky(const SunSkyParams& p) {
    const bool ok = p.sun_elevation_degrees > 0.0f && p.sun_elevation_degrees <= 90.0f &&
                    p.sun_diameter_degrees > 0.0f && p.sun_diameter_degrees <= 10.0f &&
                    std::isfinite(p.sun_azimuth_degrees) && p.sky_irradiance > 0.0f &&
                    std::isfinite(p.sky_irradiance) && p.sun_to_sky_ratio >= 0.0f &&
                    std::isfinite(p.sun_to_sky_ratio) && p.width >= 4u && p.height >= 2u &&
                    std::uint64_t{p.width} * p.height <= (std::uint64_t{1} << 27u);
    if (!ok)
        throw SceneError("sun-sky: the sun needs an elevation in (0, 90] degrees, a diameter in "
                         "(0, 10] degrees, a finite azimuth, positive finite irradiances, and "
                         "4 x 2 to 2^27 texels");
}

} // namespace

std::shared_ptr<const Environment> make_environment(std::span<const glm::vec3> texels,
                                                    std::uint32_t width, std::uint32_t height,
                                                    const std::string& name, float scale,
                                                    float rotate_degrees) {
    auto environment = std::make_shared<Environment>();
    environment->name = name;
    try {
        environment->map =
            restir::EnvironmentMap(texels, width, height, scale, rotation_radians(rotate_degrees));
    } catch (const std::invalid_argument& e) {
        std::string why = e.what();
        if (const std::string prefix = "environment map: "; why.starts_with(prefix))
            why.erase(0, prefix.size());
        throw ImageError("environment map " + name + ": " + why);
    }
    // Paths multiply the radiance by their throughput and divide it by densities: keep it far
    // from float's limit.
    float largest = 0.0f;
    for (const glm::vec3& texel : texels)
        largest = std::max({largest, texel.x, texel.y, texel.z});
    if (!(static_cast<double>(largest) * static_cast<double>(scale) <= max_environment_radiance))
        throw ImageError("environment map " + name + ": a texel's radiance times the scale is " +
                         std::to_string(static_cast<double>(largest) * static_cast<double>(scale)) +
                         ", more than the 1e30 allowed");
    return environment;
}

std::shared_ptr<const Environment> load_environment(const std::filesystem::path& path, float scale,
                                                    float rotate_degrees) {
    const Image image = read_image(path);
    return make_environment(image.pixels, image.width, image.height, path.string(), scale,
                            rotate_degrees);
}

std::vector<glm::vec3> make_sun_sky_texels(const SunSkyParams& p, SunSkyFigures* figures) {
    check_sun_sky(p);
    std::vector<glm::vec3> texels(std::size_t{p.width} * p.height);
    const float sky = fill_sky(texels, p.width, p.height, p.sky_irradiance);
    const float elevation = radians(p.sun_elevation_degrees);
    const float azimuth = radians(p.sun_azimuth_degrees);
    const glm::vec3 sun{std::sin(azimuth) * std::cos(elevation), std::sin(elevation),
                        -std::cos(azimuth) * std::cos(elevation)};
    const std::vector<std::size_t> disc =
        sun_texels(sun, 0.5f * radians(p.sun_diameter_degrees), p.width, p.height);
    // The sun's radiance L gives the horizontal irradiance L times the texels' cosine-weighted
    // solid angles, which must be the ratio times the sky's.
    double cosine_solid_angle = 0.0;
    for (const std::size_t i : disc)
        cosine_solid_angle +=
            texel_cosine_solid_angle(static_cast<std::uint32_t>(i / p.width), p.width, p.height);
    const auto sun_luminance = static_cast<double>(p.sun_to_sky_ratio * sky) / cosine_solid_angle;
    for (const std::size_t i : disc)
        texels[i] +=
            sun_colour / environment_luminance(sun_colour) * static_cast<float>(sun_luminance);
    if (figures != nullptr)
        *figures = {sky, static_cast<float>(sun_luminance * cosine_solid_angle),
                    environment_luminance(texels[disc.front()]),
                    static_cast<std::uint32_t>(disc.size())};
    return texels;
}

std::shared_ptr<const Environment> make_sun_sky_environment(const SunSkyParams& params, float scale,
                                                            float rotate_degrees) {
    const std::vector<glm::vec3> texels = make_sun_sky_texels(params);
    return make_environment(texels, params.width, params.height, "sun-sky", scale, rotate_degrees);
}

} // namespace pt
