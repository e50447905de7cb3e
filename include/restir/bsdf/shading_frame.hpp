/// @file bsdf/shading_frame.hpp
/// An orthonormal frame about a unit normal, to move directions between world space and the
/// local frame (z = normal) in which the microfacet formulas are written.
#pragma once

#include "restir/config.hpp"

#include <glm/geometric.hpp>
#include <glm/vec3.hpp>

namespace restir {

/// Orthonormal frame about a unit normal (Duff et al. 2017, branchless).
struct ShadingFrame {
    glm::vec3 tangent{1.0f, 0.0f, 0.0f};   ///< Local x.
    glm::vec3 bitangent{0.0f, 1.0f, 0.0f}; ///< Local y.
    glm::vec3 normal{0.0f, 0.0f, 1.0f};    ///< Local z.

    /// The frame of Duff et al. 2017 ("Building an Orthonormal Basis, Revisited", JCGT 6(1),
    /// listing 3) about the unit vector `n`: continuous except across n.z = 0, no division by
    /// a small number (the sign is chosen so that sign + n.z >= 1).
    RESTIR_HOST_DEVICE static ShadingFrame from_normal(glm::vec3 n) {
        const float sign = n.z >= 0.0f ? 1.0f : -1.0f;
        const float a = -1.0f / (sign + n.z);
        const float b = n.x * n.y * a;
        return {glm::vec3(1.0f + sign * n.x * n.x * a, sign * b, -sign * n.x),
                glm::vec3(b, sign + n.y * n.y * a, -n.y), n};
    }

    /// World to local: (t.v, b.v, n.v).
    RESTIR_HOST_DEVICE glm::vec3 to_local(glm::vec3 v) const {
        return {glm::dot(tangent, v), glm::dot(bitangent, v), glm::dot(normal, v)};
    }

    /// Local to world: v.x t + v.y b + v.z n.
    RESTIR_HOST_DEVICE glm::vec3 to_world(glm::vec3 v) const {
        return tangent * v.x + bitangent * v.y + normal * v.z;
    }
};

} // namespace restir
