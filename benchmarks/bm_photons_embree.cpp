// Photon shooting through Embree: restir::shoot_photons on the example renderer's built-in
// Cornell box, against the same rays cast bare through the same Embree BVH.
//
// The scene is pt::make_cornell_box() (its front is open, so photons can leave it), traced
// with pt::EmbreeScene as the restir::ClosestHitQuery, lit by its emissive triangles through
// pt::TriangleEmitters as the LightSet, and scattered by the renderer's Lambertian hook: the
// hit material's albedo, a cosine-sampled direction about the normal facing the photon, and
// no VPL on emitters. 100k photons with max_bounces 8 and a ray offset of 1e-4 times the
// diagonal of the scene's bounding box, traced on the calling thread (restir::SequentialFor);
// the other parameters are the defaults (16 emitter points, seed 0).
//
// BM_ShootPhotonsEmbree times one shoot_photons call; its counters `rays_per_photon` and
// `vpls_per_photon` report the rays cast and VPLs deposited per photon. BM_BareRaysEmbree
// casts the rays that call makes (origins and directions recorded once, outside the timed
// loop) with EmbreeScene::closest_hit and nothing else around them. Both report items =
// photons, so the ratio of their items_per_second is the shooter's cost relative to its bare
// ray casting.
#include "embree_scene.hpp"
#include "lights.hpp"
#include "ray_recording.hpp"
#include "scatter.hpp"
#include "scene.hpp"

#include "restir/core/rng.hpp"
#include "restir/vpl/photon_shooter.hpp"
#include "restir/vpl/vpl.hpp"

#include <benchmark/benchmark.h>
#include <glm/common.hpp>
#include <glm/geometric.hpp>
#include <glm/vec3.hpp>

#include <algorithm>
#include <cstddef>
#include <cstdint>
#include <limits>
#include <vector>

namespace {

constexpr std::uint32_t kPhotons = 100'000u;
constexpr std::uint32_t kMaxBounces = 8u;

using bench::Ray;

restir::PhotonParams photon_params(const pt::Scene& scene) {
    restir::PhotonParams params = restir::default_photon_params();
    params.photon_count = kPhotons;
    params.max_bounces = kMaxBounces;
    params.ray_offset = 1e-4f * pt::scene_size(scene);
    return params;
}

// The Cornell box, its BVH, its emitters and the photon parameters, built once.
struct CornellPhotons {
    pt::Scene scene = pt::make_cornell_box();
    pt::EmbreeScene rays{scene};
    pt::TriangleEmitters emitters{scene};
    pt::LambertianScatter scatter{&scene};
    restir::PhotonParams params = photon_params(scene);
};

const CornellPhotons& cornell() {
    static const CornellPhotons fixture;
    return fixture;
}

// Every ray that one shoot_photons pass casts, in order.
const std::vector<Ray>& recorded_rays() {
    static const std::vector<Ray> rays = [] {
        const CornellPhotons& f = cornell();
        std::vector<Ray> r;
        const bench::RecordingQuery<pt::EmbreeScene> query{&f.rays, &r};
        restir::shoot_photons(f.emitters, query, f.scatter, f.params);
        return r;
    }();
    return rays;
}

void BM_ShootPhotonsEmbree(benchmark::State& state) {
    const CornellPhotons& f = cornell();
    const std::size_t ray_count = recorded_rays().size();
    std::size_t vpl_count = 0u;
    for (auto _ : state) {
        std::vector<restir::Vpl> vpls =
            restir::shoot_photons(f.emitters, f.rays, f.scatter, f.params);
        benchmark::DoNotOptimize(vpls.data());
        vpl_count = vpls.size();
    }
    state.SetItemsProcessed(state.iterations() * kPhotons);
    state.counters["rays_per_photon"] =
        static_cast<double>(ray_count) / static_cast<double>(kPhotons);
    state.counters["vpls_per_photon"] =
        static_cast<double>(vpl_count) / static_cast<double>(kPhotons);
}
BENCHMARK(BM_ShootPhotonsEmbree)->Unit(benchmark::kMillisecond);

void BM_BareRaysEmbree(benchmark::State& state) {
    const CornellPhotons& f = cornell();
    const std::vector<Ray>& rays = recorded_rays();
    for (auto _ : state)
        bench::cast_bare(f.rays, rays);
    state.SetItemsProcessed(state.iterations() * kPhotons);
    state.counters["rays_per_photon"] =
        static_cast<double>(rays.size()) / static_cast<double>(kPhotons);
}
BENCHMARK(BM_BareRaysEmbree)->Unit(benchmark::kMillisecond);

} // namespace
