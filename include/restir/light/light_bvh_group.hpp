/// @file light/light_bvh_group.hpp
/// The nodes of the light BVH (light/light_bvh_view.hpp) and their importance bound (Conty
/// Estevez and Kulla 2018, Eq. 3): a node's bounds as floats (`LightBvhNode`), and the tree's
/// groups of eight children quantised in 128 bytes (`LightBvhGroup`: boxes on the grid of the
/// parent's box, octahedral cone axes, 8-bit cone angles, bfloat16 powers, every bound rounded
/// outward), with the bounds of a group's children at a shading point.
#pragma once

#include "restir/config.hpp"
#include "restir/core/math.hpp"
#include "restir/core/shading_point.hpp"

#include <glm/geometric.hpp>
#include <glm/vec3.hpp>

#include <cmath>
#include <cstdint>
#include <cstring>
#if RESTIR_STD_SIMD
#include <experimental/simd>
#endif
#include <type_traits>

RESTIR_VECTORIZE_REGION_BEGIN

namespace restir {

/// The bounds of one node (one light, or a group of lights) as `light_importance` weighs
/// them: 48 bytes. The tree keeps them quantised, eight by eight, in `LightBvhGroup`s
/// (`LightBvhGroup::node` reads one back).
struct LightBvhNode {
    glm::vec3 centre{0.0f};
    float radius = 0.0f; ///< Half the diagonal of the box.
    glm::vec3 axis{0.0f, 0.0f, 1.0f};
    float cos_theta_o = 1.0f;
    float cos_theta_e = 0.0f;
    float power = 0.0f;
    float sin_theta_o = 0.0f;
    /// A leaf: `leaf_bit` | the light id. Otherwise the index of the `LightBvhGroup` of its
    /// children.
    std::uint32_t child_or_light = 0u;

