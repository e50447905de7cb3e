// Microbenchmarks of streaming RIS (restir::resample_ris): 32 candidate lights per pixel,
// over 1k and over 1M point lights.
//
// One iteration is one pixel: a Pcg32 from make_pixel_rng(pixel, ...), a receiver point that
// changes from pixel to pixel, 32 candidates drawn by a light sampler, each scored by a
// target function that reads the light's position and power from an array, then finalize.
// Items are candidates; the time per iteration is the time of one RIS call.
#include "restir/core/discrete_sample.hpp"
#include "restir/core/rng.hpp"
#include "restir/light/attenuation.hpp"
#include "restir/light/light_sampler.hpp"
#include "restir/sampling/alias_table.hpp"
#include "restir/sampling/ris.hpp"

#include <benchmark/benchmark.h>
#include <glm/geometric.hpp>
#include <glm/vec3.hpp>

#include <cstddef>
#include <cstdint>
#include <random>
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
            return light.power * restir::yuksel_attenuation(distance, kLightRadius);
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

} // namespace
