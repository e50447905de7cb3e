/// @file reuse/history.hpp
/// Last frame's reservoirs as temporal reuse reads them. The plain form is an
/// `ImageView<const Reservoir<Sample>>` (reuse then points into it); any type with `empty`,
/// `contains` and `load` is a history too, so that an application keeps its history in its own
/// storage (packed, in its G-buffer) and translates light ids that changed between frames.
#pragma once

#include "restir/config.hpp"
#include "restir/core/reservoir.hpp"
#include "restir/reuse/image_view.hpp"
#include "restir/reuse/reuse_input.hpp"

#include <concepts>
#include <cstdint>
#include <type_traits>

namespace restir {

/// A history that temporal reuse loads from. Required expressions, for a pixel `p`:
///   `h.empty()`    -> bool, true when there is no history (frame 0, a camera cut);
///   `h.contains(p)` -> bool, whether `p` lies in last frame's image;
///   `h.load(p)`    -> Reservoir<Sample>, the reservoir of `p` (inside the image), by value;
///                     an empty reservoir when its sample no longer exists.
/// Optional: `h.surface(p)` -> the previous frame's surface at `p`, decoded by the application
/// from its own G-buffer (`HistorySurfaces`); then the frame needs no array of last frame's
/// surfaces.
template <class H, class Sample>
concept ReservoirHistory = requires(const H& h, PixelCoord p) {
    { h.empty() } -> std::convertible_to<bool>;
    { h.contains(p) } -> std::convertible_to<bool>;
    { h.load(p) } -> std::convertible_to<Reservoir<Sample>>;
};

/// A history that also gives last frame's surfaces: `h.surface(p)` -> S.
template <class H, class SurfaceT>
concept HistorySurfaces = requires(const H& h, PixelCoord p) {
    { h.surface(p) } -> std::convertible_to<SurfaceT>;
};

namespace detail {

/// A history reservoir loaded by value, with the previous-frame surface it belongs to: `Held`
/// a pointer into the previous G-buffer (`const SurfaceT*`), or a copy (`SurfaceT`) when the
/// history decodes surfaces itself. What `DiFrame::temporal_input` returns for a
/// `ReservoirHistory`.
template <class Sample, class SurfaceT, class Held = const SurfaceT*>
struct LoadedHistoryInput {
    Reservoir<Sample> reservoir{};
    Held surface{};
    /// Whether the pixel lends its reservoir (with a pointer, also only where it is not null).
    bool lends = std::is_pointer_v<Held>;
    /// The input as reuse visits it (null pointers when it lends nothing).
    RESTIR_HOST_DEVICE constexpr ReuseInput<Sample, SurfaceT> lending() const noexcept {
        if constexpr (std::is_pointer_v<Held>)
            return lends && surface != nullptr ? ReuseInput<Sample, SurfaceT>{&reservoir, surface}
                                               : ReuseInput<Sample, SurfaceT>{};
        else
            return lends ? ReuseInput<Sample, SurfaceT>{&reservoir, &surface}
                         : ReuseInput<Sample, SurfaceT>{};
    }
};

} // namespace detail

/// The history input's name before 0.2, when it was public.
template <class Sample, class SurfaceT, bool OwnsSurface = false>
using LoadedHistoryInput [[deprecated(
    "internal now: run_di_frame loads the history, and restir::ReuseInput lends one reservoir")]] =
    detail::LoadedHistoryInput<Sample, SurfaceT,
                               std::conditional_t<OwnsSurface, SurfaceT, const SurfaceT*>>;

/// The light-id translation of a history whose light set did not change: every id stays.
struct SameLightIds {
    RESTIR_HOST_DEVICE constexpr std::uint32_t operator()(std::uint32_t id) const noexcept {
        return id;
    }
};

/// What a light-id translation returns for a light that no longer exists.
inline constexpr std::uint32_t removed_light = 0xffffffffu;

} // namespace restir
