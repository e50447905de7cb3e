// The built-in Cornell box: its room, its two white blocks, its materials and its camera.
#include "scene.hpp"
#include "scene_quad.hpp"

#include <glm/vec3.hpp>

#include <array>
#include <cstdint>

namespace pt {
namespace {

glm::vec3 centroid(const Quad& quad) { return 0.25f * (quad[0] + quad[1] + quad[2] + quad[3]); }

// The Cornell box's materials, by the index that add_quad takes.
enum CornellMaterial : std::uint32_t { white, red, green, light };

// The floor, the light, the ceiling and the walls, each facing the room's interior (the light
// faces down).
void add_cornell_room(Scene& scene) {
    const glm::vec3 interior{278.0f, 274.0f, 280.0f};
    const auto add_room_quad = [&](const Quad& quad, std::uint32_t material) {
        add_quad(scene, quad, interior - centroid(quad), material);
    };
    add_room_quad(
        {{{552.8f, 0.0f, 0.0f}, {0.0f, 0.0f, 0.0f}, {0.0f, 0.0f, 559.2f}, {549.6f, 0.0f, 559.2f}}},
        white);

    // Lowered by 0.5 mm so that it is not coplanar with the ceiling.
    constexpr float light_y = 548.8f - 0.5f;
    add_quad(scene,
             {{{343.0f, light_y, 227.0f},
               {343.0f, light_y, 332.0f},
               {213.0f, light_y, 332.0f},
               {213.0f, light_y, 227.0f}}},
             {0.0f, -1.0f, 0.0f}, light);

    add_room_quad({{{556.0f, 548.8f, 0.0f},
                    {556.0f, 548.8f, 559.2f},
                    {0.0f, 548.8f, 559.2f},
                    {0.0f, 548.8f, 0.0f}}},
                  white);
    add_room_quad({{{549.6f, 0.0f, 559.2f},
                    {0.0f, 0.0f, 559.2f},
                    {0.0f, 548.8f, 559.2f},
                    {556.0f, 548.8f, 559.2f}}},
                  white);
    add_room_quad(
        {{{0.0f, 0.0f, 559.2f}, {0.0f, 0.0f, 0.0f}, {0.0f, 548.8f, 0.0f}, {0.0f, 548.8f, 559.2f}}},
        green);
    add_room_quad({{{552.8f, 0.0f, 0.0f},
                    {549.6f, 0.0f, 559.2f},
                    {556.0f, 548.8f, 559.2f},
                    {556.0f, 548.8f, 0.0f}}},
                  red);
}

// A white convex block of five faces (the floor closes it), each facing outwards.
void add_block(Scene& scene, const std::array<Quad, 5>& faces) {
    // The mean of all face corners lies strictly inside the convex block.
    glm::vec3 centre{0.0f};
    for (const Quad& face : faces) {
        centre += centroid(face);
    }
    centre /= static_cast<float>(faces.size());
    for (const Quad& face : faces) {
        add_quad(scene, face, centroid(face) - centre, white);
    }
}

void add_cornell_short_block(Scene& scene) {
    add_block(scene, {{
                         {{{130.0f, 165.0f, 65.0f},
                           {82.0f, 165.0f, 225.0f},
                           {240.0f, 165.0f, 272.0f},
                           {290.0f, 165.0f, 114.0f}}},
                         {{{290.0f, 0.0f, 114.0f},
                           {290.0f, 165.0f, 114.0f},
                           {240.0f, 165.0f, 272.0f},
                           {240.0f, 0.0f, 272.0f}}},
                         {{{130.0f, 0.0f, 65.0f},
                           {130.0f, 165.0f, 65.0f},
                           {290.0f, 165.0f, 114.0f},
                           {290.0f, 0.0f, 114.0f}}},
                         {{{82.0f, 0.0f, 225.0f},
                           {82.0f, 165.0f, 225.0f},
                           {130.0f, 165.0f, 65.0f},
                           {130.0f, 0.0f, 65.0f}}},
                         {{{240.0f, 0.0f, 272.0f},
                           {240.0f, 165.0f, 272.0f},
                           {82.0f, 165.0f, 225.0f},
                           {82.0f, 0.0f, 225.0f}}},
                     }});
}

void add_cornell_tall_block(Scene& scene) {
    add_block(scene, {{
                         {{{423.0f, 330.0f, 247.0f},
                           {265.0f, 330.0f, 296.0f},
                           {314.0f, 330.0f, 456.0f},
                           {472.0f, 330.0f, 406.0f}}},
                         {{{423.0f, 0.0f, 247.0f},
                           {423.0f, 330.0f, 247.0f},
                           {472.0f, 330.0f, 406.0f},
                           {472.0f, 0.0f, 406.0f}}},
                         {{{472.0f, 0.0f, 406.0f},
                           {472.0f, 330.0f, 406.0f},
                           {314.0f, 330.0f, 456.0f},
                           {314.0f, 0.0f, 456.0f}}},
                         {{{314.0f, 0.0f, 456.0f},
                           {314.0f, 330.0f, 456.0f},
                           {265.0f, 330.0f, 296.0f},
                           {265.0f, 0.0f, 296.0f}}},
                         {{{265.0f, 0.0f, 296.0f},
                           {265.0f, 330.0f, 296.0f},
                           {423.0f, 330.0f, 247.0f},
                           {423.0f, 0.0f, 247.0f}}},
                     }});
}

} // namespace

Scene make_cornell_box() {
    Scene scene;
    scene.name = "cornell";
    scene.materials = {
        {"white", {0.725f, 0.71f, 0.68f}, {0.0f, 0.0f, 0.0f}},
        {"red", {0.63f, 0.065f, 0.05f}, {0.0f, 0.0f, 0.0f}},
        {"green", {0.14f, 0.45f, 0.091f}, {0.0f, 0.0f, 0.0f}},
        {"light", {0.78f, 0.78f, 0.78f}, {17.0f, 12.0f, 4.0f}},
    };
    add_cornell_room(scene);
    add_cornell_short_block(scene);
    add_cornell_tall_block(scene);
    scene.camera = CameraSetup{
        {278.0f, 273.0f, -800.0f}, {278.0f, 273.0f, 0.0f}, {0.0f, 1.0f, 0.0f}, 39.3077f};
    return scene;
}

} // namespace pt
