// Microbenchmarks of streaming RIS (restir::resample_ris) and batch RIS
// (restir::resample_ris_batch over structure-of-arrays light tiles): 32 candidate lights per
// pixel, over 1k and over 1M point lights.
//
// One iteration is one pixel: a Pcg32 from make_pixel_rng(pixel, ...), a receiver point that
// changes from pixel to pixel, 32 candidates drawn by a light sampler, each scored by a
// target function that reads the light's position and power from an array, then finalize.
// Items are candidates; the time per iteration is the time of one RIS call.
#include "restir/bsdf/glossy_receiver.hpp"
#include "restir/core/discrete_sample.hpp"
#include "restir/core/math.hpp"
#include "restir/core/rng.hpp"
#include "restir/light/falloff.hpp"
#include "restir/light/receiver.hpp"
#include "restir/sampling/alias_table.hpp"
#include "restir/sampling/light_sampler.hpp"
#include "restir/sampling/light_tile_arrays.hpp"
#include "restir/sampling/light_tiles.hpp"
#include "restir/sampling/ris.hpp"
#include "restir/sampling/ris_batch.hpp"
#include "restir/sampling/tile_bsdf_candidates.hpp"

#include <benchmark/benchmark.h>
#include <glm/geometric.hpp>
#include <glm/vec3.hpp>

#include <algorithm>
#include <cstddef>
#include <cstdint>
#include <random>
#include <type_traits>
#include <vector>

