/// @file reuse/di_frame.hpp
/// The ReSTIR DI frame recipe: the order of the passes of one frame (Bitterli et al. 2020,
/// Alg. 5 with the visibility reuse of Sec. 4), which buffer each pass reads and writes, where
/// visibility is tested, and what becomes the next frame's history, written once so that
/// every pipeline calls it instead of rewriting it.
///
/// A frame is a list of steps (`DiFrame::step(i)`, `step_count()`); every pixel finishes a step
/// before any pixel starts the next (a kernel launch or a parallel loop per step):
///   1. `initial`   your candidates (`resample_ris`, `resample_ris_batch`), tested for
///                  visibility under visibility reuse,
///   2. `temporal`  combined with last frame's history at the reprojected pixel (no step when
///                  there is no history: frame 0, a camera cut, a new light set),
///   3. `spatial`   combined with k neighbours, `spatial_passes` times, each pass reading the
///                  whole output of the one before,
///   4. `boiling`   optional filter against rare bright samples (reads a window),
///   5. `finish`    the final visibility; your `shade(pixel, reservoir, visible)` is called, and
///                  the reservoir stays in `out` as the next frame's history.
/// A step's results whose sample is new are retested for visibility before a reuse pass whose
/// MIS weights trace rays reads them (`DiStep::retest`), and by the last reuse step when that
/// spares `finish` its rays (`DiFrame::last_reuse_retests`).
///
/// The application's callbacks come in one object, a `DiBridge` (reuse/di_frame_bridge.hpp).
/// Two ways to run a step, one set of rules: per pixel with a `VisibilityFunction` that traces
/// each ray when asked (`DiFrame::run_pixel`, a GPU thread with inline ray queries), or per
/// tile of pixels with a `BatchVisibility` that traces each stage's rays as one batch
/// (reuse/di_frame_tiles.hpp, CPU packets). `run_di_frame(frame, buffers, bridge, schedule)`
/// runs every step over an image.
#pragma once

#include "restir/concepts.hpp"
#include "restir/config.hpp"
#include "restir/core/math.hpp"
#include "restir/core/reservoir.hpp"
#include "restir/core/rng.hpp"
#include "restir/reuse/bias_correction.hpp"
#include "restir/reuse/boiling_filter.hpp"
#include "restir/reuse/di_frame_bridge.hpp"
#include "restir/reuse/di_frame_params.hpp"
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

