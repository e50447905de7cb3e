// The Cornell box as plain data, shared by restir-render (examples/pathtracer/scene_cornell.cpp)
// and the CUDA benchmark (benchmarks/cuda/analytic_scene.hpp): the published vertex coordinates of
// the room, the light and the two blocks (millimetres, y up), the four materials' albedo and
// emission, and the camera. Arrays of floats only (no GLM, Embree or TBB); `box()` is
// constexpr and callable from device code, so a kernel can read a value at compile time
// (`constexpr cornell::Box b = cornell::box();`) or by material (`cornell::material(m)`).
#pragma once

#include <restir/config.hpp>

#include <cstdint>

namespace cornell {

/// The materials, by the index that every triangle of the box carries.
enum Material : std::uint32_t { white, red, green, light };
inline constexpr std::uint32_t material_count = 4u;
/// Their names, by `Material`.
inline constexpr const char* material_names[material_count] = {"white", "red", "green", "light"};

/// A diffuse material: its RGB albedo and emitted radiance.
struct MaterialData {
    float albedo[3];
    float emission[3];
};

/// A planar quad: four corners in order around it, x, y, z each. Its winding is not its
/// facing: each consumer turns it to face the side `Box` names for it.
struct Quad {
    float corners[4][3];
};

/// A pinhole camera: where it looks from and at, its up vector, its vertical field of view.
struct Camera {
    float look_from[3];
    float look_at[3];
    float up[3];
    float fov_degrees;
};

/// The height of the ceiling; the light hangs 0.5 mm below it, so that it is not coplanar.
inline constexpr float ceiling_height = 548.8f;
inline constexpr float light_height = ceiling_height - 0.5f;

/// A white block: its five faces (the floor closes it), each to face outwards (away from the
/// mean of its face centroids).
struct Block {
    Quad faces[5];
};

/// The short block's faces (as published).
RESTIR_HOST_DEVICE constexpr Block short_block() noexcept {
    return {{{{{130.0f, 165.0f, 65.0f},
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
               {82.0f, 0.0f, 225.0f}}}}};
}

/// The tall block's faces (as published).
RESTIR_HOST_DEVICE constexpr Block tall_block() noexcept {
    return {{{{{423.0f, 330.0f, 247.0f},
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
               {423.0f, 0.0f, 247.0f}}}}};
}

/// The whole box.
struct Box {
    MaterialData materials[material_count]; ///< By `Material`.
    /// The room's six quads in the order both consumers add them (their triangles' order):
    /// floor, light, ceiling, back wall, left wall, right wall; the materials by quad.
    Quad room[6];
    Material room_materials[6];
    /// A point inside the room: each room quad faces it, except the light.
    float interior[3];
    /// The direction the light faces (down).
    float light_facing[3];
    /// The two white blocks.
    Block short_block;
    Block tall_block;
    /// The far corner of the room's bounding box (the near one is the origin).
    float extent[3];
    Camera camera;
};

/// The index of the light in `Box::room`.
inline constexpr std::uint32_t light_quad = 1u;

/// The box's data (as published, with the light lowered by 0.5 mm).
RESTIR_HOST_DEVICE constexpr Box box() noexcept {
    return {
        .materials = {{{0.725f, 0.71f, 0.68f}, {0.0f, 0.0f, 0.0f}},
                      {{0.63f, 0.065f, 0.05f}, {0.0f, 0.0f, 0.0f}},
                      {{0.14f, 0.45f, 0.091f}, {0.0f, 0.0f, 0.0f}},
                      {{0.78f, 0.78f, 0.78f}, {17.0f, 12.0f, 4.0f}}},
        .room = {{{{552.8f, 0.0f, 0.0f},
                   {0.0f, 0.0f, 0.0f},
                   {0.0f, 0.0f, 559.2f},
                   {549.6f, 0.0f, 559.2f}}},
                 {{{343.0f, light_height, 227.0f},
                   {343.0f, light_height, 332.0f},
                   {213.0f, light_height, 332.0f},
                   {213.0f, light_height, 227.0f}}},
                 {{{556.0f, ceiling_height, 0.0f},
                   {556.0f, ceiling_height, 559.2f},
                   {0.0f, ceiling_height, 559.2f},
                   {0.0f, ceiling_height, 0.0f}}},
                 {{{549.6f, 0.0f, 559.2f},
                   {0.0f, 0.0f, 559.2f},
                   {0.0f, ceiling_height, 559.2f},
                   {556.0f, ceiling_height, 559.2f}}},
                 {{{0.0f, 0.0f, 559.2f},
                   {0.0f, 0.0f, 0.0f},
                   {0.0f, ceiling_height, 0.0f},
                   {0.0f, ceiling_height, 559.2f}}},
                 {{{552.8f, 0.0f, 0.0f},
                   {549.6f, 0.0f, 559.2f},
                   {556.0f, ceiling_height, 559.2f},
                   {556.0f, ceiling_height, 0.0f}}}},
        .room_materials = {white, light, white, white, green, red},
        .interior = {278.0f, 274.0f, 280.0f},
        .light_facing = {0.0f, -1.0f, 0.0f},
        .short_block = short_block(),
        .tall_block = tall_block(),
        .extent = {556.0f, ceiling_height, 559.2f},
        .camera = {.look_from = {278.0f, 273.0f, -800.0f},
                   .look_at = {278.0f, 273.0f, 0.0f},
                   .up = {0.0f, 1.0f, 0.0f},
                   .fov_degrees = 39.3077f},
    };
}

/// Material `m` (white for an unknown index), in host or device code: each case a
/// compile-time constant, so a kernel reads no table.
RESTIR_HOST_DEVICE constexpr MaterialData material(std::uint32_t m) noexcept {
    switch (m) {
    case red: {
        constexpr MaterialData data = box().materials[red];
        return data;
    }
    case green: {
        constexpr MaterialData data = box().materials[green];
        return data;
    }
    case light: {
        constexpr MaterialData data = box().materials[light];
        return data;
    }
    default: {
        constexpr MaterialData data = box().materials[white];
        return data;
    }
    }
}

} // namespace cornell