    static constexpr std::uint32_t leaf_bit = 0x80000000u;
    RESTIR_HOST_DEVICE constexpr bool is_leaf() const noexcept {
        return (child_or_light & leaf_bit) != 0u;
    }
};

static_assert(std::is_trivially_copyable_v<LightBvhNode>);
static_assert(sizeof(LightBvhNode) == 48u);

namespace detail {
// sin(theta) from cos(theta), theta in [0, pi].
RESTIR_HOST_DEVICE inline float sine_of(float cosine) noexcept {
    return std::sqrt(max_of(0.0f, 1.0f - cosine * cosine));
}

// The importance bound of Conty Estevez and Kulla 2018 (Eq. 3) from a node's fields: the one
// formula of `light_importance` and of the lanes of a `LightBvhGroup`. The cone axis need not
// be a unit vector: `axis_length` is its length and `inverse_axis_length` one over it (a lane's
// octahedral axis comes unnormalised, so that its normalisation, a square root and a division,
// runs beside the projections rather than before them). Selects rather than branches throughout
// (the outcomes vary from node to node, and the lanes vectorise), as `select_float`: with `?:`
// whether the lanes vectorise depends on the caller.
RESTIR_HOST_DEVICE RESTIR_FORCE_INLINE float
importance_bound(glm::vec3 centre, float node_radius, glm::vec3 axis, float axis_length,
                 float inverse_axis_length, float cos_theta_o, float sin_theta_o, float cos_theta_e,
                 float power, const ShadingPoint& at, float near_length = 0.0f) noexcept {
    // For a region (at.radius > 0) the node's sphere grows by the region's radius: every
    // direction from a point of the region to a point of the node lies within theta_b of the
    // direction between their centres.
    const float radius = node_radius + max_of(at.radius, 0.0f);
    const glm::vec3 from_centre = at.position - centre;
    const float distance_squared = glm::dot(from_centre, from_centre);
    const float radius_squared = radius * radius;
    const float falloff = 1.0f / max_of(distance_squared, radius_squared);
    // The distance term before the cosines: 1 / max(d^2, r l) with a near-field length l > 0
    // (`LightBvhView::near_length`), else 1 / max(d^2, r^2). Between the two, a node far larger
    // than l keeps the distance to its centre when the point is inside its sphere (the lights
    // near the point weigh more than those across the node), and a node far smaller than l
    // stops growing as 1 / d^2 a few of its radii away (a light beside the point, whose
    // cosines the sphere cannot bound, no longer takes the draws of the lights that light it).
    const float near_squared =
        select_float(near_length > 0.0f, radius * near_length, radius_squared);
    const float near_falloff = 1.0f / max_of(distance_squared, near_squared);
    // Outside the sphere every cosine and sine below is kept times d (a product of two, times
    // d^2): cos(theta_w) d is the projection on the axis and sin(theta_w) d = sqrt(d^2 -
    // projection^2). A descent waits on this bound at every level, and the scaled terms need no
    // 1 / d before them: the square roots start right after d^2, and the falloff (1 / d^2
    // outside) runs beside them.
    const float distance = std::sqrt(distance_squared);
    const float axis_projection = glm::dot(axis, from_centre);
    const float normal_projection = -glm::dot(at.normal, from_centre);
    // theta_b: the half-angle of the node's sphere seen from the point.
    const float sin_b = radius;
    const float cos_b = std::sqrt(max_of(distance_squared - radius_squared, 0.0f));
    // theta_w's cosine and sine times d and the axis's length l: the projection on the axis as
    // it is, and sqrt(l^2 d^2 - projection^2).
    const float cos_w = axis_projection;
    const float sin_w = std::sqrt(max_of(
        axis_length * axis_length * distance_squared - axis_projection * axis_projection, 0.0f));
    // theta_x = max(0, theta_w - theta_o): the cone's half-angle taken off (times d again).
    const bool within_cone = cos_w > cos_theta_o * distance * axis_length;
    const float cos_x = select_float(
        within_cone, distance, (cos_w * cos_theta_o + sin_w * sin_theta_o) * inverse_axis_length);
    const float sin_x = select_float(
        within_cone, 0.0f, (sin_w * cos_theta_o - cos_w * sin_theta_o) * inverse_axis_length);
    // theta' = max(0, theta_x - theta_b), its cosine times d^2.
    const float cos_emitted =
        select_float(cos_x > cos_b, distance_squared, cos_x * cos_b + sin_x * sin_b);
    // The receiver term (theta_i between the unit normal and the direction to the centre), its
    // cosine times d^2; none for a zero normal.
    const float cos_i = normal_projection;
    const float sin_i =
        std::sqrt(max_of(distance_squared - normal_projection * normal_projection, 0.0f));
    const float cos_received =
        select_float(cos_i > cos_b, distance_squared, cos_i * cos_b + sin_i * sin_b);
    const bool has_normal = at.normal.x != 0.0f || at.normal.y != 0.0f || at.normal.z != 0.0f;
    const float receiver = select_float(has_normal, max_of(cos_received * falloff, 0.0f), 1.0f);
    const float outside =
        select_float(cos_emitted > cos_theta_e * distance_squared,
                     power * near_falloff * (cos_emitted * falloff) * receiver, 0.0f);
    // Inside the sphere (theta_b = pi) both cosines are 1.
    const float inside = select_float(1.0f > cos_theta_e, power * near_falloff, 0.0f);
    const float importance = select_float(distance_squared <= radius_squared, inside, outside);
    return select_float(is_valid_weight(importance), importance, 0.0f);
}
} // namespace detail

/// The importance bound of a node's lights at a shading point (Conty Estevez and Kulla 2018,
/// Eq. 3): power cos(theta') / d^2, times cos(theta'_i) of the receiver, where d is the
/// distance to the box's centre (at least its half diagonal), theta_b the half-angle of its
/// bounding sphere seen from the point (pi inside it), theta' = max(0, theta_w - theta_o -
/// theta_b) with theta_w between the cone axis and the direction to the point (0 when
/// theta' >= theta_e: no light of the node reaches the point), and theta'_i = max(0, theta_i -
/// theta_b) with theta_i between the receiver normal and the direction to the centre (no
/// receiver term for a zero normal). Never 0 where a light of the node lights the point (any
/// point of a region `at`). With a `near_length` l > 0 the leading 1 / d^2 is 1 / max(d^2, r l)
/// instead, r the half diagonal (`LightBvhView::near_length`: what a light BVH draws with).
RESTIR_HOST_DEVICE inline float light_importance(const LightBvhNode& node, const ShadingPoint& at,
                                                 float near_length = 0.0f) noexcept {
    return detail::importance_bound(node.centre, node.radius, node.axis, 1.0f, 1.0f,
                                    node.cos_theta_o, node.sin_theta_o, node.cos_theta_e,
                                    node.power, at, near_length);
}

/// A box: what `LightBvhGroup::box` returns.
struct LightBvhBox {
    glm::vec3 lower{0.0f};
    glm::vec3 upper{0.0f};
};

/// The grid on which the boxes of a group's children are stored: along each axis, corner code q
/// (0 to 255) is `origin + q step`. `over(box)` makes the grid of a box, the box of the group's
/// parent node: `step` is the smallest power of two (at least FLT_MIN) with 255 step covering
/// the box. Every corner the builder stores comes out exactly, with or without fused
/// multiply-adds, on any IEEE machine: the root's corners are multiples of its step, so every
/// corner below is a multiple of its own grid's step (a power of two no larger), and a corner
/// is either a multiple of a step at least its ulp, or, where the step is finer than the ulps
/// there, the light coordinate it rounds (a float, and a multiple of the step). The host and
/// the device read the same boxes, which contain the lights by construction.
struct LightBvhGrid {
    glm::vec3 origin{0.0f};
    glm::vec3 step{0.0f};

