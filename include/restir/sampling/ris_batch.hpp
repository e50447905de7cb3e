/// @file sampling/ris_batch.hpp
/// Batch resampled importance sampling: candidates in fixed-size blocks whose target values
/// are evaluated in one plain loop (which a compiler vectorises, and which a GPU thread runs
/// as unrolled scalar code), one selection per block, blocks streamed into a reservoir. The
/// selected candidate has exactly the distribution of streaming RIS (Bitterli et al. 2020,
/// Alg. 3): block b is kept with probability S_b / sum_c S_c (the reservoir update of Alg. 2
/// applied to the block's weight sum S_b), lane i of it with probability w_i / S_b, so
/// candidate i is kept with probability w_i / sum_j w_j.
#pragma once

#include "restir/config.hpp"
#include "restir/core/math.hpp"
#include "restir/core/reservoir.hpp"
#include "restir/core/rng.hpp"

#include <concepts>
#include <cstdint>

namespace restir {

/// What the application fills for one block of `Size` candidates: the target value p-hat(x_i)
/// and the reciprocal of the source density 1 / p(x_i) of each (a reciprocal, so the
/// resampling weight w_i = p-hat(x_i) / p(x_i) is a product). A lane the source could not
/// produce has `inverse_pdf` 0.
template <std::uint32_t Size>
struct CandidateBlock {
    static_assert(Size > 0u && Size <= 64u, "blocks hold 1 to 64 candidates");
    static constexpr std::uint32_t size = Size;
    float target[Size];
    float inverse_pdf[Size];
};

/// One block's resampling: the sum of its weights and the lane chosen in proportion to them.
struct BlockSelection {
    float weight_sum = 0.0f; ///< S = sum of the valid weights w_i of the block.
    float target = 0.0f;     ///< p-hat of the chosen lane.
    std::uint32_t lane = 0u; ///< The chosen lane; meaningless when `weight_sum` is 0.
};

/// Chooses a lane of `block` with probability w_i / S from one uniform number `u` in [0, 1)
/// (inversion of the block's discrete cdf). Weights that are NaN, infinite or negative count
/// as 0, as in `Reservoir::stream`. Every loop has a compile-time trip count and no
/// runtime-indexed access, so the block stays in registers on a GPU.
template <std::uint32_t Size>
RESTIR_HOST_DEVICE constexpr BlockSelection select_in_block(const CandidateBlock<Size>& block,
                                                            float u) noexcept {
    // Branch-free throughout: which lane wins is random, so branches would mispredict.
    float weight[Size];
    for (std::uint32_t i = 0; i < Size; ++i) {
        const float w = block.target[i] * block.inverse_pdf[i];
        // Not NaN, not negative, not infinite (a NaN fails both comparisons).
        weight[i] = w >= 0.0f && w <= 3.40282347e38f ? w : 0.0f;
    }
    float prefix[Size];
    float running = 0.0f;
    for (std::uint32_t i = 0; i < Size; ++i) {
        running += weight[i];
        prefix[i] = running;
    }
    // The chosen lane is the number of inclusive prefix sums at or below u * S (inversion of
    // the block's cdf); its target is gathered by masks, not by a runtime index.
    const float threshold = u * running;
    std::uint32_t below[Size]; // 1 where prefix_i <= u S; 0 for the last lane
    for (std::uint32_t i = 0; i < Size; ++i)
        below[i] = i + 1u < Size && prefix[i] <= threshold ? 1u : 0u;
    std::uint32_t lane = 0u;
    for (std::uint32_t i = 0; i < Size; ++i)
        lane += below[i];
    std::uint32_t target_bits = 0u;
    for (std::uint32_t i = 0; i < Size; ++i) {
        // Lane i is the chosen one when the prefix before it is at or below u S and its own is not.
        const std::uint32_t chosen = (i == 0u ? 1u : below[i - 1u]) & (below[i] ^ 1u);
        target_bits |= __builtin_bit_cast(std::uint32_t, block.target[i]) & (0u - chosen);
    }
    BlockSelection selection;
    selection.weight_sum = running;
    selection.target = __builtin_bit_cast(float, target_bits);
    selection.lane = lane;
    return selection;
}

/// Streams `candidate_count` candidates (M), taken in blocks of `BlockSize`, into `reservoir`
/// (over handles):
///   `evaluate_block(b, block)` -> std::uint32_t: fills `block` (a CandidateBlock<BlockSize>)
///   with the target values and inverse source densities of block b's candidates, and returns
///   the handle of its lane 0; lane i's handle is that plus i (for instance the index of the
///   block's first entry in a structure-of-arrays light buffer). When M is not a multiple of
///   the block size, the lanes of the last block beyond M are ignored.
/// Two uniform numbers per block (the block's lane, then the reservoir update) instead of one
/// per candidate. Leaves `reservoir` unfinalised, for candidates of other strategies to follow
/// (with MIS weights in `inverse_pdf`, sampling/tile_bsdf_candidates.hpp).
template <std::uint32_t BlockSize, UniformRng Rng, class EvaluateBlock>
requires(std::invocable<EvaluateBlock&, std::uint32_t, CandidateBlock<BlockSize>&>)
    RESTIR_HOST_DEVICE
    void stream_ris_batch(Rng& rng, Reservoir<std::uint32_t>& reservoir,
                          std::uint32_t candidate_count, EvaluateBlock&& evaluate_block) {
    const std::uint32_t block_count = (candidate_count + BlockSize - 1u) / BlockSize;
    for (std::uint32_t b = 0; b < block_count; ++b) {
        CandidateBlock<BlockSize> block;
        const auto first = static_cast<std::uint32_t>(evaluate_block(b, block));
        const std::uint32_t lanes = min_of(BlockSize, candidate_count - b * BlockSize);
        if (lanes < BlockSize)
            for (std::uint32_t i = 0; i < BlockSize; ++i)
                block.inverse_pdf[i] = i < lanes ? block.inverse_pdf[i] : 0.0f;
        const BlockSelection selection = select_in_block(block, next_float(rng));
        reservoir.stream_group(first + selection.lane, selection.weight_sum, selection.target,
                               lanes, next_float(rng));
    }
}

/// Batch RIS over `candidate_count` candidates (M), `stream_ris_batch` into an empty
/// reservoir. Returns the finalised reservoir over handles: W = w_sum / (M p-hat(y)) (Eq. 6).
/// f(y) W is unbiased under the conditions of `resample_ris`.
template <std::uint32_t BlockSize, UniformRng Rng, class EvaluateBlock>
requires(std::invocable<EvaluateBlock&, std::uint32_t, CandidateBlock<BlockSize>&>)
    RESTIR_HOST_DEVICE Reservoir<std::uint32_t> resample_ris_batch(Rng& rng,
                                                                   std::uint32_t candidate_count,
                                                                   EvaluateBlock&& evaluate_block) {
    Reservoir<std::uint32_t> reservoir;
    stream_ris_batch<BlockSize>(rng, reservoir, candidate_count, evaluate_block);
    reservoir.finalize();
    return reservoir;
}

} // namespace restir