/// The random streams' name before 0.2.
using DiStream [[deprecated("use restir::RngStream")]] = RngStream;

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
    using SampleType = Sample;
    using SurfaceType = S;
    DiFrameParams params = default_di_frame_params();
    std::uint32_t frame_index = 0u;
    /// This frame's G-buffer.
    Surfaces surfaces{};
    /// Last frame's G-buffer, and the reservoirs that last frame's `finish` stage left in `out`.
    /// Leave `history` empty (`{}`) when it does not apply: in frame 0, after a camera cut,
    /// and after the light set changed (its samples would belong to another integrand).
    /// `previous_surfaces` may stay empty when the history decodes them (`HistorySurfaces`).
    ImageView<const S> previous_surfaces{};
    History history{};
    Reproject reproject{};
    /// The spatial passes' offset table, by reference; null: `default_neighbour_offsets()`
    /// (static storage on the host, constant memory on a GPU). A table of your own must
    /// outlive the frame (device memory for a kernel).
    const NeighbourOffsets* offsets = nullptr;

    /// Whether the history is loaded by value (a `ReservoirHistory`) rather than viewed.
    static constexpr bool loads_history =
        !std::same_as<History, ImageView<const Reservoir<Sample>>>;
    /// Whether the history decodes last frame's surfaces itself (`HistorySurfaces`): then
    /// `previous_surfaces` may stay empty.
    static constexpr bool history_has_surfaces = HistorySurfaces<History, S>;

    /// Whether `history` is empty (frame 0, a camera cut, a new light set).
    RESTIR_HOST_DEVICE constexpr bool history_is_empty() const noexcept {
        if constexpr (loads_history)
            return history.empty();
        else
            return history.data == nullptr;
    }
    /// Whether the temporal stage runs this frame.
    RESTIR_HOST_DEVICE constexpr bool has_history() const noexcept {
        return params.temporal_reuse && !history_is_empty() &&
               (history_has_surfaces || previous_surfaces.data != nullptr);
    }

    // --- The steps ------------------------------------------------------------------------

    /// How many steps this frame has: initial, temporal (with history), the spatial passes,
    /// boiling (when on), finish.
    RESTIR_HOST_DEVICE constexpr std::uint32_t step_count() const noexcept {
        return writer_count() + 1u;
    }
    /// Step `i` (< `step_count()`), with its buffers: the writers alternate so that the last
    /// one writes `out`, which `finish` then completes in place.
    RESTIR_HOST_DEVICE constexpr DiStep step(std::uint32_t i) const noexcept {
        const std::uint32_t writers = writer_count();
        DiStep s;
        if (i >= writers) {
            s.stage = DiStage::finish;
            return s;
        }
        s.output = (writers - 1u - i) % 2u;
        s.input = 1u - s.output;
        const std::uint32_t temporal_steps = has_history() ? 1u : 0u;
        if (i == 0u) {
            s.stage = DiStage::initial;
        } else if (i <= temporal_steps) {
            s.stage = DiStage::temporal;
        } else if (i <= temporal_steps + params.spatial_passes) {
            s.stage = DiStage::spatial;
            s.pass = i - 1u - temporal_steps;
        } else {
            s.stage = DiStage::boiling;
        }
        // Before a spatial pass with traced MIS rays, the samples that a reuse step brought in
        // are tested where they now are (the initial stage tests all of its own).
        const bool reuses = s.stage == DiStage::temporal || s.stage == DiStage::spatial;
        const bool next_is_spatial =
            i >= temporal_steps && i < temporal_steps + params.spatial_passes;
        s.retest = reuses && (next_is_spatial ? retests_for_mis_rays()
                                              : i == writers - 1u && last_reuse_retests());
        return s;
    }

    /// The settings of the temporal pass as the recipe runs it: every input tested.
    RESTIR_HOST_DEVICE constexpr ReuseParams temporal_reuse_params() const noexcept {
        return {params.temporal_bias_correction, recipe_visibility()};
    }
    /// The settings of each spatial pass as the recipe runs it: every input tested.
    RESTIR_HOST_DEVICE constexpr ReuseParams spatial_reuse_params() const noexcept {
        return {params.spatial_bias_correction, recipe_visibility()};
    }
    /// The offset table of the spatial passes.
    RESTIR_HOST_DEVICE const NeighbourOffsets& offset_table() const noexcept {
        return offsets != nullptr ? *offsets : default_neighbour_offsets();
    }

    // --- The rules of visibility ----------------------------------------------------------

    /// Whether the initial stage tests `r`, and `finish` (unless `finish_retests()` is false):
    /// under visibility reuse, every reservoir that holds a sample.
    RESTIR_HOST_DEVICE constexpr bool tests(const Reservoir<Sample>& r) const noexcept {
        return carries_visibility(params.visibility) && r.has_sample();
    }
    /// Whether a step with `retest` tests its `result` for a pixel whose input was `input`: a
    /// sample the step brought in (the pixel's own was tested already).
    RESTIR_HOST_DEVICE constexpr bool retests(const Reservoir<Sample>& result,
                                              const Reservoir<Sample>& input) const {
        if (!result.has_sample())
            return false;
        if constexpr (requires {
                          { result.sample == input.sample } -> std::convertible_to<bool>;
                      })
            return !(input.has_sample() && result.sample == input.sample);
        return true;
    }
    /// Whether `finish` traces the final visibility: not when the initial stage's test is the
    /// last (no temporal or spatial step brought a sample in since), nor when the last reuse
    /// step retested the samples it brought in (`last_reuse_retests`).
    RESTIR_HOST_DEVICE constexpr bool finish_retests() const noexcept {
        return !carries_visibility(params.visibility) ||
               (reuse_step_count() > 0u && !last_reuse_retests());
    }
    /// Whether the last reuse step (temporal or spatial, right before `finish`) retests the
    /// samples it brought in, so that every final sample has been tested at its pixel and
    /// `finish` traces no ray: under visibility reuse without the boiling filter (which would
    /// read the zeroed weights), when every earlier step left its output tested (the initial
    /// stage does; reuse steps do when the MIS rays make them retest). A sample the step kept
    /// was tested at its pixel already, so only the changed ones cost a ray, where `finish`
    /// would trace one for every pixel: the same answers, fewer rays.
    RESTIR_HOST_DEVICE constexpr bool last_reuse_retests() const noexcept {
        const std::uint32_t reuse_steps = reuse_step_count();
        return carries_visibility(params.visibility) && !params.boiling_filter &&
               reuse_steps > 0u && (reuse_steps == 1u || retests_for_mis_rays());
    }

    // --- Per pixel, visibility traced when asked ------------------------------------------

    /// Step `step` at `pixel`, every ray traced through `bridge.reuse.visibility` when asked (a
    /// `VisibilityFunction`); `bridge` a `DiFrameBridge` (reuse/di_frame_bridge.hpp).
    template <class Bridge>
    requires DiFrameBridge<Bridge, Sample, S> RESTIR_HOST_DEVICE void
    run_pixel(const DiStep& step, PixelCoord pixel, const DiBuffers<Sample>& buffers,
              const Bridge& bridge) const {
        visit_stage(step.stage, [&](auto stage) {
            run_stage<decltype(stage)::value>(step, pixel, buffers, bridge);
        });
    }

    /// `run_pixel` for a step of stage `Stage` (`step.stage`), for a kernel per stage that
    /// compiles only that stage's code. The stages' bodies, in their order.
    template <DiStage Stage, class Bridge>
    requires DiFrameBridge<Bridge, Sample, S> RESTIR_HOST_DEVICE void
    run_stage(const DiStep& step, PixelCoord pixel, const DiBuffers<Sample>& buffers,
              const Bridge& bridge) const {
        static_assert(VisibilityFunction<decltype(bridge.reuse.visibility), Sample, S>,
                      "per pixel, bridge.reuse.visibility is a VisibilityFunction");
        RESTIR_ASSERT(step.stage == Stage);
        const auto& reuse = bridge.reuse;
        const ImageView<Reservoir<Sample>> output = buffers[step.output];
        const ImageView<const Reservoir<Sample>> input = buffers[step.input];
        if constexpr (Stage == DiStage::initial) {
            Reservoir<Sample> r = initial_reservoir(pixel, bridge.initial, bridge.rng_for);
            if (tests(r))
                apply_visibility(r, surface_at(surfaces, pixel), reuse.visibility);
            output[pixel] = r;
        } else if constexpr (Stage == DiStage::temporal) {
            auto rng = bridge.rng_for(pixel, RngStream::temporal);
            Reservoir<Sample> r =
                temporal(pixel, input[pixel], temporal_input(pixel, reuse), reuse, rng);
            retest_immediately(step, pixel, r, input[pixel], reuse.visibility);
            output[pixel] = r;
        } else if constexpr (Stage == DiStage::spatial) {
            auto rng = bridge.rng_for(pixel, RngStream::spatial + step.pass);
            Reservoir<Sample> r = input[pixel];
            if (combines_at(pixel))
                r = spatial_here(pixel, input, reuse,
                                 neighbour_draw(pixel, step.pass, rng, bridge.rng_for), rng);
            retest_immediately(step, pixel, r, input[pixel], reuse.visibility);
            output[pixel] = r;
        } else if constexpr (Stage == DiStage::boiling) {
            output[pixel] = boiling_filter(pixel, input, params.boiling);
        } else {
            Reservoir<Sample> r = output[pixel];
            bool visible = r.has_sample();
            if (visible && finish_retests())
                visible = reuse.visibility(r.sample, surface_at(surfaces, pixel));
            if (carries_visibility(params.visibility)) {
                apply_visibility(r, visible);
                output[pixel] = r;
            }
            bridge.shade(pixel, static_cast<const Reservoir<Sample>&>(r), visible);
        }
    }

    /// The form of 0.2: the callbacks one by one. Deprecated; to be removed in 0.4.
    template <class Initial, class Target, class Visibility, class MaterialTest, class Shift,
              class RngFor, class Shade = NoShading>
    [[deprecated("pass a restir::DiBridge: run_pixel(step, pixel, buffers, "
                 "bridge)")]] RESTIR_HOST_DEVICE void
    run_pixel(const DiStep& step, PixelCoord pixel, const DiBuffers<Sample>& buffers,
              const Initial& initial,
              const ReuseBridge<Target, Visibility, MaterialTest, Shift>& reuse,
              const RngFor& rng_for, const Shade& shade = {}) const {
        run_pixel(step, pixel, buffers, detail::bridge_of(initial, reuse, rng_for, shade));
    }
    /// The form of 0.2: the callbacks one by one. Deprecated; to be removed in 0.4.
    template <DiStage Stage, class Initial, class Target, class Visibility, class MaterialTest,
              class Shift, class RngFor, class Shade = NoShading>
    [[deprecated("pass a restir::DiBridge: run_stage<Stage>(step, pixel, buffers, "
                 "bridge)")]] RESTIR_HOST_DEVICE void
    run_stage(const DiStep& step, PixelCoord pixel, const DiBuffers<Sample>& buffers,
              const Initial& initial,
              const ReuseBridge<Target, Visibility, MaterialTest, Shift>& reuse,
              const RngFor& rng_for, const Shade& shade = {}) const {
        run_stage<Stage>(step, pixel, buffers, detail::bridge_of(initial, reuse, rng_for, shade));
    }

    // --- The parts of a stage, for the per-pixel and the per-tile runs ----------------------

    /// Whether reuse combines at `pixel` (inside the image, a valid surface); another pixel
    /// keeps its reservoir.
    RESTIR_HOST_DEVICE bool combines_at(PixelCoord pixel) const {
        return surfaces.contains(pixel) && is_valid_surface(surface_at(surfaces, pixel));
    }
    /// The initial stage's reservoir at `pixel` before its visibility test (empty for an
    /// invalid surface).
    template <class Initial, class RngFor>
    RESTIR_HOST_DEVICE Reservoir<Sample> initial_reservoir(PixelCoord pixel,
                                                           const Initial& initial_candidates,
                                                           const RngFor& rng_for) const {
        Reservoir<Sample> r{};
        if (combines_at(pixel)) {
            auto rng = rng_for(pixel, RngStream::initial);
            r = initial_candidates(pixel, surface_at(surfaces, pixel), rng);
        }
        return r;
    }
    /// The history input that the temporal stage of `pixel` reuses: a `ReuseInput` pointing
    /// into the history view, or for a `ReservoirHistory` a `detail::LoadedHistoryInput`
    /// (both lend nothing where the history does not apply).
    template <class Bridge>
    RESTIR_HOST_DEVICE auto temporal_input(PixelCoord pixel, const Bridge& bridge) const {
        std::conditional_t<loads_history, LoadedInput, ReuseInput<Sample, S>> found{};
        if (!has_history() || !combines_at(pixel))
            return found;
        const auto& here = surface_at(surfaces, pixel);
        const SimilarityParams& similarity = params.temporal.similarity;
        const PixelCoord p = history_pixel_at(here, reproject(pixel), params.temporal, frame_index);
        if constexpr (history_has_surfaces) {
            if (history.contains(p)) {
                found.reservoir = history.load(p);
                found.surface = history.surface(p);
                found.lends =
                    found.reservoir.is_well_formed() &&
                    surfaces_similar(here, found.surface, similarity, bridge.material_test);
            }
        } else if constexpr (loads_history) {
            if (history.contains(p) && previous_surfaces.contains(p)) {
                found.reservoir = history.load(p);
                if (found.reservoir.is_well_formed() &&
                    surfaces_similar(here, previous_surfaces[p], similarity, bridge.material_test))
                    found.surface = &previous_surfaces[p];
            }
        } else {
            found = reusable_input(p, here, history, previous_surfaces, similarity,
                                   bridge.material_test);
        }
        return found;
    }
    /// The temporal stage's combination of `current` with the history `found` for it
    /// (`current` unchanged where `found` lends nothing). Draws one uniform number per input
    /// that takes part.
    template <class Input, class Bridge, UniformRng Rng>
    RESTIR_HOST_DEVICE Reservoir<Sample>
    temporal(PixelCoord pixel, const Reservoir<Sample>& current, const Input& found,
             const Bridge& bridge, Rng& rng) const {
        ReuseInput<Sample, S> input{};
        if constexpr (loads_history)
            input = found.lending();
        else
            input = found;
        // One named result, returned once, so that it is built in place.
        Reservoir<Sample> result = current;
        if (input.reservoir != nullptr && combines_at(pixel))
            result =
                restir::temporal_combine(current, surface_at(surfaces, pixel), input,
                                         params.temporal, temporal_reuse_params(), bridge, rng);
        return result;
    }
    /// The neighbours that a spatial pass of `pixel` (which must `combines_at`) reuses from
    /// `input`, the whole output of the step before; `lending(p)` for each that lends, in order.
    /// Two uniform numbers, the pixel's own (`spatial_draw_span` is the recipe's: with a span,
    /// pass `neighbour_draw`'s draw to the overload below).
    template <class Bridge, UniformRng Rng, class Lending = IgnoreLending>
    RESTIR_HOST_DEVICE SpatialNeighbours<Sample, S, Surfaces>
    neighbours(PixelCoord pixel, ImageView<const Reservoir<Sample>> input, const Bridge& bridge,
               Rng& rng, const Lending& lending = {}) const {
        return neighbours(pixel, input, bridge, draw_neighbours(rng), lending);
    }
    /// The two numbers that choose the neighbours of `pixel` (inside the image) in spatial pass
    /// `pass` (`draw_neighbours`): drawn from `rng`, the pixel's generator of the pass, or, with
    /// `params.spatial_draw_span` > 1 and `pixel` not the first of its span, the first two of
    /// the pass's generator of the span's first pixel (x - x mod span, y): `rng_for(that
    /// pixel, RngStream::spatial + pass)`.
    template <UniformRng Rng, class RngFor>
    RESTIR_HOST_DEVICE NeighbourDraw neighbour_draw(PixelCoord pixel, std::uint32_t pass, Rng& rng,
                                                    const RngFor& rng_for) const {
        RESTIR_ASSERT(pixel.x >= 0);
        const std::uint32_t span = params.spatial_draw_span; // 0 counts as 1
        const auto x = static_cast<std::uint32_t>(pixel.x);
        if (span <= 1u || x % span == 0u)
            return draw_neighbours(rng);
        auto first = rng_for(PixelCoord{static_cast<std::int32_t>(x - x % span), pixel.y},
                             RngStream::spatial + pass);
        return draw_neighbours(first);
    }
    /// `neighbours` with the two numbers drawn ahead (`draw_neighbours`, `neighbour_draw`).
    template <class Bridge, class Lending = IgnoreLending>
    RESTIR_HOST_DEVICE SpatialNeighbours<Sample, S, Surfaces>
    neighbours(PixelCoord pixel, ImageView<const Reservoir<Sample>> input, const Bridge& bridge,
               NeighbourDraw draw, const Lending& lending = {}) const {
        return find_spatial_neighbours<Sample, S>(pixel, surface_at(surfaces, pixel), input,
                                                  surfaces, params.spatial, offset_table(),
                                                  bridge.material_test, draw, lending);
    }
    /// A spatial pass's combination at `pixel` (which must `combines_at`) of its reservoir in
    /// `input` with `inputs` (the set `neighbours` found, with the same generator).
    template <class Inputs, class Bridge, UniformRng Rng>
    RESTIR_HOST_DEVICE Reservoir<Sample>
    spatial(PixelCoord pixel, ImageView<const Reservoir<Sample>> input, const Inputs& inputs,
            const Bridge& bridge, Rng& rng) const {
        return combine_inputs(input[pixel], surface_at(surfaces, pixel), inputs,
                              spatial_reuse_params(), bridge, rng);
    }

