/// @file reuse/di_frame.hpp
/// The ReSTIR DI frame recipe: the order of the passes of one frame (Bitterli et al. 2020,
/// Alg. 5 with the visibility reuse of Sec. 4), which buffer each pass reads and writes, where
/// visibility is applied, and what becomes the next frame's history, written once so that an
/// integrator calls it instead of rewriting it.
///
/// Per pixel, in stages; every pixel finishes a stage before any pixel starts a stage that
/// reads its neighbours (a kernel launch or a parallel loop per such stage):
///   1. `initial`   your candidates (`resample_ris`, `resample_ris_batch`) tested for
///                  visibility under visibility reuse,
///   2. `temporal`  combined with last frame's history at the reprojected pixel (skipped when
///                  there is no history: frame 0, a camera cut, a new light set),
///   3. `spatial`   combined with k neighbours, `spatial_passes` times, each pass reading the
///                  whole output of the one before,
///   4. `boiling`   optional filter against rare bright samples (reads a window),
///   5. `finish`    the final visibility: shade f(y) W, and keep the result as the next
///                  frame's history.
/// Stages 1-2 read only their own pixel and run in one loop, as do 5 and the stage before it.
/// `run_di_frame` runs all of it over an image with your parallel loop.
#pragma once

#include "restir/concepts.hpp"
#include "restir/config.hpp"
#include "restir/core/math.hpp"
#include "restir/core/reservoir.hpp"
#include "restir/core/rng.hpp"
#include "restir/reuse/bias_correction.hpp"
#include "restir/reuse/boiling_filter.hpp"
#include "restir/reuse/history.hpp"
#include "restir/reuse/image_view.hpp"
#include "restir/reuse/neighbour_offsets.hpp"
#include "restir/reuse/reuse_input.hpp"
#include "restir/reuse/spatial.hpp"
#include "restir/reuse/surface_source.hpp"
#include "restir/reuse/temporal.hpp"
#include "restir/reuse/visibility.hpp"

#include <concepts>
#include <cstdint>
#include <type_traits>

