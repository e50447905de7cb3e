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
#include "restir/reuse/shift.hpp"
#include "restir/reuse/similarity.hpp"
#include "restir/reuse/visibility.hpp"

#include <cstdint>
#include <type_traits>

namespace restir {

/// How the inputs of a reuse step are weighted.
enum class BiasCorrection {
    /// m_i = M_i / sum_j M_j (Bitterli et al. 2020, Alg. 4). Cheapest: no extra target
    /// evaluation or ray. Biased (darker) wherever a neighbour cannot produce a sample that
    /// the receiver can: different normals, occluders, materials.
    none,
    /// m_i(x) = M_i / Z(x), Z(x) the sum of M_j over the inputs whose target (with visibility,
    /// under visibility reuse) is positive at x; Z is evaluated for the selected sample only
    /// (Bitterli et al. 2020, Alg. 6). Unbiased; 2k target evaluations and, under visibility
    /// reuse, 2k shadow rays per pixel.
    one_over_z,
    /// Generalized balance heuristic m_i(x) = M_i p-hat_i(x) / sum_j M_j p-hat_j(x) (Lin et
    /// al. 2022, with the M as confidence weights). Unbiased, usually the lowest variance;
    /// (k + 1)^2 target evaluations and, under visibility reuse, k (k + 1) shadow rays.
    balance_heuristic,
    /// Pairwise MIS (Bitterli's 2022 dissertation): the canonical input and each neighbour
    /// form a two-technique balance heuristic, the pairs weighted by their confidence.
    /// Unbiased; 3k target evaluations and, under visibility reuse, 2k shadow rays.
    pairwise,
};

/// What the reservoirs that enter a reuse step know about visibility, and which shadow rays
/// the MIS weights of the unbiased modes trace (Bitterli et al. 2020, Sec. 4 and Alg. 6).
enum class ReuseVisibility : std::uint8_t {
    /// No visibility reuse: no reservoir is visibility-tested before reuse, and reuse traces
    /// no ray. Shade f(y) W only where y is visible.
    none,
    /// Visibility reuse (every reservoir went through `apply_visibility`: W = 0 where its
    /// sample is occluded), and MIS weights that assume every sample visible from every
    /// neighbour, as RTXDI's default pairwise mode does: no ray in reuse. The weights still sum
    /// to one but give a neighbour weight for samples occluded from it, so the result is biased
    /// near shadow boundaries (docs/noise-and-bias.md).
    assumed,
    /// Visibility reuse with exact MIS weights: a neighbour's p-hat includes its visibility (a
    /// ray per neighbour and sample asked about), and each input's own sample is retested at
    /// its own surface (one ray per input), since it may come out of an earlier reuse step.
    traced,
    /// As `traced`, for inputs whose own samples have all passed `apply_visibility` at their own
    /// surfaces since they were last resampled (initial reservoirs, last frame's shaded ones,
    /// the frame recipe's retested results): the same weights with k rays fewer per pixel.
    traced_inputs_tested,
};

/// Whether reservoirs under `v` carry visibility (W = 0 where the sample is occluded).
RESTIR_HOST_DEVICE constexpr bool carries_visibility(ReuseVisibility v) noexcept {
    return v != ReuseVisibility::none;
}
/// Whether the MIS weights under `v` trace shadow rays.
RESTIR_HOST_DEVICE constexpr bool traces_mis_rays(ReuseVisibility v) noexcept {
    return v == ReuseVisibility::traced || v == ReuseVisibility::traced_inputs_tested;
}

/// How a reuse step weighs its inputs: the bias correction and the visibility it accounts for.
struct ReuseParams {
    /// Default: pairwise MIS, unbiased at O(k) cost.
    BiasCorrection bias_correction = BiasCorrection::pairwise;
    /// Default: visibility reuse with exact (traced) MIS weights.
    ReuseVisibility visibility = ReuseVisibility::traced;
};

/// The functions reuse evaluates: the target p-hat(sample, surface), the visibility of a
/// sample from a surface, the material hook of the similarity test, and the shift that carries
/// a sample from the surface that resampled it to another (reuse/shift.hpp; the identity for
/// light samples, which compiles away).
template <class Target, class Visibility, class MaterialTest = AnyMaterial,
          class Shift = IdentityShift>
struct ReuseBridge {
    Target target;
    Visibility visibility;
    MaterialTest material_test{};
    Shift shift{};
};

template <class Target, class Visibility>
ReuseBridge(Target, Visibility) -> ReuseBridge<Target, Visibility, AnyMaterial, IdentityShift>;
template <class Target, class Visibility, class MaterialTest>
ReuseBridge(Target, Visibility, MaterialTest)
    -> ReuseBridge<Target, Visibility, MaterialTest, IdentityShift>;
template <class Target, class Visibility, class MaterialTest, class Shift>
ReuseBridge(Target, Visibility, MaterialTest, Shift)
    -> ReuseBridge<Target, Visibility, MaterialTest, Shift>;

namespace detail {

/// What an input lends under a shift other than the identity: a copy of its reservoir, which
/// `ReuseTerms::lend` turns into the shifted one (the sample shifted to the receiver, W times the
/// shift's Jacobian, so that merging weighs it with p-hat_q(T(x)) W |dT/dx|, Lin et al. 2022,
/// Eq. 3.4); an input without a sample is merged as it is, with weight 0. A copy rather than a
/// choice between two references, which would put the reservoir in a GPU thread's local memory.
template <class Sample, bool Shifts>
struct LentInput {
    Reservoir<Sample> lent;
    float jacobian = 0.0f; ///< |dT/dx|, 0 where the shift fails.
    RESTIR_HOST_DEVICE explicit LentInput(const Reservoir<Sample>& r) : lent(r) {}
    RESTIR_HOST_DEVICE const Reservoir<Sample>& of(const Reservoir<Sample>&) const { return lent; }
};
/// Under the identity: the reservoir as it is, Jacobian 1 (nothing stored).
template <class Sample>
struct LentInput<Sample, false> {
    static constexpr float jacobian = 1.0f;
    RESTIR_HOST_DEVICE explicit LentInput(const Reservoir<Sample>&) {}
    RESTIR_HOST_DEVICE const Reservoir<Sample>& of(const Reservoir<Sample>& r) const { return r; }
};

/// What every bias correction evaluates: p-hat at the receiver, and p-hat_j(x) of input j as
/// the MIS weights need it, with the shifts between their surfaces.
template <class Sample, class S, class Bridge>
struct ReuseTerms {
    const S& surface;
    const ReuseParams& params;
    const Bridge& bridge;

