// The renderer's environment light: an equirectangular map of the radiance arriving from
// infinitely far away (restir::EnvironmentMap), read from an .exr or .pfm file (--env) or
// generated as a sun and a sky (the sun-sky scene).
#pragma once

#include <restir/light/environment_map.hpp>

#include <glm/vec3.hpp>

#include <cstdint>
#include <filesystem>
#include <memory>
#include <span>
#include <string>
#include <vector>

namespace pt {

/// An environment map with the name that messages and the render's summary use.
struct Environment {
    std::string name;
    restir::EnvironmentMap map;

    /// The device-callable view (radiance, pdf and sampling by direction).
    restir::EnvironmentMapView view() const { return map.view(); }
    /// The radiance arriving from `direction` (unit, towards the sky), scale applied.
    glm::vec3 radiance(glm::vec3 direction) const { return map.view().radiance(direction); }
};

/// Builds an environment from `width` x `height` texels (linear RGB radiance, row-major, row
/// 0 at +Y; the mapping of restir::equirect_uv), `scale` multiplying the radiance and
/// `rotate_degrees` turning the map about +Y. Throws ImageError with a one-line message naming
/// `name` for what restir::EnvironmentMap refuses (sizes, a NaN, infinite or negative texel, a
/// black map, a scale or rotation that is not finite) and for a texel whose radiance times
/// `scale` exceeds 1e30 (paths multiply and divide it further).
std::shared_ptr<const Environment> make_environment(std::span<const glm::vec3> texels,
                                                    std::uint32_t width, std::uint32_t height,
                                                    const std::string& name, float scale,
                                                    float rotate_degrees);

/// Reads an equirectangular environment map (.exr or .pfm, at most read_image's default
/// 8192 x 4096 pixels, refused from the header before any allocation) and builds it as
/// make_environment does. A 1 x 1 map is a constant sky. Throws ImageError.
std::shared_ptr<const Environment> load_environment(const std::filesystem::path& path, float scale,
                                                    float rotate_degrees);

/// The generated sun and sky of the sun-sky scene.
struct SunSkyParams {
    std::uint32_t width = 2048; ///< Texels around the horizon.
    std::uint32_t height = 1024;
    /// The sun's centre: its angle above the horizon (in (0, 90]), and its azimuth from -Z
    /// (the map's centre) towards +X (90 is +X).
    float sun_elevation_degrees = 35.0f;
    float sun_azimuth_degrees = -50.0f;
    float sun_diameter_degrees = 0.5f; ///< Angular diameter of the sun's disc.
    /// Irradiance of the sky alone on a horizontal plane (luminance): pi, so that a white
    /// Lambertian plane under the sky alone reflects radiance 1.
    float sky_irradiance = 3.14159265f;
    /// The sun's irradiance on a horizontal plane as a multiple of the sky's.
    float sun_to_sky_ratio = 4.0f;
};

/// The sky's irradiance on a horizontal plane and the sun's, from the map's texels (luminance,
/// scale 1): what the generated map reaches given SunSkyParams' targets.
struct SunSkyFigures {
    float sky_irradiance = 0.0f;
    float sun_irradiance = 0.0f;
    float sun_radiance = 0.0f; ///< Luminance of a sun texel (sky included).
    std::uint32_t sun_texels = 0;
};

/// The sun-sky texels: a sky gradient above the horizon (whiter and brighter towards it,
/// bluer at the zenith) normalised to `params.sky_irradiance`, a dim ground below it, and the
/// sun's disc (the texels whose centre lies inside it, at least the one the sun's centre falls
/// in) bright enough for `params.sun_to_sky_ratio`. Each texel's direction comes from
/// restir::equirect_direction, so that the map agrees with the library's mapping. `figures`
/// receives what was reached.
std::vector<glm::vec3> make_sun_sky_texels(const SunSkyParams& params,
                                           SunSkyFigures* figures = nullptr);

/// make_sun_sky_texels as an environment named "sun-sky", `scale` and `rotate_degrees` as
/// make_environment takes them. Throws SceneError for parameters out of range (an elevation
/// outside (0, 90], a sun diameter outside (0, 10] degrees, irradiances that are not
/// positive, fewer than 4 x 2 texels) and ImageError as make_environment does.
std::shared_ptr<const Environment> make_sun_sky_environment(const SunSkyParams& params,
                                                            float scale = 1.0f,
                                                            float rotate_degrees = 0.0f);

} // namespace pt