    /// The grid of box [lower, upper] (both corners multiples of their own grid's step).
    RESTIR_HOST_DEVICE static LightBvhGrid over(glm::vec3 lower, glm::vec3 upper) noexcept;
    /// Corner code `code` along `axis`.
    RESTIR_HOST_DEVICE float corner(int axis, std::uint32_t code) const noexcept {
        const float o = axis == 0 ? origin.x : axis == 1 ? origin.y : origin.z;
        const float s = axis == 0 ? step.x : axis == 1 ? step.y : step.z;
        return o + static_cast<float>(code) * s;
    }
};

namespace detail {
RESTIR_HOST_DEVICE inline std::uint32_t float_bits(float x) noexcept {
    return __builtin_bit_cast(std::uint32_t, x);
}
RESTIR_HOST_DEVICE inline float bits_float(std::uint32_t bits) noexcept {
    return __builtin_bit_cast(float, bits);
}

// The grid step over [lower, upper] along one axis (`LightBvhGrid::over`): the power of two at
// or above extent / 255, on the bit pattern, doubled once where extent * (1 / 255) rounded down
// onto one below it (255 step is exact); and at least the spacing of floats at the larger end,
// 2^-23 times the power of two at or below max(|lower|, |upper|): a finer step would tell no
// more corners apart, and a flat box (extent 0: coplanar lights) far from 0 would overflow
// lower / step. A box inside a box gets a step no larger, so its corners stay multiples of it.
// The extent is exact: the corners are multiples of the parent's step, at most 255 apart.
RESTIR_HOST_DEVICE inline float grid_step(float lower, float upper) noexcept {
    const float extent = upper - lower;
    float step = bits_float((float_bits(extent * (1.0f / 255.0f)) + 0x007fffffu) & 0x7f800000u);
    step = 255.0f * step < extent ? 2.0f * step : step;
    const float magnitude = max_of(std::fabs(lower), std::fabs(upper));
    const float spacing = bits_float(float_bits(magnitude) & 0x7f800000u) * 0x1p-23f;
    return max_of(max_of(step, spacing), 0x1p-126f); // FLT_MIN: no subnormal steps
}

// An axis from its octahedral codes (each 0 to 254, 127 the middle): the octahedron's point
// (x, y, 1 - |x| - |y|), its lower half folded out (Cigolle et al. 2014), as it is, with its
// length and one over it; normalised, the unit axis. The `_of` forms take the codes as floats
// (exact), which a host loop over a group's lanes vectorises.
struct OctahedralAxis {
    glm::vec3 direction; // not normalised
    float length;
    float inverse_length;
};
RESTIR_HOST_DEVICE inline OctahedralAxis octahedral_direction_of(float u, float v) noexcept {
    const float x = (u - 127.0f) * (1.0f / 127.0f);
    const float y = (v - 127.0f) * (1.0f / 127.0f);
    const float z = 1.0f - std::abs(x) - std::abs(y);
    const float fold = max_of(-z, 0.0f);
    const float folded_x = select_float(x >= 0.0f, x - fold, x + fold);
    const float folded_y = select_float(y >= 0.0f, y - fold, y + fold);
    const float length = std::sqrt(folded_x * folded_x + folded_y * folded_y + z * z);
    return {glm::vec3(folded_x, folded_y, z), length, 1.0f / length};
}
RESTIR_HOST_DEVICE inline glm::vec3 octahedral_axis_of(float u, float v) noexcept {
    const OctahedralAxis axis = octahedral_direction_of(u, v);
    return axis.direction * axis.inverse_length;
}
RESTIR_HOST_DEVICE inline glm::vec3 octahedral_axis(std::uint32_t u, std::uint32_t v) noexcept {
    return octahedral_axis_of(static_cast<float>(u), static_cast<float>(v));
}

// cos(theta_o) and sin(theta_o) from the cone code q, (q / 255)^2 = sin(theta_o / 2) rounded up:
// 0 is theta_o = 0 and 255 is pi (both exact); code 1 is 3e-5 radians, so the narrow cones of
// emitters whose axis the octahedral codes hold exactly (axis-aligned walls, lights facing
// down) stay narrow; steps of 0.45 degrees near 30, 0.7 near 60 and 2 near 120 degrees.
RESTIR_HOST_DEVICE inline float cone_half_sine(float code) noexcept {
    const float s = code * (1.0f / 255.0f);
    return s * s;
}
RESTIR_HOST_DEVICE inline float cone_cos_of(float code) noexcept {
    const float h = cone_half_sine(code);
    return 1.0f - 2.0f * h * h;
}
RESTIR_HOST_DEVICE inline float cone_sin_of(float code) noexcept {
    const float h = cone_half_sine(code);
    return 2.0f * h * std::sqrt(max_of(1.0f - h * h, 0.0f));
}
RESTIR_HOST_DEVICE inline float cone_cos(std::uint32_t code) noexcept {
    return cone_cos_of(static_cast<float>(code));
}
RESTIR_HOST_DEVICE inline float cone_sin(std::uint32_t code) noexcept {
    return cone_sin_of(static_cast<float>(code));
}

// cos(theta_e) from its code: (q - 128) / 128, rounded down (0 and -1 exact; 1 becomes 127/128).
RESTIR_HOST_DEVICE inline float emission_cos_of(float code) noexcept {
    return (code - 128.0f) * (1.0f / 128.0f);
}
RESTIR_HOST_DEVICE inline float emission_cos(std::uint32_t code) noexcept {
    return emission_cos_of(static_cast<float>(code));
}

// A bfloat16 power: the top 16 bits of a float (rounded up by the builder).
RESTIR_HOST_DEVICE inline float bfloat16_value(std::uint32_t bits) noexcept {
    return bits_float(bits << 16u);
}
} // namespace detail

RESTIR_HOST_DEVICE inline LightBvhGrid LightBvhGrid::over(glm::vec3 lower,
                                                          glm::vec3 upper) noexcept {
    return {lower,
            glm::vec3(detail::grid_step(lower.x, upper.x), detail::grid_step(lower.y, upper.y),
                      detail::grid_step(lower.z, upper.z))};
}

/// The children of one interior node of the flat tree, lane c for child c, quantised: 16 bytes
/// a lane, 128 bytes, two cache lines. A structure of arrays, so that the eight importance
/// bounds of a level decode and compute side by side in vector registers. A child's box is stored
/// on the grid of its parent's box (`LightBvhGrid`, which a descent carries down from the root's
/// box in `LightBvhView`); its cone axis in octahedral codes; theta_o, cos(theta_e) and the power
/// in a byte, a byte and 16 bits. Every bound is rounded outward (the box, theta_o and theta_e only
/// grow), so the importance stays positive wherever a light of the child lights a point; the
/// power is rounded up. An unused lane is a leaf without power, which no draw takes.
struct alignas(64) LightBvhGroup {
    /// Children per group, a power of two: `lane_bits` bits of a path each.
    static constexpr std::uint32_t lane_bits = 3u;
    static constexpr std::uint32_t lanes = 1u << lane_bits;

