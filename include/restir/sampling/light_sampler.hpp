/// @file sampling/light_sampler.hpp
/// The two light samplers the library ships (the source distribution of RIS candidates):
/// uniform, and proportional to power through an alias table. Their contract, `LightSampler`,
/// is part of the bridge (concepts.hpp).
#pragma once

#include "restir/concepts.hpp"
#include "restir/config.hpp"
#include "restir/core/discrete_sample.hpp"
#include "restir/core/math.hpp"
#include "restir/core/rng.hpp"
#include "restir/sampling/alias_table_view.hpp"

#include <concepts>
#include <cstdint>

namespace restir {

/// Every light with probability 1 / N.
struct UniformLightSampler {
    std::uint32_t count = 0u; ///< N, the number of lights.

    /// 48 bits from both numbers (`wide_uniform_index`): 1 / N to a relative N / 2^48.
    RESTIR_HOST_DEVICE constexpr DiscreteSample sample(float u0, float u1) const noexcept {
        if (count == 0u)
            return {};
        return {wide_uniform_index(u0, u1, count).index, 1.0f / static_cast<float>(count)};
    }
    RESTIR_HOST_DEVICE constexpr float pmf(std::uint32_t id) const noexcept {
        return id < count ? 1.0f / static_cast<float>(count) : 0.0f;
    }
    /// The same for every shading point (`ContextLightSampler`).
    RESTIR_HOST_DEVICE constexpr DiscreteSample sample(const ShadingPoint&, float u0,
                                                       float u1) const noexcept {
        return sample(u0, u1);
    }
    RESTIR_HOST_DEVICE constexpr float pmf(const ShadingPoint&, std::uint32_t id) const noexcept {
        return pmf(id);
    }
    RESTIR_HOST_DEVICE constexpr std::uint32_t light_count() const noexcept { return count; }
};

/// Lights with probability proportional to a weight (typically emitted power), in O(1)
/// through an alias table. Holds a view: the `AliasTable` it came from must outlive it.
struct PowerLightSampler {
    AliasTableView table;

    RESTIR_HOST_DEVICE constexpr DiscreteSample sample(float u0, float u1) const noexcept {
        return table.sample(u0, u1);
    }
    /// What `sample(u0, u1)` reads, for a prefetch (`AliasTableView::prefetch_address`).
    RESTIR_HOST_DEVICE constexpr const void* prefetch_address(float u0, float u1) const noexcept {
        return table.prefetch_address(u0, u1);
    }
    RESTIR_HOST_DEVICE constexpr float pmf(std::uint32_t id) const noexcept {
        return table.pmf(id);
    }
    /// The same for every shading point (`ContextLightSampler`).
    RESTIR_HOST_DEVICE constexpr DiscreteSample sample(const ShadingPoint&, float u0,
                                                       float u1) const noexcept {
        return sample(u0, u1);
    }
    RESTIR_HOST_DEVICE constexpr float pmf(const ShadingPoint&, std::uint32_t id) const noexcept {
        return pmf(id);
    }
    RESTIR_HOST_DEVICE constexpr std::uint32_t light_count() const noexcept { return table.size; }
};

namespace detail {
/// Asks for what `sampler.sample(u0, u1)` reads, where the sampler says (`prefetch_address`).
template <class Sampler>
RESTIR_HOST_DEVICE RESTIR_FORCE_INLINE void prefetch_draw(const Sampler& sampler, float u0,
                                                          float u1) {
    if constexpr (requires { sampler.prefetch_address(u0, u1); })
        RESTIR_PREFETCH(sampler.prefetch_address(u0, u1));
}

/// Asks for what `lights.sample_point(id, uv)` reads, where the light set says
/// (`prefetch_point(id, uv)` or `prefetch_address(id)`, `UnifiedLightSet` among them).
template <class Lights>
RESTIR_HOST_DEVICE RESTIR_FORCE_INLINE void prefetch_light(const Lights& lights, std::uint32_t id,
                                                           glm::vec2 uv) {
    if constexpr (requires { lights.prefetch_point(id, uv); })
        lights.prefetch_point(id, uv);
    else if constexpr (requires { lights.prefetch_address(id); })
        RESTIR_PREFETCH(lights.prefetch_address(id));
}
} // namespace detail

/// Draws a light with two numbers taken from `rng` in a fixed order. Prefer it to
/// `s.sample(next_float(rng), next_float(rng))`, whose argument order is up to the compiler:
/// host and device builds would then choose different lights from the same seed.
template <LightSampler S, UniformRng Rng>
RESTIR_HOST_DEVICE constexpr DiscreteSample sample_light(const S& sampler, Rng& rng) {
    const float u_first = next_float(rng);
    const float u_second = next_float(rng);
    return sampler.sample(u_first, u_second);
}

/// `sample_light` for a shading point.
template <ContextLightSampler S, UniformRng Rng>
RESTIR_HOST_DEVICE constexpr DiscreteSample sample_light(const S& sampler, const ShadingPoint& at,
                                                         Rng& rng) {
    const float u_first = next_float(rng);
    const float u_second = next_float(rng);
    return sampler.sample(at, u_first, u_second);
}

static_assert(LightSampler<UniformLightSampler> && ContextLightSampler<UniformLightSampler>);
static_assert(LightSampler<PowerLightSampler> && ContextLightSampler<PowerLightSampler>);

} // namespace restir
