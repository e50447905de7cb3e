/// @file reuse/boiling_filter.hpp
/// Boiling filter: spatiotemporal reuse can spread one rare, very bright sample over a growing
/// blob of pixels ("boiling"). The filter empties reservoirs whose contribution p-hat(y) * W
/// is far above the average of their neighbourhood. It removes energy, so it is biased; keep
/// it off when measuring error against a reference.
#pragma once

#include "restir/config.hpp"
#include "restir/core/reservoir.hpp"
#include "restir/reuse/image_view.hpp"

#include <cstdint>

namespace restir {

/// Settings of the boiling filter.
struct BoilingFilterParams {
    /// Half-width of the square window whose average is taken ((2r + 1)^2 reads per pixel).
    std::uint32_t radius = 4u;
    /// A reservoir is emptied when its p-hat * W exceeds this multiple of the window average.
    float threshold = 20.0f;
};

/// Window 9 x 9, threshold 20x the local average.
RESTIR_HOST_DEVICE constexpr BoilingFilterParams default_boiling_filter_params() noexcept {
    return {};
}

/// The reservoir of `pixel` after the filter: unchanged, or empty (M and the sample kept, W
/// and the weight sum 0) when its p-hat * W exceeds `threshold` times the average over the
/// window (itself included). Non-finite reservoirs in the window are left out of the average.
/// Reads `reservoirs` only; write the result to a different buffer.
template <class Sample>
RESTIR_HOST_DEVICE Reservoir<Sample> boiling_filter(PixelCoord pixel,
                                                    ImageView<const Reservoir<Sample>> reservoirs,
                                                    const BoilingFilterParams& params) {
    // Precondition: `pixel` lies in the view (a debug build checks); outside, an empty one.
    RESTIR_ASSERT(reservoirs.contains(pixel));
    if (!reservoirs.contains(pixel))
        return Reservoir<Sample>{};
    Reservoir<Sample> result = reservoirs[pixel];
    const float contribution = result.target_value * result.contribution_weight;
    if (!(contribution > 0.0f))
        return result;
    // The window clipped to the image, in 64-bit arithmetic: any radius is safe and no larger
    // than the image costs.
    const std::int64_t r = params.radius;
    const std::int64_t x0 = max_of(std::int64_t{pixel.x} - r, std::int64_t{0});
    const std::int64_t y0 = max_of(std::int64_t{pixel.y} - r, std::int64_t{0});
    const std::int64_t x1 = min_of(std::int64_t{pixel.x} + r, std::int64_t{reservoirs.width} - 1);
    const std::int64_t y1 = min_of(std::int64_t{pixel.y} + r, std::int64_t{reservoirs.height} - 1);
    float sum = 0.0f;
    std::uint32_t count = 0u;
    for (std::int64_t y = y0; y <= y1; ++y)
        for (std::int64_t x = x0; x <= x1; ++x) {
            const PixelCoord p{static_cast<std::int32_t>(x), static_cast<std::int32_t>(y)};
            if (!reservoirs[p].is_well_formed())
                continue;
            sum += reservoirs[p].target_value * reservoirs[p].contribution_weight;
            ++count;
        }
    const float average = sum / static_cast<float>(count);
    if (contribution > params.threshold * average) {
        result.weight_sum = 0.0f;
        result.contribution_weight = 0.0f;
    }
    return result;
}

} // namespace restir
