/// @file reuse/spatial.hpp
/// Spatial reuse (Bitterli et al. 2020, Sec. 4 and Alg. 5): the receiver's reservoir is
/// combined with the reservoirs of k neighbours inside a radius, chosen from a fixed
/// low-discrepancy offset set from a random start and randomly rotated per pixel. Run it any
/// number of times, ping-ponging between two reservoir buffers.
#pragma once

#include "restir/concepts.hpp"
#include "restir/config.hpp"
#include "restir/core/math.hpp"
#include "restir/core/reservoir.hpp"
#include "restir/core/rng.hpp"
#include "restir/reuse/bias_correction.hpp"
#include "restir/reuse/image_view.hpp"
#include "restir/reuse/neighbour_offsets.hpp"
#include "restir/reuse/reuse_input.hpp"
#include "restir/reuse/similarity.hpp"
#include "restir/reuse/surface_source.hpp"

#include <cmath>
#include <cstdint>
#include <type_traits>

namespace restir {

/// Where a pass looks for neighbours: k offsets in a disk of `radius` pixels. Only the
/// deprecated overload of `spatiotemporal_resample` takes it; the fused pass takes
/// `SpatialParams` again, as in 0.1. Deprecated; to be removed in 0.4.
struct [[deprecated("use restir::SpatialParams (neighbour_count, radius)")]] NeighbourSearch {
    std::uint32_t neighbour_count = 3u; ///< k, at most max_reuse_inputs - 1.
    float radius = 30.0f;               ///< In pixels.
};

/// Where one spatial pass looks for neighbours. (The bias correction and visibility are a
/// `ReuseParams` of their own.)
struct SpatialParams {
    SimilarityParams similarity{};
    /// k: neighbours tried per pixel (the paper: 5 for the biased mode, 3 for unbiased ones).
    /// At most max_reuse_inputs - 1.
    std::uint32_t neighbour_count = 3u;
    /// Radius of the neighbourhood in pixels (the paper's 30).
    float radius = 30.0f;
    /// Receivers smoother than this (`reuse_roughness`) take no neighbours: their canonical
    /// reservoir passes through. A neighbour's sample seldom lies in a narrow lobe, and one
    /// that does brings a weight bounded by the neighbour's integral, not the receiver's
    /// (docs/noise-and-bias.md, "Narrow lobes"). 0: every receiver takes neighbours.
    float min_roughness = 0.0f;
};

/// The paper's settings for the unbiased modes: k = 3 in 30 pixels.
RESTIR_HOST_DEVICE constexpr SpatialParams default_spatial_params() noexcept { return {}; }

/// `coordinate` moved by `offset` rounded to the nearest pixel, for any float and any int: an
/// offset beyond 2^24 pixels is clamped and NaN counts as 0, the sum saturates at the int
/// range; no conversion or addition is ever undefined.
RESTIR_HOST_DEVICE constexpr std::int32_t offset_coordinate(std::int32_t coordinate,
                                                            float offset) noexcept {
    // Without branches: the sign of a rotated offset is random, and branches on it were
    // mispredicted half the time (a spatial pass computes k of these per pixel).
    constexpr float limit = 16777216.0f;
    const std::uint32_t bits = __builtin_bit_cast(std::uint32_t, offset);
    const bool is_nan = (bits & 0x7fffffffu) > 0x7f800000u;
    const float clamped = is_nan ? 0.0f : min_of(max_of(offset, -limit), limit);
    // Half away from zero: 0.5 with the offset's sign, added, then truncated.
    const float half =
        __builtin_bit_cast(float, (__builtin_bit_cast(std::uint32_t, clamped) & 0x80000000u) |
                                      __builtin_bit_cast(std::uint32_t, 0.5f));
    const std::int64_t sum = std::int64_t{coordinate} + static_cast<std::int64_t>(clamped + half);
    constexpr std::int64_t lowest = -2147483647 - 1;
    constexpr std::int64_t highest = 2147483647;
    return static_cast<std::int32_t>(sum < lowest ? lowest : sum > highest ? highest : sum);
}

/// Neighbour `i` (0 <= i < k) of `pixel` for a pass that drew `start` (its first uniform
/// number, as `uniform_index(u, neighbour_offset_count)`) and `rotation` (cos and sin of an
/// angle from its second, `neighbour_rotation`): offset `start + i` of `offsets` rotated,
/// scaled by the radius (NaN and negative radii count as 0) and rounded to the nearest pixel
/// (`offset_coordinate`: offsets clamped to 2^24, defined for any rotation and any pixel). For
/// renderers that fetch the neighbours' data ahead of the pass (prefetching, packets of rays).
RESTIR_HOST_DEVICE constexpr PixelCoord spatial_neighbour(PixelCoord pixel, std::uint32_t start,
                                                          std::uint32_t i, float radius,
                                                          const NeighbourOffsets& offsets,
                                                          DiskOffset rotation = {1.0f, 0.0f}) {
    const float r = radius > 0.0f ? radius : 0.0f; // NaN and negative: no offset
    const DiskOffset table = offsets[start + i];
    const float x = (rotation.x * table.x - rotation.y * table.y) * r;
    const float y = (rotation.y * table.x + rotation.x * table.y) * r;
    return {offset_coordinate(pixel.x, x), offset_coordinate(pixel.y, y)};
}

/// The rotation (cos, sin) of the offset table for uniform number `u`: a random rotation per
/// pixel and pass, so that the fixed table leaves no directional pattern in the noise (without
/// it, the error of neighbouring pixels correlated differently along x and y).
/// (cos, sin) of the angle 2 pi u, u taken modulo 1 (a non-finite u counts as 0), within
/// 2e-7 of the exact values: a quarter turn from the two highest bits of 4u, and the Taylor
/// polynomials of degree 12 and 11 on [0, pi/2) (truncation below 6e-8). No large-argument
/// reduction, whose table a GPU would keep in local memory.
RESTIR_HOST_DEVICE inline DiskOffset neighbour_rotation(float u) noexcept {
    float turn = is_finite(u) ? u - std::floor(u) : 0.0f;
    turn = turn < 1.0f ? turn : 0.0f; // u - floor(u) rounds to 1 for tiny negative u
    const float quarters = 4.0f * turn;
    const auto quadrant = static_cast<std::uint32_t>(quarters); // 0..3
    const float x = (quarters - static_cast<float>(quadrant)) * 1.57079632679489662f;
    const float x2 = x * x;
    const float s =
        x * (1.0f + x2 * (-1.0f / 6.0f +
                          x2 * (1.0f / 120.0f +
                                x2 * (-1.0f / 5040.0f +
                                      x2 * (1.0f / 362880.0f + x2 * (-1.0f / 39916800.0f))))));
    const float c =
        1.0f +
        x2 * (-0.5f + x2 * (1.0f / 24.0f +
                            x2 * (-1.0f / 720.0f +
                                  x2 * (1.0f / 40320.0f +
                                        x2 * (-1.0f / 3628800.0f + x2 * (1.0f / 479001600.0f))))));
    // Quarter turns: (c, s) -> (-s, c) -> (-c, -s) -> (s, -c).
    const float cos_value = quadrant == 0u ? c : quadrant == 1u ? -s : quadrant == 2u ? -c : s;
    const float sin_value = quadrant == 0u ? s : quadrant == 1u ? c : quadrant == 2u ? -s : -c;
    return {cos_value, sin_value};
}

/// What a spatial pass draws for one pixel before it looks at any neighbour: the start in the
/// offset table and the rotation (`spatial_neighbour`'s `start` and `rotation`).
struct NeighbourDraw {
    std::uint32_t start = 0u;
    DiskOffset rotation{1.0f, 0.0f};
};

/// The two uniform numbers of a pixel's spatial pass, in their order: the start
/// (`uniform_index`) and the rotation (`neighbour_rotation`). `find_spatial_neighbours` takes
/// them from its generator itself; draw them ahead to know a pixel's neighbours before the search
/// (to fetch their data ahead, as the tiled recipe does).
template <UniformRng Rng>
RESTIR_HOST_DEVICE NeighbourDraw draw_neighbours(Rng& rng) {
    NeighbourDraw draw;
    draw.start = uniform_index(next_float(rng), neighbour_offset_count);
    draw.rotation = neighbour_rotation(next_float(rng));
    return draw;
}

/// Asks for the reservoirs and surfaces (an `ImageView` of them) of the k neighbours of
/// `centre` that `draw` gives, ahead of the search (`find_spatial_neighbours`), whose first read
/// of each is a cache miss in a large image. Host code; nothing on a GPU.
template <class Sample, class S>
RESTIR_HOST_DEVICE RESTIR_FORCE_INLINE void
prefetch_spatial_neighbours(PixelCoord centre, ImageView<const Reservoir<Sample>> reservoirs,
                            ImageView<const S> surfaces, const SpatialParams& params,
                            const NeighbourOffsets& offsets, NeighbourDraw draw) {
#if !defined(__CUDA_ARCH__)
    const std::uint32_t count = min_of(params.neighbour_count, max_reuse_inputs - 1u);
    for (std::uint32_t i = 0; i < count; ++i) {
        const PixelCoord p =
            spatial_neighbour(centre, draw.start, i, params.radius, offsets, draw.rotation);
        if (reservoirs.contains(p) && surfaces.contains(p)) {
            RESTIR_PREFETCH(&reservoirs[p]);
            // A surface may straddle two cache lines.
            RESTIR_PREFETCH(&surfaces[p]);
            RESTIR_PREFETCH(reinterpret_cast<const char*>(&surfaces[p] + 1) - 1);
        }
    }
#else
    static_cast<void>(centre), static_cast<void>(reservoirs), static_cast<void>(surfaces);
    static_cast<void>(params), static_cast<void>(offsets), static_cast<void>(draw);
#endif
}

/// The neighbours of a pixel that a reuse pass borrows from, as a `ReuseInputs` set for the bias
/// corrections: first the `centre` pixel where it lends (bit `centre_slot` of `lends`: the history
/// pixel of fused spatiotemporal reuse, whose neighbourhood is searched), then neighbour i of the
/// pass (`spatial_neighbour`) where it lends its reservoir: not the centre itself, inside the
/// image, a similar surface, finite (bit i of `lends`; the others are skipped, not replaced). The
/// set is streamed: a visit recomputes the neighbour from the pass's start and rotation, so that
/// no array of inputs is kept and a GPU thread holds the set in registers (host code gathers the
/// set into a `ReuseInputSpan` once per combination). Every slot lends a well-formed reservoir,
/// so the bias corrections do not check them again. With surfaces from a `SurfaceDecoder` the
/// inputs are `DecodedReuseInput`s, and a visit decodes the neighbour's surface.
template <class Sample, class S, class Surfaces = ImageView<const S>>
struct SpatialNeighbours {
    /// Whether the surfaces are viewed in an array (inputs point into it).
    static constexpr bool in_array = surfaces_in_array<Surfaces, S>;
    using Input = std::conditional_t<in_array, ReuseInput<Sample, S>, DecodedReuseInput<Sample, S>>;
    /// The bit of `lends` that says that the centre pixel lends (first).
    static constexpr std::uint32_t centre_slot = 1u << 31;
    /// 0.2's names of what `ReuseSetTraits` says of this set; to be removed in 0.4.
    [[deprecated("use restir::ReuseSetTraits<Set>::all_lend")]] static constexpr bool packed = true;
    [[deprecated("use restir::ReuseSetTraits<Set>::streamed")]] static constexpr bool streamed =
        true;

