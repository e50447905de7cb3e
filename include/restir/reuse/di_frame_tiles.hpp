/// @file reuse/di_frame_tiles.hpp
/// The frame recipe (reuse/di_frame.hpp) run per tile of pixels with batched visibility: each
/// stage over a tile gathers the shadow-ray questions it needs (its visibility tests, and the
/// MIS rays of the reuse passes), the application traces them as one batch through a
/// `BatchVisibility` (Embree packets, a ray queue), and the stage resolves. The stage order,
/// the ping-pong and the retest rules are `DiFrame`'s, the same as per pixel. Host code: a tile
/// keeps its questions and answers in arrays on the stack (about 40 KB).
#pragma once

#include "restir/config.hpp"
#include "restir/core/reservoir.hpp"
#include "restir/reuse/bias_correction.hpp"
#include "restir/reuse/di_frame.hpp"
#include "restir/reuse/image_view.hpp"
#include "restir/reuse/reuse_input.hpp"
#include "restir/reuse/surface_source.hpp"

#include <concepts>
#include <cstdint>
#include <span>

namespace restir {

/// A visibility question: is `*sample` visible from `*surface`? Both point into the recipe's
/// buffers, valid during the `trace` call that receives them. (A plain aggregate without
/// member initialisers, so that a tile's array of a thousand questions costs no zeroing.)
template <class Sample, class S>
struct VisibilityQuery {
    const Sample* sample;
    const S* surface;
};

/// Answers many visibility questions at once. Required expression:
///   `tracer.trace(queries, visible)`: sets `visible[i]` to whether `*queries[i].sample` is
///   visible from `*queries[i].surface`; both spans have the same size (at least 1).
template <class T, class Sample, class S>
concept BatchVisibility = requires(const T& tracer,
                                   std::span<const VisibilityQuery<Sample, S>> queries,
                                   std::span<bool> visible) {
    tracer.trace(queries, visible);
};

/// A `BatchVisibility` that asks a `VisibilityFunction` one question at a time.
template <class Visibility>
struct OneByOne {
    Visibility visibility;
    template <class Sample, class S>
    void trace(std::span<const VisibilityQuery<Sample, S>> queries, std::span<bool> visible) const {
        for (std::size_t i = 0; i < queries.size(); ++i)
            visible[i] = visibility(*queries[i].sample, *queries[i].surface);
    }
};

/// The most pixels a tile may hold.
inline constexpr std::uint32_t max_tile_pixels = 64u;
/// The most questions one `trace` call of a tile's stage receives.
inline constexpr std::uint32_t max_tile_queries = max_tile_pixels * (max_reuse_inputs - 1u);

/// A rectangle of pixels, [lower.x, upper.x) x [lower.y, upper.y), of at most
/// `max_tile_pixels` pixels.
struct PixelTile {
    PixelCoord lower{};
    PixelCoord upper{};
    constexpr std::uint32_t width() const noexcept {
        return static_cast<std::uint32_t>(upper.x - lower.x);
    }
    constexpr std::uint32_t pixel_count() const noexcept {
        return width() * static_cast<std::uint32_t>(upper.y - lower.y);
    }
    /// The k-th pixel in rows (0 <= k < pixel_count()).
    constexpr PixelCoord pixel(std::uint32_t k) const noexcept {
        return {lower.x + static_cast<std::int32_t>(k % width()),
                lower.y + static_cast<std::int32_t>(k / width())};
    }
    /// Calls `body(pixel, k)` for every pixel in rows, k counting from 0.
    template <class Body>
    constexpr void for_each_pixel(Body&& body) const {
        std::uint32_t k = 0u;
        for (std::int32_t y = lower.y; y < upper.y; ++y)
            for (std::int32_t x = lower.x; x < upper.x; ++x)
                body(PixelCoord{x, y}, k++);
    }
};

namespace detail {

/// The questions of one stage over a tile, traced as one batch.
template <class Sample, class S>
struct TileQueries {
    static constexpr std::uint32_t capacity = max_tile_queries;
    VisibilityQuery<Sample, S> queries[capacity];
    bool visible[capacity];
    std::uint32_t count = 0u;

