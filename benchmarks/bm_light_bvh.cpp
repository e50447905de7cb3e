// Microbenchmarks of the light BVH (restir/light/light_bvh.hpp) at 1k and 1M lights: building
// it (its size in the counters), one draw (`BM_LightBvh_Sample`) and one pmf at a shading
// point, beside one draw of the power sampler (alias table) over the same lights, a draw with a
// distant light beside the tree (`BM_LightBvh_SampleWithDistant`), and `BM_RandomRead`: the
// machine's time for one read that depends on the last, at random places in arrays of 1-64 MB
// (and, `BM_RandomRead_LightBvhSize`, of the 1M-light tree's size), the floor under a draw
// whose data does not fit in cache. `BM_Environment_Sample` and `BM_Environment_Pdf`: one draw
// and one pdf of an environment light (restir/light/environment_map.hpp) at 1024 x 512 and
// 4096 x 2048, whose sampling tables (4 and 64 MiB, the `table_bytes` counter) BM_RandomRead
// also covers.
//
// The lights fill a 10^3 box: a third small area lights facing random directions, a third
// cosine point emitters (VPLs), a third isotropic points, powers over three decades. The
// shading points are a 64 x 64 grid on the floor below them (normal up), visited row by row as
// pixels of an image would be, so that consecutive draws descend through nearby nodes.
#include "restir/core/discrete_sample.hpp"
#include "restir/core/rng.hpp"
#include "restir/light/environment_map.hpp"
#include "restir/light/light_bvh.hpp"
#include "restir/sampling/alias_table.hpp"
#include "restir/sampling/infinite_lights.hpp"
#include "restir/sampling/light_sampler.hpp"
#include "restir/sampling/light_tiles.hpp"
#include "restir/vpl/unified_light_set.hpp"

#include <benchmark/benchmark.h>
#include <glm/vec2.hpp>
#include <glm/vec3.hpp>

#include <cmath>
#include <cstddef>
#include <cstdint>
#include <map>
#include <utility>
#include <vector>

