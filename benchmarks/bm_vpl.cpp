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
#include "restir/core/rng.hpp"
#include "restir/light/light_sample.hpp"
#include "restir/sampling/alias_table.hpp"
#include "restir/vpl/emitter_points.hpp"
#include "restir/vpl/photon_shooter.hpp"
#include "restir/vpl/vpl.hpp"

#include <benchmark/benchmark.h>
#include <glm/geometric.hpp>
#include <glm/vec2.hpp>
#include <glm/vec3.hpp>

#include <array>
#include <cstddef>
#include <cstdint>
#include <vector>

// A closest-hit record. It and its Surface functions have external linkage: surface_depth is
// named only by the Surface concept, and clang flags such internal functions as unneeded.
namespace bm_vpl {

struct BoxHit {
    glm::vec3 position{0.0f};
    glm::vec3 normal{0.0f, 1.0f, 0.0f};
    bool found = false;
};

inline glm::vec3 surface_position(const BoxHit& h) { return h.position; }
inline glm::vec3 surface_normal(const BoxHit& h) { return h.normal; }
inline float surface_depth(const BoxHit&) { return 1.0f; }
inline bool is_valid_surface(const BoxHit& h) { return h.found; }

} // namespace bm_vpl

namespace {

using bm_vpl::BoxHit;

constexpr std::uint32_t kPhotons = 100'000u;
constexpr std::uint32_t kMaxBounces = 4u;
constexpr float kAlbedo = 0.5f;
constexpr float kLightHeight = 0.99f; // Just below the ceiling at y = 1.
constexpr float kLightSize = 0.5f;

// The inside of the box [-1, 1]^3: every ray from inside hits a wall.
struct ClosedBox {
    BoxHit closest_hit(glm::vec3 origin, glm::vec3 direction) const {
        float best = 1e30f;
        int axis = -1;
        for (int a = 0; a < 3; ++a) {
            if (direction[a] == 0.0f)
                continue;
            const float wall = direction[a] > 0.0f ? 1.0f : -1.0f;
            const float t = (wall - origin[a]) / direction[a];
            if (t > 0.0f && t < best) {
                best = t;
                axis = a;
            }
        }
        if (axis < 0)
            return {};
        BoxHit hit;
        hit.position = origin + best * direction;
        hit.normal = glm::vec3(0.0f);
        hit.normal[axis] = direction[axis] > 0.0f ? -1.0f : 1.0f;
        hit.found = true;
        return hit;
    }
};

struct Ray {
    glm::vec3 origin{0.0f};
    glm::vec3 direction{0.0f};
};

// ClosedBox that appends every ray it is asked to cast to `rays`.
struct RecordingBox {
    ClosedBox box;
    std::vector<Ray>* rays = nullptr;

    BoxHit closest_hit(glm::vec3 origin, glm::vec3 direction) const {
        rays->push_back({origin, direction});
        return box.closest_hit(origin, direction);
    }
};

// Lambertian walls of one albedo, sampled by cosine: weight = albedo.
struct Lambertian {
    glm::vec3 albedo{kAlbedo};

    template <class Rng>
    restir::Scattering operator()(const BoxHit& hit, glm::vec3 incoming, Rng& rng) const {
        const glm::vec3 facing = glm::dot(hit.normal, incoming) > 0.0f ? -hit.normal : hit.normal;
        const float u0 = restir::next_float(rng);
        const float u1 = restir::next_float(rng);
        return {restir::sample_emission_direction(facing, u0, u1), albedo, albedo, true, false};
    }
};

// One square diffuse emitter centred above the origin, facing down (-y).
struct CeilingLight {
    glm::vec3 corner{-0.5f * kLightSize, kLightHeight, -0.5f * kLightSize};
    glm::vec3 edge_u{kLightSize, 0.0f, 0.0f};
    glm::vec3 edge_v{0.0f, 0.0f, kLightSize};
    glm::vec3 radiance{1.0f};

    std::uint32_t light_count() const { return 1u; }
    restir::LightSample sample_point(std::uint32_t, glm::vec2 uv) const {
        restir::LightSample s;
        s.position = corner + uv.x * edge_u + uv.y * edge_v;
        s.normal = glm::normalize(glm::cross(edge_u, edge_v));
        s.radiance = radiance;
        s.area_pdf = 1.0f / glm::length(glm::cross(edge_u, edge_v));
        s.is_delta = false;
        return s;
    }
};

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
        const RecordingBox query{ClosedBox{}, &r};
        restir::shoot_photons(CeilingLight{}, query, Lambertian{}, photon_params());
        return r;
    }();
    return rays;
}

void BM_ShootPhotons(benchmark::State& state) {
    const CeilingLight lights;
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
    for (auto _ : state) {
        glm::vec3 sum{0.0f};
        for (const Ray& ray : rays) {
            const BoxHit hit = query.closest_hit(ray.origin, ray.direction);
            if (hit.found)
                sum += hit.position;
        }
        benchmark::DoNotOptimize(sum);
    }
    state.SetItemsProcessed(state.iterations() * kPhotons);
    state.counters["rays_per_photon"] =
        static_cast<double>(rays.size()) / static_cast<double>(kPhotons);
}
BENCHMARK(BM_BareRays)->Unit(benchmark::kMillisecond);

void BM_TracePhoton(benchmark::State& state) {
    const CeilingLight lights;
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
