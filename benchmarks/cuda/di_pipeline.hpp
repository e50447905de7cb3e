// The example renderer's ReSTIR DI frame written as per-pixel functions that run unchanged in a
// CUDA kernel and in a CPU loop (benchmarks/cuda/di_pipeline.cu), and its two scenes as
// analytic geometry: the Cornell box (restir-render's geometry, materials and camera) and the
// many-lights scene (its floor, camera and rules for the lights). The light tiles, target
// function and recipe settings are restir-render's.
#pragma once

#include <restir/restir.hpp>

#include <glm/geometric.hpp>
#include <glm/vec2.hpp>
#include <glm/vec3.hpp>

#include <array>
#include <cmath>
#include <cstdint>
#include <utility>
#include <vector>

namespace box {

// --- Scene ----------------------------------------------------------------------------------

enum Material : std::uint32_t { white, red, green, light };

RESTIR_HOST_DEVICE inline glm::vec3 albedo_of(std::uint32_t m) {
    switch (m) {
    case red:
        return {0.63f, 0.065f, 0.05f};
    case green:
        return {0.14f, 0.45f, 0.091f};
    case light:
        return {0.78f, 0.78f, 0.78f};
    default:
        return {0.725f, 0.71f, 0.68f};
    }
}
RESTIR_HOST_DEVICE inline glm::vec3 emission_of(std::uint32_t m) {
    return m == light ? glm::vec3(17.0f, 12.0f, 4.0f) : glm::vec3(0.0f);
}

/// A triangle a + s ab + t ac with its unit normal (the side it faces) and material.
struct Triangle {
    glm::vec3 a, ab, ac, normal;
    std::uint32_t material;
};

/// A G-buffer texel and a ray hit: the surface point, its normal (facing the ray's origin),
/// the distance along the ray (0: no surface) and the material.
struct Texel {
    glm::vec3 position{0.0f};
    glm::vec3 normal{0.0f, 1.0f, 0.0f};
    float depth = 0.0f;
    std::uint32_t material = white;
};
static_assert(sizeof(Texel) == 32u);
RESTIR_HOST_DEVICE inline glm::vec3 surface_position(const Texel& t) { return t.position; }
RESTIR_HOST_DEVICE inline glm::vec3 surface_normal(const Texel& t) { return t.normal; }
RESTIR_HOST_DEVICE inline float surface_depth(const Texel& t) { return t.depth; }
RESTIR_HOST_DEVICE inline bool is_valid_surface(const Texel& t) { return t.depth > 0.0f; }

inline constexpr std::uint32_t max_triangles = 32u;

/// The box's 32 triangles, intersected one by one (Moeller-Trumbore): the ray query of the
/// G-buffer, the photons and the shadow rays.
struct Scene {
    Triangle triangles[max_triangles];
    std::uint32_t count = 0u;

    // Distance along `direction` (not unit for shadow segments) to triangle i, or 0.
    RESTIR_HOST_DEVICE float hit_distance(std::uint32_t i, glm::vec3 origin,
                                          glm::vec3 direction) const {
        const Triangle& t = triangles[i];
        const glm::vec3 p = glm::cross(direction, t.ac);
        const float det = glm::dot(t.ab, p);
        if (det == 0.0f)
            return 0.0f;
        const float inv = 1.0f / det;
        const glm::vec3 s = origin - t.a;
        const float u = glm::dot(s, p) * inv;
        if (!(u >= 0.0f && u <= 1.0f))
            return 0.0f;
        const glm::vec3 q = glm::cross(s, t.ab);
        const float v = glm::dot(direction, q) * inv;
        if (!(v >= 0.0f && u + v <= 1.0f))
            return 0.0f;
        const float distance = glm::dot(t.ac, q) * inv;
        return distance > 0.0f ? distance : 0.0f;
    }

