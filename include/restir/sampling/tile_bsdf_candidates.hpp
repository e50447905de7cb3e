/// @file sampling/tile_bsdf_candidates.hpp
/// BSDF candidates beside light candidates taken from presampled light tiles: the batch loop
/// over tile entries (sampling/ris_batch.hpp) with each entry's weight carrying its balance-
/// heuristic MIS weight against the BSDF strategy, then the BSDF-sampled candidates
/// (sampling/bsdf_candidates.hpp) weighted against the tiles' source density. A glossy pixel
/// keeps the tiles' cache-friendly light candidates instead of drawing its own.
#pragma once

#include "restir/concepts.hpp"
#include "restir/config.hpp"
#include "restir/core/channels.hpp"
#include "restir/core/math.hpp"
#include "restir/core/reservoir.hpp"
#include "restir/core/rng.hpp"
#include "restir/light/falloff.hpp"
#include "restir/light/light_point_sample.hpp"
#include "restir/light/receiver.hpp"
#include "restir/sampling/bsdf_candidates.hpp"
#include "restir/sampling/light_tile_arrays.hpp"
#include "restir/sampling/ris_batch.hpp"

#include <glm/vec3.hpp>

#include <cmath>
#include <concepts>
#include <cstdint>

namespace restir {

namespace detail {
/// A tile entry's lane with its MIS weight folded into the inverse density: with p_light =
/// pmf area_pdf the tiles' density of the entry's point and p_bsdf = pdf_wi cos(theta_light) /
/// d^2 the BSDF strategy's there (pdf_wi for a distant light's direction; 0 for a delta light),
///   target * inverse_pdf = p-hat / (M_light p_light + M_bsdf p_bsdf),
/// the balance heuristic's resampling weight (Lin et al. 2022, Eq. 3.4).
template <ChannelNorm Norm, class Value, SamplingReceiver R>
RESTIR_HOST_DEVICE RESTIR_FORCE_INLINE TileLane tile_entry_mis_lane(const Value& value,
                                                                    const R& receiver,
                                                                    float m_light, float m_bsdf) {
    const glm::vec3 position = receiver.position;
    const float target = tile_entry_radiance_target<Norm>(value, position, receiver);
    const auto [x, y, z, d2, inverse_distance] = tile_entry_offset(value, position);
    // d cos(theta_light); d for an isotropic light and for a distant light's unit direction.
    const float emitter =
        max_of(0.0f, -(value(TilePlane::normal_x) * x + value(TilePlane::normal_y) * y +
                       value(TilePlane::normal_z) * z)) +
        value(TilePlane::isotropic) * std::sqrt(d2);
    const glm::vec3 wi{x * inverse_distance, y * inverse_distance, z * inverse_distance};
    const float pdf_wi = static_cast<float>(receiver.direction_pdf(wi));
    const float inverse_pdf = value(TilePlane::inverse_pdf);
    // p_bsdf / p_light = pdf_wi (d cos) / d^3 * (1 / area_pdf) * (1 / pmf).
    const float ratio = pdf_wi * emitter * inverse_distance * inverse_distance * inverse_distance *
                        value(TilePlane::inverse_point_pdf) * inverse_pdf;
    const float scaled = inverse_pdf / (m_light + m_bsdf * (is_valid_weight(ratio) ? ratio : 0.0f));
    return {target, is_valid_weight(scaled) ? scaled : 0.0f};
}
} // namespace detail

/// `evaluate_tile_block` for multi-strategy RIS with `counts.bsdf` BSDF candidates beside
/// `counts.light` tile candidates: each lane's `inverse_pdf` is 1 / (M_light p_light + M_bsdf
/// p_bsdf) in the entry's own measure (`detail::tile_entry_mis_lane`), so that the block's
/// weights are the balance heuristic's and sum, with the BSDF candidates', to the reservoir's
/// w_sum (finalise with `finalize_normalized(1)`). Needs the tiles' `inverse_point_pdf` plane.
template <std::uint32_t Size, ChannelNorm Norm = ChannelNorm::sum, SamplingReceiver R>
RESTIR_HOST_DEVICE std::uint32_t
evaluate_tile_block_mis(const LightTileArrays& tiles, std::uint32_t tile, std::uint32_t first,
                        const R& receiver, const CandidateCounts& counts,
                        CandidateBlock<Size>& block) {
    const float m_light = static_cast<float>(counts.light);
    const float m_bsdf = static_cast<float>(counts.bsdf);
    return detail::evaluate_tile_block_with(tiles, tile, first, block, [&](const auto& value) {
        return detail::tile_entry_mis_lane<Norm>(value, receiver, m_light, m_bsdf);
    });
}

/// Multi-strategy RIS over `counts.light` candidates from light tiles, in groups of `GroupSize`
/// consecutive entries, group g starting at the global entry `first_entry(g)` (a multiple of
/// `GroupSize`, tile t's entries being [t tile_size, (t + 1) tile_size)), and `counts.bsdf`
/// BSDF candidates (a direction from `receiver`, the light it hits from `query`), by the
/// balance heuristic over candidate counts as `resample_lights_and_bsdf`:
///   w_i = p-hat(x_i) / (M_light p_light(x_i) + M_bsdf p_bsdf(x_i)),
/// with p_light(x) = tile_source.pmf(light) area_pdf(x): `tile_source` is the sampler that
/// filled the tiles (its pmf the density of every entry, whichever entries a pixel takes, as
/// long as each is a uniformly random one of its tile) with points uniform in area, as the
/// query's `point.area_pdf` gives them. Returns the finalised reservoir of light point samples
/// (W = w_sum / p-hat(y)); shade with `unshadowed_radiance(sample, receiver) * W`. Uses 2
/// numbers per group and 4 per BSDF candidate.
template <std::uint32_t GroupSize, ChannelNorm Norm = ChannelNorm::sum, UniformRng Rng,
          class FirstEntry, LightSampler TileSource, SamplingReceiver R, LightHitQuery Query>
requires(std::invocable<FirstEntry&, std::uint32_t>)
    RESTIR_HOST_DEVICE Reservoir<LightPointSample> resample_tiles_and_bsdf(
        Rng& rng, const CandidateCounts& counts, const LightTileArrays& tiles,
        FirstEntry&& first_entry, const TileSource& tile_source, const Falloff& falloff,
        const R& receiver, const Query& query) {
    Reservoir<std::uint32_t> from_tiles;
    stream_ris_batch<GroupSize>(
        rng, from_tiles, counts.light, [&](std::uint32_t g, CandidateBlock<GroupSize>& block) {
            const auto entry = static_cast<std::uint32_t>(first_entry(g));
            return evaluate_tile_block_mis<GroupSize, Norm>(
                tiles, entry / tiles.tile_size, entry % tiles.tile_size, receiver, counts, block);
        });
    Reservoir<LightPointSample> reservoir = from_tiles.with_sample(
        from_tiles.has_sample() ? tiles.point_sample(from_tiles.sample) : LightPointSample{});
    detail::stream_bsdf_candidates<Norm>(
        rng, reservoir, counts, falloff, receiver, query, [&](const LightHit& hit) {
            return tile_source.pmf(hit.light_id) * static_cast<float>(hit.point.area_pdf);
        });
    reservoir.finalize_normalized(1.0f);
    return reservoir;
}

} // namespace restir
