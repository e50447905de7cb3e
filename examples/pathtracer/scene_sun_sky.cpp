// The sun-sky scene: an open courtyard under an environment light (by default the generated sun
// and sky of environment.cpp), with local lights next to it.
#include "scene.hpp"
#include "scene_quad.hpp"

#include <glm/vec3.hpp>

#include <cstdint>
#include <utility>

namespace pt {
namespace {

// Metres; the ground is the plane y = 0, the camera looks towards -Z.
constexpr float ground_half_size = 40.0f;

// An axis-aligned box from `lower` to `upper`, its faces facing outwards; a box standing on the
// ground (lower.y = 0) has no bottom face.
void add_box(Scene& scene, glm::vec3 lower, glm::vec3 upper, std::uint32_t material) {
    const glm::vec3 centre = 0.5f * (lower + upper);
    for (int axis = 0; axis < 3; ++axis)
        for (const bool upper_side : {false, true}) {
            if (axis == 1 && !upper_side && lower.y <= 0.0f)
                continue;
            const int a = (axis + 1) % 3, b = (axis + 2) % 3;
            glm::vec3 corner = lower;
            corner[axis] = upper_side ? upper[axis] : lower[axis];
            Quad quad{corner, corner, corner, corner};
            quad[1][a] = upper[a];
            quad[2][a] = upper[a];
            quad[2][b] = upper[b];
            quad[3][b] = upper[b];
            glm::vec3 face_centre = centre;
            face_centre[axis] = corner[axis];
            add_quad(scene, quad, face_centre - centre, material);
        }
}

enum SunSkyMaterial : std::uint32_t { ground, stone, brick, steel, warm_panel, cool_panel };

void add_sun_sky_materials(Scene& scene) {
    scene.materials = {
        {.name = "ground", .albedo = glm::vec3(0.5f)},
        {.name = "stone", .albedo = {0.70f, 0.66f, 0.60f}},
        {.name = "brick", .albedo = {0.60f, 0.35f, 0.25f}},
        // A polished metal (F0 the base colour, as cornell-glossy's gold block) that mirrors
        // the sky and the sun.
        {.name = "polished-steel",
         .albedo = {0.90f, 0.90f, 0.92f},
         .roughness = 0.2f,
         .metallic = 1.0f},
        {.name = "warm-panel", .albedo = glm::vec3(0.8f), .emission = {30.0f, 18.0f, 8.0f}},
        {.name = "cool-panel", .albedo = glm::vec3(0.8f), .emission = {8.0f, 16.0f, 30.0f}},
    };
}

// The ground, two blocks (one of polished steel), an arch and a low wall.
void add_sun_sky_geometry(Scene& scene) {
    const float g = ground_half_size;
    add_quad(scene, {{{-g, 0.0f, -g}, {g, 0.0f, -g}, {g, 0.0f, g}, {-g, 0.0f, g}}},
             {0.0f, 1.0f, 0.0f}, ground);
    add_box(scene, {-2.9f, 0.0f, -1.7f}, {-1.5f, 1.4f, -0.3f}, stone);
    add_box(scene, {1.1f, 0.0f, -0.3f}, {2.1f, 1.6f, 0.7f}, steel);
    // The arch: two pillars and a lintel.
    add_box(scene, {-1.4f, 0.0f, -4.75f}, {-0.9f, 3.0f, -4.25f}, stone);
    add_box(scene, {0.9f, 0.0f, -4.75f}, {1.4f, 3.0f, -4.25f}, stone);
    add_box(scene, {-1.4f, 3.0f, -4.75f}, {1.4f, 3.5f, -4.25f}, stone);
    // The low wall, in its own shadow on the side facing the camera.
    add_box(scene, {2.5f, 0.0f, -3.15f}, {7.0f, 1.8f, -2.85f}, brick);
}

// The local lights: a warm panel under the arch's lintel facing down, and a cool panel on the
// shadowed face of the wall facing the camera.
void add_sun_sky_panels(Scene& scene) {
    add_quad(
        scene,
        {{{-0.4f, 2.9f, -4.7f}, {0.4f, 2.9f, -4.7f}, {0.4f, 2.9f, -4.3f}, {-0.4f, 2.9f, -4.3f}}},
        {0.0f, -1.0f, 0.0f}, warm_panel);
    add_quad(scene,
             {{{4.0f, 0.6f, -2.8f}, {4.8f, 0.6f, -2.8f}, {4.8f, 1.2f, -2.8f}, {4.0f, 1.2f, -2.8f}}},
             {0.0f, 0.0f, 1.0f}, cool_panel);
}

} // namespace

Scene make_sun_sky_scene(std::shared_ptr<const Environment> environment) {
    Scene scene;
    scene.name = "sun-sky";
    add_sun_sky_materials(scene);
    add_sun_sky_geometry(scene);
    add_sun_sky_panels(scene);
    scene.environment = std::move(environment);
    // Eye height, looking a little down: the upper part of the image shows the sky.
    scene.camera = CameraSetup{{0.5f, 1.7f, 8.0f}, {0.5f, 1.2f, -2.0f}, {0.0f, 1.0f, 0.0f}, 50.0f};
    return scene;
}

} // namespace pt