private:
    // A spatial pass's combination at `pixel`: on a GPU over the streamed neighbours (kept in
    // registers), in host code over those that lend, gathered as they are found.
    template <class Bridge, UniformRng Rng>
    RESTIR_HOST_DEVICE Reservoir<Sample>
    spatial_here(PixelCoord pixel, ImageView<const Reservoir<Sample>> input, const Bridge& bridge,
                 NeighbourDraw draw, Rng& rng) const {
#if !RESTIR_STREAMED_REUSE
        if constexpr (surfaces_in_array<Surfaces, S>) {
            detail::UnsetArray<ReuseInput<Sample, S>, max_reuse_inputs - 1u> room;
            ReuseInput<Sample, S>* gathered = room.items;
            ReuseInputSpan<Sample, S> lending{gathered, 0u, no_candidate_cap, true};
            neighbours(pixel, input, bridge, draw, [&](PixelCoord p) {
                gathered[lending.count++] = {&input[p], &surfaces[p]};
            });
            return spatial(pixel, input, lending, bridge, rng);
        }
#endif
        return spatial(pixel, input, neighbours(pixel, input, bridge, draw), bridge, rng);
    }

    using LoadedInput =
        detail::LoadedHistoryInput<Sample, S,
                                   std::conditional_t<history_has_surfaces, S, const S*>>;

    RESTIR_HOST_DEVICE constexpr std::uint32_t reuse_step_count() const noexcept {
        return (has_history() ? 1u : 0u) + params.spatial_passes;
    }
    RESTIR_HOST_DEVICE constexpr std::uint32_t writer_count() const noexcept {
        return 1u + reuse_step_count() + (params.boiling_filter ? 1u : 0u);
    }
    // Reuse steps before a spatial pass whose MIS weights trace rays retest their new samples.
    RESTIR_HOST_DEVICE constexpr bool retests_for_mis_rays() const noexcept {
        return traces_mis_rays(params.visibility) &&
               params.spatial_bias_correction != BiasCorrection::none;
    }
    RESTIR_HOST_DEVICE constexpr ReuseVisibility recipe_visibility() const noexcept {
        return params.visibility == ReuseVisibility::traced ? ReuseVisibility::traced_inputs_tested
                                                            : params.visibility;
    }
    template <class Visibility>
    RESTIR_HOST_DEVICE void
    retest_immediately(const DiStep& step, PixelCoord pixel, Reservoir<Sample>& result,
                       const Reservoir<Sample>& input, const Visibility& visible) const {
        if (step.retest && retests(result, input))
            apply_visibility(result, surface_at(surfaces, pixel), visible);
    }
};