    /// Whether samples change between surfaces (a shift other than the identity).
    static constexpr bool shifts = !is_identity_shift<decltype(Bridge::shift)>;

    /// p-hat at the receiver, without visibility: the target of the result.
    RESTIR_HOST_DEVICE float here(const Sample& x) const {
        return static_cast<float>(bridge.target(x, surface));
    }
    /// What input j lends (`LentInput`).
    using Lent = LentInput<Sample, shifts>;

    /// p-hat_q of the sample of input j's reservoir `r` (which holds one), lent from surface
    /// `there`: under a shift p-hat_q(T(x)), 0 where T fails, with `lent` holding the shifted
    /// reservoir and the Jacobian; without one p-hat_q(x).
    RESTIR_HOST_DEVICE float lend(Lent& lent, const Reservoir<Sample>& r, const S& there) const {
        if constexpr (shifts) {
            const ShiftedSample<Sample> y = bridge.shift(r.sample, there, surface);
            lent.lent.sample = y.sample;
            const bool shifted = is_valid_weight(y.jacobian) && y.jacobian > 0.0f;
            lent.jacobian = shifted ? y.jacobian : 0.0f;
            lent.lent.contribution_weight *= lent.jacobian; // never enters where T fails
            return shifted ? here(y.sample) : 0.0f;
        } else {
            return here(r.sample);
        }
    }
    /// p-hat_j(x) at input j's surface, times the visibility there under visibility reuse,
    /// since input j then cannot lend samples that are occluded from it. (Its own sample
    /// included: a reservoir that went through reuse after its last visibility test may hold
    /// one.) The canonical input needs no visibility term: where the receiver sees nothing the
    /// integrand is zero whatever the weights. Under a shift, x is the receiver's and enters as
    /// p-hat_j(T(x)) |dT/dx| with T the shift from the receiver to input j's surface (Lin et
    /// al. 2022, Eq. 5.10), 0 where it fails.
    RESTIR_HOST_DEVICE float at(const Sample& x, const S& there) const {
        if constexpr (shifts) {
            const ShiftedSample<Sample> y = bridge.shift(x, surface, there);
            if (!is_valid_weight(y.jacobian) || !(y.jacobian > 0.0f))
                return 0.0f;
            return visible_target(y.sample, there) * y.jacobian;
        } else {
            return visible_target(x, there);
        }
    }
    /// p-hat_j(y_j) of input j's own sample, as `at` gives it: the reservoir keeps the target
    /// at its own surface, so only the visibility term needs computing (a ray, under traced
    /// visibility reuse, unless the inputs are known to be tested).
    RESTIR_HOST_DEVICE float own(const Reservoir<Sample>& r, const S& there) const {
        const float t = r.target_value;
        if (t > 0.0f && params.visibility == ReuseVisibility::traced &&
            !bridge.visibility(r.sample, there))
            return 0.0f;
        return t;
    }
    RESTIR_HOST_DEVICE bool traces() const { return traces_mis_rays(params.visibility); }

private:
    RESTIR_HOST_DEVICE float visible_target(const Sample& x, const S& there) const {
        const auto t = static_cast<float>(bridge.target(x, there));
        if (t > 0.0f && traces() && !bridge.visibility(x, there))
            return 0.0f;
        return t;
    }
};

/// Input sets that declare `packed` hold only inputs that take part: non-null and well-formed.
template <class Inputs>
inline constexpr bool packed_inputs = requires {
    requires Inputs::packed;
};

/// The cap a set puts on the M of the reservoirs it lends (`no_candidate_cap` by default).
template <class Inputs>
RESTIR_HOST_DEVICE constexpr std::uint32_t candidate_cap_of(const Inputs& inputs) {
    if constexpr (requires { inputs.candidate_cap; })
        return inputs.candidate_cap;
    else
        return no_candidate_cap;
}

/// Calls `visit(j, reservoir, surface)` for the inputs that take part, in slot order: slots
/// that lend a well-formed reservoir, at most max_reuse_inputs - 1 of them; j counts them.
/// The reservoir is the one the input lends, capped at the set's `candidate_cap`. Returns how
/// many took part.
template <class Sample, class S, class Inputs, class Visit>
RESTIR_HOST_DEVICE std::uint32_t for_each_input(const Inputs& inputs, Visit&& visit) {
    std::uint32_t taken = 0u;
    const std::uint32_t slots = inputs.size();
    const std::uint32_t cap = candidate_cap_of(inputs);
    for (std::uint32_t i = 0; i < slots && taken + 1u < max_reuse_inputs; ++i) {
        const auto input = lent_input<Sample, S>(inputs[i]);
        if constexpr (!packed_inputs<Inputs>)
            if (input.reservoir == nullptr || !input.reservoir->is_well_formed())
                continue;
        // The reservoir in its buffer, or a copy where the cap lowers its M.
        if (input.reservoir->candidate_count <= cap) {
            visit(taken++, *input.reservoir, lent_surface(input));
        } else {
            Reservoir<Sample> capped = *input.reservoir;
            capped.cap_candidate_count(cap);
            visit(taken++, capped, lent_surface(input));
        }
    }
    return taken;
}

/// The inputs that take part, gathered once into an array: what host code visits, so that the
/// checks and lookups of a streamed set are not repeated at every pass over the inputs; device
/// code visits the set itself and keeps no array (registers, not local memory).
template <class Input>
struct PackedInputs {
    static constexpr bool packed = true;
    Input items[max_reuse_inputs - 1u];
    std::uint32_t count = 0u;
    std::uint32_t candidate_cap = no_candidate_cap;
    RESTIR_HOST_DEVICE constexpr std::uint32_t size() const noexcept { return count; }
    RESTIR_HOST_DEVICE constexpr const Input& operator[](std::uint32_t i) const { return items[i]; }
};

template <class Sample, class S, class Inputs>
RESTIR_HOST_DEVICE auto pack_inputs(const Inputs& inputs) {
    using Input = decltype(lent_input<Sample, S>(inputs[0u]));
    PackedInputs<Input> packed;
    packed.candidate_cap = candidate_cap_of(inputs);
    const std::uint32_t slots = inputs.size();
    for (std::uint32_t i = 0; i < slots && packed.count + 1u < max_reuse_inputs; ++i) {
        const Input input = lent_input<Sample, S>(inputs[i]);
        if (input.reservoir != nullptr && input.reservoir->is_well_formed())
            packed.items[packed.count++] = input;
    }
    return packed;
}

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
    for_each_input<Sample, S>(
        inputs, [&](std::uint32_t, const Reservoir<Sample>& r, const S& there) {
            const bool lends = r.has_sample() && (!only_own_support || terms.own(r, there) > 0.0f);
            typename Terms::Lent lent(r);
            const float here = lends ? terms.lend(lent, r, there) : 0.0f;
            result.merge(lent.of(r), here, next_float(rng));
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
    detail::for_each_input<Sample, S>(inputs, [&](std::uint32_t i, const Reservoir<Sample>& r,
                                                  const S& there) {
        typename decltype(terms)::Lent lent(r);
        float here = 0.0f;
        float mis_weight = 0.0f;
        if (r.has_sample()) {
            here = terms.lend(lent, r, there);
            const Sums sums = neighbour_sums(lent.of(r).sample, i);
            if constexpr (decltype(terms)::shifts)
                // y = T(y_i): m_i = M_i p-hat_i(y_i) / (M_i p-hat_i(y_i) + |dT/dy_i| (M_c
                // p-hat_q(y) + sum_{l != i} M_l p-hat_l(T_l(y)) |dT_l/dy|)), the balance
                // heuristic over the targets carried to the receiver (Lin et al. 2022,
                // Eq. 5.10), numerator and denominator times |dT/dy_i|.
                mis_weight = safe_divide(
                    sums.own, sums.own + lent.jacobian * (canonical_count * here + sums.others));
            else
                mis_weight = safe_divide(sums.own, canonical_count * here + sums.all);
        }
        result.merge_with_mis(lent.of(r), here, mis_weight, next_float(rng));
    });
    result.finalize_normalized(1.0f);
    return result;
}

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
    const detail::ReuseTerms<Sample, S, ReuseBridge<Target, Visibility, MaterialTest, Shift>> terms{
        surface, params, bridge};
    const float canonical_count = static_cast<float>(canonical.candidate_count);
    float total_count = canonical_count;
    const std::uint32_t k = detail::for_each_input<Sample, S>(
        inputs, [&](std::uint32_t, const Reservoir<Sample>& r, const S&) {
            total_count += static_cast<float>(r.candidate_count);
        });
    // Every return returns one named result, so that it is built in place in the caller's
    // memory rather than copied through the stack.
    Reservoir<Sample> result;
    if (k == 0u) {
        result = canonical;
        return result;
    }
    const float canonical_share = canonical_count / static_cast<float>(k);
    float canonical_mis = 0.0f;
    detail::for_each_input<Sample, S>(inputs, [&](std::uint32_t, const Reservoir<Sample>& r,
                                                  const S& there) {
        const float count = static_cast<float>(r.candidate_count);
        const float pair_weight = safe_divide(count + canonical_share, total_count);
        typename decltype(terms)::Lent lent(r);
        float here = 0.0f;
        float mis_weight = 0.0f;
        if (r.has_sample()) {
            here = terms.lend(lent, r, there);
            // Under a shift, the canonical technique's density carried to input i's domain is
            // p-hat_q(T(y_i)) |dT/dy_i| (Lin et al. 2022, Eq. 5.10).
            const float own = count * terms.own(r, there);
            mis_weight =
                pair_weight * safe_divide(own, own + canonical_share * here * lent.jacobian);
        }
        result.merge_with_mis(lent.of(r), here, mis_weight, next_float(rng));
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
#if !defined(__CUDA_ARCH__)
    if constexpr (!detail::packed_inputs<Inputs>)
        return combine_with<Mode, Sample>(
            canonical, surface, detail::pack_inputs<Sample, S>(inputs), params, bridge, rng);
    else
#endif
        if constexpr (Mode == BiasCorrection::none)
        return combine_one_over_m(canonical, surface, inputs, params, bridge, rng);
    else if constexpr (Mode == BiasCorrection::one_over_z)
        return combine_one_over_z(canonical, surface, inputs, params, bridge, rng);
    else if constexpr (Mode == BiasCorrection::balance_heuristic)
        return combine_balance_heuristic(canonical, surface, inputs, params, bridge, rng);
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
    case BiasCorrection::pairwise:
        break;
    }
    return combine_with<BiasCorrection::pairwise, Sample>(receiver_reservoir, surface, inputs,
                                                          params, bridge, rng);
}

/// `combine_inputs` over `neighbour_count` inputs gathered into an array (for renderers that
/// collect a pass's inputs ahead of it); the first max_reuse_inputs - 1 well-formed ones take
/// part.
template <class Sample, Surface S, class Target, class Visibility, class MaterialTest, class Shift,
          UniformRng Rng>
requires TargetFunction<Target, Sample, S> && VisibilityFunction<Visibility, Sample, S>
    RESTIR_HOST_DEVICE Reservoir<Sample>
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