    /// restir::ClosestHitQuery: the nearest surface along the unit `direction`.
    RESTIR_HOST_DEVICE Texel closest_hit(glm::vec3 origin, glm::vec3 direction) const {
        Texel hit;
        std::uint32_t nearest = count;
        float best = 3.0e38f;
        for (std::uint32_t i = 0; i < count; ++i) {
            const float d = hit_distance(i, origin, direction);
            if (d > 0.0f && d < best) {
                best = d;
                nearest = i;
            }
        }
        if (nearest == count)
            return hit;
        const Triangle& t = triangles[nearest];
        hit.position = origin + best * direction;
        hit.normal = glm::dot(t.normal, direction) < 0.0f ? t.normal : -t.normal;
        hit.depth = best;
        hit.material = t.material;
        return hit;
    }

    /// restir::RayQuery: whether a surface lies between `from` and `to`.
    RESTIR_HOST_DEVICE bool occluded(glm::vec3 from, glm::vec3 to) const {
        const glm::vec3 d = to - from;
        for (std::uint32_t i = 0; i < count; ++i) {
            const float t = hit_distance(i, from, d);
            if (t > 0.0f && t < 1.0f)
                return true;
        }
        return false;
    }
};

/// The light's triangles as a restir::LightSet (uniform points by area; one light each).
struct Emitter {
    glm::vec3 a, ab, ac, normal, radiance;
    float area;
};
struct Emitters {
    const Emitter* emitters = nullptr;
    std::uint32_t count = 0u;
    RESTIR_HOST_DEVICE std::uint32_t light_count() const { return count; }
    RESTIR_HOST_DEVICE restir::LightSample sample_point(std::uint32_t id, glm::vec2 uv) const {
        const Emitter& e = emitters[id];
        const float su = sqrtf(uv.x);
        restir::LightSample s;
        s.position = e.a + e.ab * (su * (1.0f - uv.y)) + e.ac * (su * uv.y);
        s.normal = e.normal;
        s.radiance = e.radiance;
        s.area_pdf = 1.0f / e.area;
        s.is_delta = false;
        return s;
    }
};
using Lights = restir::UnifiedLightSet<Emitters>;

/// The photon shooter's scatter hook: Lambertian by cosine; the light reflects but holds no VPL.
struct Lambertian {
    template <class Rng>
    RESTIR_HOST_DEVICE restir::Scattering operator()(const Texel& hit, glm::vec3, Rng& rng) const {
        const float u0 = next_float(rng);
        const float u1 = next_float(rng);
        const glm::vec3 albedo = albedo_of(hit.material);
        return {restir::sample_diffuse_direction(hit.normal, u0, u1), albedo, albedo, true,
                hit.material == light};
    }
};

/// The Cornell box of restir-render (examples/pathtracer/scene.cpp): room, light, two blocks.
inline Scene make_cornell_box() {
    Scene scene;
    using Quad = glm::vec3[4];
    const auto add = [&](const Quad& q, glm::vec3 towards, std::uint32_t material) {
        glm::vec3 c[4] = {q[0], q[1], q[2], q[3]};
        if (glm::dot(glm::cross(c[2] - c[0], c[3] - c[1]), towards) < 0.0f)
            std::swap(c[1], c[3]);
        for (const auto [i, j, k] : {std::array{0, 1, 2}, std::array{0, 2, 3}}) {
            Triangle t{c[i], c[j] - c[i], c[k] - c[i], glm::vec3(0.0f), material};
            t.normal = glm::normalize(glm::cross(t.ab, t.ac));
            scene.triangles[scene.count++] = t;
        }
    };
    const auto centroid = [](const Quad& q) { return 0.25f * (q[0] + q[1] + q[2] + q[3]); };
    const glm::vec3 interior{278.0f, 274.0f, 280.0f};
    const auto room = [&](const Quad& q, std::uint32_t m) { add(q, interior - centroid(q), m); };
    room({{552.8f, 0.0f, 0.0f}, {0.0f, 0.0f, 0.0f}, {0.0f, 0.0f, 559.2f}, {549.6f, 0.0f, 559.2f}},
         white);
    constexpr float ly = 548.8f - 0.5f;
    add({{343.0f, ly, 227.0f}, {343.0f, ly, 332.0f}, {213.0f, ly, 332.0f}, {213.0f, ly, 227.0f}},
        {0.0f, -1.0f, 0.0f}, light);
    room({{556.0f, 548.8f, 0.0f},
          {556.0f, 548.8f, 559.2f},
          {0.0f, 548.8f, 559.2f},
          {0.0f, 548.8f, 0.0f}},
         white);
    room({{549.6f, 0.0f, 559.2f},
          {0.0f, 0.0f, 559.2f},
          {0.0f, 548.8f, 559.2f},
          {556.0f, 548.8f, 559.2f}},
         white);
    room({{0.0f, 0.0f, 559.2f}, {0.0f, 0.0f, 0.0f}, {0.0f, 548.8f, 0.0f}, {0.0f, 548.8f, 559.2f}},
         green);
    room({{552.8f, 0.0f, 0.0f},
          {549.6f, 0.0f, 559.2f},
          {556.0f, 548.8f, 559.2f},
          {556.0f, 548.8f, 0.0f}},
         red);
    const auto block = [&](const Quad(&faces)[5]) {
        glm::vec3 centre(0.0f);
        for (const Quad& f : faces)
            centre += centroid(f) / 5.0f;
        for (const Quad& f : faces)
            add(f, centroid(f) - centre, white);
    };
    block({{{130.0f, 165.0f, 65.0f},
            {82.0f, 165.0f, 225.0f},
            {240.0f, 165.0f, 272.0f},
            {290.0f, 165.0f, 114.0f}},
           {{290.0f, 0.0f, 114.0f},
            {290.0f, 165.0f, 114.0f},
            {240.0f, 165.0f, 272.0f},
            {240.0f, 0.0f, 272.0f}},
           {{130.0f, 0.0f, 65.0f},
            {130.0f, 165.0f, 65.0f},
            {290.0f, 165.0f, 114.0f},
            {290.0f, 0.0f, 114.0f}},
           {{82.0f, 0.0f, 225.0f},
            {82.0f, 165.0f, 225.0f},
            {130.0f, 165.0f, 65.0f},
            {130.0f, 0.0f, 65.0f}},
           {{240.0f, 0.0f, 272.0f},
            {240.0f, 165.0f, 272.0f},
            {82.0f, 165.0f, 225.0f},
            {82.0f, 0.0f, 225.0f}}});
    block({{{423.0f, 330.0f, 247.0f},
            {265.0f, 330.0f, 296.0f},
            {314.0f, 330.0f, 456.0f},
            {472.0f, 330.0f, 406.0f}},
           {{423.0f, 0.0f, 247.0f},
            {423.0f, 330.0f, 247.0f},
            {472.0f, 330.0f, 406.0f},
            {472.0f, 0.0f, 406.0f}},
           {{472.0f, 0.0f, 406.0f},
            {472.0f, 330.0f, 406.0f},
            {314.0f, 330.0f, 456.0f},
            {314.0f, 0.0f, 456.0f}},
           {{314.0f, 0.0f, 456.0f},
            {314.0f, 330.0f, 456.0f},
            {265.0f, 330.0f, 296.0f},
            {265.0f, 0.0f, 296.0f}},
           {{265.0f, 0.0f, 296.0f},
            {265.0f, 330.0f, 296.0f},
            {423.0f, 330.0f, 247.0f},
            {423.0f, 0.0f, 247.0f}}});
    return scene;
}

/// The light's triangles of `scene` as emitters.
inline std::vector<Emitter> make_emitters(const Scene& scene) {
    std::vector<Emitter> out;
    for (std::uint32_t i = 0; i < scene.count; ++i) {
        const Triangle& t = scene.triangles[i];
        if (t.material == light)
            out.push_back({t.a, t.ab, t.ac, t.normal, emission_of(light),
                           0.5f * glm::length(glm::cross(t.ab, t.ac))});
    }
    return out;
}

/// The many-lights scene's floor ([-50, 50]^2) and `count` square lights facing down over
/// [-40, 40]^2, 1 to 3 above it, as restir-render's generator makes them (sides in [max/3, max],
/// 16 colours of unit luminance times 0.25 to 1.75, 15000 W in all), in a layout of their own.
/// The lights are emitters only: unlike restir-render's, they are not in the G-buffer and cast no
/// shadows (only the floor is geometry).
inline Scene make_many_lights(std::uint32_t count, std::uint64_t seed,
                              std::vector<Emitter>& emitters) {
    Scene scene;
    const glm::vec3 corner(-50.0f, 0.0f, -50.0f);
    // Normal up: (b - a) x (c - a) with a = corner, b = +z, c = +x.
    const glm::vec3 along_x(100.0f, 0.0f, 0.0f), along_z(0.0f, 0.0f, 100.0f);
    scene.triangles[scene.count++] = {corner, along_z, along_x, {0.0f, 1.0f, 0.0f}, white};
    scene.triangles[scene.count++] = {
        corner + along_x + along_z, -along_z, -along_x, {0.0f, 1.0f, 0.0f}, white};
    restir::Pcg32 rng = restir::make_pixel_rng(0u, 0u, restir::RngStream::application, seed);
    glm::vec3 colours[16];
    float intensities[16];
    for (std::uint32_t k = 0; k < 16u; ++k) {
        const glm::vec3 c(0.2f + 0.8f * next_float(rng), 0.2f + 0.8f * next_float(rng),
                          0.2f + 0.8f * next_float(rng));
        colours[k] = c / (0.2126f * c.x + 0.7152f * c.y + 0.0722f * c.z);
        intensities[k] = 0.25f + 1.5f * next_float(rng);
    }
    const float max_side = std::min(0.3f, 0.5f * std::sqrt(6400.0f / static_cast<float>(count)));
    emitters.clear();
    std::vector<std::uint32_t> entry_of(count);
    double weighted_area = 0.0;
    for (std::uint32_t i = 0; i < count; ++i) {
        const float x = 40.0f * (2.0f * next_float(rng) - 1.0f);
        const float z = 40.0f * (2.0f * next_float(rng) - 1.0f);
        const float y = 1.0f + 2.0f * next_float(rng);
        const float side = max_side / 3.0f + (max_side - max_side / 3.0f) * next_float(rng);
        const std::uint32_t entry =
            std::min(15u, static_cast<std::uint32_t>(next_float(rng) * 16.0f));
        const float h = 0.5f * side;
        // Facing down: (b - a) x (c - a) with b along +x, c along +z.
        const glm::vec3 a(x - h, y, z - h), dx(side, 0.0f, 0.0f), dz(0.0f, 0.0f, side);
        const glm::vec3 down(0.0f, -1.0f, 0.0f);
        emitters.push_back(
            {a, dx, dz, down, glm::vec3(static_cast<float>(entry)), 0.5f * side * side});
        emitters.push_back({a + dx + dz, -dx, -dz, down, glm::vec3(static_cast<float>(entry)),
                            0.5f * side * side});
        entry_of[i] = entry;
        weighted_area += static_cast<double>(intensities[entry]) * side * side;
    }
    // A diffuse emitter of radiance L and area A emits pi L A.
    const auto scale = static_cast<float>(15000.0 / (3.14159265358979 * weighted_area));
    for (std::uint32_t i = 0; i < count; ++i) {
        const glm::vec3 radiance = colours[entry_of[i]] * (intensities[entry_of[i]] * scale);
        emitters[2 * i].radiance = emitters[2 * i + 1].radiance = radiance;
    }
    return scene;
}

// --- Camera ---------------------------------------------------------------------------------

/// A pinhole camera (restir-render's): rays through pixels, and the pixel a point projects to.
struct Camera {
    glm::vec3 position{0.0f}, forward{0.0f}, right{0.0f}, up{0.0f};
    float tan_half = 1.0f, aspect = 1.0f, width = 1.0f, height = 1.0f;

