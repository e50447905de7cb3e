/// @file light/light_bvh.hpp
/// The host builder of the light BVH (light/light_bvh_view.hpp): the emission bounds of each
/// light, their merge, the tree built over a list of them by an orientation-aware cost, and
/// the quantisation of its groups.
#pragma once

#include "restir/light/light_bounds.hpp"
#include "restir/light/light_bvh_encode.hpp"
#include "restir/light/light_bvh_split.hpp"
#include "restir/light/light_bvh_view.hpp"

#include <glm/common.hpp>
#include <glm/geometric.hpp>
#include <glm/vec3.hpp>

#include <algorithm>
#include <array>
#include <cmath>
#include <cstdint>
#include <limits>
#include <span>
#include <stdexcept>
#include <vector>

namespace restir {

/// The host-built tree over a list of lights (light id = index in the list), with
/// `LightBvhView::arity` (8) children per interior node. Each node's lights are split in two
/// by the orientation-aware surface area heuristic (SAOH, Conty Estevez and Kulla 2018: power x
/// M_Omega(cone) x surface area x a factor against splitting a long box across its short side,
/// least over 12 buckets of the lights' box on each axis, or over every position for at most
/// 16 lights; a side's cone is estimated from the box of its lights' axes), and each half again
/// the same way for three levels, which gives the node's eight children. A node of at most
/// eight lights gets one leaf each; unused children have no power. Each split moves a few
/// lights across it so that all the children of a node but one hold 1 (mod 7) lights: such a
/// child's subtree fills every lane of its groups. Where the cost could make a path longer
/// than `LightBvhView::max_depth` groups, the splits are at the median centres instead. The
/// groups are quantised from the root down, each child's box on the grid of its parent's
/// quantised box. Throws std::invalid_argument for more than 2^31 lights or a light with a negative
/// or non-finite power, or a non-finite position or one beyond +-2^64 (where squared distances
/// overflow a float). The view draws with `default_near_length(lights)` as its near-field
/// length, or the one given (0: the importance bounds of the paper).
class LightBvh : private detail::LightBvhSplits {
public:
    /// How many median light half diagonals the near-field length is by default.
    static constexpr float near_length_per_light_radius = 16.0f;

    /// The default near-field length (`LightBvhView::near_length`) of a tree over `lights`:
    /// `near_length_per_light_radius` times the median of their boxes' half diagonals (0 where
    /// most lights are points, such as VPLs). Chosen by the relative variance of one BVH
    /// candidate over the pixels of the many-light scene at 1k, 100k and 1M lights
    /// (docs/noise-and-bias.md, "Heavy tails"): 8 to 16 were best at every count.
    static float default_near_length(std::span<const LightBounds> lights) {
        if (lights.empty())
            return 0.0f;
        std::vector<float> radii(lights.size());
        for (std::size_t i = 0; i < lights.size(); ++i)
            radii[i] = lights[i].lower.x <= lights[i].upper.x
                           ? 0.5f * glm::length(lights[i].upper - lights[i].lower)
                           : 0.0f;
        const auto middle = radii.begin() + static_cast<std::ptrdiff_t>(radii.size() / 2u);
        std::nth_element(radii.begin(), middle, radii.end());
        const float length = near_length_per_light_radius * *middle;
        return std::isfinite(length) ? length : 0.0f;
    }

    explicit LightBvh(std::span<const LightBounds> lights)
        : LightBvh(lights, default_near_length(lights)) {}

    /// A tree over `lights` whose view draws with near-field length `near_length` (>= 0,
    /// finite; 0: the paper's bounds).
    LightBvh(std::span<const LightBounds> lights, float near_length) : near_length_(near_length) {
        if (!(near_length >= 0.0f && near_length < std::numeric_limits<float>::infinity()))
            throw std::invalid_argument("LightBvh: the near-field length must be finite and >= 0");
        if (lights.size() >= LightBvhNode::leaf_bit)
            throw std::invalid_argument("LightBvh: more than 2^31 lights");
        for (const LightBounds& l : lights)
            if (!(l.power >= 0.0f && l.power < std::numeric_limits<float>::infinity()) ||
                !is_usable_box(l))
                throw std::invalid_argument("LightBvh: a light with a negative or non-finite "
                                            "power or position");
        paths_.assign(lights.size(), 0u);
        if (lights.empty())
            return;
        groups_.reserve(lights.size() / (LightBvhView::arity - 1u) + 1u);
        groups_.resize(1u);
        std::vector<Item> items(lights.size());
        for (std::uint32_t id = 0u; id < items.size(); ++id)
            items[id] = Item(lights[id], id);
        const Part all = part_of(items, 0u, items.size());
        root_box(all.bounds.lower(), all.bounds.upper());
        build(items, all, 0u, 0u, 0u, LightBvhGrid::over(root_lower_, root_upper_));
    }

    LightBvhView view() const noexcept {
        return {groups_.data(), paths_.data(), static_cast<std::uint32_t>(paths_.size()),
                root_lower_,    root_upper_,   near_length_};
    }
    const std::vector<LightBvhGroup>& groups() const noexcept { return groups_; }
    const std::vector<std::uint64_t>& paths() const noexcept { return paths_; }

private:
    // The root's box: the lights' box grown until both corners are multiples of the step of
    // its own grid (which may grow with it), so that every corner below is exact.
    void root_box(glm::vec3 lower, glm::vec3 upper) {
        for (int a = 0; a < 3; ++a) {
            float low = lower[a], high = upper[a];
            for (;;) {
                const float step = detail::grid_step(low, high);
                const float snapped_low = std::floor(low / step) * step;
                const float snapped_high = std::ceil(high / step) * step;
                if (snapped_low == low && snapped_high == high)
                    break;
                low = snapped_low;
                high = snapped_high;
            }
            root_lower_[a] = low;
            root_upper_[a] = high;
        }
    }