    /// A leaf: `LightBvhNode::leaf_bit` | the light id. Otherwise the index of the group of its
    /// children.
    std::uint32_t child_or_light[lanes];
    /// Corner codes on the parent's grid, per axis: the box is [corner(lower), corner(upper)].
    std::uint8_t lower[3][lanes], upper[3][lanes];
    /// The cone axis: octahedral codes 0 to 254 (`detail::octahedral_axis`).
    std::uint8_t axis_u[lanes], axis_v[lanes];
    /// 255 sqrt(sin(theta_o / 2)), rounded up (`detail::cone_cos`, `detail::cone_sin`).
    std::uint8_t cone[lanes];
    /// 128 + 128 cos(theta_e), rounded down (`detail::emission_cos`).
    std::uint8_t emission[lanes];
    /// The power as bfloat16, rounded up (`detail::bfloat16_value`).
    std::uint16_t power[lanes];

    RESTIR_HOST_DEVICE constexpr bool is_leaf(std::uint32_t lane) const noexcept {
        return (child_or_light[lane] & LightBvhNode::leaf_bit) != 0u;
    }
    /// Lane `lane`'s box on the parent's grid.
    RESTIR_HOST_DEVICE LightBvhBox box(std::uint32_t lane,
                                       const LightBvhGrid& grid) const noexcept {
        return {glm::vec3(grid.corner(0, lower[0][lane]), grid.corner(1, lower[1][lane]),
                          grid.corner(2, lower[2][lane])),
                glm::vec3(grid.corner(0, upper[0][lane]), grid.corner(1, upper[1][lane]),
                          grid.corner(2, upper[2][lane]))};
    }
    /// The grid of lane `lane`'s box: the one its own children's boxes are stored on.
    RESTIR_HOST_DEVICE LightBvhGrid child_grid(std::uint32_t lane,
                                               const LightBvhGrid& grid) const noexcept {
        const LightBvhBox b = box(lane, grid);
        return LightBvhGrid::over(b.lower, b.upper);
    }
    /// Lane `lane` as a node, decoded (its `child_or_light` included): what the importance
    /// bounds weigh.
    RESTIR_HOST_DEVICE LightBvhNode node(std::uint32_t lane, const LightBvhGrid& grid) const {
        LightBvhNode n;
        decode(lane, grid, n.centre, n.radius);
        n.axis = detail::octahedral_axis(axis_u[lane], axis_v[lane]);
        n.cos_theta_o = detail::cone_cos(cone[lane]);
        n.sin_theta_o = detail::cone_sin(cone[lane]);
        n.cos_theta_e = detail::emission_cos(emission[lane]);
        n.power = detail::bfloat16_value(power[lane]);
        n.child_or_light = child_or_light[lane];
        return n;
    }
    /// The importance bounds of the children at `at` (`light_importance` of each `node`, their
    /// boxes on `grid`), and their sum, added lane by lane.
    RESTIR_HOST_DEVICE float importance(const ShadingPoint& at, const LightBvhGrid& grid,
                                        float (&out)[lanes], float near_length = 0.0f) const {
        bounds(at, grid, out, near_length);
        float total = 0.0f;
        RESTIR_UNROLL
        for (std::uint32_t c = 0u; c < lanes; ++c)
            total += out[c];
        return total;
    }
    /// The importance bounds alone (what `importance` writes to `out`). Inlined by force: a
    /// descent waits on them at every level, and a call passes them through memory.
    RESTIR_HOST_DEVICE RESTIR_FORCE_INLINE void bounds(const ShadingPoint& at,
                                                       const LightBvhGrid& grid,
                                                       float (&out)[lanes],
                                                       float near_length = 0.0f) const;
    /// Lane `lane`'s bound alone, as device code evaluates each lane of `bounds` (host code
    /// computes all eight side by side, the same numbers).
    RESTIR_HOST_DEVICE float bound(std::uint32_t lane, const LightBvhGrid& grid,
                                   const ShadingPoint& at, float near_length = 0.0f) const {
        glm::vec3 centre;
        float radius;
        decode(lane, grid, centre, radius);
        const detail::OctahedralAxis axis = detail::octahedral_direction_of(
            static_cast<float>(axis_u[lane]), static_cast<float>(axis_v[lane]));
        return detail::importance_bound(centre, radius, axis.direction, axis.length,
                                        axis.inverse_length, detail::cone_cos(cone[lane]),
                                        detail::cone_sin(cone[lane]),
                                        detail::emission_cos(emission[lane]),
                                        detail::bfloat16_value(power[lane]), at, near_length);
    }

private:
    /// The codes of every lane widened to floats, exactly, for host code's `bounds`: the box's
    /// corner codes in `low` and `high`, the axis's in `u` and `v`, the cone's and the
    /// emission's in `cone_code` and `emission_code`, and the power decoded in `power_value`
    /// (`bfloat16_value`). Inlined by force, as `bounds`.
    RESTIR_HOST_DEVICE RESTIR_FORCE_INLINE void
    widen_codes(float (&low)[3][lanes], float (&high)[3][lanes], float (&u)[lanes],
                float (&v)[lanes], float (&cone_code)[lanes], float (&emission_code)[lanes],
                float (&power_value)[lanes]) const;

