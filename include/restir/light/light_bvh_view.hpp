/// @file light/light_bvh_view.hpp
/// A bounding volume hierarchy over lights for spatially aware light selection (Conty Estevez
/// and Kulla 2018, "Importance Sampling of Many Lights with Adaptive Tree Splitting"), as device
/// code reads it: flat groups of four children, sampled by `LightBvhView`. Every node bounds its
/// lights' positions (a box, kept as its centre and half diagonal), their emitted power, and the
/// directions they emit in (a cone of normals of half-angle theta_o, plus the emission spread
/// theta_e beyond them). A light is drawn for a shading point by one stochastic descent that
/// picks each child in proportion to an importance bound of its lights at the point; the pmf
/// of a light is the product of the choices on its path, found by the same descent from the
/// path's bits, so it is exact and RIS with it stays unbiased. The host builder is `LightBvh`
/// (light/light_bvh.hpp).
#pragma once

#include "restir/config.hpp"
#include "restir/core/discrete_sample.hpp"
#include "restir/core/math.hpp"
#include "restir/core/shading_point.hpp"

#include <glm/geometric.hpp>
#include <glm/vec3.hpp>

#include <cmath>
#include <cstdint>
#include <type_traits>

namespace restir {

/// The bounds of one node (one light, or a group of lights) as `light_importance` weighs
/// them: 48 bytes. The tree keeps them four by four, lane by lane, in `LightBvhGroup`s.
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
// formula of `light_importance` and of the four lanes of a `LightBvhGroup`. Selects rather than
// branches throughout (the outcomes vary from node to node, and the lanes vectorise), as
// `select_float`: with `?:` whether the lanes vectorise depends on the caller.
RESTIR_HOST_DEVICE inline float importance_bound(glm::vec3 centre, float node_radius,
                                                 glm::vec3 axis, float cos_theta_o,
                                                 float sin_theta_o, float cos_theta_e, float power,
                                                 const ShadingPoint& at) noexcept {
    // For a region (at.radius > 0) the node's sphere grows by the region's radius: every
    // direction from a point of the region to a point of the node lies within theta_b of the
    // direction between their centres.
    const float radius = node_radius + max_of(at.radius, 0.0f);
    const glm::vec3 from_centre = at.position - centre;
    const float distance_squared = glm::dot(from_centre, from_centre);
    const float radius_squared = radius * radius;
    const float falloff = 1.0f / max_of(distance_squared, radius_squared);
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
    const float cos_w = axis_projection;
    const float sin_w =
        std::sqrt(max_of(distance_squared - axis_projection * axis_projection, 0.0f));
    // theta_x = max(0, theta_w - theta_o): the cone's half-angle taken off.
    const bool within_cone = cos_w > cos_theta_o * distance;
    const float cos_x =
        select_float(within_cone, distance, cos_w * cos_theta_o + sin_w * sin_theta_o);
    const float sin_x = select_float(within_cone, 0.0f, sin_w * cos_theta_o - cos_w * sin_theta_o);
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
    const float outside = select_float(cos_emitted > cos_theta_e * distance_squared,
                                       power * falloff * (cos_emitted * falloff) * receiver, 0.0f);
    // Inside the sphere (theta_b = pi) both cosines are 1.
    const float inside = select_float(1.0f > cos_theta_e, power * falloff, 0.0f);
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
/// point of a region `at`).
RESTIR_HOST_DEVICE inline float light_importance(const LightBvhNode& node,
                                                 const ShadingPoint& at) noexcept {
    return detail::importance_bound(node.centre, node.radius, node.axis, node.cos_theta_o,
                                    node.sin_theta_o, node.cos_theta_e, node.power, at);
}

/// The children of one interior node of the flat tree, lane c for child c: a structure of
/// arrays, so that the four importance bounds of a level compute side by side in vector
/// registers. The fields are those of `LightBvhNode`; 192 bytes, three cache lines. An unused
/// lane is a leaf without power, which no draw takes.
struct alignas(64) LightBvhGroup {
    static constexpr std::uint32_t lanes = 4u;

    float centre_x[lanes], centre_y[lanes], centre_z[lanes];
    float radius[lanes];
    float axis_x[lanes], axis_y[lanes], axis_z[lanes];
    float cos_theta_o[lanes], sin_theta_o[lanes], cos_theta_e[lanes];
    float power[lanes];
    /// A leaf: `LightBvhNode::leaf_bit` | the light id. Otherwise the index of the group of its
    /// children.
    std::uint32_t child_or_light[lanes];

    RESTIR_HOST_DEVICE constexpr bool is_leaf(std::uint32_t lane) const noexcept {
        return (child_or_light[lane] & LightBvhNode::leaf_bit) != 0u;
    }
    /// Lane `lane` from the fields of `node` (its `child_or_light` included).
    void set(std::uint32_t lane, const LightBvhNode& node) noexcept {
        centre_x[lane] = node.centre.x;
        centre_y[lane] = node.centre.y;
        centre_z[lane] = node.centre.z;
        radius[lane] = node.radius;
        axis_x[lane] = node.axis.x;
        axis_y[lane] = node.axis.y;
        axis_z[lane] = node.axis.z;
        cos_theta_o[lane] = node.cos_theta_o;
        sin_theta_o[lane] = node.sin_theta_o;
        cos_theta_e[lane] = node.cos_theta_e;
        power[lane] = node.power;
        child_or_light[lane] = node.child_or_light;
    }
    /// Lane `lane` as a node (what `set` stored).
    RESTIR_HOST_DEVICE LightBvhNode node(std::uint32_t lane) const noexcept {
        LightBvhNode n;
        n.centre = glm::vec3(centre_x[lane], centre_y[lane], centre_z[lane]);
        n.radius = radius[lane];
        n.axis = glm::vec3(axis_x[lane], axis_y[lane], axis_z[lane]);
        n.cos_theta_o = cos_theta_o[lane];
        n.sin_theta_o = sin_theta_o[lane];
        n.cos_theta_e = cos_theta_e[lane];
        n.power = power[lane];
        n.child_or_light = child_or_light[lane];
        return n;
    }
    /// The importance bounds of the four children at `at` (`light_importance` of each), and
    /// their sum.
    RESTIR_HOST_DEVICE float importance(const ShadingPoint& at, float (&out)[lanes]) const;
};

static_assert(std::is_trivially_copyable_v<LightBvhGroup>);
static_assert(sizeof(LightBvhGroup) == 192u);

RESTIR_HOST_DEVICE inline float LightBvhGroup::importance(const ShadingPoint& at,
                                                          float (&out)[lanes]) const {
    // The fields spelled out rather than light_importance(node(c), at): that spelling
    // vectorised less reliably and made batch draws slower (docs/performance.md, "Measured and
    // rejected"). This loop is a draw's inner cost; check BM_LightBvh_SampleBatch after any
    // change here.
    for (std::uint32_t c = 0u; c < lanes; ++c)
        out[c] =
            detail::importance_bound(glm::vec3(centre_x[c], centre_y[c], centre_z[c]), radius[c],
                                     glm::vec3(axis_x[c], axis_y[c], axis_z[c]), cos_theta_o[c],
                                     sin_theta_o[c], cos_theta_e[c], power[c], at);
    float total = 0.0f;
    for (std::uint32_t c = 0u; c < lanes; ++c)
        total += out[c];
    return total;
}

/// The flat tree as a `ContextLightSampler` (concepts.hpp). A view: the `LightBvh` it came
/// from must outlive it (copy its arrays to the device for a kernel).
struct LightBvhView {
    /// Children per interior node. Four rather than two halve the dependent levels of a draw,
    /// and each choice weighs tighter bounds: the pmf follows the lights more closely (RIS with
    /// it had 3.5 times less error per candidate on the many-lights scene; docs/performance.md).
    static constexpr std::uint32_t arity = LightBvhGroup::lanes;

    /// Group 0 holds the root's children (for one light: the light and three unused lanes).
    const LightBvhGroup* groups = nullptr;
    /// Per light: the path from the root, bits [2k, 2k + 2) the lane taken in the k-th group
    /// of the descent, and the number of groups passed in the top `depth_shift` bits.
    const std::uint64_t* paths = nullptr;
    std::uint32_t count = 0u; ///< Lights.

    static constexpr std::uint32_t depth_shift = 58u;
    /// `u0` steers the first `levels_per_number` levels, `u1` the deeper ones: each level
    /// spends about two bits of its number.
    static constexpr std::uint32_t levels_per_number = 6u;

    RESTIR_HOST_DEVICE constexpr std::uint32_t light_count() const noexcept { return count; }

    /// One light for `at`, by a descent that takes each child with probability proportional to
    /// its `light_importance`; pmf 0 when no light can light `at`.
    RESTIR_HOST_DEVICE DiscreteSample sample(const ShadingPoint& at, float u0, float u1) const {
        if (count == 0u)
            return {};
        Descent descent{u0, u1};
        while (!descent.done)
            step(at, descent);
        return descent.result;
    }

    /// `Count` draws for one shading point at once: draw k is `sample(at, u0[k], u1[k])`,
    /// exactly. The descents advance a level at a time side by side, so that a CPU overlaps
    /// their chains of dependent levels (and their cache misses) instead of waiting on each in
    /// turn (the chains, not the arithmetic, bound a single draw). In device code its loops over
    /// the draws unroll, so the descents stay in registers.
    template <std::uint32_t Count>
    RESTIR_HOST_DEVICE void sample(const ShadingPoint& at, const float (&u0)[Count],
                                   const float (&u1)[Count], DiscreteSample (&out)[Count]) const {
        Descent descents[Count];
        RESTIR_UNROLL
        for (std::uint32_t k = 0u; k < Count; ++k)
            descents[k] = Descent{u0[k], u1[k], count == 0u};
        for (bool active = count > 0u; active;) {
            active = false;
            RESTIR_UNROLL
            for (std::uint32_t k = 0u; k < Count; ++k) {
                if (!descents[k].done)
                    step(at, descents[k]);
                active = active || !descents[k].done;
            }
        }
        RESTIR_UNROLL
        for (std::uint32_t k = 0u; k < Count; ++k)
            out[k] = descents[k].result;
    }

    /// The probability that `sample(at, ...)` returns light `id`: the same descent along the
    /// light's path.
    RESTIR_HOST_DEVICE float pmf(const ShadingPoint& at, std::uint32_t id) const {
        if (id >= count)
            return 0.0f;
        const std::uint64_t path = paths[id];
        const auto depth = static_cast<std::uint32_t>(path >> depth_shift);
        std::uint32_t group = 0u;
        float pmf = 1.0f;
        for (std::uint32_t level = 0u; level < depth; ++level) {
            const LightBvhGroup& g = groups[group];
            float importance[arity];
            const float total = g.importance(at, importance);
            if (!(total > 0.0f))
                return 0.0f;
            const auto child = static_cast<std::uint32_t>(path >> (2u * level) & 3u);
            float chosen = 0.0f;
            for (std::uint32_t c = 0u; c < arity; ++c)
                chosen = c == child ? importance[c] : chosen;
            pmf *= chosen / total;
            group = g.child_or_light[child];
        }
        return pmf;
    }

private:
    // A draw under way: the group it is at, its depth, its pmf so far and its numbers.
    struct Descent {
        float u = 0.0f;
        float u_deep = 0.0f; // steers the levels from `levels_per_number` on
        bool done = false;
        std::uint32_t group = 0u;
        std::uint32_t depth = 0u;
        float pmf = 1.0f;
        DiscreteSample result{};
    };

    // One level of a draw: weighs the children of its group and takes one, in proportion to
    // their importance; ends the draw at a leaf, or where no child can light `at`.
    RESTIR_HOST_DEVICE void step(const ShadingPoint& at, Descent& d) const {
        if (d.depth == levels_per_number)
            d.u = d.u_deep;
        const LightBvhGroup& g = groups[d.group];
        prefetch_children(g);
        float importance[arity];
        const float total = g.importance(at, importance);
        if (!(total > 0.0f)) { // no child can light `at`
            d.done = true;
            return;
        }
        // The child whose interval of the cumulative importance holds u total: the number of
        // inclusive prefix sums at or below it, never past the last child of importance > 0
        // (children of importance 0 have empty intervals). Its interval's start and its
        // importance are gathered without branches: which child wins is random.
        const float x = d.u * total;
        float prefix[arity];
        float running = 0.0f;
        for (std::uint32_t c = 0u; c < arity; ++c) {
            running += importance[c];
            prefix[c] = running;
        }
        std::uint32_t child = 0u, last_positive = 0u;
        for (std::uint32_t c = 0u; c < arity; ++c) {
            child += c + 1u < arity && prefix[c] <= x ? 1u : 0u;
            last_positive = importance[c] > 0.0f ? c : last_positive;
        }
        child = min_of(child, last_positive);
#if defined(__CUDA_ARCH__)
        float start = 0.0f, chosen = 0.0f;
        for (std::uint32_t c = 0u; c < arity; ++c) {
            start = select_float(c == child, c == 0u ? 0.0f : prefix[c - 1u], start);
            chosen = select_float(c == child, importance[c], chosen);
        }
#else
        // On a CPU, loads at a runtime index (compilers turn the masks into branches).
        float before_child[arity];
        for (std::uint32_t c = 0u; c < arity; ++c)
            before_child[c] = c == 0u ? 0.0f : prefix[c - 1u];
        const float start = before_child[child];
        const float chosen = importance[child];
#endif
        d.pmf *= chosen / total;
        if (g.is_leaf(child)) {
            d.done = true;
            d.result = {g.child_or_light[child] & ~LightBvhNode::leaf_bit, d.pmf};
            return;
        }
        d.group = g.child_or_light[child];
        d.u = min_of(max_of((x - start) / chosen, 0.0f), 0x1.fffffep-1f);
        ++d.depth;
    }

    // On the host, asks for the groups of every interior child while the children are being
    // weighed: at a million lights the groups below the top levels are not in cache, and the
    // loads would otherwise wait for the choice.
    RESTIR_HOST_DEVICE void prefetch_children(const LightBvhGroup& g) const {
#if !defined(__CUDA_ARCH__)
        for (std::uint32_t c = 0u; c < arity; ++c) {
            if (!g.is_leaf(c)) {
                const char* child = reinterpret_cast<const char*>(&groups[g.child_or_light[c]]);
                for (std::uint32_t line = 0u; line < sizeof(LightBvhGroup); line += 64u)
                    RESTIR_PREFETCH(child + line);
            }
        }
#else
        (void)g;
#endif
    }
};

} // namespace restir