namespace {

constexpr std::uint32_t kCandidates = 32u;
constexpr std::uint32_t kReceiverCount = 1024u; // Receiver points cycled through, one per pixel.
constexpr float kLightRadius = 0.05f;           // Yuksel attenuation radius.

struct PointLight {
    glm::vec3 position;
    float power;
};

// Lights scattered in a 20^3 box with powers spread over two decades.
std::vector<PointLight> make_lights(std::size_t count) {
    std::mt19937 engine(0x5eed0101u);
    std::uniform_real_distribution<float> coordinate(-10.0f, 10.0f);
    std::uniform_real_distribution<float> power(0.1f, 10.0f);
    std::vector<PointLight> lights(count);
    for (PointLight& light : lights) {
        const float x = coordinate(engine);
        const float y = coordinate(engine);
        const float z = coordinate(engine);
        light.position = glm::vec3(x, y, z);
        light.power = power(engine);
    }
    return lights;
}

const std::vector<glm::vec3>& receivers() {
    static const std::vector<glm::vec3> points = [] {
        std::mt19937 engine(0x5eed0102u);
        std::uniform_real_distribution<float> coordinate(-12.0f, 12.0f);
        std::vector<glm::vec3> p(kReceiverCount);
        for (glm::vec3& point : p) {
            const float x = coordinate(engine);
            const float y = coordinate(engine);
            const float z = coordinate(engine);
            point = glm::vec3(x, y, z);
        }
        return p;
    }();
    return points;
}

template <class Sampler>
void run_ris(benchmark::State& state, const std::vector<PointLight>& lights,
             const Sampler& sampler) {
    const PointLight* light_data = lights.data();
    const glm::vec3* receiver_points = receivers().data();
    std::uint32_t pixel = 0u;
    for (auto _ : state) {
        const glm::vec3 receiver = receiver_points[pixel % kReceiverCount];
        restir::Pcg32 rng = restir::make_pixel_rng(pixel, 0u, 0u);
        const auto draw = [&sampler](restir::Pcg32& g) {
            const float u0 = restir::next_float(g);
            const float u1 = restir::next_float(g);
            const restir::DiscreteSample s = sampler.sample(u0, u1);
            return restir::SourceSample<std::uint32_t>{s.index, s.pmf};
        };
        const auto target = [light_data, receiver](std::uint32_t id) {
            const PointLight& light = light_data[id];
            const float distance = glm::length(light.position - receiver);
            return light.power * restir::yuksel_falloff(distance, kLightRadius);
        };
        auto reservoir = restir::resample_ris(rng, kCandidates, draw, target);
        benchmark::DoNotOptimize(reservoir);
        ++pixel;
    }
    state.SetItemsProcessed(state.iterations() * static_cast<std::int64_t>(kCandidates));
}

// Lights chosen proportionally to power through an alias table (PowerLightSampler).
void BM_RIS_32Candidates(benchmark::State& state) {
    const auto count = static_cast<std::size_t>(state.range(0));
    const std::vector<PointLight> lights = make_lights(count);
    std::vector<float> powers(count);
    for (std::size_t i = 0; i < count; ++i)
        powers[i] = lights[i].power;
    const restir::AliasTable table(powers);
    const restir::PowerLightSampler sampler{table.view()};
    run_ris(state, lights, sampler);
}
BENCHMARK(BM_RIS_32Candidates)->Arg(1000)->Arg(1000000);

// Lights chosen uniformly (UniformLightSampler): no alias-table lookups.
void BM_RIS_32Candidates_Uniform(benchmark::State& state) {
    const auto count = static_cast<std::size_t>(state.range(0));
    const std::vector<PointLight> lights = make_lights(count);
    const restir::UniformLightSampler sampler{static_cast<std::uint32_t>(count)};
    run_ris(state, lights, sampler);
}
BENCHMARK(BM_RIS_32Candidates_Uniform)->Arg(1000)->Arg(1000000);

// Batch RIS on the same lights and receivers: 256 tiles of 1024 lights presampled by power
// (filled once, as a renderer does once per frame; BM_LightTiles_Fill times that), each pixel
// 32 candidates as 4 blocks of 8 consecutive entries of one tile, a receiver normal, and the
// target of `evaluate_tile_block` (isotropic points: Yuksel falloff times the receiver
// cosine, a little more work than the streaming benchmarks' target).
constexpr std::uint32_t kTileCount = 256u;
constexpr std::uint32_t kTileSize = 1024u;
constexpr std::uint32_t kBlock = 8u;

struct PointLightSet {
    const PointLight* lights;
    std::uint32_t count;
    std::uint32_t light_count() const { return count; }
    restir::LightSample sample_point(std::uint32_t id, glm::vec2) const {
        restir::LightSample p;
        p.position = lights[id].position;
        p.normal = glm::vec3(0.0f); // isotropic
        p.radiance = glm::vec3(lights[id].power);
        p.area_pdf = 1.0f;
        p.is_delta = true;
        return p;
    }
    const void* prefetch_address(std::uint32_t id) const { return lights + id; }
};

struct Tiles {
    std::vector<float> planes;
    std::vector<restir::LightSampleRef> references;
    restir::LightTileArrays view;