namespace {

constexpr std::uint32_t kGrid = 64u;

std::vector<restir::LightBounds> make_lights(std::uint32_t count) {
    restir::Pcg32 rng = restir::make_pixel_rng(0u, 0u, 0u, 0x5eedu);
    std::vector<restir::LightBounds> lights;
    lights.reserve(count);
    for (std::uint32_t i = 0; i < count; ++i) {
        const glm::vec3 p = 10.0f * glm::vec3(next_float(rng), next_float(rng), next_float(rng));
        const float z = 2.0f * next_float(rng) - 1.0f;
        const float phi = 6.2831853f * next_float(rng);
        const float r = std::sqrt(1.0f - z * z);
        const glm::vec3 n(r * std::cos(phi), r * std::sin(phi), z);
        const float power = std::exp(6.9f * (next_float(rng) - 0.5f));
        if (i % 3u == 0u)
            lights.push_back(
                restir::area_light_bounds(p - glm::vec3(0.05f), p + glm::vec3(0.05f), n, power));
        else
            lights.push_back(
                restir::point_light_bounds(p, i % 3u == 1u ? n : glm::vec3(0.0f), power));
    }
    return lights;
}

const std::vector<restir::LightBounds>& lights(std::uint32_t count) {
    static std::map<std::uint32_t, std::vector<restir::LightBounds>> cache;
    auto it = cache.find(count);
    if (it == cache.end())
        it = cache.emplace(count, make_lights(count)).first;
    return it->second;
}

const restir::LightBvh& bvh(std::uint32_t count) {
    static std::map<std::uint32_t, restir::LightBvh> cache;
    auto it = cache.find(count);
    if (it == cache.end())
        it = cache.emplace(count, restir::LightBvh(lights(count))).first;
    return it->second;
}

restir::ShadingPoint floor_point(std::uint32_t i) {
    const float x = (static_cast<float>(i % kGrid) + 0.5f) * (10.0f / kGrid);
    const float z = (static_cast<float>(i / kGrid % kGrid) + 0.5f) * (10.0f / kGrid);
    return {glm::vec3(x, -1.0f, z), glm::vec3(0.0f, 1.0f, 0.0f)};
}

// The bytes a tree's view reads: its groups and its per-light paths.
std::size_t tree_bytes(const restir::LightBvh& tree) {
    return tree.groups().size() * sizeof(restir::LightBvhGroup) +
           tree.paths().size() * sizeof(std::uint64_t);
}

void BM_LightBvh_Build(benchmark::State& state) {
    const auto& input = lights(static_cast<std::uint32_t>(state.range(0)));
    for (auto _ : state) {
        restir::LightBvh built(input);
        benchmark::DoNotOptimize(built.groups().data());
    }
    state.SetItemsProcessed(state.iterations() * state.range(0));
    const restir::LightBvh& tree = bvh(static_cast<std::uint32_t>(state.range(0)));
    state.counters["groups"] = static_cast<double>(tree.groups().size());
    state.counters["tree_bytes"] = static_cast<double>(tree_bytes(tree));
    state.counters["bytes_per_light"] =
        static_cast<double>(tree_bytes(tree)) / static_cast<double>(state.range(0));
}
BENCHMARK(BM_LightBvh_Build)->Arg(1000)->Arg(1 << 20)->Unit(benchmark::kMillisecond);

// Draws from `sampler` at points along the floor, one per iteration; `found` counts the draws
// that found a light.
template <class Sampler>
void time_draws(benchmark::State& state, const Sampler& sampler) {
    restir::Pcg32 rng = restir::make_pixel_rng(1u, 0u, 0u, 1u);
    std::uint32_t i = 0u, found = 0u;
    for (auto _ : state) {
        const restir::DiscreteSample s = restir::sample_light(sampler, floor_point(i++), rng);
        found += s.pmf > 0.0f ? 1u : 0u;
        benchmark::DoNotOptimize(s);
    }
    state.SetItemsProcessed(state.iterations());
    state.counters["found"] = static_cast<double>(found) / static_cast<double>(state.iterations());
}

void BM_LightBvh_Sample(benchmark::State& state) {
    time_draws(state, bvh(static_cast<std::uint32_t>(state.range(0))).view());
}
BENCHMARK(BM_LightBvh_Sample)->Arg(1000)->Arg(1 << 20);

// `BM_LightBvh_Sample` with one distant light beside the tree, in the middle of the id space
// (`WithDistantLights`, sampling/infinite_lights.hpp), chosen with probability
// state.range(1) / 100: at 0 every draw descends the tree, which shows the wrapper's own cost
// (the split of u0 and the id mapping); at 10, one draw in ten takes the distant light.
void BM_LightBvh_SampleWithDistant(benchmark::State& state) {
    const auto count = static_cast<std::uint32_t>(state.range(0));
    time_draws(state, restir::with_distant_lights(bvh(count).view(), count / 2u, 1u,
                                                  static_cast<float>(state.range(1)) / 100.0f));
}
BENCHMARK(BM_LightBvh_SampleWithDistant)->Args({1000, 0})->Args({1 << 20, 0})->Args({1 << 20, 10});

// `Batch` draws at each shading point through the batch overload, whose descents advance side
// by side (the renderer's `--source bvh` draws its candidates four at a time); "per_draw" is
// the time of one.
template <std::uint32_t batch>
void BM_LightBvh_SampleBatch(benchmark::State& state) {
    const restir::LightBvhView view = bvh(static_cast<std::uint32_t>(state.range(0))).view();
    restir::Pcg32 rng = restir::make_pixel_rng(1u, 0u, 0u, 1u);
    std::uint32_t i = 0u, found = 0u;
    for (auto _ : state) {
        float u0[batch], u1[batch];
        for (std::uint32_t k = 0u; k < batch; ++k) {
            u0[k] = next_float(rng);
            u1[k] = next_float(rng);
        }
        restir::DiscreteSample s[batch];
        view.sample(floor_point(i++), u0, u1, s);
        for (const restir::DiscreteSample& d : s)
            found += d.pmf > 0.0f ? 1u : 0u;
        benchmark::DoNotOptimize(s);
    }
    state.SetItemsProcessed(state.iterations() * batch);
    state.counters["found"] =
        static_cast<double>(found) / static_cast<double>(state.iterations() * batch);
    state.counters["per_draw"] = benchmark::Counter(
        batch, benchmark::Counter::kIsIterationInvariantRate | benchmark::Counter::kInvert);
}
BENCHMARK(BM_LightBvh_SampleBatch<4>)->Arg(1000)->Arg(1 << 20);
BENCHMARK(BM_LightBvh_SampleBatch<8>)->Arg(1000)->Arg(1 << 20);

void BM_LightBvh_Pmf(benchmark::State& state) {
    const auto count = static_cast<std::uint32_t>(state.range(0));
    const restir::LightBvhView view = bvh(count).view();
    restir::Pcg32 rng = restir::make_pixel_rng(2u, 0u, 0u, 1u);
    std::uint32_t i = 0u;
    for (auto _ : state) {
        const float pmf = view.pmf(floor_point(i++), restir::uniform_index(next_float(rng), count));
        benchmark::DoNotOptimize(pmf);
    }
    state.SetItemsProcessed(state.iterations());
}
BENCHMARK(BM_LightBvh_Pmf)->Arg(1000)->Arg(1 << 20);

void BM_PowerSampler_Sample(benchmark::State& state) {
    const auto& input = lights(static_cast<std::uint32_t>(state.range(0)));
    std::vector<float> powers;
    for (const restir::LightBounds& l : input)
        powers.push_back(l.power);
    const restir::AliasTable table(powers);
    const restir::PowerLightSampler sampler{table.view()};
    restir::Pcg32 rng = restir::make_pixel_rng(3u, 0u, 0u, 1u);
    for (auto _ : state) {
        const restir::DiscreteSample s = restir::sample_light(sampler, rng);
        benchmark::DoNotOptimize(s);
    }
    state.SetItemsProcessed(state.iterations());
}
BENCHMARK(BM_PowerSampler_Sample)->Arg(1000)->Arg(1 << 20);

// A chain of dependent reads through one random cycle over 64-byte lines of an array of
// `bytes` (Sattolo's shuffle): each read waits for the one before, as the levels of a descent
// do.
void time_random_reads(benchmark::State& state, std::size_t bytes) {
    struct alignas(64) Line {
        std::uint32_t next;
    };
    const auto count = static_cast<std::uint32_t>(bytes / sizeof(Line));
    std::vector<Line> lines(count);
    std::vector<std::uint32_t> order(count);
    for (std::uint32_t i = 0u; i < count; ++i)
        order[i] = i;
    restir::Pcg32 rng = restir::make_pixel_rng(4u, 0u, 0u, 1u);
    for (std::uint32_t i = count - 1u; i > 0u; --i)
        std::swap(order[i], order[restir::uniform_index(next_float(rng), i)]);
    for (std::uint32_t i = 0u; i < count; ++i)
        lines[order[i]].next = order[(i + 1u) % count];
    std::uint32_t at = order[0];
    for (auto _ : state) {
        at = lines[at].next;
        benchmark::DoNotOptimize(at);
    }
    state.SetItemsProcessed(state.iterations());
    state.counters["bytes"] = static_cast<double>(std::size_t{count} * sizeof(Line));
}

// Random reads in state.range(0) MiB.
void BM_RandomRead(benchmark::State& state) {
    time_random_reads(state, (std::size_t{1} << 20u) * static_cast<std::size_t>(state.range(0)));
}
// 4 and 64 MiB are also the environment light's sampling tables at 1024 x 512 and 4096 x 2048.
BENCHMARK(BM_RandomRead)->Arg(1)->Arg(4)->Arg(8)->Arg(16)->Arg(32)->Arg(64);

// Random reads in as many bytes as the light BVH over state.range(0) lights (its groups and
// paths): `BM_LightBvh_Sample` of the same count over this is the draw's cost in random reads.
void BM_RandomRead_LightBvhSize(benchmark::State& state) {
    time_random_reads(state, tree_bytes(bvh(static_cast<std::uint32_t>(state.range(0)))));
}
BENCHMARK(BM_RandomRead_LightBvhSize)->Arg(1 << 20);

// A sky of width x (width / 2) texels: a gradient from a bright zenith to a dark ground, bluer
// away from the sun, and a sun of radius 0.5 degrees at 10^4 times the sky's radiance.
const restir::EnvironmentMap& environment(std::uint32_t width) {
    static std::map<std::uint32_t, restir::EnvironmentMap> cache;
    auto it = cache.find(width);
    if (it != cache.end())
        return it->second;
    const std::uint32_t height = width / 2u;
    std::vector<glm::vec3> texels(std::size_t{width} * height);
    const glm::vec3 sun = restir::equirect_direction({0.3f, 0.3f});
    for (std::uint32_t y = 0u; y < height; ++y) {
        for (std::uint32_t x = 0u; x < width; ++x) {
            const glm::vec3 d = restir::equirect_direction(
                {(static_cast<float>(x) + 0.5f) / static_cast<float>(width),
                 (static_cast<float>(y) + 0.5f) / static_cast<float>(height)});
            const float sky = d.y > 0.0f ? 0.3f + 0.7f * d.y : 0.05f;
            const float cos_to_sun = sun.x * d.x + sun.y * d.y + sun.z * d.z;
            glm::vec3 c = sky * glm::vec3(0.7f + 0.3f * cos_to_sun, 0.6f, 1.0f);
            if (cos_to_sun > 0.999962f) // cos(0.5 degrees)
                c = glm::vec3(1e4f, 9e3f, 8e3f);
            texels[std::size_t{y} * width + x] = c;
        }
    }
    return cache.emplace(width, restir::EnvironmentMap(texels, width, height)).first->second;
}

// One draw (direction, radiance and pdf) from two uniform numbers; the time is per draw.
void BM_Environment_Sample(benchmark::State& state) {
    const restir::EnvironmentMap& map = environment(static_cast<std::uint32_t>(state.range(0)));
    const restir::EnvironmentMapView view = map.view();
    restir::Pcg32 rng = restir::make_pixel_rng(5u, 0u, 0u, 1u);
    for (auto _ : state) {
        const float u0 = next_float(rng);
        const float u1 = next_float(rng);
        const restir::EnvironmentSample s = view.sample({u0, u1});
        benchmark::DoNotOptimize(s);
    }
    state.SetItemsProcessed(state.iterations());
    state.counters["table_bytes"] = static_cast<double>(map.table_bytes());
}
BENCHMARK(BM_Environment_Sample)->Arg(256)->Arg(1024)->Arg(4096);

// The pdf of a uniformly random direction (the BSDF-sampled side of MIS); the time is per call.
void BM_Environment_Pdf(benchmark::State& state) {
    const restir::EnvironmentMapView view =
        environment(static_cast<std::uint32_t>(state.range(0))).view();
    restir::Pcg32 rng = restir::make_pixel_rng(6u, 0u, 0u, 1u);
    for (auto _ : state) {
        const float z = 1.0f - 2.0f * next_float(rng);
        const float phi = 6.2831853f * next_float(rng);
        const float r = std::sqrt(1.0f - z * z);
        const float pdf = view.pdf({r * std::cos(phi), z, r * std::sin(phi)});
        benchmark::DoNotOptimize(pdf);
    }
    state.SetItemsProcessed(state.iterations());
}
BENCHMARK(BM_Environment_Pdf)->Arg(256)->Arg(1024)->Arg(4096);

// No emitters: a UnifiedLightSet whose only light is its environment.
struct NoEmitters {
    struct Point {
        glm::vec3 position{0.0f}, normal{0.0f}, radiance{0.0f};
        float area_pdf = 0.0f;
        bool is_delta = false;
    };
    std::uint32_t light_count() const { return 0u; }
    Point sample_point(std::uint32_t, glm::vec2) const { return {}; }
};

// `presample_lights` of 4096 light-tile entries that all draw the environment (a renderer's
// tile fill under an open sky): the time per entry, against a lone draw's in
// `BM_Environment_Sample`.
void BM_Environment_Presample(benchmark::State& state) {
    const NoEmitters none;
    const restir::UnifiedLightSet<NoEmitters> lights{
        &none, nullptr, 0u, environment(static_cast<std::uint32_t>(state.range(0))).view()};
    const restir::UniformLightSampler sampler{1u};
    constexpr std::uint32_t count = 4096u;
    std::vector<restir::PresampledLight> entries(count);
    std::uint32_t frame = 0u;
    for (auto _ : state) {
        ++frame;
        restir::presample_lights(
            sampler, lights, count,
            [&](std::uint32_t k) { return restir::make_pixel_rng(k, frame, 0u, 1u); },
            [&](std::uint32_t k, const restir::PresampledLight& e) { entries[k] = e; });
        benchmark::DoNotOptimize(entries.data());
        benchmark::ClobberMemory();
    }
    state.SetItemsProcessed(state.iterations() * std::int64_t{count});
}
BENCHMARK(BM_Environment_Presample)->Arg(256)->Arg(1024)->Arg(4096);

} // namespace
