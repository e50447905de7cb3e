/// @file sampling/light_tiles.hpp
/// Presampled light tiles (Wyman and Panteleev 2021): once per frame, a few thousand light
/// samples are drawn from the source distribution and evaluated into small contiguous tiles;
/// each pixel then draws its RIS candidates from one tile. Candidate generation reads a few
/// kilobytes that stay in cache instead of the whole light buffer and its alias table.
#pragma once

#include "restir/concepts.hpp"
#include "restir/config.hpp"
#include "restir/core/discrete_sample.hpp"
#include "restir/core/math.hpp"
#include "restir/core/rng.hpp"
#include "restir/light/light_sample.hpp"
#include "restir/sampling/light_candidates.hpp"
#include "restir/sampling/light_sampler.hpp"
#include "restir/sampling/ris.hpp"

#include <glm/vec2.hpp>

#include <cstddef>
#include <cstdint>
#include <type_traits>

namespace restir {

/// One presampled light: the reference a reservoir stores, the source density of having drawn
/// it (pmf of the light times the density 1 of its uniform uv), and the evaluated point.
struct PresampledLight {
    LightSampleRef reference{};
    float pdf = 0.0f;
    LightSample point{};
};

static_assert(std::is_trivially_copyable_v<PresampledLight>);

/// A drawn candidate as a tile entry, its point evaluated with `lights` (none when pdf is 0).
template <LightSet Lights>
RESTIR_HOST_DEVICE PresampledLight presampled(const SourceSample<LightSampleRef>& candidate,
                                              const Lights& lights) {
    PresampledLight entry;
    entry.reference = candidate.sample;
    entry.pdf = candidate.pdf;
    if (candidate.pdf > 0.0f)
        entry.point =
            to_light_sample(lights.sample_point(entry.reference.light_id, entry.reference.uv));
    return entry;
}

/// Draws one light candidate (`draw_light_candidate`: the pdf is the light's pmf) and
/// evaluates it with `lights`. A candidate taken from a tile filled this way, by a uniformly random
/// entry, has exactly the sampler's distribution: RIS over such candidates stays unbiased, since
/// RIS needs each candidate's marginal density, not independence (the estimate is the average of
/// f(x_i) / p(x_i) in expectation, which linearity gives for dependent candidates too).
template <LightSampler Sampler, LightSet Lights, UniformRng Rng>
RESTIR_HOST_DEVICE PresampledLight presample_light(const Sampler& sampler, const Lights& lights,
                                                   Rng& rng) {
    return presampled(draw_light_candidate(sampler, rng), lights);
}

/// `presample_light` from a sampler that reads the shading point, for tiles that serve the
/// region around `at` (a cell of a world-space grid, ReGIR): the entry's pdf is the light's pmf
/// at `at`, which is the density of the entries of that tile wherever they are used.
template <ContextLightSampler Sampler, LightSet Lights, UniformRng Rng>
RESTIR_HOST_DEVICE PresampledLight presample_light(const Sampler& sampler, const ShadingPoint& at,
                                                   const Lights& lights, Rng& rng) {
    return presampled(draw_light_candidate(sampler, at, rng), lights);
}

/// `tile_count` tiles of `tile_size` presampled lights each, contiguous (tile t starts at
/// entry t * tile_size). A view: the caller owns the memory and refills it every frame.
struct LightTilesView {
    const PresampledLight* entries = nullptr;
    std::uint32_t tile_count = 0u;
    std::uint32_t tile_size = 0u;

    /// The tile that a group of pixels (`group`, e.g. an 8 x 8 block index) uses in `frame`:
    /// a hash, so neighbouring groups use different tiles and tiles change every frame.
    RESTIR_HOST_DEVICE constexpr std::uint32_t tile_for(std::uint32_t group,
                                                        std::uint32_t frame) const noexcept {
        const auto h = static_cast<std::uint32_t>(mix64((std::uint64_t{frame} << 32u) | group));
        return tile_count == 0u ? 0u : h % tile_count;
    }

    /// A uniformly chosen entry of tile `tile`, from two uniform numbers in [0, 1) (48 bits:
    /// every entry equally likely within a relative tile_size / 2^48, `wide_uniform_index`).
    RESTIR_HOST_DEVICE constexpr const PresampledLight& draw(std::uint32_t tile, float u0,
                                                             float u1) const noexcept {
        RESTIR_ASSERT(tile < tile_count && tile_size > 0u);
        return entries[std::size_t{tile} * tile_size + wide_uniform_index(u0, u1, tile_size).index];
    }
};

} // namespace restir
