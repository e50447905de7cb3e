// The reuse step as it was before the streamed rewrite (one function over an array of inputs,
// a runtime switch over the bias corrections), kept as the reference that the streamed
// functions must match bit for bit (tests/reuse/streamed_reuse_test.cpp).
#pragma once

#include <restir/reuse/bias_correction.hpp>

namespace restir::legacy {

/// Combines the receiver's own (canonical) reservoir (computed for `surface`, finalised) with
/// `neighbour_count` borrowed reservoirs under `params.bias_correction`, and returns the
/// finalised result, whose M is the sum of the inputs' M. Inputs should already have passed
/// the similarity tests; any that holds non-finite values is skipped as if it were absent.
/// Consumes one uniform number from `rng` per input that takes part.
template <class Sample, Surface S, class Target, class Visibility, class MaterialTest,
          UniformRng Rng>
requires TargetFunction<Target, Sample, S> && VisibilityFunction<Visibility, Sample, S>
    RESTIR_HOST_DEVICE Reservoir<Sample>
    combine_reservoirs(const Reservoir<Sample>& receiver_reservoir, const S& surface,
                       const ReuseInput<Sample, S>* neighbours, std::uint32_t neighbour_count,
                       const ReuseParams& params,
                       const ReuseBridge<Target, Visibility, MaterialTest>& bridge, Rng& rng) {
    RESTIR_ASSERT(neighbour_count < max_reuse_inputs);
    // A canonical reservoir with non-finite fields takes part as an empty one.
    const Reservoir<Sample> canonical =
        receiver_reservoir.is_well_formed() ? receiver_reservoir : Reservoir<Sample>{};
    // Keep only well-formed inputs.
    ReuseInput<Sample, S> inputs[max_reuse_inputs];
    std::uint32_t k = 0u;
    for (std::uint32_t i = 0; i < neighbour_count && k + 1u < max_reuse_inputs; ++i)
        if (neighbours[i].reservoir->is_well_formed())
            inputs[k++] = neighbours[i];

    // p-hat at the receiver, without visibility: the target of the result.
    const auto target_here = [&](const Sample& x) {
        return static_cast<float>(bridge.target(x, surface));
    };
    // p-hat_j(x) of input j as the MIS weights need it: the target at its surface, times the
    // visibility there under visibility reuse, since input j then cannot lend samples that
    // are occluded from it. (Its own sample included: a reservoir that went through reuse
    // after its last visibility test may hold one.) The canonical input needs no visibility
    // term: where the receiver sees nothing the integrand is zero whatever the weights.
    const auto target_at = [&](const Sample& x, const S& there) {
        const auto t = static_cast<float>(bridge.target(x, there));
        if (t > 0.0f && params.visibility_reuse && params.trace_mis_visibility &&
            !bridge.visibility(x, there))
            return 0.0f;
        return t;
    };
    // p-hat_j(y_j) of input j's own sample, as target_at gives it: the reservoir keeps the
    // target at its own surface, so only the visibility term needs computing (a ray, under
    // traced visibility reuse). Saves k target evaluations per pixel.
    const auto own_target = [&](const ReuseInput<Sample, S>& input) {
        const Reservoir<Sample>& r = *input.reservoir;
        const float t = r.target_value;
        if (t > 0.0f && params.visibility_reuse && params.trace_mis_visibility &&
            !params.inputs_visibility_tested && !bridge.visibility(r.sample, *input.surface))
            return 0.0f;
        return t;
    };
    const float canonical_count = static_cast<float>(canonical.candidate_count);

    Reservoir<Sample> result;
    switch (params.bias_correction) {
    case BiasCorrection::none:
    case BiasCorrection::one_over_z: {
        // Alg. 4 / Alg. 6: w_i = p-hat_q(y_i) W_i M_i.
        result.merge(canonical, canonical.target_value, next_float(rng));
        // 1/Z counts input i at y only where p-hat_i(y) > 0, so input i must not lend a sample
        // outside that set either (a reservoir that went through reuse may hold one that is
        // occluded from its own surface); "none" skips the test.
        const bool check_own = params.bias_correction == BiasCorrection::one_over_z;
        for (std::uint32_t i = 0; i < k; ++i) {
            const Reservoir<Sample>& r = *inputs[i].reservoir;
            const bool lends = r.has_sample() && (!check_own || own_target(inputs[i]) > 0.0f);
            result.merge(r, lends ? target_here(r.sample) : 0.0f, next_float(rng));
        }
        if (params.bias_correction == BiasCorrection::none) {
            result.finalize();
            break;
        }
        // Z: the M of every input that could have produced y (the canonical one did or could,
        // since p-hat_q(y) > 0 for a selected y).
        float z = canonical_count;
        for (std::uint32_t i = 0; i < k && result.has_sample(); ++i)
            if (target_at(result.sample, *inputs[i].surface) > 0.0f)
                z += static_cast<float>(inputs[i].reservoir->candidate_count);
        result.finalize_normalized(safe_divide(1.0f, z));
        break;
    }
    case BiasCorrection::balance_heuristic: {
        // m_j(x) = M_j p-hat_j(x) / (M_c p-hat_q(x) + sum_l M_l p-hat_l(x)). Sums the
        // neighbours' terms at x and returns the term of neighbour `own` through `own_term`.
        const auto neighbour_sum = [&](const Sample& x, std::uint32_t own, float& own_term) {
            float sum = 0.0f;
            for (std::uint32_t l = 0; l < k; ++l) {
                const float term =
                    static_cast<float>(inputs[l].reservoir->candidate_count) *
                    (l == own ? own_target(inputs[l]) : target_at(x, *inputs[l].surface));
                sum += term;
                if (l == own)
                    own_term = term;
            }
            return sum;
        };
        float canonical_mis = 0.0f;
        if (canonical.has_sample()) {
            const float own = canonical_count * canonical.target_value;
            float unused = 0.0f;
            canonical_mis = safe_divide(own, own + neighbour_sum(canonical.sample, k, unused));
        }
        result.merge_with_mis(canonical, canonical.target_value, canonical_mis, next_float(rng));
        for (std::uint32_t i = 0; i < k; ++i) {
            const Reservoir<Sample>& r = *inputs[i].reservoir;
            float here = 0.0f;
            float mis_weight = 0.0f;
            if (r.has_sample()) {
                here = target_here(r.sample);
                float own = 0.0f;
                const float all_neighbours = neighbour_sum(r.sample, i, own);
                mis_weight = safe_divide(own, canonical_count * here + all_neighbours);
            }
            result.merge_with_mis(r, here, mis_weight, next_float(rng));
        }
        result.finalize_normalized(1.0f);
        break;
    }
    case BiasCorrection::pairwise: {
        if (k == 0u) {
            result = canonical;
            break;
        }
        // Pair i = (canonical with confidence M_c / k, neighbour i with M_i), worth
        // beta_i = (M_i + M_c / k) / M_total of the whole; the betas sum to one.
        float total_count = canonical_count;
        for (std::uint32_t i = 0; i < k; ++i)
            total_count += static_cast<float>(inputs[i].reservoir->candidate_count);
        const float canonical_share = canonical_count / static_cast<float>(k);
        float canonical_mis = 0.0f;
        for (std::uint32_t i = 0; i < k; ++i) {
            const Reservoir<Sample>& r = *inputs[i].reservoir;
            const S& there = *inputs[i].surface;
            const float count = static_cast<float>(r.candidate_count);
            const float pair_weight = safe_divide(count + canonical_share, total_count);
            float here = 0.0f;
            float mis_weight = 0.0f;
            if (r.has_sample()) {
                here = target_here(r.sample);
                const float own = count * own_target(inputs[i]);
                mis_weight = pair_weight * safe_divide(own, own + canonical_share * here);
            }
            result.merge_with_mis(r, here, mis_weight, next_float(rng));
            if (canonical.has_sample()) {
                const float canonical_own = canonical_share * canonical.target_value;
                canonical_mis +=
                    pair_weight *
                    safe_divide(canonical_own,
                                canonical_own + count * target_at(canonical.sample, there));
            }
        }
        result.merge_with_mis(canonical, canonical.target_value, canonical_mis, next_float(rng));
        result.finalize_normalized(1.0f);
        break;
    }
    }
    return result;
}

} // namespace restir::legacy
