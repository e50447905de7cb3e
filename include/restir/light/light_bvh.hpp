/// @file light/light_bvh.hpp
/// The host builder of the light BVH (light/light_bvh_view.hpp): the emission bounds of each
/// light, their merge, the tree built over a list of them by an orientation-aware cost, and
/// the quantisation of its groups.
#pragma once

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

// A loop marked RESTIR_VECTORIZE that a build does not vectorise (no optimisation, sanitizers)
// is only slower: no warning for it.
#if defined(__clang__)
#pragma clang diagnostic push
#pragma clang diagnostic ignored "-Wpass-failed"
#endif

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
    if (theta >= pi_f) // holds every direction already
        return;
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

namespace detail {
// The quantised fields of a group's lane: its box on `grid` and its emission bounds, every
// bound rounded outward (light/light_bvh_view.hpp decodes them).
struct LaneEncoder {
    // Extra cone angle beyond the measured rounding of the axis, for the float rounding of the
    // cone merges and of the decoding on another device (radians).
    static constexpr double cone_margin = 1e-5;

    // The box codes of [lower, upper] on `grid`: the largest corner at or below `lower` and the
    // smallest at or above `upper`, checked in the arithmetic the decoder uses (exact on the
    // grid). The box lies in the box `grid` was made over, whose corners are codes 0 and at
    // most 255.
    static void box(LightBvhGroup& g, std::uint32_t lane, const LightBvhGrid& grid, glm::vec3 lower,
                    glm::vec3 upper) {
        for (int a = 0; a < 3; ++a) {
            const double step = static_cast<double>(grid.step[a]);
            const double origin = static_cast<double>(grid.origin[a]);
            auto low = static_cast<std::uint32_t>(std::clamp(
                std::floor((static_cast<double>(lower[a]) - origin) / step), 0.0, 255.0));
            auto high = static_cast<std::uint32_t>(
                std::clamp(std::ceil((static_cast<double>(upper[a]) - origin) / step), 0.0, 255.0));
            while (low > 0u && grid.corner(a, low) > lower[a])
                --low;
            while (high < 255u && grid.corner(a, high) < upper[a])
                ++high;
            g.lower[a][lane] = static_cast<std::uint8_t>(low);
            g.upper[a][lane] = static_cast<std::uint8_t>(high);
        }
    }

    // The cone (unit `axis`, half-angle theta_o given by its cosine and sine), the emission
    // spread and the power. The axis takes the nearest octahedral codes; theta_o grows by the angle
    // the axis moved (plus `cone_margin`) and rounds up. No trigonometry: the angles add through
    // their cosines and sines.
    static void emission(LightBvhGroup& g, std::uint32_t lane, glm::vec3 axis, double cos_o,
                         double sin_o, float cos_theta_e, float power) {
        std::uint32_t u = 127u, v = 127u, cone = 255u;
        double cos_moved = 1.0, sin_moved = 0.0;
        if (cos_o > -1.0 && encode_axis(axis, u, v, cos_moved, sin_moved)) {
            static const double cos_margin = std::cos(cone_margin);
            static const double sin_margin = std::sin(cone_margin);
            const double cos_grow = cos_moved * cos_margin - sin_moved * sin_margin;
            const double sin_grow = sin_moved * cos_margin + cos_moved * sin_margin;
            // theta_o + grow < pi: grow < pi - theta_o.
            if (sin_grow >= 0.0 && cos_grow > -cos_o) {
                const double wanted_cos = cos_o * cos_grow - sin_o * sin_grow;
                const double half_sine = std::sqrt(std::max(0.5 * (1.0 - wanted_cos), 0.0));
                cone = static_cast<std::uint32_t>(
                    std::clamp(std::ceil(255.0 * std::sqrt(half_sine)), 0.0, 255.0));
                while (cone < 255u && static_cast<double>(cone_cos(cone)) > wanted_cos)
                    ++cone;
            }
        }
        g.axis_u[lane] = static_cast<std::uint8_t>(u);
        g.axis_v[lane] = static_cast<std::uint8_t>(v);
        g.cone[lane] = static_cast<std::uint8_t>(cone);
        const float cos_e = cos_theta_e >= -1.0f ? cos_theta_e : -1.0f; // NaN: any direction
        auto emission = static_cast<std::uint32_t>(
            std::clamp(std::floor(128.0f * cos_e + 128.0f), 0.0f, 255.0f));
        while (emission > 0u && emission_cos(emission) > cos_e)
            --emission;
        g.emission[lane] = static_cast<std::uint8_t>(emission);
        g.power[lane] = bfloat16_above(power);
    }