    std::uint32_t add(const Sample& sample, const S& surface) {
        RESTIR_ASSERT(count < capacity);
        queries[count] = {&sample, &surface};
        return count++;
    }
    template <class Tracer>
    void trace(const Tracer& tracer) {
        if (count > 0u)
            tracer.trace(std::span<const VisibilityQuery<Sample, S>>(queries, count),
                         std::span<bool>(visible, count));
    }
};

/// The MIS terms of one pixel traced ahead: p-hat of its own (canonical) sample at each input's
/// surface, and whether it is visible there (asked only where p-hat > 0).
template <class Sample, class S>
struct MisAnswers {
    static constexpr std::uint32_t none = 0xffffffffu;
    const Sample* sample = nullptr;
    const S* surfaces[max_reuse_inputs - 1u];
    float target[max_reuse_inputs - 1u];
    std::uint32_t query[max_reuse_inputs - 1u];
    std::uint32_t count = 0u;

    /// The entry for `x` at `surface`, or `none`.
    std::uint32_t find(const Sample& x, const S& surface) const {
        if (sample == nullptr || !(x == *sample))
            return none;
        for (std::uint32_t j = 0; j < count; ++j)
            if (surfaces[j] == &surface)
                return j;
        return none;
    }
};

/// p-hat from a pixel's answers where they have it, else evaluated.
template <class Target, class Sample, class S>
struct AnsweredTarget {
    const Target* target;
    const MisAnswers<Sample, S>* answers;
    float operator()(const Sample& x, const S& surface) const {
        const std::uint32_t j = answers->find(x, surface);
        return j != MisAnswers<Sample, S>::none ? answers->target[j]
                                                : static_cast<float>((*target)(x, surface));
    }
};

/// A `BatchVisibility` asked one question at a time: the `VisibilityFunction` of a stage that
/// runs per pixel inside a tile.
template <class Tracer>
struct OneQueryAtATime {
    const Tracer* tracer;
    template <class Sample, class S>
    bool operator()(const Sample& sample, const S& surface) const {
        const VisibilityQuery<Sample, S> query{&sample, &surface};
        bool visible = false;
        tracer->trace(std::span<const VisibilityQuery<Sample, S>>(&query, 1u),
                      std::span<bool>(&visible, 1u));
        return visible;
    }
};

/// Visibility from a pixel's answers where they have it, else traced on its own.
template <class Tracer, class Sample, class S>
struct AnsweredVisibility {
    const Tracer* tracer;
    const MisAnswers<Sample, S>* answers;
    const bool* visible;
    bool operator()(const Sample& x, const S& surface) const {
        const std::uint32_t j = answers->find(x, surface);
        if (j != MisAnswers<Sample, S>::none)
            return answers->target[j] > 0.0f && visible[answers->query[j]];
        return OneQueryAtATime<Tracer>{tracer}(x, surface);
    }
};

/// A stage's reuse over one tile: the inputs found per pixel, their MIS rays traced as one
/// batch, then every pixel combined with a bridge that answers from them.
template <class Sample, class S, class Target, class Tracer, class MaterialTest>
struct TileReuse {
    const ReuseBridge<Target, Tracer, MaterialTest>& bridge;
    /// Whether the pass's MIS weights ask about each pixel's own sample at every input's
    /// surface (pairwise and the balance heuristic, with traced rays). 1/Z asks about the
    /// sample it selects, known only after the selection: those rays go one at a time.
    bool asks;
    TileQueries<Sample, S> queries;
    MisAnswers<Sample, S> answers[max_tile_pixels];

    TileReuse(const ReuseBridge<Target, Tracer, MaterialTest>& b, const ReuseParams& reuse)
        : bridge(b), asks(traces_mis_rays(reuse.visibility) &&
                          (reuse.bias_correction == BiasCorrection::pairwise ||
                           reuse.bias_correction == BiasCorrection::defensive_pairwise ||
                           reuse.bias_correction == BiasCorrection::balance_heuristic)) {}