/// Runs one frame of the recipe over the image, per pixel, every ray traced when asked
/// (`bridge.reuse.visibility` a `VisibilityFunction`). `for_each_pixel(body)` calls
/// `body(PixelCoord)` once for every pixel of the image, in any order or in parallel, and
/// returns when all calls have returned. The final reservoirs end in `buffers.out`, the next
/// frame's history. (reuse/di_frame_tiles.hpp runs it per tile with batched rays.)
template <class Sample, Surface S, Reprojection Reproject, class History, class Surfaces,
          class Bridge, class ForEachPixel>
requires DiFrameBridge<Bridge, Sample, S> &&
    VisibilityFunction<decltype(std::declval<const Bridge&>().reuse.visibility), Sample, S>
void run_di_frame(const DiFrame<Sample, S, Reproject, History, Surfaces>& frame,
                  const DiBuffers<Sample>& buffers, const Bridge& bridge,
                  const ForEachPixel& for_each_pixel) {
    const std::uint32_t steps = frame.step_count();
    for (std::uint32_t i = 0; i < steps; ++i) {
        const DiStep step = frame.step(i);
        for_each_pixel([&](PixelCoord pixel) { frame.run_pixel(step, pixel, buffers, bridge); });
    }
}

/// The form of 0.2: the callbacks one by one. Deprecated; to be removed in 0.4.
template <class Sample, Surface S, Reprojection Reproject, class History, class Surfaces,
          class ForEachPixel, class Initial, class Target, class Visibility, class MaterialTest,
          class Shift, class RngFor, class Shade = NoShading>