    // The centre and half diagonal of lane `lane`'s box, from the codes: (lower + upper) / 2
    // and (upper - lower) in whole steps, which is fewer operations than from the corners.
    RESTIR_HOST_DEVICE void decode(std::uint32_t lane, const LightBvhGrid& grid, glm::vec3& centre,
                                   float& radius) const {
        const auto middle = [&](int a, float origin, float step) {
            return origin + static_cast<float>(std::uint32_t{lower[a][lane]} + upper[a][lane]) *
                                (0.5f * step);
        };
        const auto width = [&](int a, float step) {
            return static_cast<float>(std::uint32_t{upper[a][lane]} - lower[a][lane]) * step;
        };
        centre =
            glm::vec3(middle(0, grid.origin.x, grid.step.x), middle(1, grid.origin.y, grid.step.y),
                      middle(2, grid.origin.z, grid.step.z));
        const glm::vec3 diagonal(width(0, grid.step.x), width(1, grid.step.y),
                                 width(2, grid.step.z));
        radius = 0.5f * std::sqrt(glm::dot(diagonal, diagonal));
    }
};

static_assert(std::is_trivially_copyable_v<LightBvhGroup>);
static_assert(sizeof(LightBvhGroup) == 16u * LightBvhGroup::lanes);

RESTIR_HOST_DEVICE RESTIR_FORCE_INLINE void LightBvhGroup::bounds(const ShadingPoint& at,
                                                                  const LightBvhGrid& grid,
                                                                  float (&out)[lanes],
                                                                  float near_length) const {
    // The fields decoded and spelled out rather than light_importance(node(c, grid), at), which
    // vectorises less reliably. This loop is a draw's inner cost; check BM_LightBvh_SampleBatch
    // after any change here.
#if defined(__CUDA_ARCH__)
    RESTIR_UNROLL
    for (std::uint32_t c = 0u; c < lanes; ++c)
        out[c] = bound(c, grid, at, near_length);
#else
    // On a CPU the codes are widened to floats first (exactly), and the bounds computed from
    // floats alone: GCC vectorises a loop that reads bytes in as many lanes as bytes fill a
    // register, more than a group's eight, and so leaves the bounds scalar. The grid and the
    // point are copied: loads through references inside the loop
    // kept it from vectorising too. The same numbers as the device's loop, bit for bit.
    const LightBvhGrid g = grid;
    const ShadingPoint p = at;
    const float near = near_length;
    float low[3][lanes], high[3][lanes], u[lanes], v[lanes], cone_code[lanes], emission_code[lanes],
        power_value[lanes];
    widen_codes(low, high, u, v, cone_code, emission_code, power_value);
    RESTIR_VECTORIZE
    for (std::uint32_t c = 0u; c < lanes; ++c) {
        // decode(): (lower + upper) / 2 and upper - lower in whole steps.
        const glm::vec3 centre(g.origin.x + (low[0][c] + high[0][c]) * (0.5f * g.step.x),
                               g.origin.y + (low[1][c] + high[1][c]) * (0.5f * g.step.y),
                               g.origin.z + (low[2][c] + high[2][c]) * (0.5f * g.step.z));
        const glm::vec3 diagonal((high[0][c] - low[0][c]) * g.step.x,
                                 (high[1][c] - low[1][c]) * g.step.y,
                                 (high[2][c] - low[2][c]) * g.step.z);
        const float radius = 0.5f * std::sqrt(glm::dot(diagonal, diagonal));
        const detail::OctahedralAxis axis = detail::octahedral_direction_of(u[c], v[c]);
        out[c] = detail::importance_bound(
            centre, radius, axis.direction, axis.length, axis.inverse_length,
            detail::cone_cos_of(cone_code[c]), detail::cone_sin_of(cone_code[c]),
            detail::emission_cos_of(emission_code[c]), power_value[c], p, near);
    }
#endif
}

RESTIR_HOST_DEVICE RESTIR_FORCE_INLINE void
LightBvhGroup::widen_codes(float (&low)[3][lanes], float (&high)[3][lanes], float (&u)[lanes],
                           float (&v)[lanes], float (&cone_code)[lanes],
                           float (&emission_code)[lanes], float (&power_value)[lanes]) const {
#if RESTIR_STD_SIMD
    // GCC widens the bytes of a plain loop a few lanes at a time through the stack; as
    // eight-lane vectors they widen in a register.
    namespace stdx = std::experimental;
    using Floats = stdx::fixed_size_simd<float, lanes>;
    const auto widen = [](const std::uint8_t(&codes)[lanes], float(&to)[lanes]) {
        Floats(codes, stdx::element_aligned).copy_to(to, stdx::element_aligned);
    };
    for (int a = 0; a < 3; ++a) {
        widen(lower[a], low[a]);
        widen(upper[a], high[a]);
    }
    widen(axis_u, u);
    widen(axis_v, v);
    widen(cone, cone_code);
    widen(emission, emission_code);
    // bfloat16_value: the code is the high half of the float's bits.
    std::uint32_t power_bits[lanes];
    (stdx::fixed_size_simd<std::uint32_t, lanes>(power, stdx::element_aligned) << 16u)
        .copy_to(power_bits, stdx::element_aligned);
    std::memcpy(power_value, power_bits, sizeof(power_bits));
#else
    for (std::uint32_t c = 0u; c < lanes; ++c) {
        for (int a = 0; a < 3; ++a) {
            low[a][c] = static_cast<float>(lower[a][c]);
            high[a][c] = static_cast<float>(upper[a][c]);
        }
        u[c] = static_cast<float>(axis_u[c]);
        v[c] = static_cast<float>(axis_v[c]);
        cone_code[c] = static_cast<float>(cone[c]);
        emission_code[c] = static_cast<float>(emission[c]);
        power_value[c] = detail::bfloat16_value(power[c]);
    }
#endif
}

namespace detail {
// The sum of a group's bounds as a descent weighs them: in pairs, then pairs of pairs (half the
// chain of adding them in turn, which a draw waits for at every level).
RESTIR_HOST_DEVICE inline float pairwise_total(const float (&bounds)[LightBvhGroup::lanes]) {
    float sums[LightBvhGroup::lanes];
    RESTIR_UNROLL
    for (std::uint32_t c = 0u; c < LightBvhGroup::lanes; ++c)
        sums[c] = bounds[c];
    RESTIR_UNROLL
    for (std::uint32_t width = LightBvhGroup::lanes / 2u; width > 0u; width /= 2u) {
        RESTIR_UNROLL
        for (std::uint32_t c = 0u; c < width; ++c)
            sums[c] = sums[2u * c] + sums[2u * c + 1u];
    }
    return sums[0];
}
} // namespace detail

} // namespace restir

RESTIR_VECTORIZE_REGION_END
