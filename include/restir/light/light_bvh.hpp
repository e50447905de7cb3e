/// @file light/light_bvh.hpp
/// The host builder of the light BVH (light/light_bvh_view.hpp): the emission bounds of each
/// light, their merge, and the tree built over a list of them.
#pragma once

#include "restir/light/light_bvh_view.hpp"

#include <glm/common.hpp>
#include <glm/geometric.hpp>
#include <glm/vec3.hpp>

#include <algorithm>
#include <cmath>
#include <cstdint>
#include <limits>
#include <span>
#include <stdexcept>
#include <vector>

namespace restir {

/// Where a light (or a group of lights) emits: the box of its positions, its power, and the
/// cone of its emission: normals within theta_o of `axis`, light leaving up to theta_e beyond
/// a normal. A one-sided diffuse emitter or VPL: theta_o = 0, theta_e = pi / 2; an isotropic
/// point light: theta_o = pi, theta_e = pi / 2.
struct LightBounds {
    glm::vec3 lower{std::numeric_limits<float>::max()};
    glm::vec3 upper{-std::numeric_limits<float>::max()};
    float power = 0.0f; ///< Emitted flux summed over the channels (>= 0).
    glm::vec3 axis{0.0f, 0.0f, 1.0f};
    float cos_theta_o = 1.0f;
    float cos_theta_e = 0.0f;
};

/// A flat area light (an emitter triangle or quad) with corners spanning [lower, upper],
/// emitting on the side of the unit `normal`.
inline LightBounds area_light_bounds(glm::vec3 lower, glm::vec3 upper, glm::vec3 normal,
                                     float power) {
    return {lower, upper, power, normal, 1.0f, 0.0f};
}

/// A point light: a cosine emitter facing the unit `normal` (a VPL), or isotropic for a zero
/// normal.
inline LightBounds point_light_bounds(glm::vec3 position, glm::vec3 normal, float power) {
    const bool isotropic = normal.x == 0.0f && normal.y == 0.0f && normal.z == 0.0f;
    return {position,
            position,
            power,
            isotropic ? glm::vec3(0.0f, 0.0f, 1.0f) : normal,
            isotropic ? -1.0f : 1.0f,
            0.0f};
}

namespace detail {
// The cone (axis, half-angle) that holds cones a and b (Conty Estevez and Kulla 2018, Alg. 1).
inline void merge_cones(glm::vec3& axis, float& theta, glm::vec3 other_axis, float other_theta) {
    constexpr float pi_f = 3.14159265358979f;
    if (other_theta > theta) {
        std::swap(axis, other_axis);
        std::swap(theta, other_theta);
    }
    const float between = std::acos(std::clamp(glm::dot(axis, other_axis), -1.0f, 1.0f));
    if (std::min(between + other_theta, pi_f) <= theta)
        return;
    const float merged = 0.5f * (theta + between + other_theta);
    const glm::vec3 normal = glm::cross(axis, other_axis);
    const float normal_length = glm::length(normal);
    if (merged >= pi_f || !(normal_length > 1e-7f)) {
        theta = pi_f;
        return;
    }
    // Rotate `axis` towards `other_axis` by merged - theta (Rodrigues, the rotation axis
    // perpendicular to `axis`).
    const float turn = merged - theta;
    const glm::vec3 k = normal / normal_length;
    axis = glm::normalize(axis * std::cos(turn) + glm::cross(k, axis) * std::sin(turn));
    theta = merged;
}
} // namespace detail

/// The bounds of two groups of lights together.
inline LightBounds merge_light_bounds(const LightBounds& a, const LightBounds& b) {
    if (!(a.power > 0.0f) && a.lower.x > a.upper.x)
        return b;
    if (!(b.power > 0.0f) && b.lower.x > b.upper.x)
        return a;
    LightBounds merged;
    merged.lower = glm::min(a.lower, b.lower);
    merged.upper = glm::max(a.upper, b.upper);
    merged.power = a.power + b.power;
    glm::vec3 axis = a.axis;
    float theta = std::acos(std::clamp(a.cos_theta_o, -1.0f, 1.0f));
    detail::merge_cones(axis, theta, b.axis, std::acos(std::clamp(b.cos_theta_o, -1.0f, 1.0f)));
    merged.axis = axis;
    merged.cos_theta_o = std::cos(theta);
    merged.cos_theta_e = std::min(a.cos_theta_e, b.cos_theta_e);
    return merged;
}

/// The node of a group of lights with bounds `b` (a leaf's, for one light): what
/// `light_importance` weighs.
inline LightBvhNode light_bvh_node(const LightBounds& b) {
    LightBvhNode node;
    node.centre = 0.5f * (b.lower + b.upper);
    node.radius = 0.5f * glm::length(b.upper - b.lower);
    node.axis = b.axis;
    node.cos_theta_o = b.cos_theta_o;
    node.sin_theta_o = detail::sine_of(b.cos_theta_o);
    node.cos_theta_e = b.cos_theta_e;
    node.power = b.power;
    return node;
}

/// The host-built tree over a list of lights (light id = index in the list), with
/// `LightBvhView::arity` (4) children per interior node: a node's lights are split at the median
/// of their centres along their widest axis, and each half again along its own, so that the
/// four quarters hold n / 4 lights each (a node of at most four lights gets one leaf each; unused
/// children have no power). Depth about log4 n. Throws std::invalid_argument for more than 2^31
/// lights or a light with a negative or non-finite power or position.
class LightBvh {
public:
    explicit LightBvh(std::span<const LightBounds> lights) : lights_(lights) {
        if (lights.size() >= LightBvhNode::leaf_bit)
            throw std::invalid_argument("LightBvh: more than 2^31 lights");
        for (const LightBounds& l : lights)
            if (!(l.power >= 0.0f && l.power < std::numeric_limits<float>::infinity()) ||
                !is_finite_box(l))
                throw std::invalid_argument("LightBvh: a light with a negative or non-finite "
                                            "power or position");
        paths_.assign(lights.size(), 0u);
        if (lights.empty())
            return;
        groups_.reserve(lights.size() / (LightBvhView::arity - 1u) + 1u);
        groups_.resize(1u);
        std::vector<Item> order(lights.size());
        for (std::uint32_t id = 0u; id < order.size(); ++id)
            order[id] = {0.5f * (lights[id].lower + lights[id].upper), id};
        build(order, 0u, order.size(), 0u, 0u, 0u);
        lights_ = {};
    }