    Tiles(const std::vector<PointLight>& lights, const restir::PowerLightSampler& sampler)
        : planes(std::size_t{kTileCount} * kTileSize * restir::tile_plane_count),
          references(std::size_t{kTileCount} * kTileSize), view{planes.data(), references.data(),
                                                                kTileCount, kTileSize} {
        fill(lights, sampler, 0u);
    }
    void fill(const std::vector<PointLight>& lights, const restir::PowerLightSampler& sampler,
              std::uint32_t frame) const {
        const PointLightSet set{lights.data(), static_cast<std::uint32_t>(lights.size())};
        for (std::uint32_t i = 0; i < kTileCount * kTileSize; ++i) {
            restir::Pcg32 rng = restir::make_pixel_rng(i, frame, restir::RngStream::application);
            view.store(i / kTileSize, i % kTileSize, restir::presample_light(sampler, set, rng),
                       {restir::FalloffKind::yuksel, kLightRadius});
        }
    }
    // The same entries by `presample_lights`, which asks for each draw's reads ahead.
    void fill_batched(const std::vector<PointLight>& lights,
                      const restir::PowerLightSampler& sampler, std::uint32_t frame) const {
        const PointLightSet set{lights.data(), static_cast<std::uint32_t>(lights.size())};
        restir::presample_lights(
            sampler, set, kTileCount * kTileSize,
            [&](std::uint32_t i) {
                return restir::make_pixel_rng(i, frame, restir::RngStream::application);
            },
            [&](std::uint32_t i, const restir::PresampledLight& entry) {
                view.store(i / kTileSize, i % kTileSize, entry,
                           {restir::FalloffKind::yuksel, kLightRadius});
            });
    }
};

std::vector<float> light_powers(const std::vector<PointLight>& lights) {
    std::vector<float> powers(lights.size());
    for (std::size_t i = 0; i < lights.size(); ++i)
        powers[i] = lights[i].power;
    return powers;
}

// Batch RIS with the target at `receiver_at(position, normal)`'s receiver; the overload of
// evaluate_tile_block without a receiver when `receiver_at` is null (white Lambertian). With
// `Mis`, each lane also takes its MIS weight against one BSDF candidate
// (evaluate_tile_block_mis, as resample_tiles_and_bsdf's light candidates).
template <bool Mis = false, class ReceiverAt>
void batch_ris(benchmark::State& state, const ReceiverAt& receiver_at) {
    const std::vector<PointLight> lights = make_lights(static_cast<std::size_t>(state.range(0)));
    const restir::AliasTable table(light_powers(lights));
    const Tiles tiles(lights, restir::PowerLightSampler{table.view()});
    const glm::vec3* receiver_points = receivers().data();
    std::uint32_t pixel = 0u;
    for (auto _ : state) {
        const glm::vec3 position = receiver_points[pixel % kReceiverCount];
        const glm::vec3 normal = glm::normalize(receiver_points[(pixel + 1u) % kReceiverCount]);
        restir::Pcg32 rng = restir::make_pixel_rng(pixel, 0u, 0u);
        // Pixels take their candidates tile by tile, as the renderer orders its 8 x 8 pixel
        // blocks by tile (about 56 blocks of 64 pixels per tile at 1280 x 720), so that a tile
        // is read from memory once; blocks walk the tile with a random odd stride.
        const std::uint32_t tile = (pixel / 3584u) % kTileCount;
        const std::uint32_t start = rng.next_uint();
        const std::uint32_t stride = rng.next_uint() | 1u;
        auto reservoir = restir::resample_ris_batch<kBlock>(
            rng, kCandidates, [&](std::uint32_t b, restir::CandidateBlock<kBlock>& block) {
                const std::uint32_t first = ((start + b * stride) % (kTileSize / kBlock)) * kBlock;
                if constexpr (std::is_same_v<ReceiverAt, std::nullptr_t>)
                    return restir::evaluate_tile_block(tiles.view, tile, first, position, normal,
                                                       glm::vec3(1.0f), block);
                else if constexpr (Mis)
                    return restir::evaluate_tile_block_mis<kBlock>(
                        tiles.view, tile, first, receiver_at(position, normal),
                        restir::CandidateCounts{kCandidates, 1u}, block);
                else
                    return restir::evaluate_tile_block(tiles.view, tile, first,
                                                       receiver_at(position, normal), block);
            });
        benchmark::DoNotOptimize(reservoir);
        ++pixel;
    }
    state.SetItemsProcessed(state.iterations() * static_cast<std::int64_t>(kCandidates));
}

void BM_RIS_Batch(benchmark::State& state) { batch_ris(state, nullptr); }
BENCHMARK(BM_RIS_Batch)->Arg(1000)->Arg(1000000);

// The same through the receiver overload: a Lambertian receiver (the folded diffuse form) and a
// glossy one (GGX + Lambert, GlossyBsdf::evaluate_cos per candidate), seen from a fixed eye.
void BM_RIS_Batch_Lambertian(benchmark::State& state) {
    batch_ris(state, [](glm::vec3 position, glm::vec3 normal) {
        return restir::LambertianReceiver{position, normal, glm::vec3(restir::pi)};
    });
}
BENCHMARK(BM_RIS_Batch_Lambertian)->Arg(1000)->Arg(1000000);

// A GlossyReceiver seen from a fixed eye, for batch_ris.
restir::GlossyReceiver glossy_receiver_at(glm::vec3 position, glm::vec3 normal) {
    const glm::vec3 wo = glm::normalize(glm::vec3(0.0f, 20.0f, 30.0f) - position);
    return {position, normal, wo,
            restir::GlossyBsdf::from_metallic_roughness(glm::vec3(0.8f), 0.0f, 0.3f)};
}

void BM_RIS_Batch_Glossy(benchmark::State& state) { batch_ris(state, glossy_receiver_at); }
BENCHMARK(BM_RIS_Batch_Glossy)->Arg(1000)->Arg(1000000);

// The glossy lanes with their MIS weights against a BSDF candidate (the BSDF's density per
// lane beside p-hat): the light-candidate part of resample_tiles_and_bsdf.
void BM_RIS_Batch_GlossyMis(benchmark::State& state) { batch_ris<true>(state, glossy_receiver_at); }
BENCHMARK(BM_RIS_Batch_GlossyMis)->Arg(1000)->Arg(1000000);

// The selection step alone: blocks of 8 precomputed target values and inverse pdfs, one
// selection per block and its reservoir update (what batch RIS adds to the target
// evaluations). Items are candidates.
void BM_RIS_BatchSelect(benchmark::State& state) {
    constexpr std::uint32_t block_count = 4096u;
    std::vector<restir::CandidateBlock<kBlock>> blocks(block_count);
    std::mt19937 engine(0x5eed0103u);
    std::uniform_real_distribution<float> value(0.0f, 4.0f);
    for (auto& block : blocks)
        for (std::uint32_t i = 0; i < kBlock; ++i) {
            block.target[i] = i % 7u == 3u ? 0.0f : value(engine);
            block.inverse_pdf[i] = value(engine);
        }
    std::vector<float> uniforms(2u * block_count);
    std::uniform_real_distribution<float> unit(0.0f, 1.0f);
    for (float& u : uniforms)
        u = std::min(unit(engine), 0.99999994f);
    for (auto _ : state) {
        restir::Reservoir<std::uint32_t> reservoir;
        for (std::uint32_t b = 0; b < block_count; ++b) {
            const restir::BlockSelection chosen =
                restir::select_in_block(blocks[b], uniforms[2u * b]);
            reservoir.stream_group(b * kBlock + chosen.lane, chosen.weight_sum, chosen.target,
                                   kBlock, uniforms[2u * b + 1u]);
        }
        benchmark::DoNotOptimize(reservoir);
    }
    state.SetItemsProcessed(state.iterations() * static_cast<std::int64_t>(block_count * kBlock));
}
BENCHMARK(BM_RIS_BatchSelect);

// Filling 256 tiles of 1024 presampled lights (a renderer does this once per frame), by
// `Tiles::fill` or `Tiles::fill_batched`.
void fill_tiles(benchmark::State& state,
                void (Tiles::*fill)(const std::vector<PointLight>&,
                                    const restir::PowerLightSampler&, std::uint32_t) const) {
    const std::vector<PointLight> lights = make_lights(static_cast<std::size_t>(state.range(0)));
    const restir::AliasTable table(light_powers(lights));
    const restir::PowerLightSampler sampler{table.view()};
    const Tiles tiles(lights, sampler);
    std::uint32_t frame = 1u;
    for (auto _ : state)
        (tiles.*fill)(lights, sampler, frame++);
    state.SetItemsProcessed(state.iterations() * std::int64_t{kTileCount * kTileSize});
}

// One entry after another.
void BM_LightTiles_Fill(benchmark::State& state) { fill_tiles(state, &Tiles::fill); }
BENCHMARK(BM_LightTiles_Fill)->Arg(1000)->Arg(1000000)->Unit(benchmark::kMillisecond);

// `presample_lights`: a chunk's alias buckets and lights asked for ahead.
void BM_LightTiles_FillBatched(benchmark::State& state) { fill_tiles(state, &Tiles::fill_batched); }
BENCHMARK(BM_LightTiles_FillBatched)->Arg(1000)->Arg(1000000)->Unit(benchmark::kMillisecond);

} // namespace
