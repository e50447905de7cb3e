// Single rays against batches through Embree: pt::EmbreeScene::closest_hit / occluded one ray
// at a time, and closest_hits / occluded_segments on the 64 rays of an 8 x 8 pixel block.
//
// The scene is pt::make_cornell_box() seen through its own camera at 1280 x 720, one ray per
// pixel centre, the pixels taken block by block as the renderer does. BM_PrimaryRays_* cast
// these primary rays. BM_ShadowRays_* cast, for every primary hit, the segment to a random
// point of the ceiling light, both ends pushed 1e-4 times the scene size off their surfaces
// (restir::LightVisibility's offsets); a block's segments form one batch. All run on the
// calling thread and report items = rays. Setup checks that the batches give the single-ray
// results for every ray (same hit triangle, positions within 1e-5 relative, same blocked
// flags); the *_Packet benchmarks fail when they do not.
#include "camera.hpp"
#include "embree_scene.hpp"
#include "lights.hpp"
#include "scene.hpp"

#include "restir/core/rng.hpp"

#include <benchmark/benchmark.h>
#include <glm/geometric.hpp>
#include <glm/vec2.hpp>
#include <glm/vec3.hpp>

#include <algorithm>
#include <cmath>
#include <cstddef>
#include <cstdint>
#include <span>
#include <vector>

namespace {

constexpr std::uint32_t kWidth = 1280u;
constexpr std::uint32_t kHeight = 720u;
constexpr std::uint32_t kBlock = 8u;

// Block b of `all`, given the blocks' starts `begin` (and the end).
template <class T>
std::span<T> block(std::span<T> all, const std::vector<std::size_t>& begin, std::size_t b) {
    return all.subspan(begin[b], begin[b + 1] - begin[b]);
}

// The Cornell box, its BVH and every ray of the benchmarks, in pixel-block order; block b's
// rays are [begin[b], begin[b + 1]).
struct CornellRays {
    pt::Scene scene = pt::make_cornell_box();
    pt::EmbreeScene rays{scene};
    pt::TriangleEmitters emitters{scene};
    glm::vec3 eye{0.0f};
    std::vector<glm::vec3> directions;
    std::vector<std::size_t> primary_begin;
    std::vector<glm::vec3> shadow_from, shadow_to;
    std::vector<std::size_t> shadow_begin;
    bool primary_match = true, shadow_match = true;

    CornellRays() {
        const pt::Camera camera(*scene.camera, kWidth, kHeight);
        eye = camera.position();
        for (std::uint32_t by = 0; by < kHeight; by += kBlock)
            for (std::uint32_t bx = 0; bx < kWidth; bx += kBlock) {
                primary_begin.push_back(directions.size());
                for (std::uint32_t y = by; y < std::min(kHeight, by + kBlock); ++y)
                    for (std::uint32_t x = bx; x < std::min(kWidth, bx + kBlock); ++x)
                        directions.push_back(camera.direction(
                            {static_cast<float>(x) + 0.5f, static_cast<float>(y) + 0.5f}));
            }
        primary_begin.push_back(directions.size());

        // Primary hits one ray at a time, then the shadow segments from them.
        const float offset = 1e-4f * pt::scene_size(scene);
        restir::Pcg32 rng;
        std::vector<pt::Hit> single(directions.size());
        for (std::size_t b = 0; b + 1 < primary_begin.size(); ++b) {
            shadow_begin.push_back(shadow_from.size());
            for (std::size_t i = primary_begin[b]; i < primary_begin[b + 1]; ++i) {
                single[i] = rays.closest_hit(eye, directions[i]);
                if (!single[i].found)
                    continue;
                const std::uint32_t light = rng.next_uint() % emitters.light_count();
                const restir::LightSample point =
                    emitters.sample_point(light, {rng.next_unit_float(), rng.next_unit_float()});
                const glm::vec3 towards = point.position - single[i].position;
                const float side = glm::dot(single[i].normal, towards) < 0.0f ? -1.0f : 1.0f;
                const float light_side = glm::dot(point.normal, towards) > 0.0f ? -1.0f : 1.0f;
                shadow_from.push_back(single[i].position + single[i].normal * (side * offset));
                shadow_to.push_back(point.position + point.normal * (light_side * offset));
            }
        }
        shadow_begin.push_back(shadow_from.size());

        // The batches must agree with the single rays.
        std::vector<pt::Hit> batched(directions.size());
        for (std::size_t b = 0; b + 1 < primary_begin.size(); ++b)
            rays.closest_hits(eye, primary(b), block(std::span(batched), primary_begin, b));
        for (std::size_t i = 0; i < directions.size(); ++i) {
            const pt::Hit& s = single[i];
            const pt::Hit& p = batched[i];
            primary_match =
                primary_match && s.found == p.found &&
                (!s.found ||
                 (s.primitive == p.primitive &&
                  glm::length(s.position - p.position) <= 1e-5f * glm::length(s.position) &&
                  std::abs(s.distance - p.distance) <= 1e-5f * s.distance && s.normal == p.normal));
        }
        std::vector<std::uint8_t> blocked(shadow_from.size());
        for (std::size_t b = 0; b + 1 < shadow_begin.size(); ++b)
            rays.occluded_segments(from(b), to(b), block(std::span(blocked), shadow_begin, b));
        for (std::size_t i = 0; i < shadow_from.size(); ++i)
            shadow_match =
                shadow_match && (blocked[i] != 0u) == rays.occluded(shadow_from[i], shadow_to[i]);
    }