    static Camera look_at(glm::vec3 from, glm::vec3 at, float fov_degrees, std::uint32_t w,
                          std::uint32_t h) {
        Camera c;
        c.position = from;
        c.forward = glm::normalize(at - from);
        c.right = glm::normalize(glm::cross(c.forward, glm::vec3(0.0f, 1.0f, 0.0f)));
        c.up = glm::cross(c.right, c.forward);
        c.tan_half = std::tan(0.5f * fov_degrees * 0.017453292519943295f);
        c.width = static_cast<float>(w);
        c.height = static_cast<float>(h);
        c.aspect = c.width / c.height;
        return c;
    }
    RESTIR_HOST_DEVICE glm::vec3 direction(glm::vec2 pixel) const {
        const float sx = (2.0f * pixel.x / width - 1.0f) * tan_half * aspect;
        const float sy = (1.0f - 2.0f * pixel.y / height) * tan_half;
        return glm::normalize(forward + sx * right + sy * up);
    }
    RESTIR_HOST_DEVICE bool project(glm::vec3 point, glm::vec2& pixel) const {
        const glm::vec3 d = point - position;
        const float z = glm::dot(d, forward);
        if (!(z > 0.0f))
            return false;
        const float sx = glm::dot(d, right) / (z * tan_half * aspect);
        const float sy = glm::dot(d, up) / (z * tan_half);
        pixel = {0.5f * (sx + 1.0f) * width, 0.5f * (1.0f - sy) * height};
        return true;
    }
};

/// A scene's camera: restir-render's position, target and vertical field of view.
struct View {
    glm::vec3 from{0.0f}, at{0.0f, 0.0f, 1.0f};
    float fov_degrees = 40.0f;
};
inline constexpr View cornell_view{{278.0f, 273.0f, -800.0f}, {278.0f, 273.0f, 0.0f}, 39.3077f};
inline constexpr View many_lights_view{{0.0f, 120.0f, 100.0f}, {0.0f, 0.0f, 0.0f}, 40.0f};

/// The camera of frame `frame`: `view` swaying sideways along x (by up to 7.5 % of its distance
/// to the target, a period of about 125 frames), so that temporal reuse reprojects every frame.
inline Camera camera_of_frame(const View& view, std::uint32_t frame, std::uint32_t w,
                              std::uint32_t h) {
    const float sway =
        0.075f * glm::length(view.at - view.from) * std::sin(0.05f * static_cast<float>(frame));
    return Camera::look_at(view.from + glm::vec3(sway, 0.0f, 0.0f), view.at, view.fov_degrees, w,
                           h);
}

// --- The frame ------------------------------------------------------------------------------

using Reservoir = restir::Reservoir<restir::LightPointSample>;
using Packed = restir::PackedPointReservoir;

/// Reprojection through last frame's camera (restir::Reprojection).
struct CameraReprojection {
    Camera previous;
    const Texel* surfaces = nullptr;
    std::uint32_t width = 0u;
    RESTIR_HOST_DEVICE restir::PixelCoord operator()(restir::PixelCoord p) const {
        const Texel& s =
            surfaces[static_cast<std::uint32_t>(p.x) + static_cast<std::uint32_t>(p.y) * width];
        glm::vec2 q;
        if (!previous.project(s.position, q))
            return {-1, -1};
        return {static_cast<std::int32_t>(floorf(q.x)), static_cast<std::int32_t>(floorf(q.y))};
    }
};

/// A stored light point back as its sample (exact here: flat emitters of one radiance, VPLs).
struct LightPointDecoder {
    Lights lights;
    restir::Falloff falloff;
    RESTIR_HOST_DEVICE restir::LightPointSample operator()(std::uint32_t id,
                                                           glm::vec3 position) const {
        if (id >= lights.light_count())
            return {.light_id = restir::removed_light};
        restir::LightPointSample s =
            restir::make_light_point_sample(id, lights.sample_point(id, glm::vec2(0.0f)), falloff);
        s.position = position;
        return s;
    }
};

using PlainFrame = restir::DiFrame<restir::LightPointSample, Texel, CameraReprojection>;
using PackedFrame = restir::DiFrame<restir::LightPointSample, Texel, CameraReprojection,
                                    restir::PackedPointHistory<LightPointDecoder>>;

/// p-hat: the Euclidean norm of the unshadowed reflected radiance's channels (restir-render's).
inline constexpr restir::ChannelNorm target_norm = restir::ChannelNorm::euclidean;
struct Target {
    RESTIR_HOST_DEVICE float operator()(const restir::LightPointSample& x, const Texel& s) const {
        return restir::fold_channels<target_norm>(
            albedo_of(s.material) * restir::inv_pi *
            restir::unshadowed_irradiance(x, s.position, s.normal));
    }
};

inline constexpr std::uint32_t tile_count = 128u; // restir-render's light tiles
inline constexpr std::uint32_t tile_size = 2048u; // a power of two
inline constexpr std::uint32_t block_size = 8u;   // candidates per batch-RIS block
inline constexpr std::uint32_t pixel_block = 8u;  // pixels of a tile's block, per side
inline constexpr std::uint32_t tile_stream = restir::RngStream::application;

/// Everything a pass reads and writes, as pointers (device pointers for a kernel, host
/// pointers for the CPU); passed by value.
struct Context {
    std::uint32_t width = 0u, height = 0u;
    std::uint32_t frame = 0u;
    bool has_history = false; // whether last frame's reservoirs apply
    bool packed = false;      // history as `Packed` (28 B) instead of `Reservoir` (64 B)
    std::uint32_t candidates = 32u;
    std::uint64_t seed = 1u;
    restir::DiFrameParams params{};
    restir::NeighbourOffsets offsets{};
    View view{};
    Camera camera, previous_camera;
    const Scene* scene = nullptr;
    Lights lights{};
    restir::AliasTableView power{};
    restir::Falloff falloff{};
    float ray_offset = 0.1f;
    restir::LightTileArrays tiles{};
    bool bvh_source = false;    // candidates drawn per pixel from the light BVH, not the tiles
    restir::LightBvhView bvh{}; // over `lights`
    Texel* surfaces = nullptr;  // this frame's G-buffer
    Texel* previous_surfaces = nullptr; // last frame's
    Reservoir* current = nullptr;       // candidates, visibility, spatial, final visibility
    Reservoir* scratch = nullptr;       // temporal
    Reservoir* history = nullptr;       // last frame's final reservoirs (plain layout)
    Packed* packed_history = nullptr;   // the same, packed (written by shading)
    glm::vec3* image = nullptr;
    // This frame's recipe in both layouts, built once per frame (`build_recipes`) and read
    // where the context lives: in a kernel's parameters. (A recipe built inside the kernel
    // copied its 512-byte offset table to every thread's local memory: 728 bytes of stack,
    // and the spatial pass wrote 590 bytes a pixel to DRAM.)
    PlainFrame plain_recipe{};
    PackedFrame packed_recipe{};

