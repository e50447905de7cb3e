// How RIS candidates are drawn (--source): from light tiles presampled by power or uniformly
// per pixel block, from the tiles of a world-space grid (ReGIR), or from a light BVH per pixel.
// One interface for all: the source is chosen once, in make_initial_candidates.
#pragma once

#include "emitter_hits.hpp"
#include "gbuffer.hpp"
#include "light_set.hpp"
#include "pixel_blocks.hpp"
#include "renderer.hpp"
#include "reservoir.hpp"

#include <restir/restir.hpp>

#include <cstdint>
#include <memory>
#include <optional>
#include <span>

namespace pt {

/// The light tiles of --source power and uniform (the tiles that pixel blocks are grouped by).
inline constexpr std::uint32_t light_tile_count = 128;

/// The initial candidates of a pixel: what the source prepares per frame, and the RIS over it.
class InitialCandidates {
public:
    virtual ~InitialCandidates() = default;

    /// After a new VPL set: rebuilds what the source keeps of the light set.
    virtual void use_light_set() {}
    /// Draws what the candidates of frame (or sample) `frame_index` come from, for the
    /// G-buffer `surfaces` just traced.
    virtual void prepare_frame(std::uint32_t frame_index, std::span<const GSurface> surfaces) = 0;
    /// RIS over the candidates of pixel (x, y) with surface `s` (valid) in `frame_index`.
    virtual Reservoir initial_reservoir(std::uint32_t x, std::uint32_t y, std::uint32_t frame_index,
                                        const GSurface& s, restir::Pcg32& rng) const = 0;

    /// body(block) for every pixel block, the blocks that draw from one light tile together,
    /// so that each tile is read from memory once (sources without block tiles: in squares, as
    /// every other stage).
    template <class BlockBody>
    void for_each_block_in_draw_order(const PixelBlocks& blocks, std::uint32_t frame_index,
                                      BlockBody&& body) const {
        const restir::LightTileArrays& tiles = block_tiles();
        if (tiles.tile_count == 0u)
            return blocks.for_each_block(body);
        blocks.for_each_block_by_tile(
            light_tile_count, [&](std::uint32_t b) { return tiles.tile_for(b, frame_index); },
            body);
    }

    /// The tiles that pixel blocks draw from (empty for sources that draw per pixel).
    virtual const restir::LightTileArrays& block_tiles() const;

    /// Multi-strategy RIS over the source's own light candidates (`counts.light`, as
    /// `initial_reservoir` draws them) and `counts.bsdf` BSDF candidates at `receiver`, each
    /// weighted against the other strategy's density (--bsdf-candidates); nothing from a source
    /// that cannot tell its density at a point a BSDF ray found (the grid's tiles, or tiles
    /// whose points are drawn again from the surface).
    virtual std::optional<Reservoir> with_bsdf_candidates(std::uint32_t x, std::uint32_t y,
                                                          std::uint32_t frame_index,
                                                          const restir::CandidateCounts& counts,
                                                          const restir::GlossyReceiver& receiver,
                                                          const EmitterHits& hits,
                                                          restir::Pcg32& rng) const;
};

/// restir::resample_lights_and_bsdf over light candidates from `sampler` (at `receiver`'s point)
/// and BSDF candidates, the light candidates' points as `points` says: uniform in area, or drawn
/// from the receiver (the BSDF candidates then weighed against that map's density).
template <class Sampler>
Reservoir resample_lights_and_bsdf(const Sampler& sampler, LightPoints points,
                                   const restir::CandidateCounts& counts, const LightSet& lights,
                                   const restir::GlossyReceiver& receiver, const EmitterHits& hits,
                                   restir::Pcg32& rng) {
    const restir::ShadingPoint at{receiver.position, receiver.normal, 0.0f};
    if (points == LightPoints::solid_angle)
        return restir::resample_lights_and_bsdf<target_norm, restir::LightPoints::from_receiver>(
            rng, counts, sampler, at, lights.lights(), lights.falloff(), receiver, hits);
    return restir::resample_lights_and_bsdf<target_norm>(rng, counts, sampler, at, lights.lights(),
                                                         lights.falloff(), receiver, hits);
}

/// The source that `settings.source` names, over `lights`.
std::unique_ptr<InitialCandidates> make_initial_candidates(const RenderSettings& settings,
                                                           const Scene& scene,
                                                           const LightSet& lights,
                                                           const PixelBlocks& blocks);

} // namespace pt
