// Deterministic properties of the reuse passes: similarity tests, history
// fallback and capping, non-finite inputs, visibility, the boiling filter.
#include <restir/restir.hpp>

#include <gtest/gtest.h>

#include <algorithm>
#include <cmath>
#include <cstdint>
#include <limits>
#include <set>
#include <type_traits>
#include <utility>
#include <vector>

namespace {

using restir::BiasCorrection;
using restir::PixelCoord;
using restir::Reservoir;

struct Point {
    glm::vec3 normal{0.0f, 0.0f, 1.0f};
    float depth = 1.0f;
    bool valid = true;
    int material = 0;
};
glm::vec3 surface_position(const Point&) { return glm::vec3(0.0f); }
glm::vec3 surface_normal(const Point& p) { return p.normal; }
float surface_depth(const Point& p) { return p.depth; }
bool is_valid_surface(const Point& p) { return p.valid; }
// Material m has roughness m / 10 (0: a mirror; 10: Lambertian).
float surface_roughness(const Point& p) { return static_cast<float>(p.material) / 10.0f; }

struct LightId {
    std::uint32_t id = 0u;
};

struct Target {
    float operator()(const LightId& x, const Point&) const {
        return 1.0f + static_cast<float>(x.id);
    }
};
struct AlwaysVisible {
    bool operator()(const LightId&, const Point&) const { return true; }
};

constexpr BiasCorrection all_modes[] = {BiasCorrection::none, BiasCorrection::one_over_z,
                                        BiasCorrection::balance_heuristic,
                                        BiasCorrection::pairwise};

Reservoir<LightId> finalised(std::uint32_t light, std::uint32_t count, float weight) {
    Reservoir<LightId> r;
    r.stream(LightId{light}, weight, Target{}(LightId{light}, Point{}), 0.0f);
    r.candidate_count = count;
    r.finalize();
    return r;
}

Reservoir<LightId> poisoned() {
    Reservoir<LightId> r = finalised(3u, 4u, 2.0f);
    r.weight_sum = std::numeric_limits<float>::quiet_NaN();
    r.contribution_weight = std::numeric_limits<float>::infinity();
    return r;
}

glm::vec3 tilted_normal(float degrees) {
    const float radians = degrees * 3.14159265f / 180.0f;
    return {std::sin(radians), 0.0f, std::cos(radians)};
}

TEST(Similarity, NormalDepthValidityAndMaterialHook) {
    const restir::SimilarityParams params = restir::default_similarity_params();
    const Point receiver;
    EXPECT_TRUE(restir::surfaces_similar(receiver, Point{tilted_normal(20.0f)}, params));
    EXPECT_FALSE(restir::surfaces_similar(receiver, Point{tilted_normal(30.0f)}, params));
    EXPECT_TRUE(restir::surfaces_similar(receiver, Point{{0, 0, 1}, 1.05f}, params));
    EXPECT_FALSE(restir::surfaces_similar(receiver, Point{{0, 0, 1}, 0.85f}, params));
    EXPECT_FALSE(restir::surfaces_similar(receiver, Point{{0, 0, 1}, 1.0f, false}, params));
    EXPECT_FALSE(restir::surfaces_similar(Point{{0, 0, 1}, 1.0f, false}, receiver, params));
    const auto same_material = [](const Point& a, const Point& b) {
        return a.material == b.material;
    };
    EXPECT_FALSE(
        restir::surfaces_similar(receiver, Point{{0, 0, 1}, 1.0f, true, 7}, params, same_material));
    EXPECT_TRUE(restir::surfaces_similar(receiver, Point{}, params, same_material));
}

TEST(Similarity, RoughnessHookAcceptsLobesOfSimilarWidthOnly) {
    const restir::SimilarityParams params = restir::default_similarity_params();
    const restir::SimilarRoughness roughness{0.2f};
    const Point glossy{{0, 0, 1}, 1.0f, true, 1}; // roughness 0.1
    EXPECT_TRUE(
        restir::surfaces_similar(glossy, Point{{0, 0, 1}, 1.0f, true, 2}, params, roughness));
    EXPECT_FALSE(
        restir::surfaces_similar(glossy, Point{{0, 0, 1}, 1.0f, true, 4}, params, roughness));
    EXPECT_FALSE(
        restir::surfaces_similar(Point{{0, 0, 1}, 1.0f, true, 10}, glossy, params, roughness));
    EXPECT_TRUE(restir::surfaces_similar(glossy, glossy, params, restir::SimilarRoughness{0.0f}));
}

// The previous-frame buffers of a 3 x 1 image.
struct History {
    std::vector<Reservoir<LightId>> reservoirs;
    std::vector<Point> surfaces;
    restir::ImageView<const Reservoir<LightId>> reservoir_view() const {
        return {reservoirs.data(), 3u, 1u};
    }
    restir::ImageView<const Point> surface_view() const { return {surfaces.data(), 3u, 1u}; }
};

void expect_same(const Reservoir<LightId>& a, const Reservoir<LightId>& b) {
    EXPECT_EQ(a.sample.id, b.sample.id);
    EXPECT_EQ(a.candidate_count, b.candidate_count);
    EXPECT_EQ(a.contribution_weight, b.contribution_weight);
    EXPECT_EQ(a.weight_sum, b.weight_sum);
}

TEST(TemporalReuse, FallsBackToTheCurrentReservoirWithoutUsableHistory) {
    const restir::ReuseBridge bridge{Target{}, AlwaysVisible{}};
    const Reservoir<LightId> current = finalised(2u, 4u, 1.5f);
    History history{{finalised(1u, 8u, 1.0f), finalised(1u, 8u, 1.0f), poisoned()},
                    {Point{}, Point{tilted_normal(60.0f)}, Point{}}};
    const auto to = [](std::int32_t x) { return [x](PixelCoord) { return PixelCoord{x, 0}; }; };
    for (BiasCorrection mode : all_modes) {
        const restir::TemporalParams params = restir::default_temporal_params();
        const restir::ReuseParams reuse{mode};
        restir::Pcg32 rng;
        // Disocclusion: the reprojection names no pixel of the previous image.
        expect_same(restir::temporal_resample({0, 0}, current, Point{}, history.reservoir_view(),
                                              history.surface_view(), to(-1), params, reuse, 0u,
                                              bridge, rng),
                    current);
        // A dissimilar surface (normals 60 degrees apart).
        expect_same(restir::temporal_resample({0, 0}, current, Point{}, history.reservoir_view(),
                                              history.surface_view(), to(1), params, reuse, 0u,
                                              bridge, rng),
                    current);
        // A history holding NaN and infinity.
        expect_same(restir::temporal_resample({0, 0}, current, Point{}, history.reservoir_view(),
                                              history.surface_view(), to(2), params, reuse, 0u,
                                              bridge, rng),
                    current);
        // An invalid receiver keeps its reservoir.
        expect_same(restir::temporal_resample({0, 0}, current, Point{{0, 0, 1}, 1.0f, false},
                                              history.reservoir_view(), history.surface_view(),
                                              to(0), params, reuse, 0u, bridge, rng),
                    current);
        // Usable history is combined: M adds up.
        const Reservoir<LightId> combined = restir::temporal_resample(
            {0, 0}, current, Point{}, history.reservoir_view(), history.surface_view(), to(0),
            params, reuse, 0u, bridge, rng);
        EXPECT_EQ(combined.candidate_count, 12u);
        EXPECT_TRUE(combined.is_well_formed());
    }
}

TEST(TemporalReuse, CapsTheHistoryAtAMultipleOfTheCurrentCount) {
    const restir::ReuseBridge bridge{Target{}, AlwaysVisible{}};
    const Reservoir<LightId> current = finalised(2u, 4u, 1.5f);
    History history{{finalised(1u, 1000u, 1.0f), {}, {}}, {Point{}, Point{}, Point{}}};
    restir::TemporalParams params = restir::default_temporal_params();
    restir::Pcg32 rng;
    const auto same_pixel = [](PixelCoord p) { return p; };
    EXPECT_EQ(restir::temporal_resample({0, 0}, current, Point{}, history.reservoir_view(),
                                        history.surface_view(), same_pixel, params, {}, 0u, bridge,
                                        rng)
                  .candidate_count,
              4u + 20u * 4u);
    params.history_cap_multiplier = 0u; // no cap
    EXPECT_EQ(restir::temporal_resample({0, 0}, current, Point{}, history.reservoir_view(),
                                        history.surface_view(), same_pixel, params, {}, 0u, bridge,
                                        rng)
                  .candidate_count,
              1004u);
}

TEST(TemporalReuse, PermutationSamplingPermutesTwoByTwoBlocks) {
    restir::TemporalParams params = restir::default_temporal_params();
    EXPECT_EQ(restir::history_pixel({5, 8}, params, 3u).x, 5);
    params.permutation_sampling = true;
    bool moved = false;
    for (std::uint32_t frame = 0; frame < 8u; ++frame) {
        std::set<std::pair<int, int>> images;
        for (int y = 0; y < 4; ++y)
            for (int x = 0; x < 4; ++x) {
                const PixelCoord p = restir::history_pixel({x, y}, params, frame);
                EXPECT_EQ(p.x / 2, x / 2);
                EXPECT_EQ(p.y / 2, y / 2);
                images.insert({p.x, p.y});
                moved = moved || p.x != x || p.y != y;
            }
        EXPECT_EQ(images.size(), 16u) << "frame " << frame << " is not a bijection";
    }
    EXPECT_TRUE(moved);
}

// history_pixel_at permutes at receivers at least permutation_min_roughness rough and reads
// the reprojected pixel itself at smoother ones.
TEST(TemporalReuse, SmoothReceiversReadTheirOwnPixelsHistory) {
    restir::TemporalParams params = restir::default_temporal_params();
    params.permutation_sampling = true;
    params.permutation_min_roughness = 0.15f;
    Point mirror, rough;
    mirror.material = 1; // 0.1
    rough.material = 5;  // 0.5
    bool rough_moved = false;
    for (std::uint32_t frame = 0; frame < 8u; ++frame)
        for (int y = 0; y < 4; ++y)
            for (int x = 0; x < 4; ++x) {
                const PixelCoord p = restir::history_pixel_at(mirror, {x, y}, params, frame);
                EXPECT_EQ(p.x, x);
                EXPECT_EQ(p.y, y);
                const PixelCoord q = restir::history_pixel_at(rough, {x, y}, params, frame);
                const PixelCoord r = restir::history_pixel({x, y}, params, frame);
                EXPECT_EQ(q.x, r.x);
                EXPECT_EQ(q.y, r.y);
                rough_moved = rough_moved || q.x != x || q.y != y;
            }
    EXPECT_TRUE(rough_moved);
}

TEST(TemporalReuse, PermutationBitsSetTheBlockSize) {
    restir::TemporalParams params = restir::default_temporal_params();
    params.permutation_sampling = true;
    params.permutation_bits = 2u; // 4 x 4 blocks
    std::set<std::pair<int, int>> offsets_seen;
    for (std::uint32_t frame = 0; frame < 64u; ++frame) {
        std::set<std::pair<int, int>> images;
        for (int y = 0; y < 8; ++y)
            for (int x = 0; x < 8; ++x) {
                const PixelCoord p = restir::history_pixel({x, y}, params, frame);
                EXPECT_EQ(p.x / 4, x / 4);
                EXPECT_EQ(p.y / 4, y / 4);
                images.insert({p.x, p.y});
                if (x == 0 && y == 0)
                    offsets_seen.insert({p.x, p.y});
            }
        EXPECT_EQ(images.size(), 64u) << "frame " << frame << " is not a bijection";
    }
    // More bits than a coordinate can shift are clamped (15), not undefined behaviour.
    params.permutation_bits = 40u;
    const PixelCoord far = restir::history_pixel({70000, 5}, params, 0u);
    EXPECT_EQ(far.x >> 15, 70000 >> 15);
    EXPECT_EQ(far.y >> 15, 0);
    params.permutation_bits = 2u;
    // Each block draws its pattern per frame: 64 frames miss a given one of the 16 patterns
    // with probability (15/16)^64 < 0.02, so most appear.
    EXPECT_GE(offsets_seen.size(), 12u);
}

// The rotation's polynomial sine and cosine agree with the library functions within 4e-7 over
// a fine grid of u, lie on the unit circle, and are defined for any float.
TEST(SpatialReuse, IgnoresNonFiniteNeighboursAndInvalidReceivers) {
    const restir::ReuseBridge bridge{Target{}, AlwaysVisible{}};
    const restir::NeighbourOffsets offsets = restir::make_neighbour_offsets();
    // A 3 x 3 image: the centre is sound, every neighbour is poisoned.
    std::vector<Reservoir<LightId>> reservoirs(9, poisoned());
    reservoirs[4] = finalised(2u, 4u, 1.5f);
    const std::vector<Point> surfaces(9);
    const restir::ImageView<const Reservoir<LightId>> view{reservoirs.data(), 3u, 3u};
    const restir::ImageView<const Point> surface_view{surfaces.data(), 3u, 3u};
    for (BiasCorrection mode : all_modes) {
        restir::SpatialParams params = restir::default_spatial_params();
        const restir::ReuseParams reuse{mode};
        params.neighbour_count = 8u;
        params.radius = 1.5f;
        restir::Pcg32 rng = restir::make_pixel_rng(4u, 0u, 0u);
        const Reservoir<LightId> out = restir::spatial_resample({1, 1}, view, surface_view, params,
                                                                reuse, bridge, rng, offsets);
        EXPECT_EQ(out.sample.id, 2u);
        EXPECT_EQ(out.candidate_count, 4u);
        EXPECT_FLOAT_EQ(out.contribution_weight, reservoirs[4].contribution_weight);
    }
    // An invalid receiver (background) returns its reservoir untouched.
    std::vector<Point> background(9);
    background[4].valid = false;
    restir::Pcg32 rng;
    const restir::ImageView<const Point> background_view{background.data(), 3u, 3u};
    expect_same(restir::spatial_resample({1, 1}, view, background_view,
                                         restir::default_spatial_params(), {}, bridge, rng,
                                         offsets),
                reservoirs[4]);
}

// Receivers smoother than SpatialParams::min_roughness take no neighbours; rougher ones and
// surfaces without a roughness (Lambertian, 1) do; the neighbours' own roughness does not matter.
TEST(SpatialReuse, SmoothReceiversBelowTheMinimumRoughnessTakeNoNeighbours) {
    const restir::ReuseBridge bridge{Target{}, AlwaysVisible{}};
    const restir::NeighbourOffsets offsets = restir::make_neighbour_offsets();
    std::vector<Reservoir<LightId>> reservoirs(9, finalised(1u, 4u, 1.0f));
    reservoirs[4] = finalised(2u, 4u, 1.5f);
    std::vector<Point> surfaces(9);
    const restir::ImageView<const Reservoir<LightId>> view{reservoirs.data(), 3u, 3u};
    restir::SpatialParams params = restir::default_spatial_params();
    params.neighbour_count = 15u;
    params.radius = 1.5f;
    params.min_roughness = 0.15f;
    for (const int material : {0, 1, 2, 10}) {
        surfaces[4].material = material; // roughness material / 10
        const restir::ImageView<const Point> surface_view{surfaces.data(), 3u, 3u};
        for (BiasCorrection mode : all_modes) {
            restir::Pcg32 rng = restir::make_pixel_rng(4u, 0u, 0u);
            const Reservoir<LightId> out =
                restir::spatial_resample({1, 1}, view, surface_view, params,
                                         restir::ReuseParams{mode}, bridge, rng, offsets);
            if (material < 2) { // 0 and 0.1: below 0.15, the canonical reservoir alone
                EXPECT_EQ(out.sample.id, 2u);
                EXPECT_EQ(out.candidate_count, 4u);
                EXPECT_FLOAT_EQ(out.contribution_weight, reservoirs[4].contribution_weight);
            } else {
                EXPECT_GT(out.candidate_count, 4u) << "material " << material;
            }
        }
    }
    EXPECT_EQ(restir::reuse_roughness(Point{{0, 0, 1}, 1.0f, true, 3}), 0.3f);
    EXPECT_EQ(restir::reuse_roughness(glm::vec3(0.0f)), 1.0f); // no surface_roughness: 1
}

TEST(SpatialReuse, AddsTheCandidateCountsOfSimilarNeighbours) {
    const restir::ReuseBridge bridge{Target{}, AlwaysVisible{}};
    const restir::NeighbourOffsets offsets = restir::make_neighbour_offsets();
    std::vector<Reservoir<LightId>> reservoirs(9, finalised(1u, 4u, 1.0f));
    std::vector<Point> surfaces(9);
    for (std::uint32_t i : {0u, 2u, 6u, 8u}) // corners face away: never similar
        surfaces[i].normal = {0.0f, 0.0f, -1.0f};
    const restir::ImageView<const Reservoir<LightId>> view{reservoirs.data(), 3u, 3u};
    const restir::ImageView<const Point> surface_view{surfaces.data(), 3u, 3u};
    for (BiasCorrection mode : all_modes) {
        restir::SpatialParams params = restir::default_spatial_params();
        const restir::ReuseParams reuse{mode};
        params.neighbour_count = 15u;
        params.radius = 1.5f;
        restir::Pcg32 rng = restir::make_pixel_rng(4u, 0u, 0u);
        const Reservoir<LightId> out = restir::spatial_resample({1, 1}, view, surface_view, params,
                                                                reuse, bridge, rng, offsets);
        // Only the four edge neighbours can take part, each 4 candidates, at most once per
        // offset that lands on them.
        EXPECT_EQ(out.candidate_count % 4u, 0u);
        EXPECT_GT(out.candidate_count, 4u);
        EXPECT_TRUE(out.is_well_formed());
        EXPECT_GT(out.contribution_weight, 0.0f);
    }
}

TEST(Visibility, OccludedSampleKeepsItsCountButLosesItsWeight) {
    Reservoir<LightId> r = finalised(3u, 4u, 2.0f);
    const auto blocked = [](const LightId& x, const Point&) { return x.id != 3u; };
    EXPECT_FALSE(restir::apply_visibility(r, Point{}, blocked));
    EXPECT_EQ(r.contribution_weight, 0.0f);
    EXPECT_EQ(r.weight_sum, 0.0f);
    EXPECT_EQ(r.candidate_count, 4u);
    Reservoir<LightId> seen = finalised(2u, 4u, 2.0f);
    const Reservoir<LightId> before = seen;
    EXPECT_TRUE(restir::apply_visibility(seen, Point{}, blocked));
    expect_same(seen, before);
}

// A light set with one area light at height 2 and a query that records its segment.
struct OneLight {
    std::uint32_t light_count() const { return 1u; }
    restir::LightSample sample_point(std::uint32_t, glm::vec2 uv) const {
        restir::LightSample s;
        s.position = {uv.x, uv.y, 2.0f};
        s.normal = {0.0f, 0.0f, -1.0f};
        s.radiance = glm::vec3(1.0f);
        s.area_pdf = 1.0f;
        return s;
    }
};
struct RecordingQuery {
    mutable glm::vec3 from{0.0f}, to{0.0f};
    bool blocked = false;
    bool occluded(glm::vec3 a, glm::vec3 b) const {
        from = a;
        to = b;
        return blocked;
    }
};

TEST(Visibility, LightVisibilityOffsetsBothEndsTowardsEachOther) {
    const OneLight lights;
    RecordingQuery query;
    const restir::LightVisibility<OneLight, RecordingQuery> visible{&lights, &query, 0.01f};
    const restir::LightSampleRef ref{0u, {0.25f, 0.5f}};
    EXPECT_TRUE(visible(ref, Point{}));
    EXPECT_FLOAT_EQ(query.from.z, 0.01f);
    EXPECT_FLOAT_EQ(query.to.z, 1.99f);
    EXPECT_FLOAT_EQ(query.to.x, 0.25f);
    query.blocked = true;
    EXPECT_FALSE(visible(ref, Point{}));
}

// A VPL lies on a surface: its end moves off that surface as an area light's does, so that
// the segment cannot hit the surface the VPL lies on (a hit decided by rounding, which single
// rays and packets decide differently). An isotropic point light keeps its end.
struct PointLights {
    std::uint32_t light_count() const { return 2u; }
    restir::LightSample sample_point(std::uint32_t id, glm::vec2) const {
        restir::LightSample s;
        s.position = {0.5f, 0.5f, 2.0f};
        s.normal = id == 0u ? glm::vec3(0.0f, 0.0f, -1.0f) : glm::vec3(0.0f); // VPL, isotropic
        s.radiance = glm::vec3(1.0f);
        s.area_pdf = 1.0f;
        s.is_delta = true;
        return s;
    }
};

TEST(Visibility, VplEndsLeaveTheirSurfaceAndIsotropicPointsStay) {
    const PointLights lights;
    RecordingQuery query;
    const restir::LightVisibility<PointLights, RecordingQuery> visible{&lights, &query, 0.01f};
    EXPECT_TRUE(visible(restir::LightSampleRef{0u, {}}, Point{}));
    EXPECT_FLOAT_EQ(query.from.z, 0.01f);
    EXPECT_FLOAT_EQ(query.to.z, 1.99f);
    EXPECT_TRUE(visible(restir::LightSampleRef{1u, {}}, Point{}));
    EXPECT_FLOAT_EQ(query.to.z, 2.0f);
    // The same segments for samples that carry their point.
    const restir::LightPointVisibility<RecordingQuery> point_visible{&query, 0.01f};
    const restir::Falloff falloff{restir::FalloffKind::yuksel, 0.1f};
    for (std::uint32_t id : {0u, 1u}) {
        const restir::LightPointSample sample =
            restir::make_light_point_sample(id, lights.sample_point(id, {}), falloff);
        const restir::ShadowSegment segment = point_visible.segment(sample, Point{});
        EXPECT_TRUE(point_visible(sample, Point{}));
        EXPECT_EQ(segment.from, query.from);
        EXPECT_EQ(segment.to, query.to);
        EXPECT_FLOAT_EQ(segment.to.z, id == 0u ? 1.99f : 2.0f);
    }
}

TEST(BoilingFilter, EmptiesOnlyOutliersAboveTheLocalAverage) {
    std::vector<Reservoir<LightId>> reservoirs(25, finalised(0u, 4u, 1.0f)); // p-hat W = 1
    reservoirs[12] = finalised(0u, 4u, 100.0f);                              // p-hat W = 100
    reservoirs[0] = poisoned();
    const restir::ImageView<const Reservoir<LightId>> view{reservoirs.data(), 5u, 5u};
    restir::BoilingFilterParams params = restir::default_boiling_filter_params();
    params.radius = 2u;
    params.threshold = 10.0f; // the average over 24 sound reservoirs is (23 + 100) / 24 = 5.1
    const Reservoir<LightId> centre = restir::boiling_filter({2, 2}, view, params);
    EXPECT_EQ(centre.contribution_weight, 0.0f);
    EXPECT_EQ(centre.candidate_count, 4u);
    expect_same(restir::boiling_filter({1, 1}, view, params), reservoirs[6]);
    params.threshold = 25.0f;
    expect_same(restir::boiling_filter({2, 2}, view, params), reservoirs[12]);
}

// Preconditions a debug build checks (an assertion) and a release build survives with a
// defined result: a pixel outside the view, more inputs than one reuse step combines, a
// boiling-filter window larger than any image.
TEST(ReusePreconditions, OutOfRangeCallsAreCheckedInDebugAndDefinedInRelease) {
    const restir::ReuseBridge bridge{Target{}, AlwaysVisible{}};
    const restir::NeighbourOffsets offsets = restir::make_neighbour_offsets();
    std::vector<Reservoir<LightId>> reservoirs(9, finalised(1u, 4u, 1.0f));
    const std::vector<Point> surfaces(9);
    const restir::ImageView<const Reservoir<LightId>> view{reservoirs.data(), 3u, 3u};
    const restir::ImageView<const Point> surface_view{surfaces.data(), 3u, 3u};
    const restir::SpatialParams params = restir::default_spatial_params();
    restir::BoilingFilterParams filter = restir::default_boiling_filter_params();

    // 40 inputs where at most max_reuse_inputs - 1 fit.
    std::vector<restir::ReuseInput<LightId, Point>> many(40);
    for (auto& input : many)
        input = {&reservoirs[0], &surfaces[0]};
    const auto combine_many = [&] {
        restir::Pcg32 rng;
        return restir::combine_inputs(reservoirs[4], surfaces[4],
                                      restir::ReuseInputSpan<LightId, Point>{many.data(), 40u},
                                      restir::ReuseParams{}, bridge, rng);
    };
    // The first max_reuse_inputs - 1 inputs take part (ASan sees any read past them).
    EXPECT_EQ(combine_many().candidate_count, 4u * restir::max_reuse_inputs);
#ifdef NDEBUG
    for (PixelCoord outside : {PixelCoord{-1, 0}, PixelCoord{3, 1}, PixelCoord{1, 1000}}) {
        restir::Pcg32 rng;
        const Reservoir<LightId> r =
            restir::spatial_resample(outside, view, surface_view, params, {}, bridge, rng, offsets);
        EXPECT_EQ(r.candidate_count, 0u);
        EXPECT_EQ(r.contribution_weight, 0.0f);
        EXPECT_EQ(restir::boiling_filter(outside, view, filter).candidate_count, 0u);
    }
#else
    restir::Pcg32 rng;
    EXPECT_DEATH(
        restir::spatial_resample({-1, 0}, view, surface_view, params, {}, bridge, rng, offsets),
        "contains");
    EXPECT_DEATH(restir::boiling_filter({3, 1}, view, filter), "contains");
#endif
    // Any radius is defined and costs no more than the image (it used to loop over the whole
    // (2r + 1)^2 window, and convert the radius to int).
    filter.threshold = 1.5f;
    for (std::uint32_t radius : {0u, 1u, 1u << 30, 0xffffffffu}) {
        filter.radius = radius;
        expect_same(restir::boiling_filter({1, 1}, view, filter), reservoirs[4]);
        reservoirs[8] = finalised(1u, 4u, 100.0f); // an outlier in the corner, seen from radius 1
        EXPECT_EQ(restir::boiling_filter({2, 2}, view, filter).contribution_weight,
                  radius == 0u ? reservoirs[8].contribution_weight : 0.0f)
            << radius;
        reservoirs[8] = reservoirs[0];
    }
}

// A writable view passes where a pass reads (ImageView<T> -> ImageView<const T>), never the
// other way round.
TEST(ImageView, ConvertsToReadOnly) {
    std::vector<Reservoir<LightId>> reservoirs(6);
    const restir::ImageView<Reservoir<LightId>> writable{reservoirs.data(), 3u, 2u};
    const restir::ImageView<const Reservoir<LightId>> readable = writable;
    EXPECT_EQ(readable.data, reservoirs.data());
    EXPECT_EQ(readable.width, 3u);
    EXPECT_EQ(readable.height, 2u);
    static_assert(!std::is_convertible_v<restir::ImageView<const Reservoir<LightId>>,
                                         restir::ImageView<Reservoir<LightId>>>);
}

} // namespace
