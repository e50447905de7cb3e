/// @file sampling/light_grid.hpp
/// A world-space grid of light tiles (ReGIR: Boksansky et al. 2021, "Rendering Many Lights with
/// Grid-Based Reservoirs"). The scene's box is cut into about cubic cells. Every frame, each
/// cell that shading points look up gets a tile of lights resampled for every point that can
/// look it up, and a shading point draws its RIS candidates from its cell's tile
/// (light_tile_arrays.hpp): as cheap as light tiles, and aware of where the lights are like a
/// light BVH.
#pragma once

#include "restir/concepts.hpp"
#include "restir/config.hpp"
#include "restir/core/math.hpp"
#include "restir/core/shading_point.hpp"
#include "restir/light/light_bvh_view.hpp"
#include "restir/sampling/light_candidates.hpp"
#include "restir/sampling/light_sampler.hpp"
#include "restir/sampling/light_tiles.hpp"

#include <glm/common.hpp>
#include <glm/geometric.hpp>
#include <glm/vec3.hpp>

#include <cstdint>
#include <type_traits>

namespace restir {

/// The cells of a box, about cubic. Shading points must lie in the box; points outside it
/// belong to the nearest cell, whose region (`cell_region`) does not cover them.
struct LightGridLayout {
    glm::vec3 lower{0.0f};
    glm::vec3 cell_size{1.0f};
    glm::uvec3 cells{1u}; ///< Along x, y and z.

    /// The box [lower, upper] in `along_longest` cells along its longest side, and along the
    /// others as many cells of about that size as fit them (at least one): a flat scene gets a
    /// flat grid. Empty or degenerate sides get one cell.
    static LightGridLayout over(glm::vec3 lower, glm::vec3 upper, std::uint32_t along_longest) {
        const glm::vec3 size = glm::max(upper - lower, glm::vec3(0.0f));
        const float longest = max_of(max_of(size.x, size.y), size.z);
        const auto count = static_cast<float>(max_of(along_longest, 1u));
        LightGridLayout layout;
        layout.lower = lower;
        if (!(longest > 0.0f) || !is_finite(longest))
            return layout;
        layout.cells = glm::uvec3(glm::clamp(glm::round(size / (longest / count)), 1.0f, count));
        layout.cell_size = glm::max(size / glm::vec3(layout.cells), glm::vec3(longest * 1e-6f));
        return layout;
    }

    /// Cells in all.
    RESTIR_HOST_DEVICE constexpr std::uint32_t cell_count() const noexcept {
        return cells.x * cells.y * cells.z;
    }

    /// The cell that holds `p` (clamped to the box).
    RESTIR_HOST_DEVICE std::uint32_t cell_of(glm::vec3 p) const noexcept {
        const glm::vec3 t = (p - lower) / cell_size;
        const auto index = [](float v, std::uint32_t n) {
            // Compared in float first: a cast of a float past the range is undefined.
            return v > 0.0f ? min_of(static_cast<std::uint32_t>(min_of(v, 4294967040.0f)), n - 1u)
                            : 0u;
        };
        return index(t.x, cells.x) +
               cells.x * (index(t.y, cells.y) + cells.y * index(t.z, cells.z));
    }

    /// The cell of `p` moved by up to half a cell along each axis (`u` uniform in [0, 1)^3).
    /// Without the jitter every point of a cell shares its tile's error, and images show the
    /// cells as blocks; with it, neighbouring cells' errors mix.
    RESTIR_HOST_DEVICE std::uint32_t jittered_cell_of(glm::vec3 p, glm::vec3 u) const noexcept {
        return cell_of(p + (u - 0.5f) * cell_size);
    }

    /// The centre of cell `cell`.
    RESTIR_HOST_DEVICE glm::vec3 cell_centre(std::uint32_t cell) const noexcept {
        const glm::vec3 index(static_cast<float>(cell % cells.x),
                              static_cast<float>(cell / cells.x % cells.y),
                              static_cast<float>(cell / (cells.x * cells.y)));
        return lower + (index + 0.5f) * cell_size;
    }