    // The bfloat16 at or above a power >= 0 (the largest finite one for more).
    static std::uint16_t bfloat16_above(float power) {
        std::uint32_t bits = float_bits(power);
        bits = (bits & 0xffffu) != 0u ? bits + 0x10000u : bits;
        return static_cast<std::uint16_t>(std::min(bits >> 16u, 0x7f7fu));
    }

    // The octahedral codes of `axis` (rounded to the nearest), and the cosine and sine of the
    // angle between it and the decoded axis; false for no axis (the cone becomes the sphere).
    static bool encode_axis(glm::vec3 axis, std::uint32_t& u, std::uint32_t& v, double& cos_moved,
                            double& sin_moved) {
        const double length = glm::length(glm::dvec3(axis));
        if (!(length > 0.0 && length < std::numeric_limits<double>::infinity()))
            return false;
        const glm::dvec3 n = glm::dvec3(axis) / length;
        const double l1 = std::abs(n.x) + std::abs(n.y) + std::abs(n.z);
        double x = n.x / l1, y = n.y / l1;
        if (n.z < 0.0) {
            const double folded_x = (1.0 - std::abs(y)) * (x >= 0.0 ? 1.0 : -1.0);
            y = (1.0 - std::abs(x)) * (y >= 0.0 ? 1.0 : -1.0);
            x = folded_x;
        }
        u = static_cast<std::uint32_t>(std::clamp(std::round(127.0 * x + 127.0), 0.0, 254.0));
        v = static_cast<std::uint32_t>(std::clamp(std::round(127.0 * y + 127.0), 0.0, 254.0));
        // The angle from the decoded axis as the draws read it, measured in double on the unit
        // axis along it (the float one is unit only to rounding, which would hide small angles).
        const glm::dvec3 decoded = glm::normalize(glm::dvec3(octahedral_axis(u, v)));
        cos_moved = glm::dot(decoded, n);
        sin_moved = glm::length(glm::cross(decoded, n));
        return true;
    }
};

// acos(x) for x in [-1, 1] (Abramowitz and Stegun 4.4.45, error below 7e-5) for the split
// cost, which only ranks splits: branch-free, so that a loop over candidates vectorises.
inline float fast_acos(float x) {
    const float a = std::min(std::abs(x), 1.0f);
    const float p = 1.5707288f + a * (-0.2121144f + a * (0.0742610f + a * -0.0187293f));
    const float magnitude = std::sqrt(1.0f - a) * p;
    return x < 0.0f ? 3.14159265358979f - magnitude : magnitude;
}
} // namespace detail

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
/// overflow a float).
class LightBvh {
public:
    explicit LightBvh(std::span<const LightBounds> lights) {
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
                root_lower_, root_upper_};
    }
    const std::vector<LightBvhGroup>& groups() const noexcept { return groups_; }
    const std::vector<std::uint64_t>& paths() const noexcept { return paths_; }