namespace restir {

/// Settings of a ReSTIR DI frame.
struct DiFrameParams {
    /// Bias correction and visibility reuse of every pass: it replaces the `reuse` fields of
    /// `temporal` and `spatial`, so that all passes agree on what the reservoirs carry.
    ReuseParams reuse{};
    /// Temporal reuse; its `frame_index` is set from the frame.
    TemporalParams temporal = default_temporal_params();
    /// Each spatial pass (the paper's k = 3 in 30 px for the unbiased modes).
    SpatialParams spatial = default_spatial_params();
    /// Spatial passes per frame (the paper: 1 to 4; 0 skips spatial reuse).
    std::uint32_t spatial_passes = 1u;
    /// False skips temporal reuse in every frame.
    bool temporal_reuse = true;
    /// The boiling filter after the spatial passes (biased: off by default).
    bool boiling_filter = false;
    BoilingFilterParams boiling = default_boiling_filter_params();
    /// True when the application traces the stages' visibility rays itself (in packets, or in
    /// a separate kernel): the stages then trace none, and the caller tests every reservoir
    /// for which `DiFrame::needs_visibility_test` says so, with `apply_visibility`, before the
    /// next stage reads it. False: the stages trace them through the bridge.
    bool deferred_visibility = false;
};

/// The paper's settings: pairwise MIS with visibility reuse, temporal reuse with a history cap
/// of 20, one spatial pass of 3 neighbours in 30 pixels.
RESTIR_HOST_DEVICE constexpr DiFrameParams default_di_frame_params() noexcept { return {}; }

/// One frame of the recipe: the settings and the buffers that every pixel's stages read.
/// Views hold pointers into the application's buffers (device pointers on a GPU).
/// `Reproject` is `PixelCoord(PixelCoord)`: the previous frame's pixel that shows a pixel's
/// surface (outside the image when it was not visible). `History` is last frame's reservoirs:
/// an `ImageView` of them, or any `ReservoirHistory` (reuse/history.hpp), such as a
/// `PackedHistory` with a light-id translation. `Surfaces` is this frame's G-buffer: an
/// `ImageView` of surfaces, or a `SurfaceDecoder` (reuse/surface_source.hpp) that decodes them
/// from the application's own G-buffer. Both hooks together, `surfaces.surface(p)` and
/// `history.surface(p)`, are RTXDI's `GetGBufferSurface(pixel, previousFrame)`.
template <class Sample, Surface S, Reprojection Reproject,
          class History = ImageView<const Reservoir<Sample>>, class Surfaces = ImageView<const S>>
requires(std::same_as<History, ImageView<const Reservoir<Sample>>> ||
         ReservoirHistory<History, Sample>) &&
    SurfaceSource<Surfaces, S> struct DiFrame {
    DiFrameParams params = default_di_frame_params();
    std::uint32_t frame_index = 0u;
    /// This frame's G-buffer.
    Surfaces surfaces{};
    /// Last frame's G-buffer, and the reservoirs that last frame's `finish` stage returned.
    /// Leave `history` empty (`{}`) when it does not apply: in frame 0, after a camera cut,
    /// and after the light set changed (its samples would belong to another integrand).
    /// `previous_surfaces` may stay empty when the history decodes them (`HistorySurfaces`).
    ImageView<const S> previous_surfaces{};
    History history{};
    Reproject reproject{};
    NeighbourOffsets offsets = make_neighbour_offsets();

    /// Whether the history is loaded by value (a `ReservoirHistory`) rather than viewed.
    static constexpr bool loads_history =
        !std::same_as<History, ImageView<const Reservoir<Sample>>>;

    /// Whether the history decodes last frame's surfaces itself (`HistorySurfaces`): then
    /// `previous_surfaces` may stay empty.
    static constexpr bool history_has_surfaces = HistorySurfaces<History, S>;
    /// What `temporal_input` returns for a loaded history.
    using LoadedInput = LoadedHistoryInput<Sample, S, history_has_surfaces>;

    /// Whether `history` is empty (frame 0, a camera cut, a new light set).
    RESTIR_HOST_DEVICE constexpr bool history_is_empty() const noexcept {
        if constexpr (loads_history)
            return history.empty();
        else
            return history.data == nullptr;
    }

    /// Whether stage 2 reuses anything this frame.
    RESTIR_HOST_DEVICE constexpr bool has_history() const noexcept {
        return params.temporal_reuse && !history_is_empty() &&
               (history_has_surfaces || previous_surfaces.data != nullptr);
    }

    /// The temporal pass's settings as the recipe runs it. Under visibility reuse every
    /// reservoir that enters a pass has been tested at its own surface (by `initial`, by
    /// `finish` for the history, and by the retests between passes), which spares the MIS
    /// weights one ray per input.
    RESTIR_HOST_DEVICE constexpr TemporalParams temporal_params() const noexcept {
        TemporalParams t = params.temporal;
        t.reuse = params.reuse;
        t.reuse.inputs_visibility_tested = params.reuse.visibility_reuse;
        t.frame_index = frame_index;
        return t;
    }
    /// The spatial passes' settings as the recipe runs them (see `temporal_params`).
    RESTIR_HOST_DEVICE constexpr SpatialParams spatial_params() const noexcept {
        SpatialParams s = params.spatial;
        s.reuse = params.reuse;
        s.reuse.inputs_visibility_tested = params.reuse.visibility_reuse;
        return s;
    }

    /// Whether the passes' MIS weights trace shadow rays (visibility reuse with traced MIS
    /// visibility, in an unbiased mode): then every pass input must be tested at its own surface.
    RESTIR_HOST_DEVICE constexpr bool mis_weights_trace_rays() const noexcept {
        return params.reuse.visibility_reuse && params.reuse.trace_mis_visibility &&
               params.reuse.bias_correction != BiasCorrection::none;
    }

    /// Whether a pass's result must be tested for visibility before the next pass reads it:
    /// under visibility reuse whose MIS weights trace rays, a result whose sample is not the
    /// pixel's own `input` sample (already tested there). Stages 1 and 5 test every
    /// sample under visibility reuse (`needs_visibility_test(r)`).
    RESTIR_HOST_DEVICE constexpr bool needs_visibility_test(const Reservoir<Sample>& result,
                                                            const Reservoir<Sample>& input) const {
        if (!mis_weights_trace_rays() || !result.has_sample())
            return false;
        if constexpr (requires {
                          { result.sample == input.sample } -> std::convertible_to<bool>;
                      })
            return !(input.has_sample() && result.sample == input.sample);
        return true;
    }
    /// Whether stages 1 and 5 test `result` (visibility reuse, and it holds a sample).
    RESTIR_HOST_DEVICE constexpr bool
    needs_visibility_test(const Reservoir<Sample>& result) const noexcept {
        return params.reuse.visibility_reuse && result.has_sample();
    }

    /// Stage 1: the pixel's initial reservoir `candidates` (finalised RIS for its surface),
    /// with W = 0 when its sample is occluded, under visibility reuse.
    template <class Visibility>
    requires VisibilityFunction<Visibility, Sample, S> RESTIR_HOST_DEVICE Reservoir<Sample>
    initial(PixelCoord pixel, const Reservoir<Sample>& candidates, const Visibility& visible)
    const { return tested(pixel, candidates, visible); }

    /// Stage 2: `current` (stage 1's result) combined with the history; `current` unchanged
    /// without history. Draws one uniform number per input that takes part.
    template <class Target, class Visibility, class MaterialTest, UniformRng Rng>
    requires TargetFunction<Target, Sample, S> && VisibilityFunction<Visibility, Sample, S>
        RESTIR_HOST_DEVICE Reservoir<Sample>
        temporal(PixelCoord pixel, const Reservoir<Sample>& current,
                 const ReuseBridge<Target, Visibility, MaterialTest>& bridge, Rng& rng)
    const {
        return temporal_combine(pixel, current, temporal_input(pixel, bridge.material_test), bridge,
                                rng);
    }

    /// The first half of `temporal`: the history input that stage 2 of `pixel` reuses, for
    /// renderers that trace its MIS ray ahead of `temporal_combine`. A `ReuseInput` pointing
    /// into the history view (null pointers when none), or for a `ReservoirHistory` a
    /// `LoadedHistoryInput` (null surface when none).
    template <class MaterialTest = AnyMaterial>
    RESTIR_HOST_DEVICE auto temporal_input(PixelCoord pixel,
                                           const MaterialTest& material_test = {}) const {
        const TemporalParams t = temporal_params();
        std::conditional_t<loads_history, LoadedInput, ReuseInput<Sample, S>> input{};
        if (!has_history())
            return input;
        const auto& here = surface_at(surfaces, pixel);
        if (!is_valid_surface(here))
            return input;
        const PixelCoord p = history_pixel(reproject(pixel), t);
        if constexpr (history_has_surfaces) {
            if (history.contains(p)) {
                input.reservoir = history.load(p);
                input.surface = history.surface(p);
                input.lends = input.reservoir.is_well_formed() &&
                              surfaces_similar(here, input.surface, t.similarity, material_test);
            }
        } else if constexpr (loads_history) {
            if (history.contains(p) && previous_surfaces.contains(p)) {
                input.reservoir = history.load(p);
                if (input.reservoir.is_well_formed() &&
                    surfaces_similar(here, previous_surfaces[p], t.similarity, material_test))
                    input.surface = &previous_surfaces[p];
            }
        } else {
            input =
                reusable_input(p, here, history, previous_surfaces, t.similarity, material_test);
        }
        return input;
    }

    /// `temporal_combine` for a history input loaded by value.
    template <class Target, class Visibility, class MaterialTest, UniformRng Rng>
    requires TargetFunction<Target, Sample, S> && VisibilityFunction<Visibility, Sample, S>
        RESTIR_HOST_DEVICE Reservoir<Sample>
        temporal_combine(PixelCoord pixel, const Reservoir<Sample>& current,
                         const LoadedInput& input,
                         const ReuseBridge<Target, Visibility, MaterialTest>& bridge, Rng& rng)
    const { return temporal_combine(pixel, current, input.lending(), bridge, rng); }

    /// The second half of `temporal`: combines `current` with the `input` that
    /// `temporal_input` found.
    template <class Target, class Visibility, class MaterialTest, UniformRng Rng>
    requires TargetFunction<Target, Sample, S> && VisibilityFunction<Visibility, Sample, S>
        RESTIR_HOST_DEVICE Reservoir<Sample>
        temporal_combine(PixelCoord pixel, const Reservoir<Sample>& current,
                         ReuseInput<Sample, S> input,
                         const ReuseBridge<Target, Visibility, MaterialTest>& bridge, Rng& rng)
    const {
        // One named result, returned once, so that it is built in place.
        const bool reuses = input.reservoir != nullptr;
        Reservoir<Sample> result =
            reuses ? restir::temporal_combine(current, surface_at(surfaces, pixel), input,
                                              temporal_params(), bridge, rng)
                   : current;
        if (reuses && params.spatial_passes > 0u)
            retest(pixel, result, current, bridge.visibility);
        return result;
    }

    /// Stage 3, pass `pass`: the pixel's reservoir in `input` (the whole output of the stage
    /// before) combined with its neighbours', streamed (`SpatialNeighbours`: no array of
    /// inputs). Write the result to another buffer.
    template <class Target, class Visibility, class MaterialTest, UniformRng Rng>
    requires TargetFunction<Target, Sample, S> && VisibilityFunction<Visibility, Sample, S>
        RESTIR_HOST_DEVICE Reservoir<Sample>
        spatial(PixelCoord pixel, std::uint32_t pass, ImageView<const Reservoir<Sample>> input,
                const ReuseBridge<Target, Visibility, MaterialTest>& bridge, Rng& rng)
    const {
        // Not spatial_combine(spatial_neighbours(...)): through the returned set nvcc kept the
        // whole frame in local memory (656 bytes of stack); built here, the set stays in registers.
        if (!combines_spatially(pixel, input))
            return kept(pixel, input);
        const SpatialParams spatial = spatial_params();
        return spatial_result(pixel, pass, input,
                              find_spatial_neighbours(pixel, surface_at(surfaces, pixel), input,
                                                      surfaces, spatial, offsets,
                                                      bridge.material_test, rng),
                              bridge, rng);
    }

    /// The first half of `spatial`, for renderers that trace a pass's MIS rays ahead of it:
    /// the neighbours the pass reuses (`SpatialNeighbours`; its inputs, visited in order, name
    /// their surfaces), empty for a pixel that keeps its reservoir. `spatial_combine` takes them
    /// with the same `rng`.
    template <class MaterialTest, UniformRng Rng>
    RESTIR_HOST_DEVICE SpatialNeighbours<Sample, S, Surfaces>
    spatial_neighbours(PixelCoord pixel, ImageView<const Reservoir<Sample>> input,
                       const MaterialTest& material_test, Rng& rng) const {
        if (!surfaces.contains(pixel) || !is_valid_surface(surface_at(surfaces, pixel)))
            return {};
        const SpatialParams spatial = spatial_params();
        return find_spatial_neighbours(pixel, surface_at(surfaces, pixel), input, surfaces, spatial,
                                       offsets, material_test, rng);
    }

    /// The second half of `spatial`: combines the pixel's own reservoir in `input` with the
    /// `neighbours` that `spatial_neighbours` found (or any `ReuseInputs` set).
    template <class Inputs, class Target, class Visibility, class MaterialTest, UniformRng Rng>
    requires ReuseInputs<Inputs, Sample, S> && TargetFunction<Target, Sample, S> &&
        VisibilityFunction<Visibility, Sample, S>
            RESTIR_HOST_DEVICE Reservoir<Sample>
            spatial_combine(PixelCoord pixel, std::uint32_t pass,
                            ImageView<const Reservoir<Sample>> input, const Inputs& neighbours,
                            const ReuseBridge<Target, Visibility, MaterialTest>& bridge, Rng& rng)
    const {
        // One named result, returned once (see `temporal_combine`).
        const bool combines = combines_spatially(pixel, input);
        Reservoir<Sample> result = combines
                                       ? spatial_result(pixel, pass, input, neighbours, bridge, rng)
                                       : kept(pixel, input);
        return result;
    }

    /// Stage 4 (with `params.boiling_filter`): the pixel's reservoir in `input` (the last
    /// spatial pass's output), emptied when far brighter than its window.
    RESTIR_HOST_DEVICE Reservoir<Sample> boiling(PixelCoord pixel,
                                                 ImageView<const Reservoir<Sample>> input) const {
        return params.boiling_filter ? boiling_filter(pixel, input, params.boiling) : input[pixel];
    }

    /// Stage 5: the final visibility. Under visibility reuse W becomes 0 where the sample is
    /// occluded: shade the unshadowed f(y) W, and store the result as the next frame's
    /// `history`. Without visibility reuse the reservoir is returned as it is: store it, and
    /// shade f(y) W only where the sample is visible.
    template <class Visibility>
    requires VisibilityFunction<Visibility, Sample, S> RESTIR_HOST_DEVICE Reservoir<Sample>
    finish(PixelCoord pixel, const Reservoir<Sample>& reservoir, const Visibility& visible)
    const { return tested(pixel, reservoir, visible); }

private:
    // Whether a spatial pass combines at `pixel` (inside the views, a valid surface); a pixel
    // that does not keeps its reservoir (`kept`: empty outside the views).
    RESTIR_HOST_DEVICE bool combines_spatially(PixelCoord pixel,
                                               ImageView<const Reservoir<Sample>> input) const {
        RESTIR_ASSERT(input.contains(pixel) && surfaces.contains(pixel));
        return input.contains(pixel) && surfaces.contains(pixel) &&
               is_valid_surface(surface_at(surfaces, pixel));
    }
    RESTIR_HOST_DEVICE Reservoir<Sample> kept(PixelCoord pixel,
                                              ImageView<const Reservoir<Sample>> input) const {
        return input.contains(pixel) ? input[pixel] : Reservoir<Sample>{};
    }
    // A spatial pass's combination at a pixel that combines, retested before another pass.
    template <class Inputs, class Target, class Visibility, class MaterialTest, UniformRng Rng>
    RESTIR_HOST_DEVICE Reservoir<Sample>
    spatial_result(PixelCoord pixel, std::uint32_t pass, ImageView<const Reservoir<Sample>> input,
                   const Inputs& inputs,
                   const ReuseBridge<Target, Visibility, MaterialTest>& bridge, Rng& rng) const {
        Reservoir<Sample> result = combine_inputs(input[pixel], surface_at(surfaces, pixel), inputs,
                                                  spatial_params().reuse, bridge, rng);
        if (pass + 1u < params.spatial_passes)
            retest(pixel, result, input[pixel], bridge.visibility);
        return result;
    }
    // Stages 1 and 5: `reservoir` with W = 0 when occluded, under visibility reuse.
    template <class Visibility>
    RESTIR_HOST_DEVICE Reservoir<Sample> tested(PixelCoord pixel, Reservoir<Sample> reservoir,
                                                const Visibility& visible) const {
        if (!params.deferred_visibility && needs_visibility_test(reservoir))
            apply_visibility(reservoir, surface_at(surfaces, pixel), visible);
        return reservoir;
    }
    template <class Visibility>
    RESTIR_HOST_DEVICE void retest(PixelCoord pixel, Reservoir<Sample>& result,
                                   const Reservoir<Sample>& input,
                                   const Visibility& visible) const {
        if (!params.deferred_visibility && needs_visibility_test(result, input))
            apply_visibility(result, surface_at(surfaces, pixel), visible);
    }
};

/// Runs one frame of the recipe over the image. `for_each_pixel(body)` calls `body(PixelCoord)`
/// once for every pixel of the image, in any order or in parallel, and returns when all calls
/// have returned. `initial_candidates(pixel, surface, rng)` returns the pixel's finalised RIS
/// reservoir (called for valid surfaces only). `rng_for(pixel, stream)` returns a generator
/// for the pixel and a `RngStream` stream (e.g. `make_pixel_rng(index, frame, stream, seed)`).
/// Writes the final reservoirs to `out`, which becomes the next frame's `history`; `scratch`
/// is the second working buffer; both have the image's size and neither may be `history`.
template <class Sample, Surface S, Reprojection Reproject, class History, class Surfaces,
          class ForEachPixel, class Initial, class Target, class Visibility, class MaterialTest,
          class RngFor>
void run_di_frame(const DiFrame<Sample, S, Reproject, History, Surfaces>& frame,
                  ImageView<Reservoir<Sample>> out, ImageView<Reservoir<Sample>> scratch,
                  const ForEachPixel& for_each_pixel, const Initial& initial_candidates,
                  const ReuseBridge<Target, Visibility, MaterialTest>& bridge,
                  const RngFor& rng_for) {
    const DiFrameParams& p = frame.params;
    // Stages that read neighbours write a new buffer; ping-pong so that the last one is `out`.
    const std::uint32_t loops = 1u + p.spatial_passes + (p.boiling_filter ? 1u : 0u);
    ImageView<Reservoir<Sample>> target = loops % 2u == 1u ? out : scratch;
    ImageView<Reservoir<Sample>> other = loops % 2u == 1u ? scratch : out;
    std::uint32_t remaining = loops;
    const auto last = [&](PixelCoord pixel, Reservoir<Sample> r) {
        return remaining == 1u ? frame.finish(pixel, r, bridge.visibility) : r;
    };
    // Stages 1 and 2.
    for_each_pixel([&](PixelCoord pixel) {
        Reservoir<Sample> r{};
        const auto& surface = surface_at(frame.surfaces, pixel);
        if (is_valid_surface(surface)) {
            auto rng = rng_for(pixel, RngStream::initial);
            r = frame.initial(pixel, initial_candidates(pixel, surface, rng), bridge.visibility);
            auto temporal_rng = rng_for(pixel, RngStream::temporal);
            r = frame.temporal(pixel, r, bridge, temporal_rng);
        }
        // Without history and further passes, stage 1 has tested the sample already.
        target[pixel] = remaining == 1u && !frame.has_history() ? r : last(pixel, r);
    });
    // Stage 3.
    for (std::uint32_t pass = 0; pass < p.spatial_passes; ++pass) {
        --remaining;
        const ImageView<const Reservoir<Sample>> input = target;
        ImageView<Reservoir<Sample>> written = other;
        for_each_pixel([&](PixelCoord pixel) {
            auto rng = rng_for(pixel, RngStream::spatial + pass);
            written[pixel] = last(pixel, frame.spatial(pixel, pass, input, bridge, rng));
        });
        other = target;
        target = written;
    }
    // Stage 4; stage 5 ran in the last loop.
    if (p.boiling_filter) {
        --remaining;
        const ImageView<const Reservoir<Sample>> input = target;
        for_each_pixel(
            [&](PixelCoord pixel) { other[pixel] = last(pixel, frame.boiling(pixel, input)); });
    }
}

} // namespace restir