    /// Every point of the box whose jittered lookup can land in `cell`, as a region for
    /// `light_importance`: its centre, and as radius the cell's diagonal (such a point is less
    /// than a cell from the centre along each axis), 1 % more for rounding; any normal.
    RESTIR_HOST_DEVICE ShadingPoint cell_region(std::uint32_t cell) const noexcept {
        return {cell_centre(cell), glm::vec3(0.0f), 1.01f * glm::length(cell_size)};
    }
};

static_assert(std::is_trivially_copyable_v<LightGridLayout>);

/// A candidate of a cell's tile under way: its light, its target (the light's importance
/// bound at the cell's region) and its RIS weight, target / pmf.
struct GridCandidate {
    std::uint32_t light = 0u;
    float target = 0.0f;
    float weight = 0.0f;
};

namespace detail {
/// How many of `resample_grid_tile`'s draws and entries it takes at a time: on a CPU, the numbers
/// of 64 draws come first, for the prefetches; in device code one, with nothing to prefetch.
RESTIR_HOST_DEVICE constexpr std::uint32_t grid_tile_chunk() {
#if defined(__CUDA_ARCH__)
    return 1u;
#else
    return 64u;
#endif
}

/// Draws `count` lights from `sampler` (two numbers each, the order of `sample_light`) into
/// `scratch`, each with its pmf in `weight` for now, a chunk at a time: the numbers of a chunk
/// first, what each draw reads asked for ahead (`prefetch_draw`), then the draws.
template <LightSampler Sampler, UniformRng Rng>
RESTIR_HOST_DEVICE RESTIR_FORCE_INLINE void draw_grid_candidates(const Sampler& sampler, Rng& rng,
                                                                 std::uint32_t count,
                                                                 GridCandidate* scratch) {
    constexpr std::uint32_t chunk = grid_tile_chunk();
    for (std::uint32_t first = 0u; first < count; first += chunk) {
        const std::uint32_t n = min_of(chunk, count - first);
        float u[chunk][2];
        for (std::uint32_t k = 0u; k < n; ++k) {
            u[k][0] = next_float(rng); // the order of `sample_light`
            u[k][1] = next_float(rng);
            detail::prefetch_draw(sampler, u[k][0], u[k][1]);
        }
        for (std::uint32_t k = 0u; k < n; ++k) {
            const DiscreteSample drawn = sampler.sample(u[k][0], u[k][1]);
            scratch[first + k] = {drawn.index, 0.0f, drawn.pmf};
        }
    }
}

/// The target (the light's importance bound at `region`) and the RIS weight, target / pmf, of
/// each of the `count` candidates of `scratch` as `draw_grid_candidates` left them (0 where the
/// pmf is not positive), their bounds asked for ahead.
template <class NodeOf>
RESTIR_HOST_DEVICE RESTIR_FORCE_INLINE void
weigh_grid_candidates(const NodeOf& node_of, const ShadingPoint& region, std::uint32_t count,
                      GridCandidate* scratch) {
    constexpr std::uint32_t ahead = 16u; // bounds asked for this many candidates ahead
    for (std::uint32_t k = 0u; k < count; ++k) {
        if (k + ahead < count)
            RESTIR_PREFETCH(&node_of(scratch[k + ahead].light));
        GridCandidate& c = scratch[k];
        const float pmf = c.weight;
        c.target = pmf > 0.0f ? light_importance(node_of(c.light), region) : 0.0f;
        c.weight = pmf > 0.0f ? c.target / pmf : 0.0f;
    }
}

/// One of the `m` weighed candidates at `first` in proportion to their weights (Talbot 2005,
/// Eq. 3.2; one number), never one of weight 0: its light and, in `pmf`, the entry's pdf, the
/// reciprocal of its contribution weight (0 where no weight is positive or they overflow).
template <UniformRng Rng>
RESTIR_HOST_DEVICE RESTIR_FORCE_INLINE DiscreteSample choose_grid_entry(const GridCandidate* first,
                                                                        std::uint32_t m, Rng& rng) {
    float total = 0.0f;
    for (std::uint32_t k = 0u; k < m; ++k)
        total += first[k].weight;
    float x = next_float(rng) * total;
    std::uint32_t chosen = 0u;
    for (std::uint32_t k = 0u; k < m; ++k) {
        chosen = first[k].weight > 0.0f ? k : chosen; // never one of weight 0
        if (x < first[k].weight)
            break;
        x -= first[k].weight;
    }
    const GridCandidate y = m > 0u ? first[chosen] : GridCandidate{};
    const float pdf = total > 0.0f && y.target > 0.0f && is_finite(total)
                          ? y.target * static_cast<float>(m) / total
                          : 0.0f;
    return {y.light, pdf};
}
} // namespace detail

/// Resamples the `entry_count` entries of one cell's tile. Entry j is RIS over its own
/// `candidates_per_entry` lights drawn from `sampler`, with the lights' importance bounds at
/// `region` (`LightGridLayout::cell_region`) as the target: `node_of(id)` gives light id's
/// bounds as a `LightBvhNode` (`light_bvh_node`). Its pdf is the reciprocal of its unbiased
/// contribution weight W = sum(w) / (M p^(y)), which may stand for 1 / p in RIS at any point of
/// the region (Lin et al. 2022, GRIS): positive for every light that reaches a point of it.
/// `store(j, entry)` receives the entries; `scratch` holds entry_count * candidates_per_entry
/// candidates. An entry stays empty (pdf 0) when none of its candidates has a positive weight,
/// or when their weights overflow a float. All lights are drawn first (what each draw reads asked
/// for ahead when the sampler tells it, `prefetch_address(u0, u1)`, as `PowerLightSampler` does),
/// then weighed (their bounds prefetched ahead), then chosen (the chosen lights asked for ahead
/// of their points, `lights.prefetch_address(id)` where the set offers it): on a CPU the loops
/// carry no chain from one candidate to the next, so their cache misses overlap.
template <LightSampler Sampler, class NodeOf, LightSet Lights, UniformRng Rng, class Store>
RESTIR_HOST_DEVICE void
resample_grid_tile(const Sampler& sampler, const ShadingPoint& region, const NodeOf& node_of,
                   const Lights& lights, Rng& rng, std::uint32_t entry_count,
                   std::uint32_t candidates_per_entry, GridCandidate* scratch, Store&& store) {
    const std::uint32_t m = candidates_per_entry;
    const std::uint32_t count = entry_count * m;
    detail::draw_grid_candidates(sampler, rng, count, scratch);
    detail::weigh_grid_candidates(node_of, region, count, scratch);
    // The entries chosen a run at a time, their lights asked for ahead of their points.
    constexpr std::uint32_t chunk = detail::grid_tile_chunk();
    for (std::uint32_t run = 0u; run < entry_count; run += chunk) {
        const std::uint32_t n = min_of(chunk, entry_count - run);
        SourceSample<LightSampleRef> entries[chunk];
        for (std::uint32_t e = 0u; e < n; ++e) {
            // Entry j = run + e: one of candidates [j m, j m + m).
            const DiscreteSample y =
                detail::choose_grid_entry(scratch + std::uint64_t{run + e} * m, m, rng);
            entries[e] = with_uniform_point(y, rng);
            if (y.pmf > 0.0f) // a light, whose point `presampled` evaluates
                detail::prefetch_light(lights, y.index, entries[e].sample.uv);
        }
        for (std::uint32_t e = 0u; e < n; ++e)
            store(run + e, presampled(entries[e], lights));
    }
}

} // namespace restir
