/// @file sampling/infinite_lights.hpp
/// Distant (infinite) lights beside a sampler of the local lights. An environment map or a sun
/// gives directions, not points, so it has no position bounds for a light BVH or a light grid
/// to weigh. pbrt-v4's BVH light sampler keeps such lights beside its tree, and so does this
/// header. With probability P a distant light is chosen, by a sampler of its own. Otherwise a
/// local light is chosen, with the local sampler's pmf times 1 - P. The distant lights take the
/// ids [first, first + count) of the application's id space. The local sampler numbers the
/// other lights 0..N-1 in order, skipping that range. `WithDistantLights` wraps a
/// `ContextLightSampler` (a `LightBvhView`) or a `LightSampler` (power, uniform).
/// `resample_grid_tile_with_distant` fills a light grid's tile the same way.
#pragma once

#include "restir/concepts.hpp"
#include "restir/config.hpp"
#include "restir/core/discrete_sample.hpp"
#include "restir/core/math.hpp"
#include "restir/core/rng.hpp"
#include "restir/core/shading_point.hpp"
#include "restir/light/light_bvh_view.hpp"
#include "restir/sampling/light_candidates.hpp"
#include "restir/sampling/light_grid.hpp"
#include "restir/sampling/light_sampler.hpp"
#include "restir/sampling/light_tiles.hpp"

#include <cstdint>

namespace restir {

/// The default probability of choosing a distant light: in proportion to power,
/// P = distant power / (distant power + local power). Each power is the total emitted power of
/// its lights, in the same units. For an environment map the usual estimate is the power it
/// sends through a disc of the scene's bounding radius r: 4 pi times its average radiance times
/// pi r^2 (for a sun, its irradiance times pi r^2). A power that is not a finite number >= 0
/// counts as 0. P is 0 without distant power and 1 without local power. Any P keeps the pmf
/// exact; RIS stays unbiased while P > 0 for a scene that a distant light lights and P < 1 for
/// one that a local light lights.
RESTIR_HOST_DEVICE constexpr float distant_light_probability(float distant_power,
                                                             float local_power) noexcept {
    const float distant = is_valid_weight(distant_power) ? distant_power : 0.0f;
    const float local = is_valid_weight(local_power) ? local_power : 0.0f;
    // 1 / (1 + local / distant) rather than distant / (distant + local): the sum may overflow.
    return distant > 0.0f ? 1.0f / (1.0f + local / distant) : 0.0f;
}

/// The distant lights of an id space: the ids [first, first + count), with count =
/// `sampler.light_count()`, chosen together with probability `probability` (P). `sampler`
/// chooses among them by their index from `first` on. The default chooses each with
/// probability 1 / count; a `PowerLightSampler` over their powers chooses them by weight.
template <LightSampler Distant = UniformLightSampler>
struct DistantLights {
    std::uint32_t first = 0u; ///< The id of the first distant light.
    float probability = 0.0f; ///< P, in [0, 1]; 0 when there are none.
    Distant sampler{};        ///< Chooses among the distant lights: index i is id first + i.

