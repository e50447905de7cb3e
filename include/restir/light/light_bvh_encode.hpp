/// @file light/light_bvh_encode.hpp
/// The quantisation of the light BVH's groups (internal to light/light_bvh.hpp): a lane's box
/// on its parent's grid and its emission bounds as codes, every bound rounded outward, which
/// light/light_bvh_view.hpp decodes.
#pragma once

#include "restir/light/light_bvh_group.hpp"

#include <glm/geometric.hpp>
#include <glm/vec3.hpp>

#include <algorithm>
#include <cmath>
#include <cstdint>
#include <limits>

namespace restir::detail {

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

} // namespace restir::detail
