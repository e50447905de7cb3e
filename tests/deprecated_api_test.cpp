// The names of version 0.1 that were renamed, kept deprecated until at least 0.3: each still
// compiles and means what its new name means. This file is compiled with
// -Wno-deprecated-declarations (tests/CMakeLists.txt); that the warning fires everywhere else
// is checked by the `deprecation.warns` test (tests/deprecated/).
#include <restir/light/falloff.hpp>
#include <restir/light/irradiance.hpp>
#include <restir/light/light_bounds.hpp>
#include <restir/reuse/bias_correction.hpp>
#include <restir/reuse/di_frame.hpp>
#include <restir/reuse/di_frame_tiles.hpp>
#include <restir/reuse/history.hpp>
#include <restir/reuse/neighbour_offsets.hpp>
#include <restir/reuse/spatial.hpp>
#include <restir/reuse/spatiotemporal.hpp>
#include <restir/reuse/temporal.hpp>
#include <restir/sampling/diffuse_direction.hpp>

#include "support/stub_bridge.hpp"

#include <gtest/gtest.h>

#include <cmath>
#include <cstdint>
#include <type_traits>
#include <vector>

namespace {

TEST(DeprecatedApi, AttenuationIsFalloffKind) {
    static_assert(std::is_same_v<restir::Attenuation, restir::FalloffKind>);
    EXPECT_EQ(restir::Attenuation::yuksel, restir::FalloffKind::yuksel);
    EXPECT_EQ(restir::Attenuation::clamped_inverse_square,
              restir::FalloffKind::clamped_inverse_square);
    EXPECT_EQ(restir::Attenuation::inverse_square, restir::FalloffKind::inverse_square);
    // A 0.1 client built its falloff from the enum by its old name.
    const restir::Falloff falloff{restir::Attenuation::yuksel, 0.25f};
    EXPECT_EQ(falloff.kind, restir::Falloff::yuksel(0.25f).kind);
    EXPECT_EQ(falloff.parameter, restir::Falloff::yuksel(0.25f).parameter);
}

// Deprecated without a replacement (no caller in the library), it still merges until removed.
TEST(DeprecatedApi, MergeLightBoundsCoversBoth) {
    const restir::LightBounds a = restir::area_light_bounds(glm::vec3(0.0f), glm::vec3(1.0f),
                                                            glm::vec3(0.0f, 0.0f, 1.0f), 2.0f);
    const restir::LightBounds b =
        restir::area_light_bounds(glm::vec3(3.0f, -1.0f, 0.0f), glm::vec3(4.0f, 0.0f, 1.0f),
                                  glm::vec3(1.0f, 0.0f, 0.0f), 5.0f);
    const restir::LightBounds m = restir::merge_light_bounds(a, b);
    EXPECT_EQ(m.lower, glm::vec3(0.0f, -1.0f, 0.0f));
    EXPECT_EQ(m.upper, glm::vec3(4.0f, 1.0f, 1.0f));
    EXPECT_FLOAT_EQ(m.power, 7.0f);
    // The merged cone holds both axes: +z and +x are 90 degrees apart.
    EXPECT_LE(m.cos_theta_o, std::cos(0.785f));
    EXPECT_EQ(restir::merge_light_bounds(restir::LightBounds{}, a).power, a.power);
}

TEST(DeprecatedApi, OldFalloffFunctionsGiveTheNewOnesResults) {
    EXPECT_EQ(restir::smallest_attenuation_divisor, restir::smallest_falloff_divisor);
    const float distances[] = {0.0f, 1e-3f, 0.5f, 1.0f, 7.0f, 1e4f};
    const float parameters[] = {0.0f, 0.05f, 1.0f};
    for (const float d : distances) {
        for (const float p : parameters) {
            EXPECT_EQ(restir::yuksel_attenuation(d, p), restir::yuksel_falloff(d, p));
            EXPECT_EQ(restir::attenuate(restir::Attenuation::yuksel, d, p),
                      restir::evaluate_falloff(restir::FalloffKind::yuksel, d, p));
            if (p > 0.0f) {
                EXPECT_EQ(restir::attenuate(restir::Attenuation::clamped_inverse_square, d, p),
                          restir::clamped_inverse_square(d, p));
            }
            if (d > 0.0f) {
                EXPECT_EQ(restir::attenuate(restir::Attenuation::inverse_square, d, p),
                          restir::evaluate_falloff(restir::FalloffKind::inverse_square, d, p));
            }
        }
    }
}

TEST(DeprecatedApi, NeighborOffsetsIsNeighbourOffsets) {
    static_assert(std::is_same_v<restir::NeighborOffsets, restir::NeighbourOffsets>);
    static_assert(restir::neighbor_offset_count == restir::neighbour_offset_count);
    constexpr restir::NeighborOffsets old_table = restir::make_neighbor_offsets();
    const restir::NeighbourOffsets& table = restir::default_neighbour_offsets();
    for (std::uint32_t i = 0u; i < restir::neighbor_offset_count; ++i) {
        EXPECT_EQ(old_table[i].x, table[i].x);
        EXPECT_EQ(old_table[i].y, table[i].y);
    }
}

TEST(DeprecatedApi, OtherRenamesMeanTheSame) {
    static_assert(std::is_same_v<restir::DiStream, restir::RngStream>);
    static_assert(std::is_same_v<restir::LoadedHistoryInput<stub::Sample, stub::Surface>,
                                 restir::detail::LoadedHistoryInput<stub::Sample, stub::Surface>>);
    const glm::vec3 n(0.0f, 0.0f, 1.0f);
    const glm::vec3 a = restir::sample_emission_direction(n, 0.3f, 0.7f);
    const glm::vec3 b = restir::sample_diffuse_direction(n, 0.3f, 0.7f);
    EXPECT_EQ(a.x, b.x);
    EXPECT_EQ(a.y, b.y);
    EXPECT_EQ(a.z, b.z);
}

// The fused pass's two older forms (0.1: SpatialParams; until 0.2: NeighbourSearch) draw the
// same numbers and return the same reservoirs as the new call with default reuse settings and
// frame 0, at every pixel of a 4 x 4 history.
TEST(DeprecatedApi, SpatiotemporalResampleOlderFormsGiveTheNewResult) {
    const restir::ReuseBridge bridge{stub::Target{}, stub::Visibility{}};
    std::vector<stub::Surface> surfaces;
    std::vector<restir::Reservoir<stub::Sample>> reservoirs;
    for (std::uint32_t i = 0u; i < 16u; ++i) {
        surfaces.push_back(stub::Surface{0.5f + 0.01f * static_cast<float>(i)});
        restir::Reservoir<stub::Sample> r;
        const stub::Sample sample{i % 4u};
        r.stream(sample, 1.0f, stub::Target{}(sample, surfaces.back()), 0.5f);
        r.finalize();
        reservoirs.push_back(r);
    }
    const restir::ImageView<const restir::Reservoir<stub::Sample>> view{reservoirs.data(), 4u, 4u};
    const restir::ImageView<const stub::Surface> surface_view{surfaces.data(), 4u, 4u};
    const restir::NeighbourOffsets& offsets = restir::default_neighbour_offsets();
    restir::SpatialParams spatial = restir::default_spatial_params();
    spatial.radius = 2.0f;
    spatial.neighbour_count = 4u;
    const restir::NeighbourSearch search{spatial.neighbour_count, spatial.radius};
    const restir::TemporalParams temporal = restir::default_temporal_params();
    for (std::int32_t y = 0; y < 4; ++y) {
        for (std::int32_t x = 0; x < 4; ++x) {
            const auto i = static_cast<std::uint32_t>(x + 4 * y);
            stub::Rng rng_0_1{i + 1u}, rng_search{i + 1u}, rng_new{i + 1u};
            const auto from_0_1 = restir::spatiotemporal_resample(
                {x, y}, reservoirs[i], surfaces[i], view, surface_view, stub::Reprojection{},
                temporal, spatial, offsets, bridge, rng_0_1);
            const auto from_search = restir::spatiotemporal_resample(
                {x, y}, reservoirs[i], surfaces[i], view, surface_view, stub::Reprojection{},
                temporal, search, offsets, bridge, rng_search);
            const auto expected = restir::spatiotemporal_resample(
                {x, y}, reservoirs[i], surfaces[i], view, surface_view, stub::Reprojection{},
                temporal, spatial, restir::ReuseParams{}, 0u, bridge, rng_new, offsets);
            for (const auto& old : {from_0_1, from_search}) {
                EXPECT_EQ(old.sample.id, expected.sample.id);
                EXPECT_EQ(old.candidate_count, expected.candidate_count);
                EXPECT_EQ(old.weight_sum, expected.weight_sum);
                EXPECT_EQ(old.contribution_weight, expected.contribution_weight);
            }
            EXPECT_GT(expected.candidate_count, reservoirs[i].candidate_count) << "reuse happened";
            EXPECT_EQ(rng_0_1.state, rng_new.state);
            EXPECT_EQ(rng_search.state, rng_new.state);
        }
    }
}

// The forms of 0.2 that took the frame's callbacks one by one give the bridge form's reservoirs,
// per pixel and per tile, over two frames of a 4 x 4 image (the second with history); and
// combine_reservoirs is combine_inputs over a ReuseInputSpan.
TEST(DeprecatedApi, CallbacksOneByOneGiveTheBridgeFormsResult) {
    using R = restir::Reservoir<stub::Sample>;
    std::vector<stub::Surface> surfaces;
    for (std::uint32_t i = 0u; i < 16u; ++i)
        surfaces.push_back(stub::Surface{0.5f + 0.01f * static_cast<float>(i % 5u)});
    const auto initial = [](restir::PixelCoord p, const stub::Surface& s, stub::Rng& rng) {
        R r;
        for (std::uint32_t k = 0; k < 4u; ++k) {
            const stub::Sample x{(k + static_cast<std::uint32_t>(p.x)) % 4u};
            r.stream(x, stub::Target{}(x, s), stub::Target{}(x, s), next_float(rng));
        }
        r.finalize();
        return r;
    };
    const auto rng_for = [](restir::PixelCoord p, std::uint32_t stream) {
        return stub::Rng{static_cast<std::uint32_t>(p.x + 4 * p.y) * 97u + stream + 1u};
    };
    const auto each_pixel = [](const auto& body) {
        for (std::int32_t i = 0; i < 16; ++i)
            body(restir::PixelCoord{i % 4, i / 4});
    };
    const auto each_tile = [](const restir::DiStep&, const auto& body) {
        body(restir::PixelTile{{0, 0}, {4, 4}});
    };
    const restir::ReuseBridge pixels{stub::Target{}, stub::Visibility{}};
    const restir::ReuseBridge tiles{stub::Target{}, restir::OneByOne<stub::Visibility>{}};
    // Two frames run by `run(frame, buffers)`; the final reservoirs.
    const auto frames = [&](const auto& run) {
        std::vector<R> out(16), history(16), scratch(16);
        restir::DiFrame<stub::Sample, stub::Surface, stub::Reprojection> frame;
        frame.surfaces = {surfaces.data(), 4u, 4u};
        for (std::uint32_t f = 0; f < 2u; ++f) {
            std::swap(out, history);
            frame.frame_index = f;
            if (f > 0u) {
                frame.history = {history.data(), 4u, 4u};
                frame.previous_surfaces = frame.surfaces;
            }
            run(frame,
                restir::DiBuffers<stub::Sample>{{out.data(), 4u, 4u}, {scratch.data(), 4u, 4u}});
        }
        return out;
    };
    const auto expect_same = [](const std::vector<R>& a, const std::vector<R>& b) {
        for (std::size_t i = 0; i < a.size(); ++i) {
            EXPECT_EQ(a[i].sample.id, b[i].sample.id) << "pixel " << i;
            EXPECT_EQ(a[i].candidate_count, b[i].candidate_count) << "pixel " << i;
            EXPECT_EQ(a[i].contribution_weight, b[i].contribution_weight) << "pixel " << i;
        }
    };
    const auto by_bridge = frames([&](const auto& frame, const auto& buffers) {
        restir::run_di_frame(frame, buffers, restir::DiBridge{initial, pixels, rng_for},
                             each_pixel);
    });
    EXPECT_GT(by_bridge[5].candidate_count, 4u) << "reuse took part";
    expect_same(by_bridge, frames([&](const auto& frame, const auto& buffers) {
                    restir::run_di_frame(frame, buffers, each_pixel, initial, pixels, rng_for);
                }));
    expect_same(by_bridge, frames([&](const auto& frame, const auto& buffers) {
                    restir::run_di_frame(frame, buffers.out, buffers.scratch, each_pixel, initial,
                                         pixels, rng_for);
                }));
    expect_same(by_bridge, frames([&](const auto& frame, const auto& buffers) {
                    restir::run_di_frame(frame, buffers, each_tile, initial, tiles, rng_for);
                }));
    expect_same(by_bridge, frames([&](const auto& frame, const auto& buffers) {
                    for (std::uint32_t i = 0; i < frame.step_count(); ++i)
                        each_pixel([&](restir::PixelCoord p) {
                            frame.run_pixel(frame.step(i), p, buffers, initial, pixels, rng_for);
                        });
                }));

    const std::vector<R> inputs = by_bridge;
    std::vector<restir::ReuseInput<stub::Sample, stub::Surface>> lent;
    for (std::uint32_t i = 1u; i < 6u; ++i)
        lent.push_back({&inputs[i], &surfaces[i]});
    stub::Rng a{7u}, b{7u};
    const R old = restir::combine_reservoirs(inputs[0], surfaces[0], lent.data(), 5u,
                                             restir::ReuseParams{}, pixels, a);
    const R expected =
        restir::combine_inputs(inputs[0], surfaces[0],
                               restir::ReuseInputSpan<stub::Sample, stub::Surface>{lent.data(), 5u},
                               restir::ReuseParams{}, pixels, b);
    expect_same({old}, {expected});
}

// A set of 0.2's form, whose members say that its inputs all lend and cap their M, is still
// read that way: the same reservoir as a ReuseInputSpan with the cap.
struct MemberTraitsSet {
    static constexpr bool packed = true;
    std::uint32_t candidate_cap = restir::no_candidate_cap;
    const restir::ReuseInput<stub::Sample, stub::Surface>* inputs = nullptr;
    std::uint32_t count = 0u;
    std::uint32_t size() const { return count; }
    restir::ReuseInput<stub::Sample, stub::Surface> operator[](std::uint32_t i) const {
        return inputs[i];
    }
};

TEST(DeprecatedApi, SetMembersPackedAndCandidateCapAreStillRead) {
    using R = restir::Reservoir<stub::Sample>;
    std::vector<stub::Surface> surfaces;
    std::vector<R> reservoirs(4);
    for (std::uint32_t i = 0u; i < 4u; ++i) {
        surfaces.push_back(stub::Surface{0.5f + 0.1f * static_cast<float>(i)});
        stub::Rng rng{i + 11u};
        for (std::uint32_t k = 0; k < 8u; ++k) {
            const stub::Sample x{k % 4u};
            const float t = stub::Target{}(x, surfaces[i]);
            reservoirs[i].stream(x, t, t, next_float(rng));
        }
        reservoirs[i].finalize();
    }
    std::vector<restir::ReuseInput<stub::Sample, stub::Surface>> lent;
    for (std::uint32_t i = 1u; i < 4u; ++i)
        lent.push_back({&reservoirs[i], &surfaces[i]});
    const restir::ReuseBridge bridge{stub::Target{}, stub::Visibility{}};
    for (const std::uint32_t cap : {2u, restir::no_candidate_cap}) {
        stub::Rng a{5u}, b{5u};
        const R old = restir::combine_inputs(reservoirs[0], surfaces[0],
                                             MemberTraitsSet{cap, lent.data(), 3u},
                                             restir::ReuseParams{}, bridge, a);
        const R expected = restir::combine_inputs(
            reservoirs[0], surfaces[0],
            restir::ReuseInputSpan<stub::Sample, stub::Surface>{lent.data(), 3u, cap},
            restir::ReuseParams{}, bridge, b);
        EXPECT_EQ(old.sample.id, expected.sample.id);
        EXPECT_EQ(old.candidate_count, expected.candidate_count);
        EXPECT_EQ(old.contribution_weight, expected.contribution_weight);
    }
    // The cap lowers the M that the inputs lend: 8 + 3 x 2 against 8 + 3 x 8.
    stub::Rng c{5u};
    EXPECT_EQ(restir::combine_inputs(reservoirs[0], surfaces[0],
                                     MemberTraitsSet{2u, lent.data(), 3u}, restir::ReuseParams{},
                                     bridge, c)
                  .candidate_count,
              14u);
}

} // namespace
