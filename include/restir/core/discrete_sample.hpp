/// @file core/discrete_sample.hpp
/// The result of sampling an index from a discrete distribution.
#pragma once

#include <cstdint>
#include <type_traits>

namespace restir {

/// An index drawn from a discrete distribution, with the probability of drawing it.
struct DiscreteSample {
    std::uint32_t index = 0u; ///< The chosen entry (for light samplers: the light id).
    float pmf = 0.0f;         ///< Probability of choosing `index`; 0 means "no sample".
};

static_assert(std::is_trivially_copyable_v<DiscreteSample>);

} // namespace restir
