/// @file core/reservoir.hpp
/// Weighted reservoir for resampled importance sampling (Bitterli et al. 2020, Sec. 3-4).
#pragma once

#include "restir/config.hpp"
#include "restir/core/math.hpp"

#include <cstdint>
#include <type_traits>

namespace restir {

/// Single-sample weighted reservoir over candidates of type `Sample` (a light reference, a
/// path vertex, ...). Streaming keeps one candidate with probability proportional to its
/// resampling weight (Alg. 2); `finalize` turns the weight sum into the unbiased
/// contribution weight W (Eq. 6), and `merge` combines reservoirs (Alg. 4).
///
/// The running sum of resampling weights and the finalised W are separate fields: the first
/// is only meaningful while streaming, the second only after finalising. Weights that are
/// NaN, infinite or negative are treated as zero: the candidate still counts towards M (it
/// was drawn, so dropping it from the count would bias the estimate), but it can never be
/// selected and never corrupts the weight sum.
template <class Sample>
struct Reservoir {
    static_assert(std::is_trivially_copyable_v<Sample>,
                  "Reservoir samples must be trivially copyable (stored in GPU buffers)");

    Sample sample{};                    ///< The selected candidate y.
    float weight_sum = 0.0f;            ///< Sum of resampling weights w_i while streaming.
    float target_value = 0.0f;          ///< Target function p-hat(y) at the owning surface.
    float contribution_weight = 0.0f;   ///< W of Eq. 6, valid after a `finalize*` call.
    std::uint32_t candidate_count = 0u; ///< M: number of candidates this reservoir represents.

    /// Offers one candidate with resampling weight `weight` and target value `target`;
    /// `u` is a uniform number in [0, 1). Returns true when the candidate was selected.
    /// Alg. 2 of Bitterli et al. 2020: w_sum += w; M += 1; keep with probability w / w_sum.
    RESTIR_HOST_DEVICE constexpr bool stream(const Sample& candidate, float weight, float target,
                                             float u) noexcept {
        RESTIR_ASSERT(u >= 0.0f && u < 1.0f);
        if (!add_weight(weight, u, 1u))
            return false;
        sample = candidate;
        target_value = is_valid_weight(target) ? target : 0.0f; // W = 0 for a bad target
        return true;
    }

    /// Offers a group of `count` candidates that were already resampled among themselves
    /// (batch RIS): `weight` is the group's weight sum, `candidate` the one it chose and
    /// `target` its p-hat. The group is kept with probability weight / w_sum, so a candidate
    /// of it ends up kept with probability w_i / w_sum, as if streamed one by one.
    RESTIR_HOST_DEVICE constexpr bool stream_group(const Sample& candidate, float weight,
                                                   float target, std::uint32_t count,
                                                   float u) noexcept {
        RESTIR_ASSERT(u >= 0.0f && u < 1.0f);
        // Selects instead of a branch: whether a group wins is random.
        const bool take = add_weight(weight, u, count);
        sample = take ? candidate : sample;
        target_value = take ? (is_valid_weight(target) ? target : 0.0f) : target_value;
        return take;
    }

    /// Like `stream`, but builds the sample with `make_sample()` only when it is selected,
    /// for samples that are costly to construct.
    template <class MakeSample>
    RESTIR_HOST_DEVICE constexpr bool stream_lazy(float weight, float target, float u,
                                                  MakeSample&& make_sample) {
        if (!add_weight(weight, u, 1u))
            return false;
        sample = make_sample();
        target_value = is_valid_weight(target) ? target : 0.0f;
        return true;
    }

    /// Combines a finalised reservoir `other` into this one (Alg. 4): its sample enters with
    /// weight p-hat_q(y) * W * M, where `target_at_receiver` is p-hat_q(y) evaluated at this
    /// reservoir's surface q. M grows by `other.candidate_count`. A reservoir holding
    /// non-finite values is ignored entirely. Finish with `finalize()` (the 1/M weights of
    /// Eq. 6) or with `finalize_normalized(1 / Z)` for the unbiased 1/Z variant.
    RESTIR_HOST_DEVICE constexpr bool merge(const Reservoir& other, float target_at_receiver,
                                            float u) noexcept {
        const float weight = target_at_receiver * other.contribution_weight *
                             static_cast<float>(other.candidate_count);
        return merge_with_weight(other, weight, target_at_receiver, u);
    }

