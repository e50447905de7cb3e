/// @file reuse/surface_source.hpp
/// Where the frame recipe and spatial reuse read this frame's surfaces: an
/// `ImageView<const S>` of an array of them (reuse then points into it), or a source that
/// decodes a pixel's surface from the application's own G-buffer on demand, so that a GPU
/// renderer keeps no array of S. (Last frame's surfaces come through the history:
/// `HistorySurfaces`, reuse/history.hpp.)
#pragma once

#include "restir/config.hpp"
#include "restir/reuse/image_view.hpp"

#include <concepts>
#include <type_traits>

namespace restir {

/// A source of decoded surfaces. Required expressions, for a pixel `p`:
///   `g.contains(p)` -> bool, whether `p` lies in the image;
///   `g.surface(p)`  -> S, the surface at `p` (inside the image), by value.
/// Reuse decodes a neighbour's surface every time it visits it (the MIS weights visit each
/// neighbour up to three times): keep the decode cheap, or use an `ImageView`.
template <class G, class S>
concept SurfaceDecoder = requires(const G& g, PixelCoord p) {
    { g.contains(p) } -> std::convertible_to<bool>;
    { g.surface(p) } -> std::convertible_to<S>;
};

/// What this frame's surfaces may be read from: a view of an array of them, or a decoder.
template <class G, class S>
concept SurfaceSource = std::same_as<G, ImageView<const S>> || SurfaceDecoder<G, S>;

/// Whether surfaces of `G` are viewed in an array (reuse keeps pointers to them) rather than
/// decoded (reuse keeps copies).
template <class G, class S>
inline constexpr bool surfaces_in_array = std::same_as<G, ImageView<const S>>;

/// The surface at `p` of a view: a reference into the array.
template <class S>
RESTIR_HOST_DEVICE constexpr const S& surface_at(const ImageView<const S>& surfaces,
                                                 PixelCoord p) noexcept {
    return surfaces[p];
}

/// The surface at `p` of a decoder, by value.
template <class G>
requires requires(const G& g, PixelCoord p) { g.surface(p); }
RESTIR_HOST_DEVICE constexpr auto surface_at(const G& surfaces, PixelCoord p) {
    return surfaces.surface(p);
}

} // namespace restir
