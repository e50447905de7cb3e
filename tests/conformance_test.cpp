// Every template instantiated with the minimal stub types of tests/support/stub_bridge.hpp,
// and the types each concept rejects.
#include <restir/restir.hpp>

#include "support/stub_bridge.hpp"

#include <gtest/gtest.h>

#include <cstdint>
#include <type_traits>
#include <vector>

namespace {

// --- What the concepts accept ------------------------------------------------------------
static_assert(restir::UniformRng<stub::Rng>);
static_assert(restir::UniformRng<restir::Pcg32>);
static_assert(restir::Surface<stub::Surface>);
static_assert(restir::TargetFunction<stub::Target, stub::Sample, stub::Surface>);
static_assert(restir::LightSet<stub::LightSet>);
static_assert(restir::LightPoint<restir::LightSample>);
static_assert(restir::LightSampler<stub::LightSampler>);
static_assert(restir::RayQuery<stub::RayQuery>);
static_assert(restir::VisibilityFunction<stub::Visibility, stub::Sample, stub::Surface>);
static_assert(restir::Reprojection<stub::Reprojection>);
static_assert(restir::ClosestHitQuery<stub::ClosestHit>);
static_assert(restir::ScatterFunction<stub::Scatter, stub::Surface, stub::Rng>);
static_assert(restir::LightSet<restir::UnifiedLightSet<stub::LightSet>>);

} // namespace

// --- What they reject (declared only: concepts never call them) ---------------------------
namespace rejected {
struct DoubleRng {};
double next_float(DoubleRng&);
static_assert(!restir::UniformRng<DoubleRng>, "next_float must return float");
static_assert(!restir::UniformRng<int>, "no next_float for int");

struct SurfaceWithoutDepth {};
glm::vec3 surface_position(const SurfaceWithoutDepth&);
glm::vec3 surface_normal(const SurfaceWithoutDepth&);
bool is_valid_surface(const SurfaceWithoutDepth&);
static_assert(!restir::Surface<SurfaceWithoutDepth>, "surface_depth is required");

struct TargetReturningPointer {
    const char* operator()(const stub::Sample&, const stub::Surface&) const;
};
static_assert(!restir::TargetFunction<TargetReturningPointer, stub::Sample, stub::Surface>);
static_assert(!restir::TargetFunction<stub::Target, stub::Sample, int>, "wrong surface type");

struct LightSetWithoutCount {
    restir::LightSample sample_point(std::uint32_t, glm::vec2) const;
};
static_assert(!restir::LightSet<LightSetWithoutCount>);

struct PointWithoutPdf {
    glm::vec3 position, normal, radiance;
    bool is_delta;
};
struct LightSetReturningIncompletePoints {
    std::uint32_t light_count() const;
    PointWithoutPdf sample_point(std::uint32_t, glm::vec2) const;
};
static_assert(!restir::LightSet<LightSetReturningIncompletePoints>, "area_pdf is required");

struct SamplerWithOneNumber {
    restir::DiscreteSample sample(float) const;
    float pmf(std::uint32_t) const;
    std::uint32_t light_count() const;
};
static_assert(!restir::LightSampler<SamplerWithOneNumber>, "sample takes two numbers");

struct MutableRayQuery {
    bool occluded(glm::vec3, glm::vec3); // not const
};
static_assert(!restir::RayQuery<MutableRayQuery>, "queries must be const-callable");

struct VisibilityReturningNothing {
    void operator()(const stub::Sample&, const stub::Surface&) const;
};
static_assert(!restir::VisibilityFunction<VisibilityReturningNothing, stub::Sample, stub::Surface>);
static_assert(!restir::VisibilityFunction<stub::Visibility, stub::Sample, int>, "wrong surface");

struct ReprojectionToIndex {
    int operator()(restir::PixelCoord) const;
};
static_assert(!restir::Reprojection<ReprojectionToIndex>, "must return a PixelCoord");

struct HitWithoutNormal {};
glm::vec3 surface_position(const HitWithoutNormal&);
float surface_depth(const HitWithoutNormal&);
bool is_valid_surface(const HitWithoutNormal&);
struct QueryReturningIncompleteHits {
    HitWithoutNormal closest_hit(glm::vec3, glm::vec3) const;
};
static_assert(!restir::ClosestHitQuery<QueryReturningIncompleteHits>, "hits must be Surfaces");
static_assert(!restir::ClosestHitQuery<stub::RayQuery>, "occluded() is not closest_hit()");

struct ScatterWithoutRng {
    restir::Scattering operator()(const stub::Surface&, glm::vec3) const;
};
static_assert(!restir::ScatterFunction<ScatterWithoutRng, stub::Surface, stub::Rng>);

} // namespace rejected