    /// The number of distant lights.
    RESTIR_HOST_DEVICE constexpr std::uint32_t count() const noexcept {
        return sampler.light_count();
    }
    /// Whether `id` is one of the distant lights.
    RESTIR_HOST_DEVICE constexpr bool contains(std::uint32_t id) const noexcept {
        return id >= first && id - first < count();
    }
    /// The application's id of local light `local_id` (local ids skip the distant range).
    RESTIR_HOST_DEVICE constexpr std::uint32_t
    application_id(std::uint32_t local_id) const noexcept {
        return local_id < first ? local_id : local_id + count();
    }
    /// The local id of `id`, which must be no distant light (`contains(id)` false).
    RESTIR_HOST_DEVICE constexpr std::uint32_t local_id(std::uint32_t id) const noexcept {
        return id < first ? id : id - count();
    }
    /// The probability that the mixture chooses distant light `id`: P times its pmf among the
    /// distant lights. 0 for any other id.
    RESTIR_HOST_DEVICE constexpr float pmf(std::uint32_t id) const noexcept {
        return contains(id) ? probability * static_cast<float>(sampler.pmf(id - first)) : 0.0f;
    }
    /// A distant light from two uniform numbers, with its pmf in the mixture: P times its pmf
    /// among the distant lights. The caller has already chosen a distant light (probability P).
    RESTIR_HOST_DEVICE constexpr DiscreteSample sample(float u0, float u1) const noexcept {
        const DiscreteSample chosen = sampler.sample(u0, u1);
        return {first + chosen.index, probability * chosen.pmf};
    }
    /// The probability, or density, of a local choice in the mixture: (1 - P) times the local
    /// sampler's `pmf`. This also holds for a light grid tile entry's pdf, an unbiased
    /// contribution weight's reciprocal. For P = 0 it returns `pmf` bit for bit.
    RESTIR_HOST_DEVICE constexpr float local_pdf(float pmf) const noexcept {
        return (1.0f - probability) * pmf;
    }
};

namespace detail {
// The choice between distant and local lights from one uniform number u, and u rescaled to
// [0, 1) inside the part it fell in: [0, P) picks a distant light, [P, 1) a local one. The
// rescaled u gives the chosen sampler well distributed numbers. For P = 0, u is returned
// bit for bit: (u - 0) / (1 - 0) is u.
struct DistantSplit {
    bool distant = false;
    float u = 0.0f;
};
RESTIR_HOST_DEVICE constexpr DistantSplit split_distant(float u, float probability) noexcept {
    const bool distant = u < probability;
    const float rescaled = distant ? u / probability : (u - probability) / (1.0f - probability);
    return {distant, min_of(max_of(rescaled, 0.0f), 0x1.fffffep-1f)};
}
} // namespace detail

/// A light sampler over local lights and distant lights beside them (pbrt-v4 keeps infinite
/// lights beside its light BVH). `local` chooses among the N local lights by local ids
/// 0..N-1, and `distant` holds the distant lights' id range [first, first + count) and P.
/// The application's ids run over [0, N + count): the local lights in order with the distant
/// range inserted at `first`. The mixture's pmf is:
///   pmf(id) = P * distant pmf(id - first)         for a distant light,
///   pmf(id) = (1 - P) * local pmf(local id of id) for a local one,
///   pmf(id) = 0                                    for ids >= N + count.
/// `sample` picks a distant light when u0 < P and otherwise asks `local`; either way u0 is
/// rescaled to [0, 1) first. The result is a `ContextLightSampler` when `Local` is one, and a
/// `LightSampler` when `Local` is one. With P = 0 it returns `local`'s draws and pmfs bit for
/// bit, under the application's ids (the very same ids when count is 0). Build it with
/// `with_distant_lights`, which also checks P and `first`. A view when `Local` is one.
template <class Local, LightSampler Distant = UniformLightSampler>
requires LightSampler<Local> || ContextLightSampler<Local>
struct WithDistantLights {
    Local local{};                    ///< The local lights' sampler (local ids).
    DistantLights<Distant> distant{}; ///< The distant lights' ids, sampler and probability P.

    /// N + count: every id of the application's id space.
    RESTIR_HOST_DEVICE constexpr std::uint32_t light_count() const noexcept {
        return static_cast<std::uint32_t>(local.light_count()) + distant.count();
    }

    /// A light for `at`: a distant light with probability P, otherwise `local`'s draw for
    /// `at`. The pmf is that of `pmf(at, id)`, and 0 when `local` finds no light.
    RESTIR_HOST_DEVICE DiscreteSample sample(const ShadingPoint& at, float u0,
                                             float u1) const requires ContextLightSampler<Local> {
        const detail::DistantSplit split = detail::split_distant(u0, distant.probability);
        if (split.distant)
            return distant.sample(split.u, u1);
        return from_local(local.sample(at, split.u, u1));
    }