requires VisibilityFunction<Visibility, Sample, S>
[[deprecated("pass a restir::DiBridge: run_di_frame(frame, buffers, bridge, for_each_pixel)")]] void
run_di_frame(const DiFrame<Sample, S, Reproject, History, Surfaces>& frame,
             const DiBuffers<Sample>& buffers, const ForEachPixel& for_each_pixel,
             const Initial& initial,
             const ReuseBridge<Target, Visibility, MaterialTest, Shift>& reuse,
             const RngFor& rng_for, const Shade& shade = {}) {
    run_di_frame(frame, buffers, detail::bridge_of(initial, reuse, rng_for, shade), for_each_pixel);
}

/// The form of 0.1: the final reservoirs in `out` and `scratch` the other buffer. Deprecated;
/// to be removed in 0.4.
template <class Sample, Surface S, Reprojection Reproject, class History, class Surfaces,
          class ForEachPixel, class Initial, class Target, class Visibility, class MaterialTest,
          class Shift, class RngFor>
requires VisibilityFunction<Visibility, Sample, S>
[[deprecated("pass restir::DiBuffers{out, scratch} and a restir::DiBridge")]] void
run_di_frame(const DiFrame<Sample, S, Reproject, History, Surfaces>& frame,
             ImageView<Reservoir<Sample>> out, ImageView<Reservoir<Sample>> scratch,
             const ForEachPixel& for_each_pixel, const Initial& initial,
             const ReuseBridge<Target, Visibility, MaterialTest, Shift>& reuse,
             const RngFor& rng_for) {
    run_di_frame(frame, DiBuffers<Sample>{out, scratch},
                 detail::bridge_of(initial, reuse, rng_for, NoShading{}), for_each_pixel);
}

} // namespace restir