private:
    // The fields the bounds of lights merge by a minimum (maxima negated, so that merging is one
    // elementwise min): the box, the box of the cone axes, and the cosines of the widest cone
    // and of the widest emission spread.
    static constexpr std::size_t fields = 14u;
    static constexpr std::size_t lower_field = 0u;         // x, y, z
    static constexpr std::size_t negated_upper_field = 3u; // x, y, z
    static constexpr std::size_t axis_lower_field = 6u;    // x, y, z
    static constexpr std::size_t negated_axis_upper_field = 9u;
    static constexpr std::size_t cos_theta_o_field = 12u;
    static constexpr std::size_t cos_theta_e_field = 13u;

    // A light while building, one cache line: the splits read one array in order.
    struct Item {
        float least[fields];
        float power;
        std::uint32_t id;

        Item() = default;
        Item(const LightBounds& l, std::uint32_t light_id) : power(l.power), id(light_id) {
            for (std::size_t a = 0u; a < 3u; ++a) {
                const auto i = static_cast<glm::length_t>(a);
                least[lower_field + a] = l.lower[i];
                least[negated_upper_field + a] = -l.upper[i];
                least[axis_lower_field + a] = l.axis[i];
                least[negated_axis_upper_field + a] = -l.axis[i];
            }
            least[cos_theta_o_field] = std::clamp(l.cos_theta_o, -1.0f, 1.0f);
            least[cos_theta_e_field] = l.cos_theta_e;
        }
        float centre(int axis) const {
            const auto a = static_cast<std::size_t>(axis);
            return 0.5f * (least[lower_field + a] - least[negated_upper_field + a]);
        }
    };
    static_assert(sizeof(Item) == 64u);

    // The bounds of some lights (their `fields`, padded to a vector of 16), their power and
    // their count.
    struct Bounds {
        static constexpr std::size_t padded = 16u;
        float least[padded];
        float power;
        std::uint32_t count;

        // No lights (the default constructor leaves the fields unset: buckets are many).
        static Bounds empty() {
            Bounds b;
            for (float& f : b.least)
                f = std::numeric_limits<float>::max();
            b.power = 0.0f;
            b.count = 0u;
            return b;
        }
        void add(const Item& l) {
            float v[padded];
            for (std::size_t f = 0u; f < padded; ++f)
                v[f] = f < fields ? l.least[f] : std::numeric_limits<float>::max();
            for (std::size_t f = 0u; f < padded; ++f)
                least[f] = min_of(least[f], v[f]);
            power += l.power;
            ++count;
        }
        void add(const Bounds& b) {
            for (std::size_t f = 0u; f < padded; ++f)
                least[f] = min_of(least[f], b.least[f]);
            power += b.power;
            count += b.count;
        }
        glm::vec3 lower() const { return {least[0], least[1], least[2]}; }
        glm::vec3 upper() const { return {-least[3], -least[4], -least[5]}; }
    };

    // Lights [begin, end) of the build order and their bounds.
    struct Part {
        std::size_t begin = 0u, end = 0u;
        Bounds bounds;
        std::size_t size() const { return end - begin; }
    };

    // The exact bounds of a node, its cone kept as an angle (cones merge in angles).
    struct Exact {
        glm::vec3 lower{0.0f}, upper{0.0f};
        float power = 0.0f;
        glm::vec3 axis{0.0f, 0.0f, 1.0f};
        float theta_o = 0.0f;
        float cos_theta_e = 1.0f;

        static Exact of(const Item& l) {
            return {glm::vec3(l.least[0], l.least[1], l.least[2]),
                    glm::vec3(-l.least[3], -l.least[4], -l.least[5]),
                    l.power,
                    glm::vec3(l.least[6], l.least[7], l.least[8]),
                    angle_of(l.least[cos_theta_o_field]),
                    l.least[cos_theta_e_field]};
        }
        void add(const Exact& b) {
            lower = glm::min(lower, b.lower);
            upper = glm::max(upper, b.upper);
            power += b.power;
            detail::merge_cones(axis, theta_o, b.axis, b.theta_o);
            cos_theta_e = std::min(cos_theta_e, b.cos_theta_e);
        }
    };

    static constexpr std::uint32_t bucket_count = 12u;
    // Parts of at most this many lights are split by `split_few`, over every position.
    static constexpr std::uint32_t few = 16u;

    // acos, quick for the commonest cones (a one-sided emitter's and a point's).
    static float angle_of(float cosine) {
        return cosine >= 1.0f ? 0.0f : cosine <= -1.0f ? 3.14159265358979f : std::acos(cosine);
    }

    static bool is_usable_box(const LightBounds& l) {
        constexpr float limit = 0x1p64f;
        for (int axis = 0; axis < 3; ++axis)
            if (!(std::abs(l.lower[axis]) <= limit) || !(std::abs(l.upper[axis]) <= limit) ||
                l.lower[axis] > l.upper[axis])
                return false;
        return true;
    }

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

    // Lights (mod arity - 1): a subtree of g full groups holds (arity - 1) g + 1 lights.
    static std::uint32_t residue(std::size_t n) {
        return static_cast<std::uint32_t>(n % (LightBvhView::arity - 1u));
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

    // Groups below a node of `n` lights when every split is at the median: ceil(log_arity n).
    static std::uint32_t levels_for(std::size_t n) {
        std::uint32_t levels = 0u;
        for (std::size_t reach = 1u; reach < n; reach *= LightBvhView::arity)
            ++levels;
        return levels;
    }

    // Splits `whole` (at least two lights) in two, by the least SAOH cost over the bucket
    // boundaries of the three axes (buckets across the part's box), with `below` holding
    // `residue_a` or `residue_b` (`residue`) lights: lights of the buckets at the boundary
    // cross it to make the count so.
    static void split(std::vector<Item>& items, const Part& whole, std::uint32_t residue_a,
                      std::uint32_t residue_b, Part& below, Part& above) {
        if (whole.size() == 2u) { // nothing to choose
            below = part_of(items, whole.begin, whole.begin + 1u);
            above = part_of(items, whole.begin + 1u, whole.end);
            return;
        }
        if (whole.size() <= few) {
            split_few(items, whole, residue_a, residue_b, below, above);
            return;
        }
        const auto buckets =
            static_cast<std::uint32_t>(std::min<std::size_t>(whole.size(), bucket_count));
        Choice choice;
        best_split(items, whole, buckets, choice);
        if (choice.axis < 0) { // every centre the same: any halves of the wanted counts
            const std::size_t middle =
                whole.begin + nearest_count(whole.size() / 2u, whole.size(), residue_a, residue_b);
            below = part_of(items, whole.begin, middle);
            above = part_of(items, middle, whole.end);
            return;
        }
        const int axis = choice.axis;
        const auto bucket_at = [&](std::size_t i) {
            return bucket_of(items[i].centre(axis), choice.origin, choice.scale, buckets);
        };
        // Lomuto's partition without a branch (a split is random to a branch predictor):
        // [middle, i) stays above, so swapping light i in is right whichever side it is on.
        std::size_t middle = whole.begin;
        for (std::size_t i = whole.begin; i < whole.end; ++i) {
            const bool goes_below = bucket_at(i) <= choice.bucket;
            std::swap(items[i], items[middle]);
            middle += goes_below ? 1u : 0u;
        }
        below = {whole.begin, middle, choice.below};
        above = {middle, whole.end, choice.above};
        const std::size_t wanted =
            whole.begin + nearest_count(middle - whole.begin, whole.size(), residue_a, residue_b);
        // Lights of the buckets at the boundary cross it. A side that gains lights takes their
        // bounds; one that loses them keeps bounds that still hold it, made exact again below
        // `exact_below` lights (a large side hardly shrinks).
        constexpr std::size_t exact_below = 64u;
        while (below.end < wanted) {
            std::size_t crossing = below.end;
            while (crossing + 1u < whole.end && bucket_at(crossing) != choice.edges[1])
                ++crossing;
            std::swap(items[below.end], items[crossing]);
            below.bounds.add(items[below.end]);
            ++below.end;
            above.begin = below.end;
            if (below.end == wanted && above.size() < exact_below)
                above = part_of(items, above.begin, above.end);
        }
        while (below.end > wanted) {
            std::size_t crossing = below.end - 1u;
            while (crossing > whole.begin && bucket_at(crossing) != choice.edges[0])
                --crossing;
            std::swap(items[below.end - 1u], items[crossing]);
            --below.end;
            above.begin = below.end;
            above.bounds.add(items[above.begin]);
            if (below.end == wanted && below.size() < exact_below)
                below = part_of(items, below.begin, below.end);
        }
    }

    // `split` for at most `few` lights: the least SAOH cost over every position of the lights'
    // centres sorted along each axis whose count below is `residue_a` or `residue_b`
    // (`residue`).
    static void split_few(std::vector<Item>& items, const Part& whole, std::uint32_t residue_a,
                          std::uint32_t residue_b, Part& below, Part& above) {
        const auto n = static_cast<std::uint32_t>(whole.size());
        std::uint32_t order[3][few];
        Bounds before[3][few], after[3][few]; // [k]: the first k, the last n - k
        std::uint32_t counts[few], count_total = 0u;
        for (std::uint32_t k = 1u; k < n; ++k)
            if (residue(k) == residue_a || residue(k) == residue_b)
                counts[count_total++] = k;
        if (count_total == 0u)
            counts[count_total++] =
                static_cast<std::uint32_t>(nearest_count(n / 2u, n, residue_a, residue_b));
        const glm::vec3 extent = whole.bounds.upper() - whole.bounds.lower();
        const float longest = std::max(extent.x, std::max(extent.y, extent.z));
        Features features;
        std::uint32_t slot = 0u;
        for (int a = 0; a < 3; ++a) {
            // Sorted by centre through each light's rank (the lights before it, ties by index):
            // no branches, which a sort of so few would mispredict.
            std::uint32_t* sorted = order[a];
            float key[few];
            for (std::uint32_t i = 0u; i < few; ++i) // past n: behind every light
                key[i] = i < n ? items[whole.begin + i].centre(a)
                               : std::numeric_limits<float>::infinity();
            std::uint32_t rank[few] = {};
            for (std::uint32_t j = 0u; j < n; ++j) {
                const float other = key[j];
                for (std::uint32_t i = 0u; i < few; ++i)
                    rank[i] += static_cast<std::uint32_t>(other < key[i]) |
                               (static_cast<std::uint32_t>(other == key[i]) &
                                static_cast<std::uint32_t>(j < i));
            }
            for (std::uint32_t i = 0u; i < n; ++i)
                sorted[rank[i]] = i;
            Bounds running = Bounds::empty();
            for (std::uint32_t k = 1u; k < n; ++k) {
                running.add(items[whole.begin + sorted[k - 1u]]);
                before[a][k] = running;
            }
            running = Bounds::empty();
            for (std::uint32_t k = n - 1u; k >= 1u; --k) {
                running.add(items[whole.begin + sorted[k]]);
                after[a][k] = running;
            }
            const float thin = extent[a] > 0.0f ? longest / extent[a] : 1.0f;
            for (std::uint32_t c = 0u; c < count_total; ++c) {
                features.set(slot++, before[a][counts[c]], thin);
                features.set(slot++, after[a][counts[c]], thin);
            }
        }
        features.saoh_costs(slot);
        int axis = 0;
        std::uint32_t best = 0u;
        for (std::uint32_t k = 0u; k < slot; k += 2u)
            if (features.cost[k] + features.cost[k + 1u] <
                features.cost[best] + features.cost[best + 1u])
                best = k;
        axis = static_cast<int>(best / (2u * count_total));
        const std::uint32_t count = counts[best % (2u * count_total) / 2u];
        Item moved[few];
        for (std::uint32_t i = 0u; i < n; ++i)
            moved[i] = items[whole.begin + order[axis][i]];
        std::copy(moved, moved + n, items.begin() + static_cast<std::ptrdiff_t>(whole.begin));
        below = {whole.begin, whole.begin + count, before[axis][count]};
        above = {whole.begin + count, whole.end, after[axis][count]};
    }

    // The count in [1, n) nearest `count` that is `residue_a` or `residue_b` (`residue`).
    static std::size_t nearest_count(std::size_t count, std::size_t n, std::uint32_t residue_a,
                                     std::uint32_t residue_b) {
        constexpr std::size_t period = LightBvhView::arity - 1u;
        std::size_t best = std::clamp<std::size_t>(count, 1u, n - 1u);
        std::size_t best_distance = std::numeric_limits<std::size_t>::max();
        for (std::size_t candidate = count > period ? count - period : 1u;
             candidate <= count + period; ++candidate) {
            if (candidate < 1u || candidate >= n)
                continue;
            const std::uint32_t r = residue(candidate);
            const std::size_t distance = candidate > count ? candidate - count : count - candidate;
            if ((r == residue_a || r == residue_b) && distance < best_distance) {
                best = candidate;
                best_distance = distance;
            }
        }
        return best;
    }

    // Splits `whole` at index `middle` by the centres along its box's widest axis.
    static void median_split(std::vector<Item>& items, const Part& whole, std::size_t middle,
                             Part& below, Part& above) {
        const glm::vec3 extent = whole.bounds.upper() - whole.bounds.lower();
        const int axis = extent.x >= extent.y && extent.x >= extent.z ? 0
                         : extent.y >= extent.z                       ? 1
                                                                      : 2;
        std::nth_element(
            items.begin() + static_cast<std::ptrdiff_t>(whole.begin),
            items.begin() + static_cast<std::ptrdiff_t>(middle),
            items.begin() + static_cast<std::ptrdiff_t>(whole.end),
            [axis](const Item& a, const Item& b) { return a.centre(axis) < b.centre(axis); });
        below = part_of(items, whole.begin, middle);
        above = part_of(items, middle, whole.end);
    }

    static std::uint32_t bucket_of(float centre, float origin, float scale, std::uint32_t buckets) {
        const float at = (centre - origin) * scale;
        return at < static_cast<float>(buckets - 1u) ? static_cast<std::uint32_t>(at)
                                                     : buckets - 1u;
    }

    // Lights [begin, end) as a part.
    static Part part_of(const std::vector<Item>& items, std::size_t begin, std::size_t end) {
        Part p{begin, end, Bounds::empty()};
        for (std::size_t i = begin; i < end; ++i)
            p.bounds.add(items[i]);
        return p;
    }

    // A split: its axis (-1 where every centre is the same), the last bucket below it, the
    // last nonempty bucket below and the first above, and the bounds of both sides.
    struct Choice {
        int axis = -1;
        float origin = 0.0f, scale = 0.0f; // of the buckets along the axis
        std::uint32_t bucket = 0u;
        std::uint32_t edges[2] = {0u, 0u};
        Bounds below = Bounds::empty(), above = Bounds::empty();
    };

    // The bucket boundary of least SAOH cost over `buckets` buckets per axis.
    static void best_split(const std::vector<Item>& items, const Part& whole, std::uint32_t buckets,
                           Choice& choice) {
        // Two sets of buckets for alternate lights where there are many: consecutive lights
        // often fall in the same bucket, and each update waits for the one before.
        const std::uint32_t sets = whole.size() >= 256u ? 2u : 1u;
        Bounds bucket[2][3][bucket_count];
        for (std::uint32_t set = 0u; set < sets; ++set)
            for (auto& axis_buckets : bucket[set])
                for (std::uint32_t b = 0u; b < buckets; ++b)
                    axis_buckets[b] = Bounds::empty();
        float origin[3], scale[3];
        const glm::vec3 lower = whole.bounds.lower(), upper = whole.bounds.upper();
        for (int a = 0; a < 3; ++a) {
            origin[a] = lower[a];
            const float extent = upper[a] - lower[a];
            scale[a] = extent > 0.0f ? static_cast<float>(buckets) / extent : 0.0f;
        }
        for (std::size_t i = whole.begin; i < whole.end; ++i) {
            const Item& l = items[i];
            auto& set = bucket[i & (sets - 1u)];
            for (int a = 0; a < 3; ++a)
                set[a][bucket_of(l.centre(a), origin[a], scale[a], buckets)].add(l);
        }
        if (sets == 2u)
            for (int a = 0; a < 3; ++a)
                for (std::uint32_t b = 0u; b < buckets; ++b)
                    bucket[0][a][b].add(bucket[1][a][b]);
        const glm::vec3 extent = upper - lower;
        const float longest = std::max(extent.x, std::max(extent.y, extent.z));
        Features features;
        const std::uint32_t candidates = buckets - 1u;
        for (int a = 0; a < 3; ++a) {
            const auto& axis_buckets = bucket[0][a];
            // The thin-box factor: a long box is not split across its short side.
            const float thin = extent[a] > 0.0f ? longest / extent[a] : 1.0f;
            // Candidate b of axis a: buckets [0, b] below, (b, last] above.
            Bounds running = axis_buckets[0];
            for (std::uint32_t b = 0u; b < candidates; ++b) {
                features.set(Features::slot(a, b, false, candidates), running, thin);
                running.add(axis_buckets[b + 1u]);
            }
            running = axis_buckets[candidates];
            for (std::uint32_t b = candidates; b-- > 0u;) {
                features.set(Features::slot(a, b, true, candidates), running, thin);
                running.add(axis_buckets[b]);
            }
        }
        features.saoh_costs(6u * candidates);
        float best_cost = std::numeric_limits<float>::infinity();
        for (int a = 0; a < 3; ++a) {
            if (!(scale[a] > 0.0f))
                continue;
            for (std::uint32_t b = 0u; b < candidates; ++b) {
                const std::uint32_t k = Features::slot(a, b, false, candidates);
                const std::uint32_t k_above = Features::slot(a, b, true, candidates);
                const float cost = features.cost[k] + features.cost[k_above];
                if (features.count[k] > 0u && features.count[k_above] > 0u && cost < best_cost) {
                    best_cost = cost;
                    choice.axis = a;
                    choice.bucket = b;
                }
            }
        }
        if (choice.axis < 0)
            return;
        choice.origin = origin[choice.axis];
        choice.scale = scale[choice.axis];
        choice.edges[0] = 0u;
        choice.edges[1] = buckets;
        for (std::uint32_t b = 0u; b < buckets; ++b) {
            const Bounds& in = bucket[0][choice.axis][b];
            (b <= choice.bucket ? choice.below : choice.above).add(in);
            if (in.count > 0u && b <= choice.bucket)
                choice.edges[0] = b;
            if (in.count > 0u && b > choice.bucket)
                choice.edges[1] = std::min(choice.edges[1], b);
        }
    }

    // What the cost of a side needs, for every candidate of the three axes, copied out as a
    // structure of arrays: the cost loop vectorises. Only the slots in use are written, and
    // the loop runs over whole vectors of them (the rest zeroed first).
    struct Features {
        static constexpr std::uint32_t vector = 16u;
        static constexpr std::uint32_t slots =
            3u * 2u * (few > bucket_count ? few - 1u : bucket_count - 1u) + vector;
        float least[fields][slots];
        float power[slots], thin[slots], cost[slots];
        std::uint32_t count[slots];

        // Side `above` of candidate `b` of `axis`, of `candidates` per axis.
        static std::uint32_t slot(int axis, std::uint32_t b, bool above, std::uint32_t candidates) {
            return (static_cast<std::uint32_t>(axis) * 2u + (above ? 1u : 0u)) * candidates + b;
        }
        void set(std::uint32_t k, const Bounds& bounds, float thin_box) {
            for (std::size_t f = 0u; f < fields; ++f)
                least[f][k] = bounds.least[f];
            power[k] = bounds.power;
            thin[k] = thin_box;
            count[k] = bounds.count;
        }

        // The SAOH cost (the orientation-aware SAH of Conty Estevez and Kulla 2018) of each side:
        // its power times the orientation measure of its cone times the surface area of its box,
        // times the axis's thin-box factor. The cone is estimated as the spread of the lights' axes
        // (the half diagonal of their box seen from its centre) plus their widest own cone: a split
        // heuristic needs no exact cone.
        void saoh_costs(std::uint32_t used) {
            const std::uint32_t whole = (used + vector - 1u) / vector * vector;
            for (std::uint32_t k = used; k < whole; ++k) {
                for (auto& field : least)
                    field[k] = 0.0f;
                power[k] = thin[k] = 0.0f;
            }
            RESTIR_VECTORIZE
            for (std::uint32_t k = 0u; k < whole; ++k) {
                constexpr float pi_f = 3.14159265358979f;
                const float x =
                    max_of(-least[negated_upper_field][k] - least[lower_field][k], 0.0f);
                const float y =
                    max_of(-least[negated_upper_field + 1u][k] - least[lower_field + 1u][k], 0.0f);
                const float z =
                    max_of(-least[negated_upper_field + 2u][k] - least[lower_field + 2u][k], 0.0f);
                const float area = 2.0f * (x * y + y * z + z * x);
                // sin^2 of the spread of the axes: their box's half diagonal squared over its
                // corner's distance squared (no axes: no spread).
                float middle_squared = 0.0f, half_squared = 0.0f;
                for (std::size_t a = 0u; a < 3u; ++a) {
                    const float low = least[axis_lower_field + a][k];
                    const float high = -least[negated_axis_upper_field + a][k];
                    middle_squared += 0.25f * (low + high) * (low + high);
                    half_squared += 0.25f * (high - low) * (high - low);
                }
                const float all = middle_squared + half_squared;
                const float sin_squared = all > 0.0f ? half_squared / all : 0.0f;
                const float sin_spread = std::sqrt(sin_squared);
                const float cos_spread = std::sqrt(1.0f - sin_squared);
                // theta_o = spread + the widest own cone, by the sum of angles (pi where they
                // add up past it).
                const float cos_own = least[cos_theta_o_field][k];
                const float sin_own = std::sqrt(max_of(1.0f - cos_own * cos_own, 0.0f));
                const bool sphere = cos_own <= -cos_spread;
                const float cos_o = sphere ? -1.0f : cos_spread * cos_own - sin_spread * sin_own;
                const float sin_o = sphere ? 0.0f : sin_spread * cos_own + cos_spread * sin_own;
                // M_Omega (Conty Estevez and Kulla 2018, the SAOH) with theta_w = min(theta_o +
                // theta_e, pi): where theta_o + theta_e <= pi, theta_w - theta_o = theta_e and
                // cos(theta_o - 2 theta_w) = cos(theta_o + 2 theta_e); else pi - theta_o and
                // cos(theta_o).
                const float cos_e = least[cos_theta_e_field][k];
                const float sin_e = std::sqrt(max_of(1.0f - cos_e * cos_e, 0.0f));
                const bool within = cos_e >= -cos_o;
                const float widening = detail::fast_acos(within ? cos_e : -cos_o);
                const float cos_far =
                    within ? cos_o * (2.0f * cos_e * cos_e - 1.0f) - sin_o * (2.0f * sin_e * cos_e)
                           : cos_o;
                const float measure = 2.0f * pi_f * (1.0f - cos_o) +
                                      0.5f * pi_f * (2.0f * widening * sin_o - cos_far + cos_o);
                cost[k] = power[k] * measure * area * thin[k];
            }
        }
    };

    std::vector<LightBvhGroup> groups_;
    std::vector<std::uint64_t> paths_;
    glm::vec3 root_lower_{0.0f}, root_upper_{0.0f};
};

} // namespace restir

#if defined(__clang__)
#pragma clang diagnostic pop
#endif
