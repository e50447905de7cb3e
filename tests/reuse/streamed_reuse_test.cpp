// Properties of the streamed reuse step (one function per bias correction, inputs visited one
// at a time through a set): a set that computes its inputs on demand gives exactly what an
// array of the same inputs gives (and draws the same random numbers), a slot that lends
// nothing or a malformed reservoir takes part as if it were absent, a set's cap equals capping
// the reservoirs themselves, and the result's M is the sum of the M that took part. For every
// mode and visibility setting. The spatial pass's set (`find_spatial_neighbours`) holds the
// neighbours that lend, in the order the search found them, and visited as it is (as a GPU
// thread visits it) gives what the array of them gives. Compiled with -ffp-contract=off
// (tests/CMakeLists.txt): the two sets instantiate the step twice, and the compiler may contract
// the two copies differently.
#include <restir/restir.hpp>

#include "reuse/synthetic_image.hpp"

#include <gtest/gtest.h>

#include <cstdint>
#include <iterator>
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

// A set that computes its inputs on demand, as the library's spatial and fused sets do: slot i
// lends pixel i + 1 of the buffers, except the slots of `holes`, which lend nothing.
struct ComputedInputs {
    const Reservoir<LightId>* reservoirs = nullptr;
    const Patch* patches = nullptr;
    std::uint32_t slots = 0u;
    std::uint32_t holes = 0u; // bit i: slot i lends nothing
    std::uint32_t candidate_cap = restir::no_candidate_cap;
    std::uint32_t size() const { return slots; }
    Input operator[](std::uint32_t i) const {
        if ((holes >> i) & 1u)
            return {};
        return {&reservoirs[i + 1u], &patches[i + 1u]};
    }
};

} // namespace

// Its cap, told as an application tells reuse about a set of its own.
template <>
struct restir::ReuseSetTraits<ComputedInputs> {
    static constexpr bool all_lend(const ComputedInputs&) noexcept { return false; }
    static constexpr std::uint32_t candidate_cap(const ComputedInputs& inputs) noexcept {
        return inputs.candidate_cap;
    }
    static constexpr bool streamed = false;
};

