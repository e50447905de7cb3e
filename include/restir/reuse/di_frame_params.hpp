/// @file reuse/di_frame_params.hpp
/// The settings of a ReSTIR DI frame (reuse/di_frame.hpp): visibility reuse, the bias
/// corrections, the temporal and spatial passes and the boiling filter, with the paper's
/// defaults, and named presets that trade among error, bias and time.
#pragma once

#include "restir/config.hpp"
#include "restir/reuse/boiling_filter.hpp"
#include "restir/reuse/reuse_params.hpp"
#include "restir/reuse/spatial.hpp"
#include "restir/reuse/temporal.hpp"

#include <cstdint>

namespace restir {

/// Settings of a ReSTIR DI frame. Every field is read; none overrides another.
struct DiFrameParams {
    /// Visibility reuse and the MIS rays, for every pass (all passes must agree on what the
    /// reservoirs carry). The recipe tests every reservoir before a pass reads it, so `traced`
    /// and `traced_inputs_tested` are the same here: exact weights, no ray for an input's own
    /// sample.
    ReuseVisibility visibility = ReuseVisibility::traced;
    /// Bias correction of the temporal pass.
    BiasCorrection temporal_bias_correction = BiasCorrection::pairwise;
    /// Bias correction of each spatial pass.
    BiasCorrection spatial_bias_correction = BiasCorrection::pairwise;
    /// False skips temporal reuse in every frame.
    bool temporal_reuse = true;
    TemporalParams temporal = default_temporal_params();
    /// Spatial passes per frame (the paper: 1 to 4; 0 skips spatial reuse).
    std::uint32_t spatial_passes = 1u;
    /// Each spatial pass (the paper's k = 3 in 30 px for the unbiased modes).
    SpatialParams spatial = default_spatial_params();
    /// Pixels along a row that take one neighbour draw in a spatial pass: 1 (each its own, the
    /// default) or more, where pixel (x, y) reuses from the offsets that pixel (x - x mod
    /// span, y) draws (`DiFrame::neighbour_draw`). Neighbours of adjacent pixels then lie side
    /// by side, so a GPU warp's reads of them touch fewer cache lines; each pixel's neighbours
    /// are still drawn independently of the reservoirs, so the passes stay unbiased.
    std::uint32_t spatial_draw_span = 1u;
    /// The boiling filter after the spatial passes (biased: off by default).
    bool boiling_filter = false;
    BoilingFilterParams boiling = default_boiling_filter_params();
};

/// The paper's settings: pairwise MIS with visibility reuse and traced MIS rays, temporal reuse
/// with a history cap of 20, one spatial pass of 3 neighbours in 30 pixels.
RESTIR_HOST_DEVICE constexpr DiFrameParams default_di_frame_params() noexcept { return {}; }

/// Named settings of a frame, each a measured trade (docs/noise-and-bias.md, "Presets").
enum class DiFramePreset : std::uint8_t {
    /// Unbiased, for the frame and for the running mean of frames: pairwise MIS with traced
    /// MIS rays, 5 neighbours, a history cap of 4 with permutation sampling (consecutive frames
    /// less alike, so that their mean converges faster), receivers smoother than roughness 0.1
    /// (narrow lobes, `SpatialParams::min_roughness`, `TemporalParams::
    /// permutation_min_roughness`) without spatial neighbours and with their own pixel's
    /// history. restir-render's defaults.
    unbiased,
    /// Unbiased, for the frame alone: 3 neighbours and the paper's cap of 20 without
    /// permutation, with defensive pairwise MIS (`BiasCorrection::defensive_pairwise`: the
    /// pixel's own reservoir, strong after a long history, keeps a share of its own where
    /// neighbours' targets differ), and no spatial neighbours for receivers smoother than
    /// roughness 0.15 (`SpatialParams::min_roughness`: neighbours' samples seldom lie in a
    /// narrow lobe), within half the paper's radius (15 px at 1080 rows: neighbours nearer in
    /// the scene, with samples drawn for surfaces more like the pixel's, noise a little more
    /// correlated from pixel to pixel); less error a frame for less time, a running mean that
    /// converges slower.
    balanced,
    /// Biased, for speed: as `balanced`, with MIS weights that assume every sample visible
    /// (`ReuseVisibility::assumed`: no ray in reuse; a little light lost or gained near shadow
    /// boundaries).
    fast,
};

/// The settings of `preset` (spatial radius in pixels at 1080 rows: scale it with the image).
RESTIR_HOST_DEVICE constexpr DiFrameParams di_frame_preset(DiFramePreset preset) noexcept {
    DiFrameParams p = default_di_frame_params();
    if (preset == DiFramePreset::unbiased) {
        p.spatial.neighbour_count = 5u;
        p.temporal.history_cap_multiplier = 4u;
        p.temporal.permutation_sampling = true;
        p.temporal.permutation_min_roughness = 0.1f;
        p.spatial.min_roughness = 0.1f;
    }
    if (preset != DiFramePreset::unbiased) {
        p.temporal_bias_correction = BiasCorrection::defensive_pairwise;
        p.spatial_bias_correction = BiasCorrection::defensive_pairwise;
        p.spatial.min_roughness = 0.15f;
        p.spatial.radius *= 0.5f; // half the paper's 30 px
    }
    if (preset == DiFramePreset::fast)
        p.visibility = ReuseVisibility::assumed;
    return p;
}

} // namespace restir
