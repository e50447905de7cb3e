/// @file light/light_bvh_view.hpp
/// A bounding volume hierarchy over lights for spatially aware light selection (Conty Estevez
/// and Kulla 2018, "Importance Sampling of Many Lights with Adaptive Tree Splitting"), as device
/// code reads it: flat nodes, sampled by `LightBvhView`. Every node bounds its lights'
/// positions (a box, kept as its centre and half diagonal), their emitted power, and the
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

/// One node of the flat tree: 48 bytes.
struct LightBvhNode {
    glm::vec3 centre{0.0f};
    float radius = 0.0f; ///< Half the diagonal of the box.
    glm::vec3 axis{0.0f, 0.0f, 1.0f};
    float cos_theta_o = 1.0f;
    float cos_theta_e = 0.0f;
    float power = 0.0f;
    float sin_theta_o = 0.0f;
    /// A leaf: `leaf_bit` | the light id. Otherwise the index of the first of its
    /// `LightBvhView::arity` children (the others follow it; unused ones have no power).
    std::uint32_t child_or_light = 0u;

    static constexpr std::uint32_t leaf_bit = 0x80000000u;
    RESTIR_HOST_DEVICE constexpr bool is_leaf() const noexcept {
        return (child_or_light & leaf_bit) != 0u;
    }
};

static_assert(std::is_trivially_copyable_v<LightBvhNode>);
static_assert(sizeof(LightBvhNode) == 48u);

namespace detail {
// cos(max(0, a - b)) and sin(max(0, a - b)) from the sines and cosines of a, b in [0, pi].
RESTIR_HOST_DEVICE inline float cos_difference_clamped(float sin_a, float cos_a, float sin_b,
                                                       float cos_b) noexcept {
    return cos_a > cos_b ? 1.0f : cos_a * cos_b + sin_a * sin_b;
}
RESTIR_HOST_DEVICE inline float sin_difference_clamped(float sin_a, float cos_a, float sin_b,
                                                       float cos_b) noexcept {
    return cos_a > cos_b ? 0.0f : sin_a * cos_b - cos_a * sin_b;
}
RESTIR_HOST_DEVICE inline float sine_of(float cosine) noexcept {
    return std::sqrt(max_of(0.0f, 1.0f - cosine * cosine));
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
    // Selects rather than branches throughout: the outcomes vary from node to node.
    // For a region (at.radius > 0) the node's sphere grows by the region's radius: every
    // direction from a point of the region to a point of the node lies within theta_b of the
    // direction between their centres.
    const float radius = node.radius + max_of(at.radius, 0.0f);
    const glm::vec3 from_centre = at.position - node.centre;
    const float distance_squared = glm::dot(from_centre, from_centre);
    const float radius_squared = radius * radius;
    const float inverse_distance =
        distance_squared > 0.0f ? 1.0f / std::sqrt(distance_squared) : 0.0f;
    const glm::vec3 direction = from_centre * inverse_distance;
    const bool inside = distance_squared <= radius_squared;
    const float sphere_sine = min_of(radius * inverse_distance, 1.0f);
    const float sin_b = inside ? 0.0f : sphere_sine;
    const float cos_b = inside ? -1.0f : detail::sine_of(sphere_sine);
    const float cos_w = glm::dot(node.axis, direction);
    const float sin_w = detail::sine_of(cos_w);
    const float cos_x =
        detail::cos_difference_clamped(sin_w, cos_w, node.sin_theta_o, node.cos_theta_o);
    const float sin_x =
        detail::sin_difference_clamped(sin_w, cos_w, node.sin_theta_o, node.cos_theta_o);
    const float cos_emitted = detail::cos_difference_clamped(sin_x, cos_x, sin_b, cos_b);
    float importance = cos_emitted > node.cos_theta_e
                           ? node.power * cos_emitted / max_of(distance_squared, radius_squared)
                           : 0.0f;
    const bool has_normal = at.normal.x != 0.0f || at.normal.y != 0.0f || at.normal.z != 0.0f;
    if (has_normal) {
        const float cos_i = -glm::dot(at.normal, direction);
        const float cos_received =
            detail::cos_difference_clamped(detail::sine_of(cos_i), cos_i, sin_b, cos_b);
        importance *= max_of(cos_received, 0.0f);
    }
    return is_valid_weight(importance) ? importance : 0.0f;
}

/// The flat tree as a `ContextLightSampler` (concepts.hpp). A view: the `LightBvh` it came
/// from must outlive it (copy its arrays to the device for a kernel).
struct LightBvhView {
    /// Children per interior node. Four rather than two halve the dependent levels of a draw,
    /// and each choice weighs tighter bounds: the pmf follows the lights more closely (RIS with
    /// it had 3.5 times less error per candidate on the many-lights scene; docs/performance.md).
    static constexpr std::uint32_t arity = 4u;