namespace {

// A receiver and up to 15 inputs on random patches: buffer slot 0 is the receiver.
struct Trial {
    std::vector<Patch> patches;
    std::vector<Reservoir<LightId>> reservoirs;
    std::uint32_t count = 0u; // inputs
};

Trial random_trial(std::uint32_t trial, restir::Pcg32& rng) {
    Trial t;
    t.count = restir::uniform_index(next_float(rng), 16u);
    t.patches.resize(t.count + 1u);
    t.reservoirs.resize(t.count + 1u);
    for (std::uint32_t i = 0; i <= t.count; ++i) {
        t.patches[i] = {restir::uniform_index(next_float(rng), pixel_count), true};
        t.reservoirs[i] = random_reservoir(t.patches[i].id, 1u + trial % 40u, rng);
    }
    // Now and then a malformed input or an occluded (W = 0) one.
    if (t.count > 0u && trial % 7u == 0u)
        t.reservoirs[1].weight_sum = std::numeric_limits<float>::quiet_NaN();
    if (t.count > 1u && trial % 5u == 0u)
        restir::apply_visibility(t.reservoirs[2], false);
    return t;
}

constexpr BiasCorrection modes[] = {BiasCorrection::none, BiasCorrection::one_over_z,
                                    BiasCorrection::balance_heuristic, BiasCorrection::pairwise,
                                    BiasCorrection::defensive_pairwise};

restir::ReuseParams params_of(BiasCorrection mode, int variant) {
    constexpr restir::ReuseVisibility visibility[] = {
        restir::ReuseVisibility::traced, restir::ReuseVisibility::traced_inputs_tested,
        restir::ReuseVisibility::assumed, restir::ReuseVisibility::none};
    return {mode, visibility[variant]};
}

// Equal bit for bit, and the two generators left in the same state.
void expect_same(const Reservoir<LightId>& a, const Reservoir<LightId>& b, restir::Pcg32 rng_a,
                 restir::Pcg32 rng_b, std::uint32_t trial) {
    ASSERT_EQ(a.sample.id, b.sample.id) << "trial " << trial;
    ASSERT_EQ(a.candidate_count, b.candidate_count) << "trial " << trial;
    ASSERT_EQ(a.weight_sum, b.weight_sum) << "trial " << trial;
    ASSERT_EQ(a.target_value, b.target_value) << "trial " << trial;
    ASSERT_EQ(a.contribution_weight, b.contribution_weight) << "trial " << trial;
    ASSERT_EQ(rng_a.next_uint(), rng_b.next_uint()) << "the same random numbers drawn";
}

// The computed set, with holes and a cap, against an array of the inputs that take part, the
// capped ones capped beforehand; the result's M is the receiver's plus the inputs' capped M.
TEST(StreamedReuse, ComputedSetEqualsTheArrayOfItsInputs) {
    restir::Pcg32 rng = restir::make_pixel_rng(7u, 0u, 0u);
    std::uint32_t compared = 0, borrowed = 0;
    for (std::uint32_t trial = 0; trial < 4000; ++trial) {
        Trial t = random_trial(trial, rng);
        ComputedInputs set{t.reservoirs.data(), t.patches.data(), t.count};
        set.holes = trial % 3u == 0u ? rng.next_uint() : 0u;
        set.candidate_cap = trial % 4u == 0u ? 1u + trial % 30u : restir::no_candidate_cap;

        std::vector<Reservoir<LightId>> capped(t.count + 1u);
        std::vector<Input> array;
        std::uint32_t expected_m = t.reservoirs[0].candidate_count;
        for (std::uint32_t i = 0; i < t.count; ++i) {
            if (set[i].reservoir == nullptr)
                continue;
            capped[i + 1u] = t.reservoirs[i + 1u];
            capped[i + 1u].cap_candidate_count(set.candidate_cap);
            array.push_back({&capped[i + 1u], &t.patches[i + 1u]});
            if (capped[i + 1u].is_well_formed())
                expected_m += capped[i + 1u].candidate_count;
        }

        for (BiasCorrection mode : modes)
            for (int variant = 0; variant < 4; ++variant) {
                const restir::ReuseParams params = params_of(mode, variant);
                const restir::ReuseBridge bridge{StreamedTarget{}, StreamedVisibility{}};
                restir::Pcg32 a =
                    restir::make_pixel_rng(trial, 1u, static_cast<std::uint32_t>(variant));
                restir::Pcg32 b = a;
                const Reservoir<LightId> streamed =
                    restir::combine_inputs(t.reservoirs[0], t.patches[0], set, params, bridge, a);
                const Reservoir<LightId> gathered = restir::combine_inputs(
                    t.reservoirs[0], t.patches[0],
                    restir::ReuseInputSpan<LightId, Patch>{
                        array.data(), static_cast<std::uint32_t>(array.size())},
                    params, bridge, b);
                ASSERT_NO_FATAL_FAILURE(expect_same(streamed, gathered, a, b, trial));
                ASSERT_EQ(streamed.candidate_count, expected_m) << "trial " << trial;
                ++compared;
                borrowed += streamed.sample.id != t.reservoirs[0].sample.id;
            }
    }
    EXPECT_EQ(compared, 4000u * 4u * std::size(modes));
    EXPECT_GT(borrowed, compared / 4u) << "reuse should often pick a borrowed sample";
}

// An input whose reservoir holds a non-finite or negative field (a corrupted buffer) changes
// nothing: the result and the numbers drawn are those without it.
TEST(StreamedReuse, MalformedInputTakesPartAsIfAbsent) {
    restir::Pcg32 rng = restir::make_pixel_rng(11u, 0u, 0u);
    for (std::uint32_t trial = 0; trial < 1000; ++trial) {
        Trial t = random_trial(trial * 7u + 1u, rng); // never the NaN of random_trial
        if (t.count == 0u)
            continue;
        const std::uint32_t bad = 1u + restir::uniform_index(next_float(rng), t.count);
        switch (trial % 3u) {
        case 0u:
            t.reservoirs[bad].weight_sum = std::numeric_limits<float>::quiet_NaN();
            break;
        case 1u:
            t.reservoirs[bad].contribution_weight = std::numeric_limits<float>::infinity();
            break;
        default:
            t.reservoirs[bad].target_value = -1.0f;
            break;
        }
        ASSERT_FALSE(t.reservoirs[bad].is_well_formed());
        std::vector<Input> with, without;
        for (std::uint32_t i = 1; i <= t.count; ++i) {
            with.push_back({&t.reservoirs[i], &t.patches[i]});
            if (i != bad)
                without.push_back({&t.reservoirs[i], &t.patches[i]});
        }
        for (BiasCorrection mode : modes)
            for (int variant = 0; variant < 4; ++variant) {
                const restir::ReuseParams params = params_of(mode, variant);
                const restir::ReuseBridge bridge{StreamedTarget{}, StreamedVisibility{}};
                restir::Pcg32 a =
                    restir::make_pixel_rng(trial, 2u, static_cast<std::uint32_t>(variant));
                restir::Pcg32 b = a;
                const Reservoir<LightId> r_with = restir::combine_inputs(
                    t.reservoirs[0], t.patches[0],
                    restir::ReuseInputSpan<LightId, Patch>{with.data(),
                                                           static_cast<std::uint32_t>(with.size())},
                    params, bridge, a);
                const Reservoir<LightId> r_without = restir::combine_inputs(
                    t.reservoirs[0], t.patches[0],
                    restir::ReuseInputSpan<LightId, Patch>{
                        without.data(), static_cast<std::uint32_t>(without.size())},
                    params, bridge, b);
                ASSERT_NO_FATAL_FAILURE(expect_same(r_with, r_without, a, b, trial));
            }
    }
}

// The spatial set over a 6 x 3 image whose reservoirs are now and then malformed (NaN) and
// whose background patch is invalid: its slots are the neighbours the search reported, in
// order, and each bias correction visiting the set itself (no gathering, as on a GPU) gives
// what it gives over the array of those inputs, with the same numbers drawn.
TEST(StreamedReuse, SpatialSetHoldsTheLendingNeighboursInOrder) {
    restir::Pcg32 rng = restir::make_pixel_rng(13u, 0u, 0u);
    const restir::NeighbourOffsets offsets = restir::make_neighbour_offsets();
    std::vector<Patch> patches(pixel_count);
    std::vector<Reservoir<LightId>> reservoirs(pixel_count);
    std::uint32_t sets = 0, slots = 0, skipped = 0;
    for (std::uint32_t trial = 0; trial < 400; ++trial) {
        for (std::uint32_t i = 0; i < pixel_count; ++i) {
            patches[i] = {i, i != background_patch};
            reservoirs[i] = random_reservoir(i, 1u + trial % 9u, rng);
            if (restir::uniform_index(next_float(rng), 5u) == 0u)
                reservoirs[i].weight_sum = std::numeric_limits<float>::quiet_NaN();
        }
        const restir::ImageView<const Reservoir<LightId>> view{reservoirs.data(), width, height};
        const restir::ImageView<const Patch> surfaces{patches.data(), width, height};
        restir::SpatialParams params = restir::default_spatial_params();
        params.neighbour_count = 1u + trial % 15u;
        params.radius = 1.0f + static_cast<float>(trial % 4u);
        const std::uint32_t p = restir::uniform_index(next_float(rng), pixel_count);
        if (p == background_patch || !reservoirs[p].is_well_formed())
            continue;
        const restir::ReuseBridge bridge{StreamedTarget{}, StreamedVisibility{}};
        restir::Pcg32 search = restir::make_pixel_rng(trial, 3u, 0u);
        std::vector<Input> found;
        const auto set = restir::find_spatial_neighbours(
            pixel_of(p), patches[p], view, surfaces, params, offsets, bridge.material_test, search,
            [&](restir::PixelCoord q) {
                found.push_back({&view[q], &surfaces[q]});
            });
        ASSERT_EQ(set.size(), found.size()) << "trial " << trial;
        // Drawn ahead (`draw_neighbours`, as the tiled recipe draws them), the same numbers are
        // taken and the same neighbours found.
        restir::Pcg32 ahead = restir::make_pixel_rng(trial, 3u, 0u);
        const restir::NeighbourDraw draw = restir::draw_neighbours(ahead);
        const auto drawn = restir::find_spatial_neighbours<LightId, Patch>(
            pixel_of(p), patches[p], view, surfaces, params, offsets, bridge.material_test, draw);
        ASSERT_EQ(drawn.lends, set.lends) << "trial " << trial;
        ASSERT_EQ(drawn.start, set.start) << "trial " << trial;
        restir::Pcg32 after = search;
        ASSERT_EQ(ahead.next_uint(), after.next_uint()) << "trial " << trial;
        for (std::uint32_t j = 0; j < set.size(); ++j) {
            ASSERT_EQ(set[j].reservoir, found[j].reservoir) << "trial " << trial;
            ASSERT_EQ(set[j].surface, found[j].surface) << "trial " << trial;
        }
        skipped += set.count - set.size();
        slots += set.size();
        ++sets;
        for (BiasCorrection mode : modes)
            for (int variant = 0; variant < 4; ++variant) {
                const restir::ReuseParams reuse = params_of(mode, variant);
                restir::Pcg32 a = search;
                restir::Pcg32 b = search;
                const auto combine = [&](const auto& inputs, restir::Pcg32& g) {
                    switch (mode) {
                    case BiasCorrection::none:
                        return restir::combine_one_over_m(reservoirs[p], patches[p], inputs, reuse,
                                                          bridge, g);
                    case BiasCorrection::one_over_z:
                        return restir::combine_one_over_z(reservoirs[p], patches[p], inputs, reuse,
                                                          bridge, g);
                    case BiasCorrection::balance_heuristic:
                        return restir::combine_balance_heuristic(reservoirs[p], patches[p], inputs,
                                                                 reuse, bridge, g);
                    case BiasCorrection::defensive_pairwise:
                        return restir::combine_defensive_pairwise(reservoirs[p], patches[p], inputs,
                                                                  reuse, bridge, g);
                    case BiasCorrection::pairwise:
                        break;
                    }
                    return restir::combine_pairwise(reservoirs[p], patches[p], inputs, reuse,
                                                    bridge, g);
                };
                const Reservoir<LightId> streamed = combine(set, a);
                const Reservoir<LightId> gathered = combine(
                    restir::ReuseInputSpan<LightId, Patch>{
                        found.data(), static_cast<std::uint32_t>(found.size())},
                    b);
                ASSERT_NO_FATAL_FAILURE(expect_same(streamed, gathered, a, b, trial));
            }
    }
    EXPECT_GT(sets, 200u); // about 300 of the 400 centres are valid and well-formed
    EXPECT_GT(slots, sets * 2u) << "sets should hold several neighbours";
    EXPECT_GT(skipped, sets / 4u) << "the search should skip malformed and invalid neighbours";
}

} // namespace
