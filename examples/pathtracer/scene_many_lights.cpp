// The procedural many-lights scene: a floor under many small coloured lights.
#include "scene.hpp"
#include "scene_quad.hpp"

#include <restir/core/rng.hpp>

#include <glm/vec3.hpp>

#include <algorithm>
#include <array>
#include <cmath>
#include <cstddef>
#include <cstdint>
#include <numbers>
#include <string>
#include <utility>

namespace pt {
namespace {

float luminance(glm::vec3 rgb) { return 0.2126f * rgb.x + 0.7152f * rgb.y + 0.0722f * rgb.z; }

// The many-lights scene: a floor of [-50, 50]^2 and lights over [-40, 40]^2, 1 to 3 above it,
// in 16 colours. The lights' total luminance-weighted power does not depend on their count:
// it lights the floor to an average outgoing radiance of about 0.5.
constexpr float floor_half_size = 50.0f;
constexpr float lit_half_size = 40.0f;
constexpr float min_light_height = 1.0f;
constexpr float max_light_height = 3.0f;
constexpr std::uint32_t palette_size = 16;
constexpr float total_light_power = 15000.0f;

// The lights' colours: random colours of unit luminance times an intensity in [0.25, 1.75).
struct LightPalette {
    std::array<glm::vec3, palette_size> colours{};
    std::array<float, palette_size> intensities{};
};

LightPalette draw_palette(restir::Pcg32& rng) {
    LightPalette palette;
    for (std::uint32_t k = 0; k < palette_size; ++k) {
        glm::vec3 colour{0.2f + 0.8f * next_float(rng), 0.2f + 0.8f * next_float(rng),
                         0.2f + 0.8f * next_float(rng)};
        palette.colours[k] = colour / luminance(colour);
        palette.intensities[k] = 0.25f + 1.5f * next_float(rng);
    }
    return palette;
}

// `count` square lights facing down, each of a random palette entry (material 1 + entry), with
// sides in [max/3, max], max shrinking as the lights get denser. Returns the sum of intensity
// times area over the lights.
double add_light_quads(Scene& scene, std::uint32_t count, const LightPalette& palette,
                       restir::Pcg32& rng) {
    const float lit_area = 4.0f * lit_half_size * lit_half_size;
    const float max_side = std::min(0.3f, 0.5f * std::sqrt(lit_area / static_cast<float>(count)));
    const float min_side = max_side / 3.0f;
    double weighted_area = 0.0;
    for (std::uint32_t i = 0; i < count; ++i) {
        const float x = lit_half_size * (2.0f * next_float(rng) - 1.0f);
        const float z = lit_half_size * (2.0f * next_float(rng) - 1.0f);
        const float y = min_light_height + (max_light_height - min_light_height) * next_float(rng);
        const float side = min_side + (max_side - min_side) * next_float(rng);
        const auto entry =
            std::min(static_cast<std::uint32_t>(next_float(rng) * static_cast<float>(palette_size)),
                     palette_size - 1);
        const float h = 0.5f * side;
        add_quad(scene,
                 {{{x - h, y, z - h}, {x + h, y, z - h}, {x + h, y, z + h}, {x - h, y, z + h}}},
                 {0.0f, -1.0f, 0.0f}, 1 + entry);
        weighted_area +=
            static_cast<double>(palette.intensities[entry]) * static_cast<double>(side * side);
    }
    return weighted_area;
}

// The palette's materials "light-00" to "light-15", scaled so that the lights, whose
// intensity-weighted area is `weighted_area`, emit the total power.
void add_light_materials(Scene& scene, const LightPalette& palette, double weighted_area) {
    // A diffuse emitter of radiance L and area A emits pi * L * A.
    const auto scale = static_cast<float>(static_cast<double>(total_light_power) /
                                          (std::numbers::pi * weighted_area));
    for (std::uint32_t k = 0; k < palette_size; ++k) {
        std::string name = "light-";
        if (k < 10) {
            name += '0';
        }
        name += std::to_string(k);
        scene.materials.push_back(
            {.name = std::move(name),
             .albedo = {0.8f, 0.8f, 0.8f},
             .emission = palette.colours[k] * (palette.intensities[k] * scale)});
    }
}

} // namespace

Scene make_many_lights(std::uint32_t light_count, std::uint64_t seed) {
    constexpr std::uint32_t max_lights = 10'000'000;
    if (light_count == 0 || light_count > max_lights) {
        throw SceneError("many-lights: the light count must be between 1 and 10000000");
    }
    Scene scene;
    scene.name = "many-lights";
    scene.positions.reserve(4 * (std::size_t{light_count} + 1));
    scene.indices.reserve(6 * (std::size_t{light_count} + 1));
    scene.triangle_materials.reserve(2 * (std::size_t{light_count} + 1));
    scene.materials.reserve(palette_size + 1);
    scene.materials.push_back({.name = "floor", .albedo = {0.725f, 0.71f, 0.68f}});

    const float f = floor_half_size;
    add_quad(scene, {{{-f, 0.0f, -f}, {f, 0.0f, -f}, {f, 0.0f, f}, {-f, 0.0f, f}}},
             {0.0f, 1.0f, 0.0f}, 0);

    restir::Pcg32 rng = restir::make_pixel_rng(0u, 0u, RenderStream::scene_layout, seed);
    const LightPalette palette = draw_palette(rng);
    const double weighted_area = add_light_quads(scene, light_count, palette, rng);
    add_light_materials(scene, palette, weighted_area);

    scene.camera =
        CameraSetup{{0.0f, 120.0f, 100.0f}, {0.0f, 0.0f, 0.0f}, {0.0f, 1.0f, 0.0f}, 40.0f};
    return scene;
}

} // namespace pt
