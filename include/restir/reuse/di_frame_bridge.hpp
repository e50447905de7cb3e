/// @file reuse/di_frame_bridge.hpp
/// What a frame of the recipe (reuse/di_frame.hpp) needs from the application, in one object:
/// the steps' vocabulary (`DiStage`, `DiStep`), the two reservoir buffers (`DiBuffers`), and
/// the bridge (`DiBridge`): the initial candidates, the reuse functions (`ReuseBridge`: target,
/// visibility, material hook, shift), the pixels' random streams and the shading callback.
/// `visit_stage` is the one place that turns a step's stage into the code that runs it, for
/// the per-pixel, per-tile and per-kernel runs alike.
#pragma once

#include "restir/config.hpp"
#include "restir/core/reservoir.hpp"
#include "restir/core/rng.hpp"
#include "restir/reuse/image_view.hpp"
#include "restir/reuse/reuse_params.hpp"

#include <concepts>
#include <cstdint>
#include <type_traits>
#include <utility>

namespace restir {

/// The stages of a frame, in their order.
enum class DiStage : std::uint8_t { initial, temporal, spatial, boiling, finish };

/// A stage as a type, for code compiled once per stage (`visit_stage`).
template <DiStage Stage>
using DiStageConstant = std::integral_constant<DiStage, Stage>;

/// Calls `f(DiStageConstant<stage>{})` and returns its result: the one dispatch from a step's
/// stage to the code that runs it (a kernel per stage, a tile's batched stage, a pixel's).
/// A new stage is added here, in `DiStage`, in `DiFrame::step` and in `DiFrame::run_stage`.
RESTIR_CALLS_ANY_SIDE
template <class F>
RESTIR_HOST_DEVICE constexpr decltype(auto) visit_stage(DiStage stage, F&& f) {
    switch (stage) {
    case DiStage::initial:
        return std::forward<F>(f)(DiStageConstant<DiStage::initial>{});
    case DiStage::temporal:
        return std::forward<F>(f)(DiStageConstant<DiStage::temporal>{});
    case DiStage::spatial:
        return std::forward<F>(f)(DiStageConstant<DiStage::spatial>{});
    case DiStage::boiling:
        return std::forward<F>(f)(DiStageConstant<DiStage::boiling>{});
    case DiStage::finish:
        break;
    }
    return std::forward<F>(f)(DiStageConstant<DiStage::finish>{});
}

/// One step of a frame: a stage, the buffers it reads and writes (0: `out`, 1: `scratch` of
/// `DiBuffers`), and whether its new samples are retested before the next step reads them.
struct DiStep {
    DiStage stage = DiStage::initial;
    std::uint32_t pass = 0u;   ///< The spatial pass (0 for the other stages).
    std::uint32_t input = 0u;  ///< Buffer read (the initial stage reads none).
    std::uint32_t output = 0u; ///< Buffer written; `finish` writes the buffer it reads, `out`.
    /// Results whose sample differs from the input's are visibility-tested (W = 0 when
    /// occluded): the next step is a spatial pass whose MIS weights trace rays (an unbiased
    /// mode under `ReuseVisibility::traced`), or this is the last reuse step and its input was
    /// tested throughout, so that `finish` needs no ray (`DiFrame::finish_retests`).
    bool retest = false;
};

/// The two reservoir buffers of a frame, each of the image's size: the final reservoirs end
/// in `out` (the next frame's history), `scratch` is the other side of the ping-pong. Neither
/// may be the history.
template <class Sample>
struct DiBuffers {
    ImageView<Reservoir<Sample>> out{};
    ImageView<Reservoir<Sample>> scratch{};
    RESTIR_HOST_DEVICE constexpr ImageView<Reservoir<Sample>> operator[](std::uint32_t i) const {
        return i == 0u ? out : scratch;
    }
};

/// A `shade(pixel, reservoir, visible)` that does nothing: the final reservoirs stay in `out`.
struct NoShading {
    template <class Sample>
    RESTIR_HOST_DEVICE constexpr void operator()(PixelCoord, const Reservoir<Sample>&,
                                                 bool) const noexcept {}
};

/// The application's side of a frame, one object with a member per callback:
///   `initial(pixel, surface, rng)`  the pixel's finalised RIS reservoir (`resample_ris`,
///                                   `resample_lights_and_bsdf`, ...), called for valid
///                                   surfaces only, `rng` from `rng_for(pixel,
///                                   RngStream::initial)`;
///   `reuse`                         a `ReuseBridge`: p-hat, visibility (a
///                                   `VisibilityFunction` for `run_di_frame` per pixel, a
///                                   `BatchVisibility` per tile), material hook, shift;
///   `rng_for(pixel, stream)`        a `UniformRng` for the pixel and a `RngStream` stream, the
///                                   same generator at every call with the same arguments;
///   `shade(pixel, reservoir, visible)` called by `finish` with the final reservoir and
///                                   whether f(y) W is to be shaded (`NoShading` by default).
/// Members may be references (`DiBridge<const I&, ...>`) to callbacks that live elsewhere.
template <class Initial, class Reuse, class RngFor, class Shade = NoShading>
struct DiBridge {
    Initial initial;
    Reuse reuse;
    RngFor rng_for;
    Shade shade{};
};

template <class Initial, class Reuse, class RngFor>
DiBridge(Initial, Reuse, RngFor) -> DiBridge<Initial, Reuse, RngFor, NoShading>;
template <class Initial, class Reuse, class RngFor, class Shade>
DiBridge(Initial, Reuse, RngFor, Shade) -> DiBridge<Initial, Reuse, RngFor, Shade>;

namespace detail {
/// A bridge that refers to callbacks passed one by one (the deprecated forms of 0.2).
template <class Initial, class Reuse, class RngFor, class Shade>
RESTIR_HOST_DEVICE constexpr DiBridge<const Initial&, const Reuse&, const RngFor&, const Shade&>
bridge_of(const Initial& initial, const Reuse& reuse, const RngFor& rng_for, const Shade& shade) {
    return {initial, reuse, rng_for, shade};
}

template <class Bridge>
using BridgeRng = std::remove_cvref_t<decltype(std::declval<const Bridge&>().rng_for(
    PixelCoord{}, std::uint32_t{}))>;
} // namespace detail

/// A bridge (`DiBridge`, or a type of your own with the same members) whose callbacks fit
/// frames of `Sample`s over surfaces `S`. The visibility's form is checked by the run that
/// takes it (per pixel or per tile).
template <class B, class Sample, class S>
concept DiFrameBridge = requires(const B& bridge, PixelCoord pixel, const S& surface,
                                 const Reservoir<Sample>& r, detail::BridgeRng<B>& rng) {
    requires UniformRng<detail::BridgeRng<B>>;
    { bridge.initial(pixel, surface, rng) } -> std::convertible_to<Reservoir<Sample>>;
    { bridge.reuse.target(r.sample, surface) } -> std::convertible_to<float>;
    bridge.shade(pixel, r, true);
};

} // namespace restir
