/// @file light/light_bvh_items.hpp
/// The lights as the light BVH's builder carries them (internal to light/light_bvh.hpp): each
/// light's bounds in one cache line, the bounds of a set of lights merged by elementwise
/// minima, and a node's exact bounds.
#pragma once

#include "restir/light/light_bounds.hpp"

#include <glm/common.hpp>
#include <glm/vec3.hpp>

#include <algorithm>
#include <cmath>
#include <cstddef>
#include <cstdint>
#include <limits>

namespace restir::detail {

/// The builder's types, all static: `LightBvhSplits` and `LightBvh` derive from it.
struct LightBvhItems {
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
};

} // namespace restir::detail
