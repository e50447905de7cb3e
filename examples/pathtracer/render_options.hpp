// restir-render's command line: every flag, its default and its checks, parsed without
// exiting so that tests and the fuzz target can call it.
#pragma once

#include "renderer.hpp"

#include <cstdint>
#include <optional>
#include <stdexcept>
#include <string>
#include <vector>

namespace pt {

/// Everything restir-render's flags set.
struct RenderOptions {
    RenderSettings settings = default_render_settings();
    std::string scene = "cornell";
    MaterialMode materials = MaterialMode::mtl;
    std::uint32_t lights = 1000;
    std::uint64_t scene_seed = 0;
    std::string environment;         ///< --env: an equirectangular .exr or .pfm map.
    float environment_scale = 1.0f;  ///< --env-scale: multiplies the environment's radiance.
    float environment_rotate = 0.0f; ///< --env-rotate: degrees about +Y.
    std::uint64_t max_memory_mb = 0;
    std::vector<float> look_from, look_at;
    std::optional<float> fov;
    std::uint32_t frames = 16;
    std::vector<std::string> outs{"out/render.png"};
    /// Images of the last frame alone (--out-frame), written as --out's are.
    std::vector<std::string> frame_outs;
    std::optional<float> exposure;
    std::string reference;
    std::string csv;

    static RenderSettings default_render_settings() {
        RenderSettings settings;
        settings.width = 512;
        settings.height = 512;
        return settings;
    }
};

/// A command line that cannot be used; `what()` is a one-line message.
struct UsageError : std::runtime_error {
    using std::runtime_error::runtime_error;
};

/// Parses and checks restir-render's command line (argv[0] is the program). Returns nothing
/// after --help, with the help text in `help`. Throws UsageError for an unknown flag, a value
/// out of range or not finite, inconsistent flags, or a render beyond the memory limit.
std::optional<RenderOptions> parse_render_options(int argc, const char* const* argv,
                                                  std::string& help);

/// The scene that `options` name (cornell, cornell-glossy, cornell-spheres, many-lights,
/// sun-sky or an OBJ file), its materials made Lambertian with --materials diffuse, under the --env
/// map, or under the generated sun and sky for sun-sky without one (--env-scale and --env-rotate
/// apply to either). Throws SceneError, or ImageError for a map that cannot be used.
Scene load_scene(const RenderOptions& options);

} // namespace pt
