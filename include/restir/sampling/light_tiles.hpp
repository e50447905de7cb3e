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
    // Field by field: GCC 12 copies freshly built structs whole, and each such load of values
    // just stored in narrower pieces waits for the stores (store-to-load forwarding fails).
    PresampledLight entry;
    entry.reference.light_id = candidate.sample.light_id;
    entry.reference.uv = candidate.sample.uv;
    entry.pdf = candidate.pdf;
    if (candidate.pdf > 0.0f) {
        const auto p = lights.sample_point(entry.reference.light_id, entry.reference.uv);
        entry.point.position = p.position;
        entry.point.normal = p.normal;
        entry.point.radiance = p.radiance;
        entry.point.area_pdf = p.area_pdf;
        entry.point.is_delta = p.is_delta;
        entry.point.is_distant = is_distant_point(p);
    }
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

/// `presample_light` for entries 0 to count - 1, entry k with its own generator `rng_of(k)`
/// (four numbers each, as `presample_light` draws them), each handed to `store(k, entry)`: the
/// same entries as `presample_light(sampler, lights, rng)` one by one. On a CPU a chunk of draws
/// takes its numbers first and asks for what the draws read ahead (the sampler's
/// `prefetch_address(u0, u1)`, then the lights' `prefetch_address(id)`, where they offer them),
/// so that the cache misses of a tile fill's random reads overlap instead of queueing.
template <LightSampler Sampler, LightSet Lights, class RngOf, class Store>
RESTIR_HOST_DEVICE void presample_lights(const Sampler& sampler, const Lights& lights,
                                         std::uint32_t count, RngOf&& rng_of, Store&& store) {
#if defined(__CUDA_ARCH__)
    constexpr std::uint32_t chunk = 1u; // nothing to prefetch
#else
    constexpr std::uint32_t chunk = 64u;
#endif
    for (std::uint32_t first = 0u; first < count; first += chunk) {
        const std::uint32_t n = min_of(chunk, count - first);
        float u[chunk][4];
        for (std::uint32_t k = 0u; k < n; ++k) {
            auto rng = rng_of(first + k);
            for (float& number : u[k]) // light, then uv: the order of `draw_light_candidate`
                number = next_float(rng);
            detail::prefetch_draw(sampler, u[k][0], u[k][1]);
        }
        DiscreteSample drawn[chunk];
        for (std::uint32_t k = 0u; k < n; ++k) {
            drawn[k] = sampler.sample(u[k][0], u[k][1]);
            if (drawn[k].pmf > 0.0f) // a light, whose point `presampled` evaluates
                detail::prefetch_light(lights, drawn[k].index, glm::vec2(u[k][2], u[k][3]));
        }
        for (std::uint32_t k = 0u; k < n; ++k)
            store(
                first + k,
                presampled({{drawn[k].index, glm::vec2(u[k][2], u[k][3])}, drawn[k].pmf}, lights));
    }
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