    std::size_t blocks() const { return primary_begin.size() - 1u; }
    std::span<const glm::vec3> primary(std::size_t b) const {
        return block(std::span(directions), primary_begin, b);
    }
    std::span<const glm::vec3> from(std::size_t b) const {
        return block(std::span(shadow_from), shadow_begin, b);
    }
    std::span<const glm::vec3> to(std::size_t b) const {
        return block(std::span(shadow_to), shadow_begin, b);
    }
};

const CornellRays& cornell() {
    static const CornellRays fixture;
    return fixture;
}

void BM_PrimaryRays_Single(benchmark::State& state) {
    const CornellRays& f = cornell();
    std::vector<pt::Hit> hits(f.directions.size());
    for (auto _ : state) {
        for (std::size_t i = 0; i < f.directions.size(); ++i)
            hits[i] = f.rays.closest_hit(f.eye, f.directions[i]);
        benchmark::DoNotOptimize(hits.data());
        benchmark::ClobberMemory();
    }
    state.SetItemsProcessed(state.iterations() * static_cast<std::int64_t>(hits.size()));
}
BENCHMARK(BM_PrimaryRays_Single)->Unit(benchmark::kMillisecond);

void BM_PrimaryRays_Packet(benchmark::State& state) {
    const CornellRays& f = cornell();
    if (!f.primary_match)
        state.SkipWithError("batched primary hits differ from single-ray hits");
    std::vector<pt::Hit> hits(f.directions.size());
    for (auto _ : state) {
        for (std::size_t b = 0; b < f.blocks(); ++b)
            f.rays.closest_hits(f.eye, f.primary(b), block(std::span(hits), f.primary_begin, b));
        benchmark::DoNotOptimize(hits.data());
        benchmark::ClobberMemory();
    }
    state.SetItemsProcessed(state.iterations() * static_cast<std::int64_t>(hits.size()));
}
BENCHMARK(BM_PrimaryRays_Packet)->Unit(benchmark::kMillisecond);

void BM_ShadowRays_Single(benchmark::State& state) {
    const CornellRays& f = cornell();
    std::vector<std::uint8_t> blocked(f.shadow_from.size());
    for (auto _ : state) {
        for (std::size_t i = 0; i < blocked.size(); ++i)
            blocked[i] = f.rays.occluded(f.shadow_from[i], f.shadow_to[i]) ? 1u : 0u;
        benchmark::DoNotOptimize(blocked.data());
        benchmark::ClobberMemory();
    }
    state.SetItemsProcessed(state.iterations() * static_cast<std::int64_t>(blocked.size()));
}
BENCHMARK(BM_ShadowRays_Single)->Unit(benchmark::kMillisecond);

void BM_ShadowRays_Packet(benchmark::State& state) {
    const CornellRays& f = cornell();
    if (!f.shadow_match)
        state.SkipWithError("batched occlusion differs from single-ray occlusion");
    std::vector<std::uint8_t> blocked(f.shadow_from.size());
    for (auto _ : state) {
        for (std::size_t b = 0; b < f.blocks(); ++b)
            f.rays.occluded_segments(f.from(b), f.to(b),
                                     block(std::span(blocked), f.shadow_begin, b));
        benchmark::DoNotOptimize(blocked.data());
        benchmark::ClobberMemory();
    }
    state.SetItemsProcessed(state.iterations() * static_cast<std::int64_t>(blocked.size()));
}
BENCHMARK(BM_ShadowRays_Packet)->Unit(benchmark::kMillisecond);

} // namespace
