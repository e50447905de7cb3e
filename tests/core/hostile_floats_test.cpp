// Every public function that takes a random number, a weight or a distance accepts any float
// (NaN, infinities, negative, out of range, denormal) with a defined, in-range result. The
// sanitised build checks the float-to-integer conversions (-fsanitize=float-cast-overflow);
// the assertions here check the ranges.
#include <restir/restir.hpp>

#include <gtest/gtest.h>

#include <cstdint>
#include <limits>
#include <vector>

namespace {

constexpr float hostile[] = {std::numeric_limits<float>::quiet_NaN(),
                             std::numeric_limits<float>::infinity(),
                             -std::numeric_limits<float>::infinity(),
                             -1.0f,
                             -0.0f,
                             1.0f,
                             1.5f,
                             1e30f,
                             -1e30f,
                             std::numeric_limits<float>::denorm_min(),
                             0.99999994f};

TEST(HostileFloats, LightSamplersAndAliasTablesReturnAnIndexInRange) {
    const restir::UniformLightSampler uniform{10u};
    const restir::AliasTable table(std::vector<float>{1.0f, 2.0f, 3.0f, 0.5f});
    const restir::PowerLightSampler power{table.view()};
    for (float u : hostile)
        for (float v : hostile) {
            EXPECT_LT(uniform.sample(u, v).index, 10u) << u << " " << v;
            EXPECT_LT(table.sample(u, v).index, 4u) << u << " " << v;
            EXPECT_LT(power.sample(u, v).index, 4u) << u << " " << v;
            EXPECT_LT(restir::uniform_index(u, 7u), 7u) << u;
        }
}

TEST(HostileFloats, BlockSelectionAndTilesStayInRange) {
    restir::CandidateBlock<8> block{};
    for (std::uint32_t i = 0; i < 8u; ++i) {
        block.target[i] = hostile[i];
        block.inverse_pdf[i] = hostile[(i + 3u) % 11u];
    }
    std::vector<restir::PresampledLight> entries(6);
    const restir::LightTilesView tiles{entries.data(), 2u, 3u};
    for (float u : hostile) {
        const restir::BlockSelection chosen = restir::select_in_block(block, u);
        EXPECT_LT(chosen.lane, 8u) << u;
        EXPECT_GE(chosen.weight_sum, 0.0f) << u; // invalid weights count as 0
        const restir::PresampledLight& drawn = tiles.draw(1u, u, u);
        EXPECT_GE(&drawn, entries.data() + 3);
        EXPECT_LT(&drawn, entries.data() + 6);
    }
}

TEST(HostileFloats, ReservoirsNeverHoldNegativeOrNanWeights) {
    for (float weight : hostile)
        for (float target : hostile)
            for (float u : {0.0f, 0.5f, 0.99999994f}) { // u in [0, 1): a precondition
                restir::Reservoir<std::uint32_t> r;
                r.stream(1u, 1.0f, 1.0f, 0.0f);
                r.stream(2u, weight, target, u);
                r.finalize();
                EXPECT_TRUE(r.is_well_formed()) << weight << " " << target << " " << u;
                EXPECT_GE(r.contribution_weight, 0.0f) << weight << " " << target;
            }
}

TEST(HostileFloats, NeighboursAndDirectionsAreDefined) {
    const restir::NeighbourOffsets offsets = restir::make_neighbour_offsets();
    for (float u : hostile) {
        const restir::PixelCoord n =
            restir::spatial_neighbour({5, 5}, 3u, 1u, u, offsets, restir::neighbour_rotation(u));
        EXPECT_LE(n.x, 5 + 16777217);
        EXPECT_GE(n.y, 5 - 16777217);
        for (float v : hostile) {
            const glm::vec3 d = restir::sample_diffuse_direction(glm::vec3(0.0f, 0.0f, 1.0f), u, v);
            (void)d; // any value: only the absence of undefined behaviour is checked
        }
    }
}

TEST(HostileFloats, FalloffsAreNeverNegative) {
    for (float d : hostile)
        for (float p : hostile)
            for (restir::FalloffKind kind :
                 {restir::FalloffKind::yuksel, restir::FalloffKind::clamped_inverse_square,
                  restir::FalloffKind::inverse_square}) {
                if (!(d >= 0.0f) || (kind != restir::FalloffKind::inverse_square && !(p > 0.0f)))
                    continue; // outside the preconditions (asserted in debug builds)
                EXPECT_FALSE(restir::evaluate_falloff(kind, d, p) < 0.0f) << d << " " << p;
            }
}

} // namespace
