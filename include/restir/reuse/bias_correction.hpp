/// @file reuse/bias_correction.hpp
/// Combining a receiver's own (canonical) reservoir with reservoirs borrowed from other
/// surfaces, under one of four bias corrections. This is generalized RIS (Lin et al. 2022,
/// Eq. 3.4): input i enters with resampling weight w_i = m_i(y_i) p-hat_q(y_i) W_i, and the
/// result W = (sum_i w_i) / p-hat_q(y) is unbiased whenever the m_i sum to one at every
/// point where the integrand is non-zero, and m_i vanishes where input i cannot produce the
/// point. docs/noise-and-bias.md discusses each mode.
#pragma once

#include "restir/concepts.hpp"
#include "restir/config.hpp"
#include "restir/core/math.hpp"
#include "restir/core/reservoir.hpp"
#include "restir/core/rng.hpp"
#include "restir/reuse/reuse_input.hpp"
#include "restir/reuse/reuse_params.hpp"
#include "restir/reuse/reuse_terms.hpp"
#include "restir/reuse/shift.hpp"
#include "restir/reuse/similarity.hpp"
#include "restir/reuse/visibility.hpp"

#include <cstdint>
#include <type_traits>

namespace restir {

namespace detail {

/// The merges of 1/M and 1/Z (Alg. 4): the canonical reservoir, then every input with weight
/// p-hat_q(y_i) W_i M_i (under a shift p-hat_q(T(y_i)) W_i M_i |dT/dy_i|); with
/// `only_own_support` an input lends only a sample it could produce (p-hat_i(y_i) > 0 with its
/// visibility), as 1/Z needs.
template <class Sample, class S, class Inputs, class Terms, class Rng>
RESTIR_HOST_DEVICE Reservoir<Sample> merge_inputs(const Reservoir<Sample>& canonical,
                                                  const Inputs& inputs, const Terms& terms,
                                                  bool only_own_support, Rng& rng) {
    Reservoir<Sample> result;
    result.merge(canonical, canonical.target_value, next_float(rng));
    const LentTargets<Sample, S, Terms, Inputs> targets(inputs, terms, !only_own_support);
    for_each_input<Sample, S>(
        inputs, [&](std::uint32_t j, const Reservoir<Sample>& r, const S& there) {
            const bool lends = r.has_sample() && (!only_own_support || terms.own(r, there) > 0.0f);
            typename Terms::Lent lent = r;
            float jacobian = 1.0f;
            const float here = lends ? targets.lend(j, lent, there, jacobian) : 0.0f;
            result.merge(lent, here, next_float(rng));
        });
    return result;
}

} // namespace detail

/// Bias correction `none` (Bitterli et al. 2020, Alg. 4): w_i = p-hat_q(y_i) W_i M_i, W with
/// the 1/M weights. The inputs are visited once.
template <class Sample, Surface S, class Inputs, class Target, class Visibility, class MaterialTest,
          class Shift, UniformRng Rng>
requires ReuseInputs<Inputs, Sample, S> RESTIR_HOST_DEVICE Reservoir<Sample>
combine_one_over_m(const Reservoir<Sample>& canonical, const S& surface, const Inputs& inputs,
                   const ReuseParams& params,
                   const ReuseBridge<Target, Visibility, MaterialTest, Shift>& bridge, Rng& rng) {
    const detail::ReuseTerms<Sample, S, ReuseBridge<Target, Visibility, MaterialTest, Shift>> terms{
        surface, params, bridge};
    Reservoir<Sample> result =
        detail::merge_inputs<Sample, S>(canonical, inputs, terms, false, rng);
    result.finalize();
    return result;
}

/// Bias correction `one_over_z` (Bitterli et al. 2020, Alg. 6): the inputs merged as for 1/M,
/// each lending only samples it can produce (p-hat_i(y_i) > 0 with its visibility), then
/// W normalised by 1 / Z(y), Z the M of the inputs whose p-hat (with visibility) is positive at
/// the kept y. The inputs are visited twice.
template <class Sample, Surface S, class Inputs, class Target, class Visibility, class MaterialTest,
          class Shift, UniformRng Rng>
requires ReuseInputs<Inputs, Sample, S> RESTIR_HOST_DEVICE Reservoir<Sample>
combine_one_over_z(const Reservoir<Sample>& canonical, const S& surface, const Inputs& inputs,
                   const ReuseParams& params,
                   const ReuseBridge<Target, Visibility, MaterialTest, Shift>& bridge, Rng& rng) {
    const detail::ReuseTerms<Sample, S, ReuseBridge<Target, Visibility, MaterialTest, Shift>> terms{
        surface, params, bridge};
    Reservoir<Sample> result = detail::merge_inputs<Sample, S>(canonical, inputs, terms, true, rng);
    // Z: the M of every input that could have produced y (the canonical one did or could,
    // since p-hat_q(y) > 0 for a selected y).
    float z = static_cast<float>(canonical.candidate_count);
    if (result.has_sample())
        detail::for_each_input<Sample, S>(
            inputs, [&](std::uint32_t, const Reservoir<Sample>& r, const S& there) {
                if (terms.at(result.sample, there) > 0.0f)
                    z += static_cast<float>(r.candidate_count);
            });
    result.finalize_normalized(safe_divide(1.0f, z));
    return result;
}

/// Bias correction `balance_heuristic` (Lin et al. 2022): m_j(x) = M_j p-hat_j(x) /
/// (M_c p-hat_q(x) + sum_l M_l p-hat_l(x)). Each input's weight visits all inputs again:
/// (k + 1)^2 target evaluations.
template <class Sample, Surface S, class Inputs, class Target, class Visibility, class MaterialTest,
          class Shift, UniformRng Rng>
requires ReuseInputs<Inputs, Sample, S> RESTIR_HOST_DEVICE Reservoir<Sample>
combine_balance_heuristic(const Reservoir<Sample>& canonical, const S& surface,
                          const Inputs& inputs, const ReuseParams& params,
                          const ReuseBridge<Target, Visibility, MaterialTest, Shift>& bridge,
                          Rng& rng) {
    const detail::ReuseTerms<Sample, S, ReuseBridge<Target, Visibility, MaterialTest, Shift>> terms{
        surface, params, bridge};
    const float canonical_count = static_cast<float>(canonical.candidate_count);
    // sum_l M_l p-hat_l(x) over the inputs (`all`) and without input `own` (`others`); input
    // `own` contributes M_own p-hat_own(y_own) (`own`).
    struct Sums {
        float all = 0.0f, others = 0.0f, own = 0.0f;
    };
    const auto neighbour_sums = [&](const Sample& x, std::uint32_t own) {
        Sums sums;
        detail::for_each_input<Sample, S>(
            inputs, [&](std::uint32_t l, const Reservoir<Sample>& r, const S& there) {
                const float term = static_cast<float>(r.candidate_count) *
                                   (l == own ? terms.own(r, there) : terms.at(x, there));
                sums.all += term;
                if (l == own)
                    sums.own = term;
                else
                    sums.others += term;
            });
        return sums;
    };
    Reservoir<Sample> result;
    float canonical_mis = 0.0f;
    if (canonical.has_sample()) {
        const float own = canonical_count * canonical.target_value;
        canonical_mis =
            safe_divide(own, own + neighbour_sums(canonical.sample, max_reuse_inputs).all);
    }
    result.merge_with_mis(canonical, canonical.target_value, canonical_mis, next_float(rng));
    detail::for_each_input<Sample, S>(
        inputs, [&](std::uint32_t i, const Reservoir<Sample>& r, const S& there) {
            typename decltype(terms)::Lent lent = r;
            float jacobian = 1.0f;
            float here = 0.0f;
            float mis_weight = 0.0f;
            if (r.has_sample()) {
                here = terms.lend(lent, there, jacobian);
                const Sums sums = neighbour_sums(lent.sample, i);
                if constexpr (decltype(terms)::shifts)
                    // y = T(y_i): m_i = M_i p-hat_i(y_i) / (M_i p-hat_i(y_i) + |dT/dy_i| (M_c
                    // p-hat_q(y) + sum_{l != i} M_l p-hat_l(T_l(y)) |dT_l/dy|)), the balance
                    // heuristic over the targets carried to the receiver (Lin et al. 2022,
                    // Eq. 5.10), numerator and denominator times |dT/dy_i|.
                    mis_weight = safe_divide(
                        sums.own, sums.own + jacobian * (canonical_count * here + sums.others));
                else
                    mis_weight = safe_divide(sums.own, canonical_count * here + sums.all);
            }
            result.merge_with_mis(lent, here, mis_weight, next_float(rng));
        });
    result.finalize_normalized(1.0f);
    return result;
}

namespace detail {
/// Pairwise MIS (Bitterli's 2022 dissertation) with confidence weights M: pair i = (canonical,
/// input i), split by a two-technique balance heuristic, the shares summing to one. Plain
/// (`Defensive` false): pair i is worth (M_i + M_c / k) / M_total, the canonical's confidence
/// in it M_c / k. Defensive: the canonical keeps M_c / M_total of its own, pair i is worth
/// M_i / M_total and the canonical's confidence in it is M_c. The inputs are visited twice
/// (their M, then the pairs): 3k target evaluations.
template <bool Defensive, class Sample, class S, class Inputs, class Target, class Visibility,
          class MaterialTest, class Shift, UniformRng Rng>
RESTIR_HOST_DEVICE Reservoir<Sample>
combine_pairs(const Reservoir<Sample>& canonical, const S& surface, const Inputs& inputs,
              const ReuseParams& params,
              const ReuseBridge<Target, Visibility, MaterialTest, Shift>& bridge, Rng& rng) {
    const ReuseTerms<Sample, S, ReuseBridge<Target, Visibility, MaterialTest, Shift>> terms{
        surface, params, bridge};
    const float canonical_count = static_cast<float>(canonical.candidate_count);
    float total_count = canonical_count;
    const std::uint32_t k =
        for_each_input<Sample, S>(inputs, [&](std::uint32_t, const Reservoir<Sample>& r, const S&) {
            total_count += static_cast<float>(r.candidate_count);
        });
    // Every return returns one named result, so that it is built in place in the caller's
    // memory rather than copied through the stack.
    Reservoir<Sample> result;
    if (k == 0u) {
        result = canonical;
        return result;
    }
    // The canonical's confidence inside each pair, and the part of the pairs' worth it brings.
    const float canonical_share =
        Defensive ? canonical_count : canonical_count / static_cast<float>(k);
    const float pair_canonical = Defensive ? 0.0f : canonical_share;
    float canonical_mis = Defensive ? safe_divide(canonical_count, total_count) : 0.0f;
    const LentTargets<Sample, S, decltype(terms), Inputs> targets(inputs, terms);
    for_each_input<Sample, S>(inputs, [&](std::uint32_t j, const Reservoir<Sample>& r,
                                          const S& there) {
        const float count = static_cast<float>(r.candidate_count);
        const float pair_weight = safe_divide(count + pair_canonical, total_count);
        typename decltype(terms)::Lent lent = r;
        float jacobian = 1.0f;
        float here = 0.0f;
        float mis_weight = 0.0f;
        if (r.has_sample()) {
            here = targets.lend(j, lent, there, jacobian);
            // Under a shift, the canonical technique's density carried to input i's domain is
            // p-hat_q(T(y_i)) |dT/dy_i| (Lin et al. 2022, Eq. 5.10).
            const float own = count * terms.own(r, there);
            mis_weight = pair_weight * safe_divide(own, own + canonical_share * here * jacobian);
        }
        result.merge_with_mis(lent, here, mis_weight, next_float(rng));
        if (canonical.has_sample()) {
            const float canonical_own = canonical_share * canonical.target_value;
            canonical_mis += pair_weight *
                             safe_divide(canonical_own,
                                         canonical_own + count * terms.at(canonical.sample, there));
        }
    });
    result.merge_with_mis(canonical, canonical.target_value, canonical_mis, next_float(rng));
    result.finalize_normalized(1.0f);
    return result;
}
} // namespace detail

/// Bias correction `pairwise` (Bitterli's 2022 dissertation): pair i = (canonical with
/// confidence M_c / k, input i with M_i), worth beta_i = (M_i + M_c / k) / M_total of the whole,
/// split by a two-technique balance heuristic; the betas sum to one. The inputs are visited
/// twice (their M, then the pairs): 3k target evaluations.
template <class Sample, Surface S, class Inputs, class Target, class Visibility, class MaterialTest,
          class Shift, UniformRng Rng>
requires ReuseInputs<Inputs, Sample, S> RESTIR_HOST_DEVICE Reservoir<Sample>
combine_pairwise(const Reservoir<Sample>& canonical, const S& surface, const Inputs& inputs,
                 const ReuseParams& params,
                 const ReuseBridge<Target, Visibility, MaterialTest, Shift>& bridge, Rng& rng) {
    return detail::combine_pairs<false, Sample>(canonical, surface, inputs, params, bridge, rng);
}

/// Bias correction `defensive_pairwise`: pairwise MIS in which the canonical keeps M_c /
/// M_total of its own and pair i, worth M_i / M_total, is split with confidences M_c and M_i.
/// The same cost as `combine_pairwise`.
template <class Sample, Surface S, class Inputs, class Target, class Visibility, class MaterialTest,
          class Shift, UniformRng Rng>
requires ReuseInputs<Inputs, Sample, S> RESTIR_HOST_DEVICE Reservoir<Sample>
combine_defensive_pairwise(const Reservoir<Sample>& canonical, const S& surface,
                           const Inputs& inputs, const ReuseParams& params,
                           const ReuseBridge<Target, Visibility, MaterialTest, Shift>& bridge,
                           Rng& rng) {
    return detail::combine_pairs<true, Sample>(canonical, surface, inputs, params, bridge, rng);
}

/// Combines the receiver's own (canonical) reservoir (computed for `surface`, finalised) with
/// the borrowed `inputs` under bias correction `Mode`, chosen at compile time, and returns the
/// finalised result, whose M is the sum of the inputs' M. Inputs should already have passed
/// the similarity tests; any that holds non-finite values is skipped as if it were absent, and
/// at most max_reuse_inputs - 1 take part. Consumes one uniform number per input that takes
/// part. A canonical reservoir with non-finite fields takes part as an empty one.
template <BiasCorrection Mode, class Sample, Surface S, class Inputs, class Target,
          class Visibility, class MaterialTest, class Shift, UniformRng Rng>
requires ReuseInputs<Inputs, Sample, S> && TargetFunction<Target, Sample, S> &&
    VisibilityFunction<Visibility, Sample, S>
        RESTIR_HOST_DEVICE Reservoir<Sample>
        combine_with(const Reservoir<Sample>& receiver_reservoir, const S& surface,
                     const Inputs& inputs, const ReuseParams& params,
                     const ReuseBridge<Target, Visibility, MaterialTest, Shift>& bridge, Rng& rng) {
    const Reservoir<Sample> canonical =
        receiver_reservoir.is_well_formed() ? receiver_reservoir : Reservoir<Sample>{};
#if !RESTIR_STREAMED_REUSE
    if constexpr (ReuseSetTraits<Inputs>::streamed) {
        detail::UnsetArray<detail::LentInputOf<Sample, S, Inputs>, max_reuse_inputs - 1u> room;
        return combine_with<Mode, Sample>(canonical, surface,
                                          detail::gather_inputs<Sample, S>(inputs, room.items),
                                          params, bridge, rng);
    } else
#endif
        if constexpr (Mode == BiasCorrection::none)
        return combine_one_over_m(canonical, surface, inputs, params, bridge, rng);
    else if constexpr (Mode == BiasCorrection::one_over_z)
        return combine_one_over_z(canonical, surface, inputs, params, bridge, rng);
    else if constexpr (Mode == BiasCorrection::balance_heuristic)
        return combine_balance_heuristic(canonical, surface, inputs, params, bridge, rng);
    else if constexpr (Mode == BiasCorrection::defensive_pairwise)
        return combine_defensive_pairwise(canonical, surface, inputs, params, bridge, rng);
    else
        return combine_pairwise(canonical, surface, inputs, params, bridge, rng);
}

/// `combine_with` for the mode in `params.bias_correction`, chosen at run time.
template <class Sample, Surface S, class Inputs, class Target, class Visibility, class MaterialTest,
          class Shift, UniformRng Rng>
requires ReuseInputs<Inputs, Sample, S> && TargetFunction<Target, Sample, S> &&
    VisibilityFunction<Visibility, Sample, S>
        RESTIR_HOST_DEVICE Reservoir<Sample>
        combine_inputs(const Reservoir<Sample>& receiver_reservoir, const S& surface,
                       const Inputs& inputs, const ReuseParams& params,
                       const ReuseBridge<Target, Visibility, MaterialTest, Shift>& bridge,
                       Rng& rng) {
    switch (params.bias_correction) {
    case BiasCorrection::none:
        return combine_with<BiasCorrection::none, Sample>(receiver_reservoir, surface, inputs,
                                                          params, bridge, rng);
    case BiasCorrection::one_over_z:
        return combine_with<BiasCorrection::one_over_z, Sample>(receiver_reservoir, surface, inputs,
                                                                params, bridge, rng);
    case BiasCorrection::balance_heuristic:
        return combine_with<BiasCorrection::balance_heuristic, Sample>(receiver_reservoir, surface,
                                                                       inputs, params, bridge, rng);
    case BiasCorrection::defensive_pairwise:
        return combine_with<BiasCorrection::defensive_pairwise, Sample>(
            receiver_reservoir, surface, inputs, params, bridge, rng);
    case BiasCorrection::pairwise:
        break;
    }
    return combine_with<BiasCorrection::pairwise, Sample>(receiver_reservoir, surface, inputs,
                                                          params, bridge, rng);
}

/// `combine_inputs` over `neighbour_count` inputs gathered into an array; the first
/// max_reuse_inputs - 1 well-formed ones take part. Deprecated (pass a `ReuseInputSpan` to
/// `combine_inputs`); to be removed in 0.4.
template <class Sample, Surface S, class Target, class Visibility, class MaterialTest, class Shift,
          UniformRng Rng>
requires TargetFunction<Target, Sample, S> && VisibilityFunction<Visibility, Sample, S>
[[deprecated(
    "pass restir::ReuseInputSpan{inputs, count} to restir::combine_inputs")]] RESTIR_HOST_DEVICE
    Reservoir<Sample>
    combine_reservoirs(const Reservoir<Sample>& receiver_reservoir, const S& surface,
                       const ReuseInput<Sample, S>* neighbours, std::uint32_t neighbour_count,
                       const ReuseParams& params,
                       const ReuseBridge<Target, Visibility, MaterialTest, Shift>& bridge,
                       Rng& rng) {
    RESTIR_ASSERT(neighbour_count < max_reuse_inputs);
    return combine_inputs(receiver_reservoir, surface,
                          ReuseInputSpan<Sample, S>{neighbours, neighbour_count}, params, bridge,
                          rng);
}

} // namespace restir
