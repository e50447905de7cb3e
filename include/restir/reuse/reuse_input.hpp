/// @file reuse/reuse_input.hpp
/// A reservoir that a reuse step borrows, and the test that decides whether a pixel's
/// reservoir may be borrowed at all.
#pragma once

#include "restir/concepts.hpp"
#include "restir/config.hpp"
#include "restir/core/reservoir.hpp"
#include "restir/reuse/image_view.hpp"
#include "restir/reuse/similarity.hpp"

namespace restir {

/// A reservoir borrowed from another pixel or frame, with the surface it was computed for.
/// Both pointers refer into the caller's buffers; null when there is nothing to borrow.
template <class Sample, class SurfaceT>
struct ReuseInput {
    const Reservoir<Sample>* reservoir = nullptr;
    const SurfaceT* surface = nullptr;
};

/// The reservoir of pixel `p` with its surface, if `receiver` may borrow it: `p` lies in both
/// images, the reservoir is finite and the surfaces are similar. Otherwise null pointers.
template <class Sample, Surface S, class MaterialTest>
RESTIR_HOST_DEVICE ReuseInput<Sample, S>
reusable_input(PixelCoord p, const S& receiver, ImageView<const Reservoir<Sample>> reservoirs,
               ImageView<const S> surfaces, const SimilarityParams& similarity,
               const MaterialTest& material_test) {
    if (!reservoirs.contains(p) || !surfaces.contains(p) || !reservoirs[p].is_well_formed() ||
        !surfaces_similar(receiver, surfaces[p], similarity, material_test))
        return {};
    return {&reservoirs[p], &surfaces[p]};
}

} // namespace restir
