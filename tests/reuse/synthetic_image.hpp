// A synthetic image with a known answer per pixel, for the unbiasedness tests of the reuse
// passes and of the frame recipe.
//
// The world: 18 surface patches in a 6 x 3 grid, 12 lights. Patch s has a target p-hat_s(l)
// that is zero for about a quarter of the lights (lights "behind" it, so neighbours' samples
// can have zero target at a receiver), a visibility V_s(l) that blocks about a quarter of them,
// and an integrand f_s(l) = p-hat_s(l) V_s(l) c(l), where the colour-like factor c keeps the
// target from being exactly proportional to f. One patch is background (invalid surface).
// The camera pans: at frame t, pixel (x, y) sees patch ((x + t) mod 6, y), so the previous
// frame saw the same patch at (x + 1, y), and the right-most column is disoccluded. Row 1 has
// wrong motion vectors that point one pixel too far, at a different patch.
// The truth at a pixel is sum_l f_s(l) for the patch it sees. `glossy_world()` is the same
// image with p-hat from glossy receivers (make_glossy_world), `sky_world()` with a third of its
// lights distant (make_sky_world).
#pragma once

#include <restir/restir.hpp>

#include <glm/geometric.hpp>

#include <array>
#include <cstdint>

namespace restir::test::synthetic {

using restir::PixelCoord;

constexpr std::int32_t width = 6;
constexpr std::int32_t height = 3;
constexpr std::uint32_t pixel_count = width * height;
constexpr std::uint32_t light_count = 12;
constexpr std::uint32_t initial_candidates = 4;
constexpr std::uint32_t background_patch = 2 * width + 4;

struct Patch {
    std::uint32_t id = 0u;
    bool valid = true;
};
// Required by the Surface concept; the reuse passes themselves never ask for positions.
inline glm::vec3 surface_position(const Patch& p) {
    return {static_cast<float>(p.id % width), static_cast<float>(p.id / width), 0.0f};
}
inline glm::vec3 surface_normal(const Patch&) { return {0.0f, 0.0f, 1.0f}; }
inline float surface_depth(const Patch&) { return 1.0f; }
inline bool is_valid_surface(const Patch& p) { return p.valid; }
/// The glossy world's roughness of patch p (restir::reuse_roughness; the reuse passes read it
/// only where told to treat smooth receivers apart).
inline float surface_roughness(const Patch& p) {
    return 0.05f + 0.19f * static_cast<float>(p.id % width);
}

struct LightId {
    std::uint32_t id = 0u;
    friend bool operator==(const LightId&, const LightId&) = default;
};

inline std::uint32_t hash(std::uint32_t a, std::uint32_t b) {
    return static_cast<std::uint32_t>(restir::mix64((std::uint64_t{a} << 32u) | b));
}

// p-hat, visibility and integrand tables.
struct World {
    std::array<std::array<float, light_count>, pixel_count> target{};
    std::array<std::array<bool, light_count>, pixel_count> visible{};
    std::array<double, pixel_count> truth{};
    /// A second source distribution over lights per patch (the glossy world's BSDF-guided
    /// choice; empty in the plain world).
    std::array<std::array<float, light_count>, pixel_count> guided_pmf{};

