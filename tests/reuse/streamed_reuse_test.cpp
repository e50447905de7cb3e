// The streamed reuse step (one function per bias correction, inputs visited one at a time)
// gives bit for bit what the array-based step before it gave (tests/reuse/legacy_combine.hpp),
// for every mode, visibility setting, input count and malformed input (compiled with
// -ffp-contract=off: tests/CMakeLists.txt).
#include <restir/restir.hpp>

#include "reuse/legacy_combine.hpp"
#include "reuse/synthetic_image.hpp"

#include <gtest/gtest.h>

#include <cmath>
#include <cstdint>
#include <limits>
#include <vector>

namespace {

using namespace restir::test::synthetic;
using restir::BiasCorrection;
using restir::Reservoir;
using Input = restir::ReuseInput<LightId, Patch>;

// Bridge types of this file alone: the reuse functions instantiated for them are compiled here,
// without contraction, and not taken at link time from another test's instantiation.
struct StreamedTarget : Target {};
struct StreamedVisibility : Visibility {};

// A finalised RIS reservoir of `candidates` uniform candidates for patch `s`.
Reservoir<LightId> random_reservoir(std::uint32_t s, std::uint32_t candidates, restir::Pcg32& rng) {
    Reservoir<LightId> r;
    for (std::uint32_t c = 0; c < candidates; ++c) {
        const LightId x{restir::uniform_index(next_float(rng), light_count)};
        const float target = Target{}(x, Patch{s, true});
        r.stream(x, target * static_cast<float>(light_count), target, next_float(rng));
    }
    r.finalize();
    return r;
}

TEST(StreamedReuse, EqualsTheArrayBasedStepBitForBit) {
    restir::Pcg32 rng = restir::make_pixel_rng(7u, 0u, 0u);
    std::uint32_t compared = 0, differing_samples = 0;
    for (std::uint32_t trial = 0; trial < 4000; ++trial) {
        // Surfaces: the receiver and up to 15 inputs on random patches.
        const std::uint32_t count = restir::uniform_index(next_float(rng), 16u);
        std::vector<Patch> patches(count + 1u);
        std::vector<Reservoir<LightId>> reservoirs(count + 1u);
        for (std::uint32_t i = 0; i <= count; ++i) {
            patches[i] = {restir::uniform_index(next_float(rng), pixel_count), true};
            reservoirs[i] = random_reservoir(patches[i].id, 1u + trial % 40u, rng);
        }
        // Now and then a malformed input or an occluded (W = 0) one.
        if (count > 0u && trial % 7u == 0u)
            reservoirs[1].weight_sum = std::numeric_limits<float>::quiet_NaN();
        if (count > 1u && trial % 5u == 0u)
            restir::apply_visibility(reservoirs[2], false);
        std::vector<Input> inputs(count);
        for (std::uint32_t i = 0; i < count; ++i)
            inputs[i] = {&reservoirs[i + 1u], &patches[i + 1u]};

        for (BiasCorrection mode : {BiasCorrection::none, BiasCorrection::one_over_z,
                                    BiasCorrection::balance_heuristic, BiasCorrection::pairwise})
            for (int variant = 0; variant < 4; ++variant) {
                restir::ReuseParams params{mode, variant != 3, variant != 2};
                params.inputs_visibility_tested = variant == 1;
                const restir::ReuseBridge bridge{StreamedTarget{}, StreamedVisibility{}};
                restir::Pcg32 a =
                    restir::make_pixel_rng(trial, 1u, static_cast<std::uint32_t>(variant));
                restir::Pcg32 b = a;
                const Reservoir<LightId> old = restir::legacy::combine_reservoirs(
                    reservoirs[0], patches[0], inputs.data(), count, params, bridge, a);
                const Reservoir<LightId> streamed = restir::combine_reservoirs(
                    reservoirs[0], patches[0], inputs.data(), count, params, bridge, b);
                ASSERT_EQ(old.sample.id, streamed.sample.id) << "trial " << trial;
                ASSERT_EQ(old.candidate_count, streamed.candidate_count) << "trial " << trial;
                ASSERT_EQ(old.weight_sum, streamed.weight_sum) << "trial " << trial;
                ASSERT_EQ(old.target_value, streamed.target_value) << "trial " << trial;
                ASSERT_EQ(old.contribution_weight, streamed.contribution_weight)
                    << "trial " << trial;
                ASSERT_EQ(a.next_uint(), b.next_uint()) << "the same random numbers drawn";
                ++compared;
                differing_samples += old.sample.id != reservoirs[0].sample.id;
            }
    }
    EXPECT_EQ(compared, 4000u * 16u);
    EXPECT_GT(differing_samples, compared / 4u) << "reuse should often pick a borrowed sample";
}

} // namespace