    LightBvhView view() const noexcept {
        return {groups_.data(), paths_.data(), static_cast<std::uint32_t>(paths_.size())};
    }
    const std::vector<LightBvhGroup>& groups() const noexcept { return groups_; }
    const std::vector<std::uint64_t>& paths() const noexcept { return paths_; }

private:
    // A light while building: its centre beside its id, so that the splits read one array in
    // order rather than the lights by id.
    struct Item {
        glm::vec3 centre;
        std::uint32_t id;
    };

    static bool is_finite_box(const LightBounds& l) {
        for (int axis = 0; axis < 3; ++axis)
            if (!std::isfinite(l.lower[axis]) || !std::isfinite(l.upper[axis]) ||
                l.lower[axis] > l.upper[axis])
                return false;
        return true;
    }

    // Fills group `index` with the children of the node over order[begin, end), a node `depth`
    // groups below the root reached by `path`, and returns the node's bounds.
    LightBounds build(std::vector<Item>& order, std::size_t begin, std::size_t end,
                      std::uint32_t index, std::uint32_t depth, std::uint64_t path) {
        // The children's ranges: one light each for up to four, else the quarters.
        constexpr std::uint32_t arity = LightBvhView::arity;
        if (end - begin <= 64u)
            prefetch_lights(order, begin, end);
        std::size_t bounds_of_part[arity + 1u] = {begin, begin, begin, begin, end};
        if (end - begin <= arity) {
            for (std::uint32_t c = 0u; c <= arity; ++c)
                bounds_of_part[c] = std::min(begin + c, end);
        } else {
            const std::size_t middle = split(order, begin, end);
            bounds_of_part[1] = split(order, begin, middle);
            bounds_of_part[2] = middle;
            bounds_of_part[3] = split(order, middle, end);
        }
        LightBounds bounds; // empty
        for (std::uint32_t c = 0u; c < arity; ++c) {
            const std::size_t first = bounds_of_part[c], last = bounds_of_part[c + 1u];
            LightBvhNode child; // an unused lane: a leaf without power, which no draw takes
            child.child_or_light = LightBvhNode::leaf_bit;
            const std::uint64_t child_path = path | (std::uint64_t{c} << (2u * depth));
            if (last - first == 1u) {
                const std::uint32_t id = order[first].id;
                child = light_bvh_node(lights_[id]);
                child.child_or_light = LightBvhNode::leaf_bit | id;
                paths_[id] = child_path | (std::uint64_t{depth + 1u} << LightBvhView::depth_shift);
                bounds = merge_light_bounds(bounds, lights_[id]);
            } else if (last - first > 1u) {
                // The group right before its subtree: a descent reads forward in memory.
                const auto group = static_cast<std::uint32_t>(groups_.size());
                groups_.emplace_back();
                const LightBounds below = build(order, first, last, group, depth + 1u, child_path);
                child = light_bvh_node(below);
                child.child_or_light = group;
                bounds = merge_light_bounds(bounds, below);
            }
            groups_[index].set(c, child);
        }
        return bounds;
    }

    // Asks for the bounds of the lights of order[begin, end) at once: the leaves below read
    // them by id, in an order that misses the caches at a million lights.
    void prefetch_lights(const std::vector<Item>& order, std::size_t begin, std::size_t end) const {
#if defined(__GNUC__) || defined(__clang__)
        for (std::size_t i = begin; i < end; ++i)
            __builtin_prefetch(&lights_[order[i].id]);
#else
        (void)order, (void)begin, (void)end;
#endif
    }

    // Splits order[begin, end) (at least two lights) at the median of their centres along their
    // widest axis; returns the first index of the upper half.
    static std::size_t split(std::vector<Item>& order, std::size_t begin, std::size_t end) {
        glm::vec3 lo(std::numeric_limits<float>::max());
        glm::vec3 hi(-std::numeric_limits<float>::max());
        for (std::size_t i = begin; i < end; ++i) {
            lo = glm::min(lo, order[i].centre);
            hi = glm::max(hi, order[i].centre);
        }
        const glm::vec3 extent = hi - lo;
        const int axis = extent.x >= extent.y && extent.x >= extent.z ? 0
                         : extent.y >= extent.z                       ? 1
                                                                      : 2;
        const std::size_t middle = begin + (end - begin) / 2u;
        std::nth_element(
            order.begin() + static_cast<std::ptrdiff_t>(begin),
            order.begin() + static_cast<std::ptrdiff_t>(middle),
            order.begin() + static_cast<std::ptrdiff_t>(end),
            [axis](const Item& a, const Item& b) { return a.centre[axis] < b.centre[axis]; });
        return middle;
    }

    std::span<const LightBounds> lights_; // while building
    std::vector<LightBvhGroup> groups_;
    std::vector<std::uint64_t> paths_;
};

} // namespace restir
