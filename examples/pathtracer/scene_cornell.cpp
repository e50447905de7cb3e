// The built-in Cornell box (examples/common/cornell_box.hpp, shared with the CUDA benchmark) as
// the renderer's scenes: its room, its two blocks, its materials and its camera; diffuse
// ("cornell"), with a glossy floor, a metal block and a rough block ("cornell-glossy"), or lit
// by three emissive spheres instead of its ceiling light ("cornell-spheres").
#include "scene.hpp"
#include "scene_quad.hpp"

#include "../common/cornell_box.hpp"

#include <glm/vec3.hpp>

#include <array>
#include <cstdint>

namespace pt {
namespace {

glm::vec3 centroid(const Quad& quad) { return 0.25f * (quad[0] + quad[1] + quad[2] + quad[3]); }

glm::vec3 to_vec3(const float (&v)[3]) { return {v[0], v[1], v[2]}; }
Quad to_quad(const cornell::Quad& q) {
    return {to_vec3(q.corners[0]), to_vec3(q.corners[1]), to_vec3(q.corners[2]),
            to_vec3(q.corners[3])};
}

// The floor, the light, the ceiling and the walls (cornell::Box::room, in its order), each
// facing the room's interior; the light faces down. The floor takes `floor_material`; without
// `with_light` the light's quad is left out.
void add_cornell_room(Scene& scene, const cornell::Box& box, std::uint32_t floor_material,
                      bool with_light = true) {
    const glm::vec3 interior = to_vec3(box.interior);
    for (std::uint32_t i = 0; i < 6u; ++i) {
        if (i == cornell::light_quad && !with_light)
            continue;
        const Quad quad = to_quad(box.room[i]);
        const glm::vec3 towards =
            i == cornell::light_quad ? to_vec3(box.light_facing) : interior - centroid(quad);
        add_quad(scene, quad, towards, i == 0u ? floor_material : box.room_materials[i]);
    }
}

// A convex block of five faces (the floor closes it), each facing outwards.
void add_block(Scene& scene, const cornell::Block& block, std::uint32_t material) {
    std::array<Quad, 5> faces;
    for (std::size_t i = 0; i < faces.size(); ++i)
        faces[i] = to_quad(block.faces[i]);
    // The mean of all face corners lies strictly inside the convex block.
    glm::vec3 centre{0.0f};
    for (const Quad& face : faces) {
        centre += centroid(face);
    }
    centre /= static_cast<float>(faces.size());
    for (const Quad& face : faces) {
        add_quad(scene, face, centroid(face) - centre, material);
    }
}

// The box's four diffuse materials (indices cornell::Material) and its camera; no geometry.
Scene cornell_materials_and_camera(const cornell::Box& box, const char* name) {
    Scene scene;
    scene.name = name;
    for (std::uint32_t m = 0; m < cornell::material_count; ++m) {
        Material material;
        material.name = cornell::material_names[m];
        material.albedo = to_vec3(box.materials[m].albedo);
        material.emission = to_vec3(box.materials[m].emission);
        scene.materials.push_back(material);
    }
    scene.camera = CameraSetup{to_vec3(box.camera.look_from), to_vec3(box.camera.look_at),
                               to_vec3(box.camera.up), box.camera.fov_degrees};
    return scene;
}

// Appends `material` and returns its index.
std::uint32_t add_material(Scene& scene, const Material& material) {
    scene.materials.push_back(material);
    return static_cast<std::uint32_t>(scene.materials.size() - 1u);
}

} // namespace

Scene make_cornell_box() {
    constexpr cornell::Box box = cornell::box();
    Scene scene = cornell_materials_and_camera(box, "cornell");
    add_cornell_room(scene, box, cornell::white);
    add_block(scene, box.short_block, cornell::white);
    add_block(scene, box.tall_block, cornell::white);
    return scene;
}

Scene make_glossy_cornell_box() {
    constexpr cornell::Box box = cornell::box();
    Scene scene = cornell_materials_and_camera(box, "cornell-glossy");
    const glm::vec3 white = scene.materials[cornell::white].albedo;
    // F0 0.04: a dielectric of refractive index 1.5, ((n - 1) / (n + 1))^2.
    const Material floor{
        .name = "polished-floor", .albedo = white, .specular = 0.04f, .roughness = 0.12f};
    // Gold's reflectance at normal incidence, roughly (linear RGB), as the metal's base colour.
    const Material gold{.name = "brushed-gold",
                        .albedo = {1.0f, 0.78f, 0.34f},
                        .roughness = 0.25f,
                        .metallic = 1.0f};
    const Material satin{
        .name = "satin-white", .albedo = white, .specular = 0.04f, .roughness = 0.6f};
    add_cornell_room(scene, box, add_material(scene, floor));
    add_block(scene, box.short_block, add_material(scene, satin));
    add_block(scene, box.tall_block, add_material(scene, gold));
    return scene;
}

Scene make_cornell_spheres() {
    constexpr cornell::Box box = cornell::box();
    Scene scene = cornell_materials_and_camera(box, "cornell-spheres");
    add_cornell_room(scene, box, cornell::white, false);
    add_block(scene, box.short_block, cornell::white);
    add_block(scene, box.tall_block, cornell::white);
    // Their flux, pi L 4 pi r^2 summed over the channels, 1.2 to 1.8 x 10^6 each: together
    // about three times the ceiling light's (pi L A).
    struct Lamp {
        const char* name;
        glm::vec3 centre;
        float radius;
        glm::vec3 emission;
    };
    const Lamp lamps[] = {
        {"warm-sphere",
         {185.0f, 215.0f, 170.0f},
         45.0f,
         {8.0f, 5.0f, 2.0f}}, // over the short block
        {"cool-sphere",
         {420.0f, 90.0f, 140.0f},
         35.0f,
         {3.0f, 7.0f, 16.0f}}, // before the tall block
        {"white-sphere", {278.0f, 440.0f, 280.0f}, 60.0f, {4.5f, 4.2f, 3.6f}}}; // under the ceiling
    for (const Lamp& lamp : lamps) {
        const std::uint32_t material = add_material(
            scene, {.name = lamp.name, .albedo = glm::vec3(0.5f), .emission = lamp.emission});
        scene.shapes.add(Sphere{lamp.centre, lamp.radius, material});
    }
    return scene;
}

} // namespace pt