    // Fills group `index` with the children of `node`, a node `depth` groups below the root
    // reached by `path` whose children's boxes are stored on `grid`; returns the node's exact
    // bounds.
    Exact build(std::vector<Item>& items, const Part& node, std::uint32_t index,
                std::uint32_t depth, std::uint64_t path, const LightBvhGrid& grid) {
        constexpr std::uint32_t arity = LightBvhView::arity;
        Part parts[arity];
        const std::uint32_t part_count = split_node(items, node, depth, parts);
        Exact bounds;
        for (std::uint32_t c = 0u; c < arity; ++c) {
            groups_[index].child_or_light[c] = LightBvhNode::leaf_bit; // unused: no power
            if (c >= part_count)
                continue; // a new group's codes are all 0: no power
            const Part& part = parts[c];
            detail::LaneEncoder::box(groups_[index], c, grid, part.bounds.lower(),
                                     part.bounds.upper());
            const std::uint64_t child_path =
                path | (std::uint64_t{c} << (LightBvhGroup::lane_bits * depth));
            Exact below;
            if (part.size() == 1u) {
                const Item& light = items[part.begin];
                below = Exact::of(light);
                groups_[index].child_or_light[c] = LightBvhNode::leaf_bit | light.id;
                paths_[light.id] =
                    child_path | (std::uint64_t{depth + 1u} << LightBvhView::depth_shift);
            } else {
                // The group right before its subtree: a descent reads forward in memory.
                const auto group = static_cast<std::uint32_t>(groups_.size());
                groups_[index].child_or_light[c] = group;
                const LightBvhGrid child_grid = groups_[index].child_grid(c, grid);
                groups_.emplace_back();
                below = build(items, part, group, depth + 1u, child_path, child_grid);
            }
            // The cone's cosine and sine: a light's own, or from the merged angle.
            const double cos_o =
                part.size() == 1u ? static_cast<double>(items[part.begin].least[cos_theta_o_field])
                                  : std::cos(static_cast<double>(below.theta_o));
            const double sin_o = part.size() == 1u ? std::sqrt(std::max(1.0 - cos_o * cos_o, 0.0))
                                                   : std::sin(static_cast<double>(below.theta_o));
            detail::LaneEncoder::emission(groups_[index], c, below.axis, cos_o, sin_o,
                                          below.cos_theta_e, below.power);
            if (c == 0u)
                bounds = below;
            else
                bounds.add(below);
        }
        return bounds;
    }

    // The children of `node` (more than one light): one light each for up to `arity`, else
    // log2(arity) levels of binary splits, and more where a half was a single light early.
    // Returns the number of children.
    std::uint32_t split_node(std::vector<Item>& items, const Part& node, std::uint32_t depth,
                             Part (&parts)[LightBvhView::arity]) {
        constexpr std::uint32_t arity = LightBvhView::arity;
        if (node.size() <= arity) {
            for (std::size_t i = node.begin; i < node.end; ++i)
                parts[i - node.begin] = part_of(items, i, i + 1u);
            return static_cast<std::uint32_t>(node.size());
        }
        parts[0] = node;
        // The cost may isolate a few lights at each level; where that could overflow a path,
        // medians keep the remaining depth at log_arity of the lights.
        if (depth + 1u + levels_for(node.size()) > LightBvhView::max_depth) {
            for (std::uint32_t count = 1u; count < arity; count *= 2u)
                for (std::uint32_t k = count; k-- > 0u;) {
                    const Part whole = parts[k];
                    median_split(items, whole, whole.begin + whole.size() / 2u, parts[2u * k],
                                 parts[2u * k + 1u]);
                }
            return arity;
        }
        std::uint32_t count = 0u;
        divide(items, node, arity, parts, count);
        while (count < arity) {
            std::uint32_t largest = 0u;
            for (std::uint32_t k = 1u; k < count; ++k)
                largest = parts[k].size() > parts[largest].size() ? k : largest;
            for (std::uint32_t k = count; k > largest + 1u; --k)
                parts[k] = parts[k - 1u];
            const Part whole = parts[largest];
            split(items, whole, 1u, residue(whole.size() - 1u), parts[largest],
                  parts[largest + 1u]);
            ++count;
        }
        return count;
    }

    // Appends `whole` to `parts` as `portions` children (fewer for fewer lights), by binary
    // splits whose halves aim at portions / 2 (mod arity - 1) lights each, one of them carrying
    // the rest: every child but one then fills its groups.
    void divide(std::vector<Item>& items, const Part& whole, std::uint32_t portions,
                Part (&parts)[LightBvhView::arity], std::uint32_t& count) {
        if (portions == 1u || whole.size() == 1u) {
            parts[count++] = whole;
            return;
        }
        const std::uint32_t half = portions / 2u;
        Part below, above;
        split(items, whole, residue(half), residue(whole.size() - half), below, above);
        divide(items, below, half, parts, count);
        divide(items, above, half, parts, count);
    }

    std::vector<LightBvhGroup> groups_;
    std::vector<std::uint64_t> paths_;
    glm::vec3 root_lower_{0.0f}, root_upper_{0.0f};
    float near_length_ = 0.0f;
};

} // namespace restir
