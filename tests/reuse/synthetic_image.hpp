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
// The truth at a pixel is sum_l f_s(l) for the patch it sees.
#pragma once

#include <restir/restir.hpp>

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

    World() {
        for (std::uint32_t s = 0; s < pixel_count; ++s)
            for (std::uint32_t l = 0; l < light_count; ++l) {
                const std::uint32_t h = hash(s, l);
                target[s][l] =
                    (h % 4u == 0u) ? 0.0f : 0.2f + static_cast<float>(h % 1000u) / 500.0f;
                visible[s][l] = (h / 4u) % 4u != 0u;
                truth[s] += integrand(s, l);
            }
    }
    static double colour(std::uint32_t l) { return 0.5 + 0.25 * static_cast<double>(l % 3u); }
    double integrand(std::uint32_t s, std::uint32_t l) const {
        return visible[s][l] ? static_cast<double>(target[s][l]) * colour(l) : 0.0;
    }
};

inline const World& world() {
    static const World w;
    return w;
}

struct Target {
    float operator()(const LightId& x, const Patch& p) const { return world().target[p.id][x.id]; }
};
struct Visibility {
    bool operator()(const LightId& x, const Patch& p) const { return world().visible[p.id][x.id]; }
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