    /// Combines `other` with an explicit MIS weight m_i (generalized RIS, Lin et al. 2022,
    /// Eq. 3.4): the resampling weight is m_i * p-hat_q(y) * W. M grows by
    /// `other.candidate_count`. Finish with `finalize_normalized(1)`, since the MIS weights
    /// already sum to one over the inputs.
    RESTIR_HOST_DEVICE constexpr bool merge_with_mis(const Reservoir& other,
                                                     float target_at_receiver, float mis_weight,
                                                     float u) noexcept {
        const float weight = mis_weight * target_at_receiver * other.contribution_weight;
        return merge_with_weight(other, weight, target_at_receiver, u);
    }

    /// Eq. 6 of Bitterli et al. 2020: W = w_sum / (M * p-hat(y)), the estimate of 1 / p(y)
    /// for resampling weights w_i = p-hat(x_i) / p(x_i). W is 0 when nothing was selected.
    RESTIR_HOST_DEVICE constexpr void finalize() noexcept {
        contribution_weight =
            safe_divide(weight_sum, static_cast<float>(candidate_count) * target_value);
    }

    /// W = normalization * w_sum / p-hat(y), for streams whose resampling weights already
    /// carry their MIS weights (normalization = 1) or for the 1/Z correction
    /// (normalization = 1 / Z).
    RESTIR_HOST_DEVICE constexpr void finalize_normalized(float normalization = 1.0f) noexcept {
        contribution_weight = safe_divide(normalization * weight_sum, target_value);
    }

    /// Limits M to `cap` (temporal history clamp, Sec. 4 of Bitterli et al. 2020). The weight
    /// sum is scaled by the same factor, so W = w_sum / (M p-hat) is unchanged whether this is
    /// called before or after finalising; only the reservoir's share in later merges shrinks.
    RESTIR_HOST_DEVICE constexpr void cap_candidate_count(std::uint32_t cap) noexcept {
        if (candidate_count <= cap)
            return;
        weight_sum *= static_cast<float>(cap) / static_cast<float>(candidate_count);
        candidate_count = cap;
    }

    /// The same reservoir holding `other_sample` instead of its sample: for resampling over a
    /// cheap handle (an index into presampled lights) and storing what the handle names.
    template <class Other>
    RESTIR_HOST_DEVICE constexpr Reservoir<Other> with_sample(const Other& other_sample) const {
        Reservoir<Other> result;
        result.sample = other_sample;
        result.weight_sum = weight_sum;
        result.target_value = target_value;
        result.contribution_weight = contribution_weight;
        result.candidate_count = candidate_count;
        return result;
    }

    /// True when a candidate with positive weight has been selected.
    RESTIR_HOST_DEVICE constexpr bool has_sample() const noexcept {
        return weight_sum > 0.0f && target_value > 0.0f;
    }

    /// True when every scalar field is finite and non-negative.
    RESTIR_HOST_DEVICE constexpr bool is_well_formed() const noexcept {
        return is_valid_weight(weight_sum) && is_valid_weight(target_value) &&
               is_valid_weight(contribution_weight);
    }

    /// Resets a reservoir whose fields are not finite (for instance one read back from a
    /// corrupted buffer); returns true when it had to.
    RESTIR_HOST_DEVICE constexpr bool sanitize() noexcept {
        if (is_well_formed())
            return false;
        *this = Reservoir{};
        return true;
    }

private:
    // Shared selection step: accepts the weight (or treats it as 0), counts `count`
    // candidates, and says whether the new candidate replaces the current one.
    RESTIR_HOST_DEVICE constexpr bool add_weight(float weight, float u,
                                                 std::uint32_t count) noexcept {
        // M saturates instead of wrapping around: an add, then a select on its carry (two
        // instructions on the chain from one call to the next, where min(count, max - M) takes
        // four).
        const std::uint32_t total = candidate_count + count;
        candidate_count = total < candidate_count ? 0xffffffffu : total;
        // Invalid weights become 0 without a branch: a zero weight is never selected, since
        // u * w_sum < 0 is false for u >= 0.
        const float accepted = is_valid_weight(weight) ? weight : 0.0f;
        const float new_sum = weight_sum + accepted;
        if (!is_finite(new_sum))
            return false;
        weight_sum = new_sum;
        return u * weight_sum < accepted;
    }

    RESTIR_HOST_DEVICE constexpr bool merge_with_weight(const Reservoir& other, float weight,
                                                        float target_at_receiver,
                                                        float u) noexcept {
        if (!other.is_well_formed())
            return false;
        if (!add_weight(weight, u, other.candidate_count))
            return false;
        sample = other.sample;
        target_value = is_valid_weight(target_at_receiver) ? target_at_receiver : 0.0f;
        return true;
    }
};

} // namespace restir
