/// @file reuse/reuse_params.hpp
/// How a reuse step weighs its inputs (the bias correction and the visibility it accounts for),
/// and the functions it evaluates (`ReuseBridge`: target, visibility, material hook, shift).
/// reuse/bias_correction.hpp combines reservoirs with them.
#pragma once

#include "restir/config.hpp"
#include "restir/reuse/shift.hpp"
#include "restir/reuse/similarity.hpp"

#include <cstdint>

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
    /// Pairwise MIS in which the canonical input also keeps a share of its own, M_c / M_total,
    /// beside the pairs (each worth M_i / M_total, split with confidences M_c and M_i): with
    /// equal M it weighs its own sample by (1 + sum_i p-hat_q / (p-hat_q + p-hat_i)) / (k + 1),
    /// at least 1 / (k + 1). Unbiased; the cost of `pairwise`. Less error a frame where
    /// neighbouring pixels' targets differ and the canonical reservoir is strong (a long
    /// history), more where neighbours are as good (docs/noise-and-bias.md, "The spatial
    /// pass"); the `balanced` preset's choice.
    defensive_pairwise,
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

} // namespace restir