    PixelCoord centre{};
    std::uint32_t start = 0u;
    DiskOffset rotation{1.0f, 0.0f};
    float radius = 0.0f;
    const NeighbourOffsets* offsets = nullptr;
    ImageView<const Reservoir<Sample>> reservoirs{};
    Surfaces surfaces{};
    std::uint32_t count = 0u; ///< The neighbours tried.
    /// Bit i: neighbour i lends its reservoir; bit `centre_slot`: the centre does.
    std::uint32_t lends = 0u;
    std::uint32_t candidate_cap = no_candidate_cap; ///< Caps the M each input lends.

    /// Neighbour i's pixel.
    RESTIR_HOST_DEVICE constexpr PixelCoord pixel(std::uint32_t i) const {
        return spatial_neighbour(centre, start, i, radius, *offsets, rotation);
    }
    /// The inputs that lend.
    RESTIR_HOST_DEVICE constexpr std::uint32_t size() const noexcept { return bit_count(lends); }
    /// The j-th input that lends.
    RESTIR_HOST_DEVICE constexpr Input operator[](std::uint32_t j) const {
        RESTIR_ASSERT(j < size());
        PixelCoord p = centre;
        if ((lends & centre_slot) == 0u)
            p = pixel(nth_set_bit(lends, j));
        else if (j > 0u)
            p = pixel(nth_set_bit(lends, j - 1u));
        if constexpr (in_array)
            return {&reservoirs[p], &surfaces[p]};
        else
            return {&reservoirs[p], surfaces.surface(p)};
    }
};

/// The spatial neighbours lend only well-formed reservoirs, computed at each visit.
template <class Sample, class S, class Surfaces>
struct ReuseSetTraits<SpatialNeighbours<Sample, S, Surfaces>> {
    RESTIR_HOST_DEVICE static constexpr bool
    all_lend(const SpatialNeighbours<Sample, S, Surfaces>&) noexcept {
        return true;
    }
    RESTIR_HOST_DEVICE static constexpr std::uint32_t
    candidate_cap(const SpatialNeighbours<Sample, S, Surfaces>& inputs) noexcept {
        return inputs.candidate_cap;
    }
    static constexpr bool streamed = true;
};

/// What `find_spatial_neighbours` tells about each neighbour that lends: nothing.
struct IgnoreLending {
    RESTIR_HOST_DEVICE constexpr void operator()(PixelCoord) const noexcept {}
};

/// The neighbours of `pixel` that a spatial pass with `params` reuses: k offsets taken
/// consecutively from `offsets` from the drawn start, rotated by the drawn angle (`draw`, from
/// `draw_neighbours`), scaled by the radius and rounded, each tested once (`lends_reservoir`).
/// `centre` is the pixel whose neighbourhood is searched (the receiver, or its reprojection into
/// the previous frame); `surface` the receiver's; `surfaces` an `ImageView` or a
/// `SurfaceDecoder`. `lending(p)` is called for each neighbour that lends, in order (host code
/// gathers them there once, where visiting the streamed set again would recompute each
/// neighbour).
template <class Sample, Surface S, class Surfaces, class MaterialTest,
          class Lending = IgnoreLending>
requires SurfaceSource<Surfaces, S> RESTIR_HOST_DEVICE SpatialNeighbours<Sample, S, Surfaces>
find_spatial_neighbours(PixelCoord centre, const S& surface,
                        ImageView<const Reservoir<Sample>> reservoirs, const Surfaces& surfaces,
                        const SpatialParams& params, const NeighbourOffsets& offsets,
                        const MaterialTest& material_test, NeighbourDraw draw,
                        const Lending& lending = {}) {
    using Set = SpatialNeighbours<Sample, S, Surfaces>;
    Set set;
    // Locals while searching: the set is the caller's memory.
    const std::uint32_t count = reuse_roughness(surface) < params.min_roughness
                                    ? 0u
                                    : min_of(params.neighbour_count, max_reuse_inputs - 1u);
    std::uint32_t lends = 0u;
    for (std::uint32_t i = 0; i < count; ++i) {
        const PixelCoord p =
            spatial_neighbour(centre, draw.start, i, params.radius, offsets, draw.rotation);
        if ((p.x == centre.x && p.y == centre.y) ||
            !lends_reservoir(p, surface, reservoirs, surfaces, params.similarity, material_test))
            continue;
        lends |= 1u << i;
        lending(p);
    }
    set.centre = centre;
    set.start = draw.start;
    set.rotation = draw.rotation;
    set.radius = params.radius;
    set.offsets = &offsets;
    set.reservoirs = reservoirs;
    set.surfaces = surfaces;
    set.count = count;
    set.lends = lends;
    return set;
}

/// `find_spatial_neighbours` with its two uniform numbers taken from `rng` (`draw_neighbours`).
template <class Sample, Surface S, class Surfaces, class MaterialTest, UniformRng Rng,
          class Lending = IgnoreLending>
requires SurfaceSource<Surfaces, S> RESTIR_HOST_DEVICE SpatialNeighbours<Sample, S, Surfaces>
find_spatial_neighbours(PixelCoord centre, const S& surface,
                        ImageView<const Reservoir<Sample>> reservoirs, const Surfaces& surfaces,
                        const SpatialParams& params, const NeighbourOffsets& offsets,
                        const MaterialTest& material_test, Rng& rng, const Lending& lending = {}) {
    return find_spatial_neighbours<Sample, S>(centre, surface, reservoirs, surfaces, params,
                                              offsets, material_test, draw_neighbours(rng),
                                              lending);
}

/// Spatial resampling of one pixel: its own reservoir from `reservoirs` combined with its
/// neighbours' under `reuse`, the neighbours streamed (`SpatialNeighbours`) from `offsets`. Reads
/// `reservoirs` and `surfaces` only; write the result to a different buffer. A pixel with an
/// invalid surface keeps its reservoir. Precondition: `pixel` lies in both views (a debug
/// build checks); outside them the result is empty.
template <class Sample, Surface S, class Target, class Visibility, class MaterialTest, class Shift,
          UniformRng Rng>
requires TargetFunction<Target, Sample, S> && VisibilityFunction<Visibility, Sample, S>
    RESTIR_HOST_DEVICE Reservoir<Sample>
    spatial_resample(PixelCoord pixel, ImageView<const Reservoir<Sample>> reservoirs,
                     ImageView<const S> surfaces, const SpatialParams& params,
                     const ReuseParams& reuse,
                     const ReuseBridge<Target, Visibility, MaterialTest, Shift>& bridge, Rng& rng,
                     const NeighbourOffsets& offsets = default_neighbour_offsets()) {
    RESTIR_ASSERT(reservoirs.contains(pixel) && surfaces.contains(pixel));
    if (!reservoirs.contains(pixel) || !surfaces.contains(pixel))
        return Reservoir<Sample>{};
    const Reservoir<Sample>& own = reservoirs[pixel];
    const S& surface = surfaces[pixel];
    if (!is_valid_surface(surface))
        return own;
#if RESTIR_STREAMED_REUSE
    // Streamed: the set stays in registers.
    return combine_inputs(own, surface,
                          find_spatial_neighbours(pixel, surface, reservoirs, surfaces, params,
                                                  offsets, bridge.material_test, rng),
                          reuse, bridge, rng);
#else
    // Gathered as they are found: no neighbour is computed twice.
    detail::UnsetArray<ReuseInput<Sample, S>, max_reuse_inputs - 1u> room;
    ReuseInput<Sample, S>* gathered = room.items;
    ReuseInputSpan<Sample, S> lending{gathered, 0u, no_candidate_cap, true};
    find_spatial_neighbours(pixel, surface, reservoirs, surfaces, params, offsets,
                            bridge.material_test, rng, [&](PixelCoord p) {
                                gathered[lending.count++] = {&reservoirs[p], &surfaces[p]};
                            });
    return combine_inputs(own, surface, lending, reuse, bridge, rng);
#endif
}

} // namespace restir
