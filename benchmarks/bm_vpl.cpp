// Microbenchmarks of the VPL photon shooter: restir::shoot_photons over a whole budget, the
// same rays cast bare through the scene's ray query, and restir::trace_photon for one photon.
//
// The scene: the inside of the closed box [-1, 1]^3 (an analytic slab test, so every ray from
// inside hits a wall), Lambertian walls of albedo 0.5 sampled by cosine, and one square
// emitter of side 0.5 just below the ceiling (y = 0.99), facing down; the emitter is not part
// of the geometry. Photons use the default parameters (16 emitter points, seed 0) with
// max_bounces 4, so a photon casts 1 + 1/2 + 1/4 + 1/8 = 1.875 rays on average and leaves a
// VPL at every hit; the counters `rays_per_photon` and `vpls_per_photon` report the measured
// values.
//
// BM_ShootPhotons times one shoot_photons call of 100k photons (emitter points, alias table,
// tracing in batches and compaction into the returned vector) on the calling thread.
// BM_BareRays casts the rays that call makes (origins and directions recorded once, outside
// the timed loop) through the same query, with nothing else around them. Both report items =
// photons, so the ratio of their items_per_second is the shooter's cost relative to its bare
// ray casting. BM_TracePhoton traces one photon per iteration from a prepared PhotonSource
// into a scratch array, without the batching and compaction of shoot_photons.
#include "ray_recording.hpp"
#include "vpl/box_scene.hpp" // the photon tests' scene: tests/vpl/box_scene.hpp

#include <restir/restir.hpp>

#include <benchmark/benchmark.h>
#include <glm/vec3.hpp>

#include <array>
#include <cstddef>
#include <cstdint>
#include <vector>

namespace {

using bench::Ray;
using restir::test::ClosedBox;
using restir::test::Lambertian;
using restir::test::RectangleLights;

constexpr std::uint32_t kPhotons = 100'000u;
constexpr std::uint32_t kMaxBounces = 4u;

// One square emitter of side 0.5 just below the ceiling, facing down.
RectangleLights ceiling_light() {
    return {{restir::test::ceiling_light(0.99f, 0.5f, glm::vec3(1.0f))}};
}

restir::PhotonParams photon_params() {
    restir::PhotonParams params = restir::default_photon_params();
    params.photon_count = kPhotons;
    params.max_bounces = kMaxBounces;
    return params;
}

// Every ray that one shoot_photons pass casts, in order.
const std::vector<Ray>& recorded_rays() {
    static const std::vector<Ray> rays = [] {
        std::vector<Ray> r;
        const ClosedBox box;
        const bench::RecordingQuery<ClosedBox> query{&box, &r};
        restir::shoot_photons(ceiling_light(), query, Lambertian{}, photon_params());
        return r;
    }();
    return rays;
}

void BM_ShootPhotons(benchmark::State& state) {
    const RectangleLights lights = ceiling_light();
    const ClosedBox query;
    const Lambertian scatter;
    const restir::PhotonParams params = photon_params();
    std::size_t vpl_count = 0u;
    for (auto _ : state) {
        std::vector<restir::Vpl> vpls = restir::shoot_photons(lights, query, scatter, params);
        benchmark::DoNotOptimize(vpls.data());
        vpl_count = vpls.size();
    }
    state.SetItemsProcessed(state.iterations() * kPhotons);
    state.counters["rays_per_photon"] =
        static_cast<double>(recorded_rays().size()) / static_cast<double>(kPhotons);
    state.counters["vpls_per_photon"] =
        static_cast<double>(vpl_count) / static_cast<double>(kPhotons);
}
BENCHMARK(BM_ShootPhotons)->Unit(benchmark::kMillisecond);

void BM_BareRays(benchmark::State& state) {
    const std::vector<Ray>& rays = recorded_rays();
    const ClosedBox query;
    for (auto _ : state)
        bench::cast_bare(query, rays);
    state.SetItemsProcessed(state.iterations() * kPhotons);
    state.counters["rays_per_photon"] =
        static_cast<double>(rays.size()) / static_cast<double>(kPhotons);
}
BENCHMARK(BM_BareRays)->Unit(benchmark::kMillisecond);

void BM_TracePhoton(benchmark::State& state) {
    const RectangleLights lights = ceiling_light();
    const ClosedBox query;
    const Lambertian scatter;
    const restir::PhotonParams params = photon_params();
    const restir::PhotonEmitters emitters(lights, params.points_per_emitter, params.seed);
    const restir::PhotonSource source = emitters.source();
    std::array<restir::Vpl, kMaxBounces> scratch{};
    std::uint32_t photon = 0u;
    for (auto _ : state) {
        std::uint32_t written =
            restir::trace_photon(photon, source, query, scatter, params, scratch.data());
        benchmark::DoNotOptimize(written);
        benchmark::DoNotOptimize(scratch.data());
        if (++photon == kPhotons)
            photon = 0u;
    }
    state.SetItemsProcessed(state.iterations());
}
BENCHMARK(BM_TracePhoton);

} // namespace
