/// @file core/channels.hpp
/// How a target function folds the three colour channels of a contribution into the one
/// number p-hat that resampling needs.
#pragma once

#include "restir/config.hpp"

#include <glm/vec3.hpp>

#include <cmath>

namespace restir {

/// The fold of an RGB contribution f into p-hat.
enum class ChannelNorm {
    /// f_r + f_g + f_b.
    sum,
    /// sqrt(f_r^2 + f_g^2 + f_b^2). One sample drawn with p proportional to |f|_2 minimises the
    /// summed variance of the three channel estimates, sum_c integral f_c^2 / p - I_c^2 (by
    /// Cauchy-Schwarz): it picks saturated contributions more often than the sum does, so a
    /// single sample's colour strays less.
    euclidean
};

/// p-hat of the contribution `f` under `Norm`.
template <ChannelNorm Norm>
RESTIR_HOST_DEVICE inline float fold_channels(glm::vec3 f) noexcept {
    if constexpr (Norm == ChannelNorm::euclidean)
        return std::sqrt(f.x * f.x + f.y * f.y + f.z * f.z);
    else
        return f.x + f.y + f.z;
}

} // namespace restir
