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

struct Ray {
    glm::vec3 origin{0.0f};
    glm::vec3 direction{0.0f};
};

// EmbreeScene that appends every ray it is asked to cast to `rays`.
struct RecordingEmbree {
    const pt::EmbreeScene* scene = nullptr;
    std::vector<Ray>* rays = nullptr;

    pt::Hit closest_hit(glm::vec3 origin, glm::vec3 direction) const {
        rays->push_back({origin, direction});
        return scene->closest_hit(origin, direction);
    }
};

// The renderer's photon scatter hook: Lambertian with the hit material's albedo, sampled by
// cosine about the normal facing the photon; emitters hold no VPL.
struct Lambertian {
    const pt::Scene* scene = nullptr;

    restir::Scattering operator()(const pt::Hit& hit, glm::vec3 incoming,
                                  restir::Pcg32& rng) const {
        const pt::Material& m = scene->materials[scene->triangle_materials[hit.triangle]];
        const glm::vec3 facing = glm::dot(hit.normal, incoming) < 0.0f ? hit.normal : -hit.normal;
        const float u0 = restir::next_float(rng);
        const float u1 = restir::next_float(rng);
        return restir::Scattering{restir::sample_emission_direction(facing, u0, u1), m.albedo,
                                  m.albedo, true, m.is_emissive()};
    }
};

// Diagonal of the bounding box of the scene's vertices.
float scene_size(const pt::Scene& scene) {
    glm::vec3 low(std::numeric_limits<float>::max());
    glm::vec3 high(-std::numeric_limits<float>::max());
    for (const glm::vec3& p : scene.positions) {
        low = glm::min(low, p);
        high = glm::max(high, p);
    }
    return std::max(glm::length(high - low), 1e-6f);
}

restir::PhotonParams photon_params(const pt::Scene& scene) {
    restir::PhotonParams params = restir::default_photon_params();
    params.photon_count = kPhotons;
    params.max_bounces = kMaxBounces;
    params.ray_offset = 1e-4f * scene_size(scene);
    return params;
}

// The Cornell box, its BVH, its emitters and the photon parameters, built once.
struct CornellPhotons {
    pt::Scene scene = pt::make_cornell_box();
    pt::EmbreeScene rays{scene};
    pt::TriangleEmitters emitters{scene};
    Lambertian scatter{&scene};
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
        const RecordingEmbree query{&f.rays, &r};
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
    for (auto _ : state) {
        glm::vec3 sum{0.0f};
        for (const Ray& ray : rays) {
            const pt::Hit hit = f.rays.closest_hit(ray.origin, ray.direction);
            if (hit.found)
                sum += hit.position;
        }
        benchmark::DoNotOptimize(sum);
    }
    state.SetItemsProcessed(state.iterations() * kPhotons);
    state.counters["rays_per_photon"] =
        static_cast<double>(rays.size()) / static_cast<double>(kPhotons);
}
BENCHMARK(BM_BareRaysEmbree)->Unit(benchmark::kMillisecond);

} // namespace
