/// @file reuse/temporal.hpp
/// Temporal reuse (Bitterli et al. 2020, Sec. 4 and Alg. 5): the receiver's fresh reservoir
/// is combined with the previous frame's reservoir at the pixel that the application's
/// reprojection names, when that pixel's surface is similar. The history's M is capped at a
/// multiple of the current M so that stale samples cannot dominate.
#pragma once

#include "restir/concepts.hpp"
#include "restir/config.hpp"
#include "restir/core/math.hpp"
#include "restir/core/reservoir.hpp"
#include "restir/core/rng.hpp"
#include "restir/reuse/bias_correction.hpp"
#include "restir/reuse/image_view.hpp"
#include "restir/reuse/reuse_input.hpp"
#include "restir/reuse/similarity.hpp"

#include <concepts>
#include <cstdint>

namespace restir {

/// Where temporal reuse looks and how much it trusts what it finds. (The bias correction and
/// visibility are a `ReuseParams` of their own, the frame number an argument.)
struct TemporalParams {
    SimilarityParams similarity{};
    /// The history's M is capped at this multiple of the current reservoir's M (the paper's
    /// 20); 0 disables the cap.
    std::uint32_t history_cap_multiplier = 20u;
    /// Permutation sampling (Wyman and Panteleev 2021): reads the history of a pixel whose
    /// coordinates differ in their lowest bits by a per-frame pattern, so that neighbouring
    /// pixels stop sharing correlated histories. Off by default.
    bool permutation_sampling = false;
    /// The pattern XORs this many low bits of each coordinate: the history comes from within
    /// blocks of 2^bits x 2^bits pixels (1: 2 x 2, as in the paper). At most 15.
    std::uint32_t permutation_bits = 1u;
    /// Permutation sampling only at receivers at least this rough (`reuse_roughness`): a
    /// smoother one reads its own reprojected pixel's history, since a neighbour's sample
    /// seldom lies in a narrow lobe (docs/noise-and-bias.md, "Narrow lobes"). 0: everywhere.
    float permutation_min_roughness = 0.0f;
};

/// The paper's settings: 25 degrees / 10 %, cap 20.
RESTIR_HOST_DEVICE constexpr TemporalParams default_temporal_params() noexcept { return {}; }

/// Where to look up the previous frame: `reproject(pixel)` -> PixelCoord in the previous
/// image (from motion vectors or camera reprojection); a coordinate outside the previous
/// image means the surface was not visible there (disocclusion).
template <class F>
concept Reprojection = requires(const F& reproject, PixelCoord pixel) {
    { reproject(pixel) } -> std::convertible_to<PixelCoord>;
};

/// The previous-frame pixel that `pixel` reuses in frame `frame_index`: the reprojected one,
/// permuted when permutation sampling is on (a bijection on blocks of 2^bits x 2^bits pixels,
/// a pattern per frame).
RESTIR_HOST_DEVICE constexpr PixelCoord history_pixel(PixelCoord reprojected,
                                                      const TemporalParams& params,
                                                      std::uint32_t frame_index) noexcept {
    if (!params.permutation_sampling)
        return reprojected;
    // A pattern per frame and per block, so that over the image the history moves along x as
    // often as along y (one pattern for the whole frame left the error of 20 accumulated frames
    // correlated more along one axis, as the frames' draws happened to fall).
    const std::uint32_t bits = min_of(params.permutation_bits, 15u); // shifts stay defined
    const std::uint64_t block =
        (std::uint64_t{static_cast<std::uint32_t>(reprojected.x) >> bits} << 32u) |
        (static_cast<std::uint32_t>(reprojected.y) >> bits);
    const std::uint64_t pattern = mix64(frame_index ^ mix64(block));
    const std::uint32_t mask = (1u << bits) - 1u;
    return {reprojected.x ^ static_cast<std::int32_t>(pattern & mask),
            reprojected.y ^ static_cast<std::int32_t>((pattern >> 32u) & mask)};
}

/// `history_pixel` for a receiver `surface`: not permuted where the surface is smoother than
/// `params.permutation_min_roughness`.
template <class S>
RESTIR_HOST_DEVICE PixelCoord history_pixel_at(const S& surface, PixelCoord reprojected,
                                               const TemporalParams& params,
                                               std::uint32_t frame_index) {
    if (reuse_roughness(surface) < params.permutation_min_roughness)
        return reprojected;
    return history_pixel(reprojected, params, frame_index);
}

/// The largest M a previous-frame reservoir may lend to a receiver whose own M is
/// `current_count`: `params.history_cap_multiplier` times it (saturating), or no limit for a
/// multiplier of 0.
RESTIR_HOST_DEVICE constexpr std::uint32_t history_cap(std::uint32_t current_count,
                                                       const TemporalParams& params) noexcept {
    if (params.history_cap_multiplier == 0u)
        return 0xffffffffu;
    // multiplier * M, saturating instead of wrapping around to a small cap.
    const std::uint64_t cap = std::uint64_t{params.history_cap_multiplier} * current_count;
    return static_cast<std::uint32_t>(cap < 0xffffffffull ? cap : 0xffffffffull);
}

/// The second half of `temporal_resample`: `current` (finalised, for `surface`) combined with
/// the history `input` that `reusable_input` found for it, its M capped; `current` unchanged when
/// `input` is null. For renderers that look the history up ahead of the pass (to trace its MIS
/// ray in a batch) and should not look it up twice.
template <class Sample, Surface S, class Target, class Visibility, class MaterialTest, class Shift,
          UniformRng Rng>
requires TargetFunction<Target, Sample, S> && VisibilityFunction<Visibility, Sample, S>
    RESTIR_HOST_DEVICE Reservoir<Sample>
    temporal_combine(const Reservoir<Sample>& current, const S& surface,
                     ReuseInput<Sample, S> input, const TemporalParams& params,
                     const ReuseParams& reuse,
                     const ReuseBridge<Target, Visibility, MaterialTest, Shift>& bridge, Rng& rng) {
    if (input.reservoir == nullptr)
        return current;
    return combine_inputs(
        current, surface,
        ReuseInputSpan<Sample, S>{&input, 1u, history_cap(current.candidate_count, params)}, reuse,
        bridge, rng);
}

/// Temporal resampling of one pixel. `current` is the pixel's finalised reservoir for this
/// frame (initial candidates, possibly visibility-tested) computed for `surface`;
/// `previous_reservoirs` and `previous_surfaces` are last frame's buffers. Returns the
/// combined, finalised reservoir; without usable history (disocclusion, dissimilar surface,
/// non-finite history) it returns `current` unchanged. `frame_index` selects the permutation.
template <class Sample, Surface S, Reprojection Reproject, class Target, class Visibility,
          class MaterialTest, class Shift, UniformRng Rng>
requires TargetFunction<Target, Sample, S> && VisibilityFunction<Visibility, Sample, S>
    RESTIR_HOST_DEVICE Reservoir<Sample> temporal_resample(
        PixelCoord pixel, const Reservoir<Sample>& current, const S& surface,
        ImageView<const Reservoir<Sample>> previous_reservoirs,
        ImageView<const S> previous_surfaces, const Reproject& reproject,
        const TemporalParams& params, const ReuseParams& reuse, std::uint32_t frame_index,
        const ReuseBridge<Target, Visibility, MaterialTest, Shift>& bridge, Rng& rng) {
    if (!is_valid_surface(surface))
        return current;
    return temporal_combine(
        current, surface,
        reusable_input(history_pixel_at(surface, reproject(pixel), params, frame_index), surface,
                       previous_reservoirs, previous_surfaces, params.similarity,
                       bridge.material_test),
        params, reuse, bridge, rng);
}

} // namespace restir