    /// Records the MIS questions of pixel `k`: its sample `canonical` at the surfaces of the
    /// lending inputs of `inputs` (a `ReuseInputs` set).
    template <class Inputs>
    void ask(std::uint32_t k, const Reservoir<Sample>& canonical, const Inputs& inputs) {
        MisAnswers<Sample, S>& a = answers[k];
        a.sample = &canonical.sample;
        for_each_input<Sample, S>(
            inputs, [&](std::uint32_t, const Reservoir<Sample>&, const S& there) {
                const float t = static_cast<float>(bridge.target(canonical.sample, there));
                a.surfaces[a.count] = &there;
                a.target[a.count] = t;
                a.query[a.count++] =
                    t > 0.0f ? queries.add(canonical.sample, there) : MisAnswers<Sample, S>::none;
            });
    }
    /// The bridge for pixel `k`'s combination.
    auto answered(std::uint32_t k) const {
        return ReuseBridge<AnsweredTarget<Target, Sample, S>, AnsweredVisibility<Tracer, Sample, S>,
                           MaterialTest>{{&bridge.target, &answers[k]},
                                         {&bridge.visibility, &answers[k], queries.visible},
                                         bridge.material_test};
    }
};

} // namespace detail

/// Visibility reuse for a batch of reservoirs, their shadow rays traced by one
/// `tracer.trace` call (a `BatchVisibility`): `for_each(ask)` calls `ask(reservoir, surface)`
/// for each reservoir to test (at most `max_tile_pixels`, each holding a sample; both stay
/// valid until this returns), and each gets W = 0 where its sample is occluded from its surface.
template <class Sample, class S, class Tracer, class ForEach>
requires BatchVisibility<Tracer, Sample, S>
void apply_visibility_batch(const Tracer& tracer, ForEach&& for_each) {
    detail::TileQueries<Sample, S> queries;
    Reservoir<Sample>* asked[max_tile_pixels];
    for_each([&](Reservoir<Sample>& r, const S& surface) {
        RESTIR_ASSERT(queries.count < max_tile_pixels && r.has_sample());
        asked[queries.count] = &r;
        queries.add(r.sample, surface);
    });
    queries.trace(tracer);
    for (std::uint32_t q = 0; q < queries.count; ++q)
        apply_visibility(*asked[q], queries.visible[q]);
}

namespace detail {

/// Tests the reservoirs of `output` in `tile` for which `needs(pixel, reservoir)` holds, as
/// one batch: W = 0 where occluded.
template <class Sample, class S, class Surfaces, class Tracer, class Needs>
void test_tile(const PixelTile& tile, ImageView<Reservoir<Sample>> output, const Surfaces& surfaces,
               const Tracer& tracer, const Needs& needs) {
    apply_visibility_batch<Sample, S>(tracer, [&](const auto& ask) {
        tile.for_each_pixel([&](PixelCoord pixel, std::uint32_t) {
            Reservoir<Sample>& r = output[pixel];
            if (needs(pixel, r))
                ask(r, surfaces[pixel]);
        });
    });
}

/// `TileReuse` for a frame's reuse bridge (a `ReuseBridge` without a shift).
template <class Sample, class S, class Target, class Tracer, class MaterialTest>
TileReuse<Sample, S, Target, Tracer, MaterialTest>
tile_reuse(const ReuseBridge<Target, Tracer, MaterialTest>& bridge, const ReuseParams& params) {
    return {bridge, params};
}

/// Tests the results of a reuse step over `tile` whose sample the step brought in, when the
/// step retests (`DiStep::retest`).
template <class Frame, class Sample, class Bridge>
void retest_tile(const Frame& frame, const DiStep& step, const PixelTile& tile,
                 const DiBuffers<Sample>& buffers, const Bridge& bridge) {
    if (!step.retest)
        return;
    const ImageView<const Reservoir<Sample>> input = buffers[step.input];
    test_tile<Sample, typename Frame::SurfaceType>(
        tile, buffers[step.output], frame.surfaces, bridge.reuse.visibility,
        [&](PixelCoord pixel, const Reservoir<Sample>& r) {
            return frame.retests(r, input[pixel]);
        });
}

/// A stage over a tile. By default per pixel (`DiFrame::run_stage`), its rays traced one at a
/// time: right for a stage that traces none (the boiling filter); the stages that trace rays
/// gather them into one batch (the specialisations below).
template <DiStage Stage>
struct TileStage {
    template <class Frame, class Sample, class Bridge>
    static void run(const Frame& frame, const DiStep& step, const PixelTile& tile,
                    const DiBuffers<Sample>& buffers, const Bridge& bridge) {
        const auto& reuse = bridge.reuse;
        const ReuseBridge one_at_a_time{
            reuse.target, OneQueryAtATime<decltype(reuse.visibility)>{&reuse.visibility},
            reuse.material_test, reuse.shift};
        const auto per_pixel =
            bridge_of(bridge.initial, one_at_a_time, bridge.rng_for, bridge.shade);
        tile.for_each_pixel([&](PixelCoord pixel, std::uint32_t) {
            frame.template run_stage<Stage>(step, pixel, buffers, per_pixel);
        });
    }
};

/// The initial stage: the candidates of every pixel, then their visibility as one batch.
template <>
struct TileStage<DiStage::initial> {
    template <class Frame, class Sample, class Bridge>
    static void run(const Frame& frame, const DiStep& step, const PixelTile& tile,
                    const DiBuffers<Sample>& buffers, const Bridge& bridge) {
        const ImageView<Reservoir<Sample>> output = buffers[step.output];
        tile.for_each_pixel([&](PixelCoord pixel, std::uint32_t) {
            output[pixel] = frame.initial_reservoir(pixel, bridge.initial, bridge.rng_for);
        });
        test_tile<Sample, typename Frame::SurfaceType>(
            tile, output, frame.surfaces, bridge.reuse.visibility,
            [&](PixelCoord, const Reservoir<Sample>& r) { return frame.tests(r); });
    }
};

/// The temporal stage: every pixel's history input found and its MIS rays asked, traced as
/// one batch, then every pixel combined with the answers.
template <>
struct TileStage<DiStage::temporal> {
    template <class Frame, class Sample, class Bridge>
    static void run(const Frame& frame, const DiStep& step, const PixelTile& tile,
                    const DiBuffers<Sample>& buffers, const Bridge& bridge) {
        using S = typename Frame::SurfaceType;
        const ImageView<Reservoir<Sample>> output = buffers[step.output];
        const ImageView<const Reservoir<Sample>> input = buffers[step.input];
        auto reuse = tile_reuse<Sample, S>(bridge.reuse, frame.temporal_reuse_params());
        decltype(frame.temporal_input(PixelCoord{}, bridge.reuse)) found[max_tile_pixels];
        tile.for_each_pixel([&](PixelCoord pixel, std::uint32_t k) {
            found[k] = frame.temporal_input(pixel, bridge.reuse);
            ReuseInput<Sample, S> lent{};
            if constexpr (Frame::loads_history)
                lent = found[k].lending();
            else
                lent = found[k];
            if (reuse.asks && input[pixel].has_sample())
                reuse.ask(k, input[pixel], ReuseInputSpan<Sample, S>{&lent, 1u});
        });
        reuse.queries.trace(bridge.reuse.visibility);
        tile.for_each_pixel([&](PixelCoord pixel, std::uint32_t k) {
            auto rng = bridge.rng_for(pixel, RngStream::temporal);
            output[pixel] = frame.temporal(pixel, input[pixel], found[k], reuse.answered(k), rng);
        });
        retest_tile(frame, step, tile, buffers, bridge);
    }
};

/// The spatial stage: every pixel's neighbours found (those two pixels ahead prefetched) and
/// its MIS rays asked, traced as one batch, then every pixel combined with the answers.
template <>
struct TileStage<DiStage::spatial> {
    /// How many pixels ahead the search asks for the neighbours of: their first reads are the
    /// pass's cache misses, which one pixel ahead leaves partly exposed.
    static constexpr std::uint32_t ahead = 2u;