    RESTIR_HOST_DEVICE restir::PixelCoord pixel(std::uint32_t x, std::uint32_t y) const {
        return {static_cast<std::int32_t>(x), static_cast<std::int32_t>(y)};
    }
    RESTIR_HOST_DEVICE restir::LightPointVisibility<Scene> visibility() const {
        return {scene, ray_offset};
    }
    RESTIR_HOST_DEVICE restir::ReuseBridge<Target, restir::LightPointVisibility<Scene>>
    bridge() const {
        return {Target{}, visibility()};
    }
    template <class Frame>
    RESTIR_HOST_DEVICE const Frame& recipe() const {
        if constexpr (Frame::loads_history)
            return packed_recipe;
        else
            return plain_recipe;
    }
    void build_recipes() {
        plain_recipe = frame_recipe<PlainFrame>();
        packed_recipe = frame_recipe<PackedFrame>();
    }
    template <class Frame>
    Frame frame_recipe() const {
        Frame f{.params = params,
                .frame_index = frame,
                .surfaces = {surfaces, width, height},
                .reproject = {previous_camera, surfaces, width},
                .offsets = offsets};
        if (has_history) {
            f.previous_surfaces = {previous_surfaces, width, height};
            if constexpr (Frame::loads_history)
                f.history = {{packed_history, width, height}, {lights, falloff}};
            else
                f.history = {history, width, height};
        }
        return f;
    }
};

/// The recipe's settings for this benchmark: restir-render's (pairwise MIS, visibility reuse,
/// one spatial pass in 30 px per 1080 rows), with 5 neighbours; `mis_rays` false makes the
/// reuse passes ray-free (RTXDI's default), so that every ray is traced in a pass of its own.
inline restir::DiFrameParams recipe_params(std::uint32_t height, bool mis_rays) {
    restir::DiFrameParams p = restir::default_di_frame_params();
    p.spatial.neighbour_count = 5u;
    p.spatial.radius = 30.0f * static_cast<float>(height) / 1080.0f;
    p.reuse.trace_mis_visibility = mis_rays;
    p.deferred_visibility = !mis_rays;
    return p;
}

// Each pass's work at one item (a pixel (x, y); for the tiles, entry x of row 0).

RESTIR_HOST_DEVICE inline void gbuffer_pixel(const Context& c, std::uint32_t x, std::uint32_t y) {
    const glm::vec3 d =
        c.camera.direction({static_cast<float>(x) + 0.5f, static_cast<float>(y) + 0.5f});
    c.surfaces[x + y * c.width] = c.scene->closest_hit(c.camera.position, d);
}

RESTIR_HOST_DEVICE inline void tile_entry(const Context& c, std::uint32_t i, std::uint32_t) {
    restir::Pcg32 rng = restir::make_pixel_rng(i, c.frame, tile_stream, c.seed);
    const restir::PowerLightSampler power{c.power};
    c.tiles.store(i / c.tiles.tile_size, i % c.tiles.tile_size,
                  restir::presample_light(power, c.lights, rng), c.falloff);
}

// Streaming RIS over candidates drawn from the light BVH for the surface (restir-render's
// bvh_reservoir; the source pdf is the light's pmf there).
RESTIR_HOST_DEVICE inline Reservoir bvh_candidates(const Context& c, const Texel& s,
                                                   restir::Pcg32& rng) {
    const restir::ShadingPoint at{s.position, s.normal};
    return restir::resample_ris(
        rng, c.candidates,
        [&](restir::Pcg32& g) {
            const restir::SourceSample<restir::LightSampleRef> x =
                restir::draw_light_candidate(c.bvh, at, g);
            restir::SourceSample<restir::LightPointSample> candidate{{}, x.pdf};
            if (x.pdf > 0.0f)
                candidate.sample = restir::make_light_point_sample(
                    x.sample.light_id, c.lights.sample_point(x.sample.light_id, x.sample.uv),
                    c.falloff);
            return candidate;
        },
        [&](const restir::LightPointSample& x) { return Target{}(x, s); });
}

// Stage 1 (restir-render's tile_reservoir): batch RIS over the pixel block's tile; tested for
// visibility here only when the recipe traces its rays itself.
template <class Frame>
RESTIR_HOST_DEVICE void candidates_pixel(const Context& c, std::uint32_t x, std::uint32_t y) {
    const std::uint32_t i = x + y * c.width;
    const Texel& s = c.surfaces[i];
    Reservoir r{};
    if (is_valid_surface(s) && c.bvh_source) {
        restir::Pcg32 rng = restir::make_pixel_rng(i, c.frame, restir::RngStream::initial, c.seed);
        r = c.recipe<Frame>().initial(c.pixel(x, y), bvh_candidates(c, s, rng), c.visibility());
    } else if (is_valid_surface(s)) {
        restir::Pcg32 rng = restir::make_pixel_rng(i, c.frame, restir::RngStream::initial, c.seed);
        const std::uint32_t columns = (c.width + pixel_block - 1u) / pixel_block;
        const std::uint32_t tile =
            c.tiles.tile_for(x / pixel_block + y / pixel_block * columns, c.frame);
        const std::uint32_t block_mask = c.tiles.tile_size / block_size - 1u;
        const std::uint32_t start = rng.next_uint();
        const std::uint32_t stride = rng.next_uint() | 1u;
        const glm::vec3 channel_weights = albedo_of(s.material) * restir::inv_pi;
        const auto picked = restir::resample_ris_batch<block_size>(
            rng, c.candidates, [&](std::uint32_t b, restir::CandidateBlock<block_size>& block) {
                const std::uint32_t first = ((start + b * stride) & block_mask) * block_size;
                return restir::evaluate_tile_block<block_size, target_norm>(
                    c.tiles, tile, first, s.position, s.normal, channel_weights, block);
            });
        r = c.recipe<Frame>().initial(
            c.pixel(x, y), picked.with_sample(c.tiles.point_sample(picked.sample)), c.visibility());
    }
    c.current[i] = r;
}

// Stages 1 and 5 with deferred visibility: the shadow ray of the pixel's sample (W = 0 when
// occluded).
template <class Frame>
RESTIR_HOST_DEVICE void visibility_pixel(const Context& c, std::uint32_t x, std::uint32_t y) {
    const std::uint32_t i = x + y * c.width;
    if (c.recipe<Frame>().needs_visibility_test(c.current[i]))
        restir::apply_visibility(c.current[i], c.surfaces[i], c.visibility());
}

template <class Frame>
RESTIR_HOST_DEVICE void temporal_pixel(const Context& c, std::uint32_t x, std::uint32_t y) {
    const std::uint32_t i = x + y * c.width;
    Reservoir r = c.current[i];
    if (is_valid_surface(c.surfaces[i])) {
        restir::Pcg32 rng = restir::make_pixel_rng(i, c.frame, restir::RngStream::temporal, c.seed);
        r = c.recipe<Frame>().temporal(c.pixel(x, y), r, c.bridge(), rng);
    }
    c.scratch[i] = r;
}

template <class Frame>
RESTIR_HOST_DEVICE void spatial_pixel(const Context& c, std::uint32_t x, std::uint32_t y) {
    const std::uint32_t i = x + y * c.width;
    restir::Pcg32 rng = restir::make_pixel_rng(i, c.frame, restir::RngStream::spatial, c.seed);
    c.current[i] = c.recipe<Frame>().spatial(c.pixel(x, y), 0u, {c.scratch, c.width, c.height},
                                             c.bridge(), rng);
}

// Shading: emission plus f(y) W, unshadowed (the final visibility pass zeroed W of occluded
// samples); the result stored as next frame's history (packed, or left in `current`).
template <class Frame>
RESTIR_HOST_DEVICE void shade_pixel(const Context& c, std::uint32_t x, std::uint32_t y) {
    const std::uint32_t i = x + y * c.width;
    const Texel& s = c.surfaces[i];
    const Reservoir& r = c.current[i];
    glm::vec3 color(0.0f);
    if (is_valid_surface(s)) {
        color = emission_of(s.material);
        if (r.has_sample() && r.contribution_weight > 0.0f)
            color += albedo_of(s.material) * restir::inv_pi *
                     restir::unshadowed_irradiance(r.sample, s.position, s.normal) *
                     r.contribution_weight;
    }
    c.image[i] = color;
    if (c.packed)
        c.packed_history[i] = restir::pack_reservoir(r);
}

/// The passes of a frame, in order.
enum class Pass : std::uint32_t {
    gbuffer,
    tiles,
    candidates,
    visibility,
    temporal,
    spatial,
    final_visibility,
    shading,
    count
};
inline constexpr std::uint32_t pass_count = static_cast<std::uint32_t>(Pass::count);
inline const char* pass_name(Pass p) {
    constexpr const char* names[] = {
        "G-buffer (analytic rays)",         "light tiles",    "initial candidates",
        "visibility (analytic rays)",       "temporal reuse", "spatial reuse",
        "final visibility (analytic rays)", "shading"};
    return names[static_cast<std::uint32_t>(p)];
}
/// Whether the pass traces rays of the analytic scene only (its cost is not the library's).
inline bool is_ray_pass(Pass p) {
    return p == Pass::gbuffer || p == Pass::visibility || p == Pass::final_visibility;
}

/// Pass `P` at item (x, y).
template <Pass P, class Frame>
RESTIR_HOST_DEVICE void run_item(const Context& c, std::uint32_t x, std::uint32_t y) {
    if constexpr (P == Pass::gbuffer)
        gbuffer_pixel(c, x, y);
    else if constexpr (P == Pass::tiles)
        tile_entry(c, x, y);
    else if constexpr (P == Pass::candidates)
        candidates_pixel<Frame>(c, x, y);
    else if constexpr (P == Pass::visibility || P == Pass::final_visibility)
        visibility_pixel<Frame>(c, x, y);
    else if constexpr (P == Pass::temporal)
        temporal_pixel<Frame>(c, x, y);
    else if constexpr (P == Pass::spatial)
        spatial_pixel<Frame>(c, x, y);
    else
        shade_pixel<Frame>(c, x, y);
}

} // namespace box
