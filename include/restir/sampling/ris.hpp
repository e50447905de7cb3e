/// @file sampling/ris.hpp
/// Streaming resampled importance sampling (Talbot et al. 2005; Bitterli et al. 2020,
/// Alg. 3), from one source distribution or from several combined by the balance heuristic.
#pragma once

#include "restir/concepts.hpp"
#include "restir/config.hpp"
#include "restir/core/math.hpp"
#include "restir/core/reservoir.hpp"
#include "restir/core/rng.hpp"

#include <concepts>
#include <cstdint>
#include <type_traits>
#include <utility>

namespace restir {

/// A candidate drawn from a source distribution, with that distribution's density (or
/// probability) at the candidate.
template <class Sample>
struct SourceSample {
    Sample sample{};
    float pdf = 0.0f;
};

/// Streams `candidate_count` candidates from one source distribution and returns the
/// finalised reservoir (Alg. 3 of Bitterli et al. 2020):
///   `draw(rng)`       -> SourceSample<Sample>, a candidate x_i and its source pdf p(x_i);
///   `target(sample)`  -> float, the target function p-hat(x_i) >= 0.
/// Resampling weight w_i = p-hat(x_i) / p(x_i) (Eq. 5 without the 1/M, which `finalize`
/// applies), W = w_sum / (M p-hat(y)) (Eq. 6). f(y) * W is an unbiased estimate of the
/// integral of f wherever p(x) > 0 at every x with f(x) p-hat(x) != 0 (see docs/algorithms.md).
template <UniformRng Rng, std::invocable<Rng&> Draw, class Target>
RESTIR_HOST_DEVICE auto resample_ris(Rng& rng, std::uint32_t candidate_count, Draw&& draw,
                                     Target&& target) {
    using Sample = std::remove_cvref_t<decltype(draw(rng).sample)>;
    Reservoir<Sample> reservoir;
    for (std::uint32_t i = 0; i < candidate_count; ++i) {
        const SourceSample<Sample> candidate = draw(rng);
        const float target_value = target(candidate.sample);
        reservoir.stream(candidate.sample, safe_divide(target_value, candidate.pdf), target_value,
                         next_float(rng));
    }
    reservoir.finalize();
    return reservoir;
}

/// `resample_ris` with the reuse passes' form of the target, `target(sample, surface)`
/// (`TargetFunction`), evaluated at `surface`: one p-hat serves the initial candidates and every
/// reuse pass.
template <UniformRng Rng, std::invocable<Rng&> Draw, class Target, class SurfaceT>
requires TargetFunction<
    Target, std::remove_cvref_t<decltype(std::declval<Draw&>()(std::declval<Rng&>()).sample)>,
    SurfaceT>
    RESTIR_HOST_DEVICE auto resample_ris(Rng& rng, std::uint32_t candidate_count, Draw&& draw,
                                         const Target& target, const SurfaceT& surface) {
    return resample_ris(rng, candidate_count, draw,
                        [&](const auto& sample) { return target(sample, surface); });
}

/// One sampling technique of multiple-importance RIS: `candidate_count` candidates drawn
/// with `draw(rng) -> Sample`, whose density is `pdf(sample) -> float` (0 where the
/// technique cannot produce the sample).
template <class Draw, class Pdf>
struct SourceStrategy {
    std::uint32_t candidate_count = 0u;
    Draw draw;
    Pdf pdf;
};

template <class Draw, class Pdf>
SourceStrategy(std::uint32_t, Draw, Pdf) -> SourceStrategy<Draw, Pdf>;

/// Streams candidates from several techniques, for instance light sampling and BSDF
/// sampling, weighted by the balance heuristic over candidate counts (generalized RIS,
/// Lin et al. 2022, Eq. 3.4 with m_s(x) = M_s p_s(x) / sum_t M_t p_t(x)):
///   w_i = m_s(x_i) p-hat(x_i) / p_s(x_i) = p-hat(x_i) / sum_t M_t p_t(x_i),
///   W   = w_sum / p-hat(y).
/// Unbiased wherever, at every x with f(x) p-hat(x) != 0, some technique has p_t(x) > 0.
/// All techniques must produce the same sample type.
template <UniformRng Rng, class Target, class FirstStrategy, class... OtherStrategies>
RESTIR_HOST_DEVICE auto resample_ris_mis(Rng& rng, Target&& target, const FirstStrategy& first,
                                         const OtherStrategies&... others) {
    using Sample = std::remove_cvref_t<decltype(first.draw(rng))>;
    static_assert((std::same_as<Sample, std::remove_cvref_t<decltype(others.draw(rng))>> && ...),
                  "every strategy must draw the same sample type");
    // Balance-heuristic denominator: sum_t M_t p_t(x).
    const auto weighted_density_sum = [&](const Sample& x) {
        return static_cast<float>(first.candidate_count) * first.pdf(x) +
               (0.0f + ... + (static_cast<float>(others.candidate_count) * others.pdf(x)));
    };
    Reservoir<Sample> reservoir;
    const auto stream_from = [&](const auto& strategy) {
        for (std::uint32_t i = 0; i < strategy.candidate_count; ++i) {
            const Sample x = strategy.draw(rng);
            const float target_value = target(x);
            reservoir.stream(x, safe_divide(target_value, weighted_density_sum(x)), target_value,
                             next_float(rng));
        }
    };
    stream_from(first);
    (stream_from(others), ...);
    reservoir.finalize_normalized(1.0f);
    return reservoir;
}

} // namespace restir
