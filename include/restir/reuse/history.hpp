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

/// A history reservoir loaded by value, with the previous-frame surface it belongs to: a
/// pointer into the previous G-buffer, or, when the history decodes surfaces itself
/// (`OwnsSurface`), a copy. What `DiFrame::temporal_input` returns for a `ReservoirHistory`.
template <class Sample, class SurfaceT, bool OwnsSurface = false>
struct LoadedHistoryInput {
    Reservoir<Sample> reservoir{};
    const SurfaceT* surface = nullptr; ///< Null when the pixel lends nothing.
    /// The input as reuse visits it (null pointers when it lends nothing).
    RESTIR_HOST_DEVICE constexpr ReuseInput<Sample, SurfaceT> lending() const noexcept {
        return surface != nullptr ? ReuseInput<Sample, SurfaceT>{&reservoir, surface}
                                  : ReuseInput<Sample, SurfaceT>{};
    }
};

template <class Sample, class SurfaceT>
struct LoadedHistoryInput<Sample, SurfaceT, true> {
    Reservoir<Sample> reservoir{};
    SurfaceT surface{};
    bool lends = false;
    RESTIR_HOST_DEVICE constexpr ReuseInput<Sample, SurfaceT> lending() const noexcept {
        return lends ? ReuseInput<Sample, SurfaceT>{&reservoir, &surface}
                     : ReuseInput<Sample, SurfaceT>{};
    }
};

} // namespace detail

/// The history input's name before 0.2, when it was public.
template <class Sample, class SurfaceT, bool OwnsSurface = false>
using LoadedHistoryInput [[deprecated(
    "internal now: run_di_frame loads the history, and restir::ReuseInput lends one reservoir")]] =
    detail::LoadedHistoryInput<Sample, SurfaceT, OwnsSurface>;

/// The light-id translation of a history whose light set did not change: every id stays.
struct SameLightIds {
    RESTIR_HOST_DEVICE constexpr std::uint32_t operator()(std::uint32_t id) const noexcept {
        return id;
    }
};

/// What a light-id translation returns for a light that no longer exists.
inline constexpr std::uint32_t removed_light = 0xffffffffu;

} // namespace restir
