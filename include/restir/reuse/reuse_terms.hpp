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

namespace restir::detail {

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

/// Input sets that declare `streamed` recompute an input at every visit (host code gathers
/// them into an array first).
template <class Inputs>
inline constexpr bool streamed_inputs = requires {
    requires Inputs::streamed;
};

/// The most inputs a set holds: its `capacity` where it declares one (a single input: 1),
/// else max_reuse_inputs - 1.
template <class Inputs>
inline constexpr std::uint32_t input_capacity = [] {
    if constexpr (requires { Inputs::capacity; })
        return std::uint32_t{Inputs::capacity};
    else
        return max_reuse_inputs - 1u;
}();

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
    // A single input (the temporal pass's) has nothing to overlap with.
    static constexpr bool can_evaluate_ahead = !Terms::shifts && input_capacity<Inputs> > 1u;
    float values[max_reuse_inputs - 1u];
#endif
    const Terms& terms;
    bool ahead = false; ///< Whether `values` holds them.

    /// `evaluate_ahead` false where only some inputs lend (1/Z asks each for its own sample's
    /// visibility first): each is then evaluated at its merge.
    RESTIR_HOST_DEVICE LentTargets(const Inputs& inputs, const Terms& t, bool evaluate_ahead = true)
        : terms(t), ahead(can_evaluate_ahead && evaluate_ahead) {
#if !RESTIR_STREAMED_REUSE
        if constexpr (can_evaluate_ahead)
            if (ahead)
                for_each_input<Sample, S>(
                    inputs, [&](std::uint32_t j, const Reservoir<Sample>& r, const S&) {
                        values[j] = r.has_sample() ? terms.here(r.sample) : 0.0f;
                    });
#else
        static_cast<void>(inputs);
#endif
    }

    /// `terms.lend(lent, r, there)` of input j (its reservoir `r`, which holds a sample).
    RESTIR_HOST_DEVICE float lend(std::uint32_t j, typename Terms::Lent& lent,
                                  const Reservoir<Sample>& r, const S& there) const {
#if !RESTIR_STREAMED_REUSE
        if constexpr (can_evaluate_ahead)
            if (ahead)
                return values[j];
#endif
        static_cast<void>(j);
        return terms.lend(lent, r, there);
    }
};

/// The inputs that take part, gathered once into an array: what host code visits, so that the
/// checks and lookups of a streamed set are not repeated at every pass over the inputs; device
/// code visits the set itself and keeps no array (registers, not local memory).
template <class Input, std::uint32_t Capacity = max_reuse_inputs - 1u>
struct PackedInputs {
    static constexpr bool packed = true;
    static constexpr std::uint32_t capacity = Capacity;
    Input items[Capacity];
    std::uint32_t count = 0u;
    std::uint32_t candidate_cap = no_candidate_cap;
    RESTIR_HOST_DEVICE constexpr std::uint32_t size() const noexcept { return count; }
    RESTIR_HOST_DEVICE constexpr const Input& operator[](std::uint32_t i) const { return items[i]; }
};

template <class Sample, class S, class Inputs>
RESTIR_HOST_DEVICE auto pack_inputs(const Inputs& inputs) {
    using Input = decltype(lent_input<Sample, S>(inputs[0u]));
    PackedInputs<Input, input_capacity<Inputs>> packed;
    packed.candidate_cap = candidate_cap_of(inputs);
    const std::uint32_t slots = inputs.size();
    for (std::uint32_t i = 0; i < slots && packed.count < input_capacity<Inputs>; ++i) {
        const Input input = lent_input<Sample, S>(inputs[i]);
        if (input.reservoir != nullptr && input.reservoir->is_well_formed())
            packed.items[packed.count++] = input;
    }
    return packed;
}

} // namespace restir::detail
