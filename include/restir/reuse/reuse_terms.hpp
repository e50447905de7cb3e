/// @file reuse/reuse_terms.hpp
/// What every bias correction of reuse/bias_correction.hpp evaluates, shared by the four modes
/// (internal): p-hat at the receiver and at the inputs' surfaces, carried through the bridge's
/// shift, and the visit of the inputs that take part.
#pragma once

#include "restir/config.hpp"
#include "restir/core/math.hpp"
#include "restir/core/reservoir.hpp"
#include "restir/reuse/reuse_input.hpp"
#include "restir/reuse/reuse_params.hpp"
#include "restir/reuse/shift.hpp"

#include <cstdint>
#include <type_traits>
#include <utility>

namespace restir::detail {

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
    /// What input j lends, initialised with its reservoir: under a shift a copy, which `lend`
    /// shifts to the receiver (a copy rather than a choice between two references, which would
    /// put the reservoir in a GPU thread's local memory); under the identity the reservoir itself.
    using Lent = std::conditional_t<shifts, Reservoir<Sample>, const Reservoir<Sample>&>;

    /// p-hat_q of the sample of `lent` (input j's reservoir, which holds one), lent from surface
    /// `there`: under a shift p-hat_q(T(x)), 0 where T fails, with `lent`'s sample shifted, its W
    /// times the Jacobian, so that merging weighs it with p-hat_q(T(x)) W |dT/dx| (Lin et al.
    /// 2022, Eq. 3.4), and `jacobian` set to |dT/dx| (0 where T fails); without one p-hat_q(x).
    RESTIR_HOST_DEVICE float lend(Lent& lent, const S& there, float& jacobian) const {
        if constexpr (shifts) {
            const ShiftedSample<Sample> y = bridge.shift(lent.sample, there, surface);
            lent.sample = y.sample;
            const bool shifted = is_valid_weight(y.jacobian) && y.jacobian > 0.0f;
            jacobian = shifted ? y.jacobian : 0.0f;
            lent.contribution_weight *= jacobian; // never enters where T fails
            return shifted ? here(y.sample) : 0.0f;
        } else {
            static_cast<void>(there), static_cast<void>(jacobian);
            return here(lent.sample);
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

/// Calls `visit(j, reservoir, surface)` for the inputs that take part, in slot order: slots
/// that lend a well-formed reservoir, at most max_reuse_inputs - 1 of them; j counts them.
/// The reservoir is the one the input lends, its M capped at the set's cap (`ReuseSetTraits`).
/// Returns how many took part.
template <class Sample, class S, class Inputs, class Visit>
RESTIR_HOST_DEVICE std::uint32_t for_each_input(const Inputs& inputs, Visit&& visit) {
    std::uint32_t taken = 0u;
    const std::uint32_t slots = inputs.size();
    const std::uint32_t cap = ReuseSetTraits<Inputs>::candidate_cap(inputs);
    const bool all_lend = ReuseSetTraits<Inputs>::all_lend(inputs);
    for (std::uint32_t i = 0; i < slots && taken + 1u < max_reuse_inputs; ++i) {
        const auto input = lent_input<Sample, S>(inputs[i]);
        if (!all_lend && (input.reservoir == nullptr || !input.reservoir->is_well_formed()))
            continue;
            // The reservoir in its buffer, or a copy where the cap lowers its M.
#if RESTIR_STREAMED_REUSE
        // Two calls rather than a choice of reference, which would put the copy in a GPU
        // thread's local memory.
        if (input.reservoir->candidate_count <= cap) {
            visit(taken++, *input.reservoir, lent_surface(input));
        } else {
            Reservoir<Sample> capped = *input.reservoir;
            capped.cap_candidate_count(cap);
            visit(taken++, capped, lent_surface(input));
        }
#else
        // One call: a second copy of `visit` costs a host loop more than the choice.
        UnsetArray<Reservoir<Sample>, 1u> capped;
        const Reservoir<Sample>* lent = input.reservoir;
        if (lent->candidate_count > cap) {
            capped.items[0] = *lent;
            capped.items[0].cap_candidate_count(cap);
            lent = capped.items;
        }
        visit(taken++, *lent, lent_surface(input));
#endif
    }
    return taken;
}

/// p-hat_q of the samples of the inputs that take part, for the merges of the bias corrections
/// (`ReuseTerms::lend`). Host code without a shift evaluates them all in one loop ahead of the
/// merges: the evaluations are independent, and between the merges' random choices of sample
/// (branches the CPU mispredicts) they would not overlap. Device code and
/// shifted samples evaluate each at its merge, so that a GPU thread keeps no array.
template <class Sample, class S, class Terms, class Inputs>
struct LentTargets {
#if RESTIR_STREAMED_REUSE
    static constexpr bool can_evaluate_ahead = false;
#else
    static constexpr bool can_evaluate_ahead = !Terms::shifts;
    float values[max_reuse_inputs - 1u];
#endif
    const Terms& terms;
    bool ahead = false; ///< Whether `values` holds them.

    /// `evaluate_ahead` false where only some inputs lend (1/Z asks each for its own sample's
    /// visibility first): each is then evaluated at its merge. A single input (the temporal
    /// pass's) has nothing to overlap with.
    RESTIR_HOST_DEVICE LentTargets(const Inputs& inputs, const Terms& t, bool evaluate_ahead = true)
        : terms(t), ahead(can_evaluate_ahead && evaluate_ahead && inputs.size() > 1u) {
#if !RESTIR_STREAMED_REUSE
        if constexpr (can_evaluate_ahead)
            if (ahead)
                for_each_input<Sample, S>(
                    inputs, [&](std::uint32_t j, const Reservoir<Sample>& r, const S&) {
                        values[j] = r.has_sample() ? terms.here(r.sample) : 0.0f;
                    });
#endif
    }

    /// `terms.lend(lent, there, jacobian)` of input j.
    RESTIR_HOST_DEVICE float lend(std::uint32_t j, typename Terms::Lent& lent, const S& there,
                                  float& jacobian) const {
#if !RESTIR_STREAMED_REUSE
        if constexpr (can_evaluate_ahead)
            if (ahead)
                return values[j];
#endif
        static_cast<void>(j);
        return terms.lend(lent, there, jacobian);
    }
};

/// The input type that set `Inputs` lends, as reuse visits it.
template <class Sample, class S, class Inputs>
using LentInputOf = decltype(lent_input<Sample, S>(std::declval<const Inputs&>()[0u]));

/// Host code: the inputs of `inputs` that take part, gathered once into `items` (the caller's
/// array, not zeroed), so that the checks and lookups of a streamed set are not repeated at
/// every pass over its inputs. Device code visits the set itself and keeps no array (registers,
/// not local memory).
template <class Sample, class S, class Inputs>
RESTIR_HOST_DEVICE ReuseInputSpan<Sample, S, decltype(LentInputOf<Sample, S, Inputs>::surface)>
gather_inputs(const Inputs& inputs, LentInputOf<Sample, S, Inputs>* items) {
    ReuseInputSpan<Sample, S, decltype(LentInputOf<Sample, S, Inputs>::surface)> span{
        items, 0u, ReuseSetTraits<Inputs>::candidate_cap(inputs), true};
    const bool all_lend = ReuseSetTraits<Inputs>::all_lend(inputs);
    const std::uint32_t slots = inputs.size();
    for (std::uint32_t i = 0; i < slots && span.count + 1u < max_reuse_inputs; ++i) {
        const auto input = lent_input<Sample, S>(inputs[i]);
        if (all_lend || (input.reservoir != nullptr && input.reservoir->is_well_formed()))
            items[span.count++] = input;
    }
    return span;
}

} // namespace restir::detail