    World() {
        for (std::uint32_t s = 0; s < pixel_count; ++s)
            for (std::uint32_t l = 0; l < light_count; ++l) {
                const std::uint32_t h = hash(s, l);
                target[s][l] =
                    (h % 4u == 0u) ? 0.0f : 0.2f + static_cast<float>(h % 1000u) / 500.0f;
                visible[s][l] = (h / 4u) % 4u != 0u;
            }
        sum_truth();
    }
    static double colour(std::uint32_t l) { return 0.5 + 0.25 * static_cast<double>(l % 3u); }
    double integrand(std::uint32_t s, std::uint32_t l) const {
        return visible[s][l] ? static_cast<double>(target[s][l]) * colour(l) : 0.0;
    }
    void sum_truth() {
        for (std::uint32_t s = 0; s < pixel_count; ++s) {
            truth[s] = 0.0;
            for (std::uint32_t l = 0; l < light_count; ++l)
                truth[s] += integrand(s, l);
        }
    }
};

inline const World& world() {
    static const World w;
    return w;
}

/// The same image with glossy receivers: patch s is a point of a floor (z = 0) with a GGX +
/// Lambert BSDF (restir::GlossyBsdf) whose roughness runs from 0.05 to 1 along each row (row 2
/// metallic), seen from one camera, so that neighbours' lobes differ in width and direction;
/// the 12 lights are isotropic points, some below the floor. p-hat_s(l) is the folded
/// unshadowed radiance I_l f_s(wo, wi) cos / d^2 (restir::unshadowed_radiance at a
/// restir::GlossyReceiver); visibility as in the plain world; `guided_pmf` chooses lights in
/// proportion to the BSDF's sampling density towards them.
inline World make_glossy_world() {
    World w;
    const glm::vec3 camera{2.5f, -3.0f, 4.0f};
    for (std::uint32_t s = 0; s < pixel_count; ++s) {
        const glm::vec3 position{static_cast<float>(s % width), static_cast<float>(s / width),
                                 0.0f};
        const float roughness = 0.05f + 0.19f * static_cast<float>(s % width);
        restir::GlossyReceiver receiver{
            position, {0.0f, 0.0f, 1.0f}, glm::normalize(camera - position), {}};
        receiver.bsdf = restir::GlossyBsdf::from_metallic_roughness(
            {0.8f, 0.6f, 0.4f}, s / width == 2u ? 1.0f : 0.0f, roughness);
        float pdf_sum = 0.0f;
        for (std::uint32_t l = 0; l < light_count; ++l) {
            const std::uint32_t h = hash(l, 77u);
            restir::LightSample light;
            light.position = {static_cast<float>(h % 700u) / 100.0f - 0.5f,
                              static_cast<float>((h / 700u) % 400u) / 100.0f - 0.5f,
                              l % 5u == 4u ? -0.5f : 0.5f + static_cast<float>(h % 13u) / 10.0f};
            light.normal = glm::vec3(0.0f);
            light.radiance = glm::vec3(1.0f + static_cast<float>(l % 4u));
            light.area_pdf = 1.0f;
            light.is_delta = true;
            const restir::LightPointSample point =
                restir::make_light_point_sample(l, light, restir::Falloff::exact());
            w.target[s][l] = restir::fold_channels<restir::ChannelNorm::sum>(
                restir::unshadowed_radiance(point, receiver));
            const glm::vec3 wi = glm::normalize(light.position - position);
            w.guided_pmf[s][l] = receiver.direction_pdf(wi);
            pdf_sum += w.guided_pmf[s][l];
        }
        for (std::uint32_t l = 0; l < light_count; ++l)
            w.guided_pmf[s][l] = pdf_sum > 0.0f ? w.guided_pmf[s][l] / pdf_sum : 0.0f;
    }
    w.sum_truth();
    return w;
}

inline const World& glossy_world() {
    static const World w = make_glossy_world();
    return w;
}

/// The glossy world under a sky: lights 8 to 11 are distant (an environment's directions, as
/// restir::environment_light_sample makes them: `LightSample::is_distant`, radiance over a
/// density per steradian), the same direction from every patch, some below the floor's
/// horizon; lights 0 to 7 stay isotropic points. p-hat is restir::unshadowed_radiance of the
/// lights' `LightPointSample`s at the patches' GGX receivers, so a distant sample reused at a
/// neighbour is evaluated there with no position (`positional` 0).
inline World make_sky_world() {
    World w = make_glossy_world();
    const glm::vec3 camera{2.5f, -3.0f, 4.0f};
    for (std::uint32_t s = 0; s < pixel_count; ++s) {
        const glm::vec3 position{static_cast<float>(s % width), static_cast<float>(s / width),
                                 0.0f};
        restir::GlossyReceiver receiver{
            position, {0.0f, 0.0f, 1.0f}, glm::normalize(camera - position), {}};
        receiver.bsdf = restir::GlossyBsdf::from_metallic_roughness(
            {0.8f, 0.6f, 0.4f}, s / width == 2u ? 1.0f : 0.0f,
            0.05f + 0.19f * static_cast<float>(s % width));
        for (std::uint32_t l = 8; l < light_count; ++l) {
            const std::uint32_t h = hash(l, 91u);
            restir::LightSample sky;
            sky.position = glm::normalize(glm::vec3(
                static_cast<float>(h % 200u) / 100.0f - 1.0f,
                static_cast<float>((h / 200u) % 200u) / 100.0f - 1.0f, l == 11u ? -0.3f : 0.8f));
            sky.normal = glm::vec3(0.0f);
            sky.radiance = glm::vec3(0.5f + 0.3f * static_cast<float>(l % 3u));
            sky.area_pdf = 0.25f; // per steradian
            sky.is_distant = true;
            const restir::LightPointSample point =
                restir::make_light_point_sample(l, sky, restir::Falloff::exact());
            w.target[s][l] = restir::fold_channels<restir::ChannelNorm::sum>(
                restir::unshadowed_radiance(point, receiver));
        }
    }
    w.sum_truth();
    return w;
}
inline const World& sky_world() {
    static const World w = make_sky_world();
    return w;
}

struct Target {
    const World* w = &world();
    float operator()(const LightId& x, const Patch& p) const { return w->target[p.id][x.id]; }
};
struct Visibility {
    const World* w = &world();
    bool operator()(const LightId& x, const Patch& p) const { return w->visible[p.id][x.id]; }
};

inline PixelCoord pixel_of(std::uint32_t index) {
    return {static_cast<std::int32_t>(index % width), static_cast<std::int32_t>(index / width)};
}

inline Patch patch_seen(PixelCoord p, std::uint32_t frame) {
    const auto column = static_cast<std::uint32_t>(p.x + static_cast<std::int32_t>(frame)) % width;
    const std::uint32_t id = column + static_cast<std::uint32_t>(p.y) * width;
    return {id, id != background_patch};
}

struct Reproject {
    PixelCoord operator()(PixelCoord p) const { return {p.x + (p.y == 1 ? 2 : 1), p.y}; }
};

} // namespace restir::test::synthetic