namespace {

// --- Every template with the stub types ----------------------------------------------------
TEST(Conformance, TemplatesInstantiateWithStubTypes) {
    stub::Rng rng;
    const stub::Surface surface{0.5f};
    const stub::Target target;
    const stub::LightSet lights;
    const stub::LightSampler sampler;
    const stub::RayQuery query;

    const auto draw = [&](stub::Rng& r) {
        const restir::DiscreteSample c = restir::sample_light(sampler, r);
        return restir::SourceSample<stub::Sample>{{c.index}, c.pmf};
    };
    const auto at_surface = [&](const stub::Sample& s) { return target(s, surface); };
    restir::Reservoir<stub::Sample> r = restir::resample_ris(rng, 4u, draw, at_surface);
    EXPECT_EQ(r.candidate_count, 4u);
    EXPECT_TRUE(r.has_sample());

    const restir::SourceStrategy strategy{2u, [](stub::Rng&) { return stub::Sample{0u}; },
                                          [](const stub::Sample&) { return 1.0f; }};
    const auto mis = restir::resample_ris_mis(rng, at_surface, strategy, strategy);
    EXPECT_EQ(mis.candidate_count, 4u);

    restir::Reservoir<stub::Sample> merged;
    merged.merge(r, target(r.sample, surface), next_float(rng));
    merged.merge_with_mis(mis, target(mis.sample, surface), 0.5f, next_float(rng));
    merged.stream_lazy(1.0f, 1.0f, next_float(rng), [] { return stub::Sample{1u}; });
    merged.cap_candidate_count(3u);
    merged.finalize();
    EXPECT_TRUE(merged.is_well_formed());

    const restir::LightSample point = lights.sample_point(r.sample.id, glm::vec2(0.5f));
    EXPECT_FALSE(query.occluded(surface_position(surface), point.position));
}

TEST(Conformance, ReusePassesInstantiateWithStubTypes) {
    stub::Rng rng;
    const restir::ReuseBridge bridge{stub::Target{}, stub::Visibility{}};
    const std::vector<stub::Surface> surfaces(4, stub::Surface{0.5f});
    std::vector<restir::Reservoir<stub::Sample>> reservoirs(4);
    for (restir::Reservoir<stub::Sample>& r : reservoirs) {
        r.stream(stub::Sample{1u}, 1.0f, stub::Target{}(stub::Sample{1u}, surfaces[0]), 0.5f);
        r.finalize();
    }
    const restir::ImageView<const restir::Reservoir<stub::Sample>> view{reservoirs.data(), 2u, 2u};
    const restir::ImageView<const stub::Surface> surface_view{surfaces.data(), 2u, 2u};
    const restir::NeighbourOffsets offsets = restir::make_neighbour_offsets();
    restir::SpatialParams spatial = restir::default_spatial_params();
    spatial.radius = 1.0f;
    const restir::TemporalParams temporal = restir::default_temporal_params();

    const restir::ReuseParams reuse{};
    auto out = restir::temporal_resample({0, 0}, reservoirs[0], surfaces[0], view, surface_view,
                                         stub::Reprojection{}, temporal, reuse, 0u, bridge, rng);
    EXPECT_EQ(out.candidate_count, 2u);
    out =
        restir::spatial_resample({0, 0}, view, surface_view, spatial, reuse, bridge, rng, offsets);
    EXPECT_GE(out.candidate_count, 1u);
    out = restir::spatiotemporal_resample({1, 1}, reservoirs[3], surfaces[3], view, surface_view,
                                          stub::Reprojection{}, temporal, spatial, reuse, 0u,
                                          bridge, rng, offsets);
    EXPECT_GE(out.candidate_count, 2u);
    EXPECT_TRUE(restir::apply_visibility(out, surfaces[0], stub::Visibility{}));
    out = restir::boiling_filter({0, 0}, view, restir::default_boiling_filter_params());
    EXPECT_TRUE(out.is_well_formed());
    const stub::LightSet lights;
    const stub::RayQuery query;
    const restir::LightVisibility<stub::LightSet, stub::RayQuery> light_visibility{&lights, &query,
                                                                                   1e-3f};
    EXPECT_TRUE(light_visibility(restir::LightSampleRef{}, surfaces[0]));
    const auto scaled =
        restir::LightVisibility<stub::LightSet, stub::RayQuery>::for_scene(lights, query, 550.0f);
    EXPECT_FLOAT_EQ(scaled.ray_offset, 0.055f);
    // Neither visibility adapter can be built without a ray offset (it would be 0).
    static_assert(!std::is_constructible_v<restir::LightVisibility<stub::LightSet, stub::RayQuery>,
                                           const stub::LightSet*, const stub::RayQuery*>);
    static_assert(!std::is_constructible_v<restir::LightPointVisibility<stub::RayQuery>,
                                           const stub::RayQuery*>);
    const auto point_scaled =
        restir::LightPointVisibility<stub::RayQuery>::for_scene(query, 550.0f);
    EXPECT_FLOAT_EQ(point_scaled.ray_offset, 0.055f);
}

// The frame recipe per pixel and per tile with batched rays, every stage and mode compiled.
TEST(Conformance, FrameRecipeInstantiatesWithStubTypes) {
    const std::vector<stub::Surface> surfaces(4, stub::Surface{0.5f});
    std::vector<restir::Reservoir<stub::Sample>> history(4), out(4), scratch(4);
    restir::DiFrame<stub::Sample, stub::Surface, stub::Reprojection> frame{
        .surfaces = {surfaces.data(), 2u, 2u},
        .previous_surfaces = {surfaces.data(), 2u, 2u},
        .history = {history.data(), 2u, 2u}};
    frame.params.spatial.radius = 1.0f;
    frame.params.boiling_filter = true;
    for (restir::Reservoir<stub::Sample>& r : history) {
        r.stream(stub::Sample{2u}, 1.0f, stub::Target{}(stub::Sample{2u}, surfaces[0]), 0.5f);
        r.finalize();
    }
    const restir::DiBuffers<stub::Sample> buffers{{out.data(), 2u, 2u}, {scratch.data(), 2u, 2u}};
    const auto initial = [](restir::PixelCoord, const stub::Surface& s, stub::Rng& rng) {
        restir::Reservoir<stub::Sample> r;
        r.stream(stub::Sample{1u}, 1.0f, stub::Target{}(stub::Sample{1u}, s), next_float(rng));
        r.finalize();
        return r;
    };
    const auto rng_for = [](restir::PixelCoord, std::uint32_t) { return stub::Rng{}; };
    std::uint32_t shaded = 0u;
    const auto shade = [&](restir::PixelCoord, const restir::Reservoir<stub::Sample>&, bool) {
        ++shaded;
    };
    const auto for_each_pixel = [](const auto& body) {
        for (std::int32_t i = 0; i < 4; ++i)
            body(restir::PixelCoord{i % 2, i / 2});
    };
    const restir::DiBridge bridge{initial, restir::ReuseBridge{stub::Target{}, stub::Visibility{}},
                                  rng_for, shade};
    static_assert(restir::DiFrameBridge<decltype(bridge), stub::Sample, stub::Surface>);
    // The concept says no to a bridge whose members do not fit: candidates of another sample
    // type, a generator factory that takes no stream, a shading callback that takes no answer.
    const auto other_sample = [](restir::PixelCoord, const stub::Surface&, stub::Rng&) {
        return restir::Reservoir<float>{};
    };
    const auto no_stream = [](restir::PixelCoord) { return stub::Rng{}; };
    const auto no_answer = [](restir::PixelCoord, const restir::Reservoir<stub::Sample>&) {};
    using Reuse = restir::ReuseBridge<stub::Target, stub::Visibility>;
    static_assert(
        !restir::DiFrameBridge<restir::DiBridge<decltype(other_sample), Reuse, decltype(rng_for)>,
                               stub::Sample, stub::Surface>);
    static_assert(
        !restir::DiFrameBridge<restir::DiBridge<decltype(initial), Reuse, decltype(no_stream)>,
                               stub::Sample, stub::Surface>);
    static_assert(
        !restir::DiFrameBridge<
            restir::DiBridge<decltype(initial), Reuse, decltype(rng_for), decltype(no_answer)>,
            stub::Sample, stub::Surface>);
    restir::run_di_frame(frame, buffers, bridge, for_each_pixel);
    EXPECT_EQ(shaded, 4u);
    EXPECT_GT(out[0].candidate_count, 1u) << "the history took part";
    const auto one_tile = [](const restir::DiStep&, const auto& body) {
        body(restir::PixelTile{{0, 0}, {2, 2}});
    };
    restir::run_di_frame(
        frame, buffers,
        restir::DiBridge{initial,
                         restir::ReuseBridge{stub::Target{}, restir::OneByOne<stub::Visibility>{}},
                         rng_for, shade},
        one_tile);
    EXPECT_EQ(shaded, 8u);
}

TEST(Conformance, PhotonShooterInstantiatesWithStubTypes) {
    const stub::LightSet lights;
    restir::PhotonParams params = restir::default_photon_params();
    params.photon_count = 8u;
    params.max_bounces = 2u;
    const std::vector<restir::Vpl> vpls =
        restir::shoot_photons(lights, stub::ClosestHit{}, stub::Scatter{}, params);
    EXPECT_EQ(vpls.size(), 8u); // one deposit each, then absorbed
    const restir::UnifiedLightSet<stub::LightSet> unified{&lights, vpls.data(),
                                                          static_cast<std::uint32_t>(vpls.size())};
    EXPECT_EQ(unified.light_count(), lights.light_count() + 8u);
    EXPECT_EQ(restir::unified_light_powers(unified).size(), unified.light_count());
    const restir::Falloff falloff{};
    const glm::vec3 e =
        restir::unshadowed_irradiance(unified.sample_point(0u, glm::vec2(0.5f)), glm::vec3(0.0f),
                                      glm::vec3(0.0f, 1.0f, 0.0f), falloff);
    EXPECT_GE(e.x, 0.0f);
}

} // namespace
