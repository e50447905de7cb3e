// The built-in Cornell box (examples/common/cornell_box.hpp, shared with the CUDA benchmark) as
// the renderer's scene: its room, its two white blocks, its materials and its camera.
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
// facing the room's interior; the light faces down.
void add_cornell_room(Scene& scene, const cornell::Box& box) {
    const glm::vec3 interior = to_vec3(box.interior);
    for (std::uint32_t i = 0; i < 6u; ++i) {
        const Quad quad = to_quad(box.room[i]);
        const glm::vec3 towards =
            i == cornell::light_quad ? to_vec3(box.light_facing) : interior - centroid(quad);
        add_quad(scene, quad, towards, box.room_materials[i]);
    }
}

// A white convex block of five faces (the floor closes it), each facing outwards.
void add_block(Scene& scene, const cornell::Block& block) {
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
        add_quad(scene, face, centroid(face) - centre, cornell::white);
    }
}

} // namespace

Scene make_cornell_box() {
    constexpr cornell::Box box = cornell::box();
    Scene scene;
    scene.name = "cornell";
    for (std::uint32_t m = 0; m < cornell::material_count; ++m)
        scene.materials.push_back({cornell::material_names[m], to_vec3(box.materials[m].albedo),
                                   to_vec3(box.materials[m].emission)});
    add_cornell_room(scene, box);
    add_block(scene, box.short_block);
    add_block(scene, box.tall_block);
    scene.camera = CameraSetup{to_vec3(box.camera.look_from), to_vec3(box.camera.look_at),
                               to_vec3(box.camera.up), box.camera.fov_degrees};
    return scene;
}

} // namespace pt
