/// @file reuse/spatiotemporal.hpp
/// Fused spatiotemporal reuse (as in Wyman and Panteleev 2021): one resampling step that
/// combines the receiver's fresh reservoir with the previous frame's reservoir at the
/// reprojected pixel and with k previous-frame reservoirs around it. One pass instead of two,
/// and no dependency on this frame's neighbours, at the price of reusing only history.
#pragma once

#include "restir/concepts.hpp"
#include "restir/config.hpp"
#include "restir/core/reservoir.hpp"
#include "restir/core/rng.hpp"
#include "restir/reuse/bias_correction.hpp"
#include "restir/reuse/image_view.hpp"
#include "restir/reuse/neighbour_offsets.hpp"
#include "restir/reuse/reuse_input.hpp"
#include "restir/reuse/similarity.hpp"
#include "restir/reuse/spatial.hpp"
#include "restir/reuse/temporal.hpp"

#include <cstdint>

namespace restir {

/// Fused spatiotemporal resampling of one pixel in frame `frame_index`. `temporal` supplies the
/// similarity, history cap and permutation; `spatial` the neighbour count and radius (its
/// similarity is the temporal one's); `reuse` the bias correction. Every previous-frame
/// reservoir is capped at `temporal.history_cap_multiplier` times the current M. Without a
/// usable history pixel (disocclusion) the neighbours around the reprojected position are
/// still reused.
template <class Sample, Surface S, Reprojection Reproject, class Target, class Visibility,
          class MaterialTest, class Shift, UniformRng Rng>
requires TargetFunction<Target, Sample, S> && VisibilityFunction<Visibility, Sample, S>
    RESTIR_HOST_DEVICE Reservoir<Sample>
    spatiotemporal_resample(PixelCoord pixel, const Reservoir<Sample>& current, const S& surface,
                            ImageView<const Reservoir<Sample>> previous_reservoirs,
                            ImageView<const S> previous_surfaces, const Reproject& reproject,
                            const TemporalParams& temporal, const SpatialParams& spatial,
                            const ReuseParams& reuse, std::uint32_t frame_index,
                            const ReuseBridge<Target, Visibility, MaterialTest, Shift>& bridge,
                            Rng& rng,
                            const NeighbourOffsets& offsets = default_neighbour_offsets()) {
    if (!is_valid_surface(surface))
        return current;
    const PixelCoord previous = history_pixel_at(surface, reproject(pixel), temporal, frame_index);

    const ReuseInput<Sample, S> history =
        reusable_input(previous, surface, previous_reservoirs, previous_surfaces,
                       temporal.similarity, bridge.material_test);
    const std::uint32_t history_count = history.reservoir != nullptr ? 1u : 0u;

    SpatialParams neighbourhood;
    neighbourhood.similarity = temporal.similarity;
    neighbourhood.radius = spatial.radius;
    neighbourhood.min_roughness = spatial.min_roughness;
    neighbourhood.neighbour_count =
        min_of(spatial.neighbour_count, max_reuse_inputs - 1u - history_count);
    // The history pixel (the search's centre) first, then the previous-frame neighbours around
    // it, each capped.
    SpatialNeighbours<Sample, S> inputs =
        find_spatial_neighbours(previous, surface, previous_reservoirs, previous_surfaces,
                                neighbourhood, offsets, bridge.material_test, rng);
    if (history.reservoir != nullptr)
        inputs.lends |= SpatialNeighbours<Sample, S>::centre_slot;
    inputs.candidate_cap = history_cap(current.candidate_count, temporal);
    return combine_inputs(current, surface, inputs, reuse, bridge, rng);
}

/// The fused pass as 0.1 called it: the bias correction was `TemporalParams::reuse` (now
/// `reuse`, here the default: pairwise MIS with traced rays) and the frame number
/// `TemporalParams::frame_index` (now `frame_index`, here 0). Kept until at least 0.3.
template <class Sample, Surface S, Reprojection Reproject, class Target, class Visibility,
          class MaterialTest, class Shift, UniformRng Rng>
requires TargetFunction<Target, Sample, S> && VisibilityFunction<Visibility, Sample, S>
[[deprecated("pass ReuseParams and the frame index after SpatialParams")]] RESTIR_HOST_DEVICE
    Reservoir<Sample>
    spatiotemporal_resample(PixelCoord pixel, const Reservoir<Sample>& current, const S& surface,
                            ImageView<const Reservoir<Sample>> previous_reservoirs,
                            ImageView<const S> previous_surfaces, const Reproject& reproject,
                            const TemporalParams& temporal, const SpatialParams& spatial,
                            const NeighbourOffsets& offsets,
                            const ReuseBridge<Target, Visibility, MaterialTest, Shift>& bridge,
                            Rng& rng) {
    return spatiotemporal_resample(pixel, current, surface, previous_reservoirs, previous_surfaces,
                                   reproject, temporal, spatial, ReuseParams{}, 0u, bridge, rng,
                                   offsets);
}

/// The fused pass as it was between 0.1 and 0.2, with the neighbour search in a
/// `NeighbourSearch` and the bias correction in the removed `TemporalParams::reuse`: here
/// `reuse` and `frame_index` are arguments of their own. Kept until at least 0.3.
template <class Sample, Surface S, Reprojection Reproject, class Target, class Visibility,
          class MaterialTest, class Shift, UniformRng Rng>
requires TargetFunction<Target, Sample, S> && VisibilityFunction<Visibility, Sample, S>
[[deprecated("pass SpatialParams, ReuseParams and the frame index")]] RESTIR_HOST_DEVICE
    Reservoir<Sample>
    spatiotemporal_resample(PixelCoord pixel, const Reservoir<Sample>& current, const S& surface,
                            ImageView<const Reservoir<Sample>> previous_reservoirs,
                            ImageView<const S> previous_surfaces, const Reproject& reproject,
                            const TemporalParams& temporal, const NeighbourSearch& search,
                            const NeighbourOffsets& offsets,
                            const ReuseBridge<Target, Visibility, MaterialTest, Shift>& bridge,
                            Rng& rng, const ReuseParams& reuse = {},
                            std::uint32_t frame_index = 0u) {
    SpatialParams spatial;
    spatial.neighbour_count = search.neighbour_count;
    spatial.radius = search.radius;
    return spatiotemporal_resample(pixel, current, surface, previous_reservoirs, previous_surfaces,
                                   reproject, temporal, spatial, reuse, frame_index, bridge, rng,
                                   offsets);
}

} // namespace restir