    template <class Frame, class Sample, class Bridge>
    static void run(const Frame& frame, const DiStep& step, const PixelTile& tile,
                    const DiBuffers<Sample>& buffers, const Bridge& bridge) {
        using S = typename Frame::SurfaceType;
        const ImageView<const Reservoir<Sample>> input = buffers[step.input];
        auto reuse = tile_reuse<Sample, S>(bridge.reuse, frame.spatial_reuse_params());
        using Rng = decltype(bridge.rng_for(PixelCoord{}, 0u));
        Rng rngs[max_tile_pixels];
        NeighbourDraw draws[max_tile_pixels];
        bool combines[max_tile_pixels];
        // The lending neighbours of each pixel, gathered as they are found.
        detail::UnsetArray<ReuseInput<Sample, S>[max_reuse_inputs - 1u], max_tile_pixels> room;
        ReuseInputSpan<Sample, S> lending[max_tile_pixels];
        tile.for_each_pixel([&](PixelCoord pixel, std::uint32_t k) {
            rngs[k] = bridge.rng_for(pixel, RngStream::spatial + step.pass);
            combines[k] = frame.combines_at(pixel);
            if (combines[k])
                draws[k] = frame.neighbour_draw(pixel, step.pass, rngs[k], bridge.rng_for);
        });
        // Not a lambda: GCC deletes calls of functions whose only effects are prefetches.
        for (std::uint32_t k = 0; k < ahead && k < tile.pixel_count(); ++k)
            if (combines[k])
                prefetch_spatial_neighbours(tile.pixel(k), input, frame.surfaces,
                                            frame.params.spatial, frame.offset_table(), draws[k]);
        tile.for_each_pixel([&](PixelCoord pixel, std::uint32_t k) {
            if (const std::uint32_t next = k + ahead; next < tile.pixel_count() && combines[next])
                prefetch_spatial_neighbours(tile.pixel(next), input, frame.surfaces,
                                            frame.params.spatial, frame.offset_table(),
                                            draws[next]);
            ReuseInput<Sample, S>* gathered = room.items[k];
            lending[k] = {gathered, 0u, no_candidate_cap, true};
            if (!combines[k])
                return;
            // In the streamed set's order.
            frame.neighbours(pixel, input, bridge.reuse, draws[k], [&](PixelCoord p) {
                gathered[lending[k].count++] = {&input[p], &frame.surfaces[p]};
            });
            if (reuse.asks && input[pixel].has_sample())
                reuse.ask(k, input[pixel], lending[k]);
        });
        reuse.queries.trace(bridge.reuse.visibility);
        const ImageView<Reservoir<Sample>> output = buffers[step.output];
        tile.for_each_pixel([&](PixelCoord pixel, std::uint32_t k) {
            output[pixel] =
                combines[k] ? frame.spatial(pixel, input, lending[k], reuse.answered(k), rngs[k])
                            : input[pixel];
        });
        retest_tile(frame, step, tile, buffers, bridge);
    }
};

/// The finish stage: the final visibility of the pixels that need it as one batch, then
/// every pixel shaded.
template <>
struct TileStage<DiStage::finish> {
    template <class Frame, class Sample, class Bridge>
    static void run(const Frame& frame, const DiStep& step, const PixelTile& tile,
                    const DiBuffers<Sample>& buffers, const Bridge& bridge) {
        using S = typename Frame::SurfaceType;
        constexpr std::uint32_t none = MisAnswers<Sample, S>::none;
        const ImageView<Reservoir<Sample>> output = buffers[step.output];
        TileQueries<Sample, S> queries;
        std::uint32_t asked[max_tile_pixels];
        const bool retests = frame.finish_retests();
        tile.for_each_pixel([&](PixelCoord pixel, std::uint32_t k) {
            const Reservoir<Sample>& r = output[pixel];
            asked[k] =
                retests && r.has_sample() ? queries.add(r.sample, frame.surfaces[pixel]) : none;
        });
        queries.trace(bridge.reuse.visibility);
        tile.for_each_pixel([&](PixelCoord pixel, std::uint32_t k) {
            Reservoir<Sample>& r = output[pixel];
            const bool visible = r.has_sample() && (asked[k] == none || queries.visible[asked[k]]);
            if (carries_visibility(frame.params.visibility))
                apply_visibility(r, visible);
            bridge.shade(pixel, static_cast<const Reservoir<Sample>&>(r), visible);
        });
    }
};

} // namespace detail

/// Step `step` of `frame` over `tile`, its rays traced in batches through
/// `bridge.reuse.visibility` (a `BatchVisibility`); `bridge` a `DiFrameBridge`. Every pixel of
/// the image must finish a step before any starts the next. Needs this frame's surfaces in an
/// array (`ImageView`), whose addresses the questions carry.
template <class Sample, Surface S, Reprojection Reproject, class History, class Surfaces,
          class Bridge>
requires DiFrameBridge<Bridge, Sample, S> &&
    BatchVisibility<decltype(std::declval<const Bridge&>().reuse.visibility), Sample, S>
void run_di_step(const DiFrame<Sample, S, Reproject, History, Surfaces>& frame, const DiStep& step,
                 const PixelTile& tile, const DiBuffers<Sample>& buffers, const Bridge& bridge) {
    static_assert(surfaces_in_array<Surfaces, S>,
                  "run_di_step needs this frame's surfaces in an ImageView");
    static_assert(
        requires(const Sample& a, const Sample& b) {
            { a == b } -> std::convertible_to<bool>;
        },
        "run_di_step matches MIS answers by sample: Sample needs operator==");
    RESTIR_ASSERT(tile.pixel_count() <= max_tile_pixels);
    visit_stage(step.stage, [&](auto stage) {
        detail::TileStage<decltype(stage)::value>::run(frame, step, tile, buffers, bridge);
    });
}

/// Runs one frame of the recipe, per tile with batched rays (`bridge.reuse.visibility` a
/// `BatchVisibility`). `for_each_tile(step, body)` calls `body(PixelTile)` for tiles that
/// cover the image once (each of at most `max_tile_pixels`), in any order or in parallel, and
/// returns when all calls have returned; it gets the step so that it may order tiles per stage
/// or time each step.
template <class Sample, Surface S, Reprojection Reproject, class History, class Surfaces,
          class Bridge, class ForEachTile>
requires DiFrameBridge<Bridge, Sample, S> &&
    BatchVisibility<decltype(std::declval<const Bridge&>().reuse.visibility), Sample, S>
void run_di_frame(const DiFrame<Sample, S, Reproject, History, Surfaces>& frame,
                  const DiBuffers<Sample>& buffers, const Bridge& bridge,
                  const ForEachTile& for_each_tile) {
    const std::uint32_t steps = frame.step_count();
    for (std::uint32_t i = 0; i < steps; ++i) {
        const DiStep step = frame.step(i);
        for_each_tile(
            step, [&](const PixelTile& tile) { run_di_step(frame, step, tile, buffers, bridge); });
    }
}

/// The form of 0.2: the callbacks one by one. Deprecated; to be removed in 0.4.
template <class Sample, Surface S, Reprojection Reproject, class History, class Surfaces,
          class Initial, class Target, class Tracer, class MaterialTest, class RngFor,
          class Shade = NoShading>
requires BatchVisibility<Tracer, Sample, S>
[[deprecated("pass a restir::DiBridge: run_di_step(frame, step, tile, buffers, bridge)")]] void
run_di_step(const DiFrame<Sample, S, Reproject, History, Surfaces>& frame, const DiStep& step,
            const PixelTile& tile, const DiBuffers<Sample>& buffers, const Initial& initial,
            const ReuseBridge<Target, Tracer, MaterialTest>& reuse, const RngFor& rng_for,
            const Shade& shade = {}) {
    run_di_step(frame, step, tile, buffers, detail::bridge_of(initial, reuse, rng_for, shade));
}

/// The form of 0.2: the callbacks one by one. Deprecated; to be removed in 0.4.
template <class Sample, Surface S, Reprojection Reproject, class History, class Surfaces,
          class ForEachTile, class Initial, class Target, class Tracer, class MaterialTest,
          class RngFor, class Shade = NoShading>
requires BatchVisibility<Tracer, Sample, S>
[[deprecated("pass a restir::DiBridge: run_di_frame(frame, buffers, bridge, for_each_tile)")]] void
run_di_frame(const DiFrame<Sample, S, Reproject, History, Surfaces>& frame,
             const DiBuffers<Sample>& buffers, const ForEachTile& for_each_tile,
             const Initial& initial, const ReuseBridge<Target, Tracer, MaterialTest>& reuse,
             const RngFor& rng_for, const Shade& shade = {}) {
    run_di_frame(frame, buffers, detail::bridge_of(initial, reuse, rng_for, shade), for_each_tile);
}

} // namespace restir