    const LightBvhNode* nodes = nullptr;
    /// Per light: the path from the root, bits [2k, 2k + 2) the child taken at depth k, and
    /// the depth in the top `depth_shift` bits.
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
        std::uint32_t node = 0u;
        float pmf = 1.0f;
        float u = u0;
        for (std::uint32_t depth = 0u; !nodes[node].is_leaf(); ++depth) {
            if (depth == levels_per_number)
                u = u1;
            prefetch_grandchildren(nodes[node]);
            const std::uint32_t first = nodes[node].child_or_light;
            float importance[arity];
            const float total = children_importance(first, at, importance);
            if (!(total > 0.0f)) // no child can light `at`
                return {};
            // The child whose interval of the cumulative importance holds u total, by counting
            // (selects, not branches: which child wins is random); never one of importance 0.
            const float x = u * total;
            float before = 0.0f, start = 0.0f, chosen = 0.0f;
            std::uint32_t child = 0u, last_positive = 0u;
            for (std::uint32_t c = 0u; c < arity; ++c) {
                const float after = before + importance[c];
                const bool passed = c + 1u < arity && after <= x;
                child += passed ? 1u : 0u;
                last_positive = importance[c] > 0.0f ? c : last_positive;
                before = after;
            }
            child = min_of(child, last_positive);
            before = 0.0f;
            for (std::uint32_t c = 0u; c < arity; ++c) {
                start = c == child ? before : start;
                chosen = c == child ? importance[c] : chosen;
                before += importance[c];
            }
            pmf *= chosen / total;
            node = first + child;
            u = min_of(max_of((x - start) / chosen, 0.0f), 0x1.fffffep-1f);
        }
        if (count == 1u && !(light_importance(nodes[0], at) > 0.0f))
            return {};
        return {nodes[node].child_or_light & ~LightBvhNode::leaf_bit, pmf};
    }

    /// The probability that `sample(at, ...)` returns light `id`: the same descent along the
    /// light's path.
    RESTIR_HOST_DEVICE float pmf(const ShadingPoint& at, std::uint32_t id) const {
        if (id >= count)
            return 0.0f;
        if (count == 1u)
            return light_importance(nodes[0], at) > 0.0f ? 1.0f : 0.0f;
        const std::uint64_t path = paths[id];
        const auto depth = static_cast<std::uint32_t>(path >> depth_shift);
        std::uint32_t node = 0u;
        float pmf = 1.0f;
        for (std::uint32_t level = 0u; level < depth; ++level) {
            const std::uint32_t first = nodes[node].child_or_light;
            float importance[arity];
            const float total = children_importance(first, at, importance);
            if (!(total > 0.0f))
                return 0.0f;
            const auto child = static_cast<std::uint32_t>(path >> (2u * level) & 3u);
            float chosen = 0.0f;
            for (std::uint32_t c = 0u; c < arity; ++c)
                chosen = c == child ? importance[c] : chosen;
            pmf *= chosen / total;
            node = first + child;
        }
        return pmf;
    }

private:
    // On the host, asks for the children of every interior child while their parent's children
    // are being weighed: at a million lights the nodes below the top levels are not in cache,
    // and the loads would otherwise wait for the choice. (A group of four is 192 bytes.)
    RESTIR_HOST_DEVICE void prefetch_grandchildren(const LightBvhNode& parent) const {
#if (defined(__GNUC__) || defined(__clang__)) && !defined(__CUDA_ARCH__)
        for (std::uint32_t c = 0u; c < arity; ++c) {
            const LightBvhNode& child = nodes[parent.child_or_light + c];
            if (!child.is_leaf()) {
                const char* group = reinterpret_cast<const char*>(&nodes[child.child_or_light]);
                for (std::uint32_t line = 0u; line < arity * sizeof(LightBvhNode); line += 64u)
                    __builtin_prefetch(group + line);
            }
        }
#else
        (void)parent;
#endif
    }

    // The importance of the children of an interior node whose first child is `first`, and
    // their sum.
    RESTIR_HOST_DEVICE float children_importance(std::uint32_t first, const ShadingPoint& at,
                                                 float (&importance)[arity]) const {
        float total = 0.0f;
        for (std::uint32_t c = 0u; c < arity; ++c) {
            importance[c] = light_importance(nodes[first + c], at);
            total += importance[c];
        }
        return total;
    }
};

} // namespace restir