    /// The probability that `sample(at, ...)` returns `id` (the mixture's pmf above).
    RESTIR_HOST_DEVICE float pmf(const ShadingPoint& at,
                                 std::uint32_t id) const requires ContextLightSampler<Local> {
        if (distant.contains(id))
            return distant.pmf(id);
        if (id >= light_count())
            return 0.0f;
        return distant.local_pdf(static_cast<float>(local.pmf(at, distant.local_id(id))));
    }

    /// The same for a `LightSampler` `local`, which reads no shading point.
    RESTIR_HOST_DEVICE DiscreteSample sample(float u0,
                                             float u1) const requires LightSampler<Local> {
        const detail::DistantSplit split = detail::split_distant(u0, distant.probability);
        if (split.distant)
            return distant.sample(split.u, u1);
        return from_local(local.sample(split.u, u1));
    }

    /// The probability that `sample(u0, u1)` returns `id`.
    RESTIR_HOST_DEVICE float pmf(std::uint32_t id) const requires LightSampler<Local> {
        if (distant.contains(id))
            return distant.pmf(id);
        if (id >= light_count())
            return 0.0f;
        return distant.local_pdf(static_cast<float>(local.pmf(distant.local_id(id))));
    }

    /// What `sample(u0, u1)` reads, for a prefetch, when `local` tells it
    /// (`PowerLightSampler::prefetch_address`). For a distant draw it returns this object.
    RESTIR_HOST_DEVICE const void* prefetch_address(float u0, float u1) const requires
        requires(const Local& l, float u) {
        l.prefetch_address(u, u);
    }
    {
        const detail::DistantSplit split = detail::split_distant(u0, distant.probability);
        return split.distant ? static_cast<const void*>(this) : local.prefetch_address(split.u, u1);
    }

private:
    RESTIR_HOST_DEVICE constexpr DiscreteSample from_local(DiscreteSample chosen) const noexcept {
        return {distant.application_id(chosen.index), distant.local_pdf(chosen.pmf)};
    }
};

/// `local` with distant lights beside it at ids [first, first + count), count =
/// `distant.light_count()`, chosen among themselves by `distant` (say a `PowerLightSampler` over
/// their powers): distant light i, id first + i, gets P times `distant.pmf(i)`. Pass
/// `distant_light_probability(distant_power, local_power)` as P for the default, in proportion
/// to power. P is clamped to [0, 1], NaN counts as 0, and P is 0 when count is 0. `first` must
/// be at most N, the local light count; a larger one is clamped to N (asserted in debug
/// builds).
template <class Local, LightSampler Distant>
requires LightSampler<Local> || ContextLightSampler<Local>
    RESTIR_HOST_DEVICE constexpr WithDistantLights<Local, Distant>
    with_distant_lights(const Local& local, std::uint32_t first, const Distant& distant,
                        float probability) noexcept {
    const auto local_count = static_cast<std::uint32_t>(local.light_count());
    RESTIR_ASSERT(first <= local_count);
    const bool any = static_cast<std::uint32_t>(distant.light_count()) > 0u;
    // In this order NaN ends as 0 (every comparison with it is false).
    const float p = any ? min_of(max_of(0.0f, probability), 1.0f) : 0.0f;
    return {local, {min_of(first, local_count), p, distant}};
}

/// `local` with `count` distant lights beside it at ids [first, first + count), each chosen
/// with probability P / count (the overload above with `UniformLightSampler{count}`).
template <class Local>
requires LightSampler<Local> || ContextLightSampler<Local>
    RESTIR_HOST_DEVICE constexpr WithDistantLights<Local>
    with_distant_lights(const Local& local, std::uint32_t first, std::uint32_t count,
                        float probability) noexcept {
    return with_distant_lights(local, first, UniformLightSampler{count}, probability);
}

/// `resample_grid_tile` with distant lights beside the grid (sampling/light_grid.hpp). Each
/// entry is a distant light with probability P = `distant.probability`, drawn from
/// `distant.sampler` with pdf P times its pmf among them, with a uniform uv
/// (`with_uniform_point`). Otherwise it is an entry of `resample_grid_tile`: RIS over
/// `candidates_per_entry` local lights from `sampler`, local ids mapped to the application's,
/// with pdf (1 - P) / W. Every entry thus has the mixture's distribution on its own, and
/// f / pdf is an unbiased estimate of the sum of f over the local and the distant lights at
/// every point of `region`: the local part counts (1 - P) times with weight 1 / (1 - P), the
/// distant part P times with weight 1 / P. Pixels read the tile as before, taking entries as
/// candidates with their pdfs. `node_of` and `lights` take the application's ids; `node_of` is
/// never asked about a distant light. `scratch` holds entry_count * candidates_per_entry
/// candidates, as for `resample_grid_tile`. The entries' distant-or-local coins come in
/// blocks of 32, and each block's local entries are resampled in one call, so the draws
/// still overlap their cache misses. With P = 0 no coin is drawn, and the tile is that of
/// `resample_grid_tile` over the local sampler with the application's ids, bit for bit.
template <LightSampler Sampler, LightSampler Distant, class NodeOf, LightSet Lights, UniformRng Rng,
          class Store>
RESTIR_HOST_DEVICE void resample_grid_tile_with_distant(
    const Sampler& sampler, const DistantLights<Distant>& distant, const ShadingPoint& region,
    const NodeOf& node_of, const Lights& lights, Rng& rng, std::uint32_t entry_count,
    std::uint32_t candidates_per_entry, GridCandidate* scratch, Store&& store) {
    // The local sampler in the application's ids, its pmfs unchanged (P = 0).
    const WithDistantLights<Sampler, Distant> local{sampler,
                                                    {distant.first, 0.0f, distant.sampler}};
    const float probability = distant.probability;
    if (!(probability > 0.0f)) {
        resample_grid_tile(local, region, node_of, lights, rng, entry_count, candidates_per_entry,
                           scratch, store);
        return;
    }
    constexpr std::uint32_t block_size = 32u; // entries whose coins fit one mask
    for (std::uint32_t block = 0u; block < entry_count; block += block_size) {
        const std::uint32_t n = min_of(block_size, entry_count - block);
        std::uint32_t local_mask = 0u, local_count = 0u;
        for (std::uint32_t k = 0u; k < n; ++k) {
            if (!(next_float(rng) < probability)) {
                local_mask |= 1u << k;
                ++local_count;
            }
        }
        // `resample_grid_tile` stores its entries in order, one each: the k-th goes to the
        // block's k-th local position. Its entries are alike, so which goes where is no matter.
        std::uint32_t position = 0u;
        resample_grid_tile(local, region, node_of, lights, rng, local_count, candidates_per_entry,
                           scratch, [&](std::uint32_t, PresampledLight entry) {
                               while ((local_mask >> position & 1u) == 0u)
                                   ++position;
                               entry.pdf = distant.local_pdf(entry.pdf);
                               store(block + position++, entry);
                           });
        for (std::uint32_t k = 0u; k < n; ++k) {
            if ((local_mask >> k & 1u) != 0u)
                continue;
            const float u_first = next_float(rng); // named: the order of the draws is fixed
            const float u_second = next_float(rng);
            store(block + k,
                  presampled(with_uniform_point(distant.sample(u_first, u_second), rng), lights));
        }
    }
}

static_assert(LightSampler<WithDistantLights<PowerLightSampler>> &&
              ContextLightSampler<WithDistantLights<PowerLightSampler>>);
static_assert(ContextLightSampler<WithDistantLights<LightBvhView>> &&
              !LightSampler<WithDistantLights<LightBvhView>>);

} // namespace restir
