// Microbenchmarks of the reuse passes: restir::temporal_resample and restir::spatial_resample
// (k = 3 and k = 5 neighbours in a 30-pixel radius) under each of the four bias corrections.
//
// The scene: a 128 x 128 image of a gently rolling height field seen from above, lit by 4096
// point lights. Normals stay within 6 degrees of vertical and view depths within about 5 % of each
// other, so every pair of valid surfaces passes the default similarity test; a small corner
// of the image is background. At this image size about a fifth of the spatial neighbour
// offsets (30-pixel radius) fall outside the image and are skipped. The camera pans one
// pixel per frame, so the previous frame's pixel is the one to the right, and the right-most
// column is disoccluded.
//
// Samples are LightSampleRef (point lights ignore uv). The target function is
// power * cos(theta) * yuksel_falloff(distance) at the surface. Visibility is a
// deterministic hash of the light id and a 0.5-unit cell of the surface position that
// blocks about a quarter of the lights: it stands in for a shadow ray, whose cost is
// excluded here so that the figures isolate the library's work. With visibility reuse (the
// default) the unbiased modes query it at the neighbours, so the counters
// `visibility_per_pixel` and `targets_per_pixel` (averages over every pixel of the image,
// counted in a separate untimed sweep) show how the work grows with k: O(k) for pairwise
// and 1/Z, O(k^2) for the balance heuristic.
//
// The reservoirs a pass reads (32-candidate RIS with lights chosen by power, then
// apply_visibility, for the current and the previous frame) are computed once, outside the
// timed loop. One iteration is one pixel, cycling through the image: a Pcg32 from
// make_pixel_rng, then one call of the pass. Items are pixels.
#include "restir/core/discrete_sample.hpp"
#include "restir/core/reservoir.hpp"
#include "restir/core/rng.hpp"
#include "restir/light/falloff.hpp"
#include "restir/light/light_sample.hpp"
#include "restir/reuse/bias_correction.hpp"
#include "restir/reuse/image_view.hpp"
#include "restir/reuse/neighbour_offsets.hpp"
#include "restir/reuse/spatial.hpp"
#include "restir/reuse/temporal.hpp"
#include "restir/reuse/visibility.hpp"
#include "restir/sampling/alias_table.hpp"
#include "restir/sampling/light_sampler.hpp"
#include "restir/sampling/ris.hpp"

#include <benchmark/benchmark.h>
#include <glm/geometric.hpp>
#include <glm/vec3.hpp>

#include <cmath>
#include <cstddef>
#include <cstdint>
#include <random>
#include <vector>

namespace {

using restir::BiasCorrection;
using restir::LightSampleRef;
using restir::PixelCoord;
using restir::Reservoir;

constexpr std::uint32_t kWidth = 128u;
constexpr std::uint32_t kHeight = 128u;
constexpr std::uint32_t kPixelCount = kWidth * kHeight; // A power of two: cycling is a mask.
constexpr std::uint32_t kLightCount = 4096u;
constexpr std::uint32_t kCandidates = 32u;   // Initial RIS candidates per pixel.
constexpr float kLightRadius = 0.05f;        // Yuksel attenuation radius.
constexpr float kPixelSize = 20.0f / 128.0f; // World units per pixel on the ground.
constexpr float kCameraHeight = 20.0f;       // Orthographic camera looking straight down.
constexpr float kShadowCell = 0.5f;          // Size of the cells the occlusion hash reads.
constexpr std::uint32_t kPreviousFrame = 0u;
constexpr std::uint32_t kCurrentFrame = 1u;

// A G-buffer texel.
struct GSurface {
    glm::vec3 position{0.0f};
    glm::vec3 normal{0.0f, 1.0f, 0.0f};
    float depth = 1.0f;
    bool valid = false;
};

glm::vec3 surface_position(const GSurface& s) { return s.position; }
glm::vec3 surface_normal(const GSurface& s) { return s.normal; }
float surface_depth(const GSurface& s) { return s.depth; }
bool is_valid_surface(const GSurface& s) { return s.valid; }

struct PointLight {
    glm::vec3 position;
    float power;
};

// Height field h(x, z) = a sin(k x) cos(k z): gradient at most a k = 0.1 (a tilt under 6
// degrees), heights within +-0.5 under a camera 20 units above.
constexpr float kBumpAmplitude = 0.5f;
constexpr float kBumpFrequency = 0.2f;

// The surface that pixel (x, y) sees at `frame`: the camera pans by one pixel per frame
// along +x, and pixels with x + y < 12 (a corner, about 0.5 % of the image) see background.
GSurface surface_seen(std::uint32_t x, std::uint32_t y, std::uint32_t frame) {
    GSurface s;
    s.valid = x + y >= 12u;
    const float wx = (static_cast<float>(x + frame) + 0.5f) * kPixelSize - 10.0f;
    const float wz = (static_cast<float>(y) + 0.5f) * kPixelSize - 10.0f;
    const float sx = std::sin(kBumpFrequency * wx);
    const float cx = std::cos(kBumpFrequency * wx);
    const float sz = std::sin(kBumpFrequency * wz);
    const float cz = std::cos(kBumpFrequency * wz);
    const float h = kBumpAmplitude * sx * cz;
    const float dhdx = kBumpAmplitude * kBumpFrequency * cx * cz;
    const float dhdz = -kBumpAmplitude * kBumpFrequency * sx * sz;
    s.position = glm::vec3(wx, h, wz);
    s.normal = glm::normalize(glm::vec3(-dhdx, 1.0f, -dhdz));
    s.depth = kCameraHeight - h;
    return s;
}

// Lights above the ground, spread a little beyond the image, powers over two decades.
std::vector<PointLight> make_lights() {
    std::mt19937 engine(0x5eed0201u);
    std::uniform_real_distribution<float> across(-12.0f, 12.0f);
    std::uniform_real_distribution<float> height(1.0f, 6.0f);
    std::uniform_real_distribution<float> power(0.1f, 10.0f);
    std::vector<PointLight> lights(kLightCount);
    for (PointLight& light : lights) {
        const float x = across(engine);
        const float y = height(engine);
        const float z = across(engine);
        light.position = glm::vec3(x, y, z);
        light.power = power(engine);
    }
    return lights;
}

// Calls of the target and visibility functions, counted outside the timed loop.
struct CallCounts {
    std::uint64_t targets = 0u;
    std::uint64_t visibility = 0u;
};

// p-hat = power * cos(theta) * attenuation at the surface, without visibility.
template <bool Counting>
struct LightTarget {
    const PointLight* lights = nullptr;
    CallCounts* counts = nullptr;

    float operator()(const LightSampleRef& sample, const GSurface& surface) const {
        if constexpr (Counting)
            ++counts->targets;
        const PointLight& light = lights[sample.light_id];
        const glm::vec3 to_light = light.position - surface_position(surface);
        const float distance = glm::length(to_light);
        const float cosine = glm::dot(surface_normal(surface), to_light) / distance;
        if (!(cosine > 0.0f))
            return 0.0f;
        return light.power * cosine * restir::yuksel_falloff(distance, kLightRadius);
    }
};

// Stand-in for a shadow ray: a light is blocked from a surface when a hash of the light id
// and the surface's 0.5-unit cell says so (about 1 in 4), so nearby surfaces mostly agree.
template <bool Counting>
struct HashedVisibility {
    CallCounts* counts = nullptr;

    bool operator()(const LightSampleRef& sample, const GSurface& surface) const {
        if constexpr (Counting)
            ++counts->visibility;
        const glm::vec3 cell = glm::floor(surface_position(surface) / kShadowCell);
        const auto cx = static_cast<std::uint64_t>(static_cast<std::int64_t>(cell.x) & 0xfffff);
        const auto cy = static_cast<std::uint64_t>(static_cast<std::int64_t>(cell.y) & 0xfffff);
        const auto cz = static_cast<std::uint64_t>(static_cast<std::int64_t>(cell.z) & 0xfffff);
        const std::uint64_t key = (cx << 40u) | (cy << 20u) | cz;
        const std::uint64_t h = restir::mix64(restir::mix64(key) ^ sample.light_id);
        return (h & 3u) != 0u;
    }
};

template <bool Counting>
using Bridge = restir::ReuseBridge<LightTarget<Counting>, HashedVisibility<Counting>>;

template <bool Counting>
Bridge<Counting> make_bridge(const PointLight* lights, CallCounts* counts) {
    return {LightTarget<Counting>{lights, counts}, HashedVisibility<Counting>{counts}, {}};
}

// Previous frame's pixel: the camera moved one pixel along +x.
struct PanReprojection {
    PixelCoord operator()(PixelCoord p) const { return {p.x + 1, p.y}; }
};

PixelCoord pixel_at(std::uint32_t index) {
    return {static_cast<std::int32_t>(index % kWidth), static_cast<std::int32_t>(index / kWidth)};
}

// Surfaces and visibility-tested initial reservoirs of two consecutive frames.
struct Scene {
    std::vector<PointLight> lights;
    std::vector<GSurface> previous_surfaces, current_surfaces;
    std::vector<Reservoir<LightSampleRef>> previous_reservoirs, current_reservoirs;
    const restir::NeighbourOffsets& offsets = restir::default_neighbour_offsets();

    restir::ImageView<const GSurface> previous_surface_view() const {
        return {previous_surfaces.data(), kWidth, kHeight};
    }
    restir::ImageView<const GSurface> current_surface_view() const {
        return {current_surfaces.data(), kWidth, kHeight};
    }
    restir::ImageView<const Reservoir<LightSampleRef>> previous_reservoir_view() const {
        return {previous_reservoirs.data(), kWidth, kHeight};
    }
    restir::ImageView<const Reservoir<LightSampleRef>> current_reservoir_view() const {
        return {current_reservoirs.data(), kWidth, kHeight};
    }
};

void render_initial(const Scene& scene, const restir::PowerLightSampler& sampler,
                    std::uint32_t frame, std::vector<GSurface>& surfaces,
                    std::vector<Reservoir<LightSampleRef>>& reservoirs) {
    surfaces.resize(kPixelCount);
    reservoirs.assign(kPixelCount, Reservoir<LightSampleRef>{});
    const LightTarget<false> target{scene.lights.data(), nullptr};
    const HashedVisibility<false> visibility{};
    for (std::uint32_t i = 0; i < kPixelCount; ++i) {
        const GSurface surface = surface_seen(i % kWidth, i / kWidth, frame);
        surfaces[i] = surface;
        if (!surface.valid)
            continue;
        restir::Pcg32 rng = restir::make_pixel_rng(i, frame, restir::RngStream::initial);
        reservoirs[i] = restir::resample_ris(
            rng, kCandidates,
            [&sampler](restir::Pcg32& g) {
                const restir::DiscreteSample s = restir::sample_light(sampler, g);
                return restir::SourceSample<LightSampleRef>{{s.index, glm::vec2(0.0f)}, s.pmf};
            },
            [&target, &surface](const LightSampleRef& x) { return target(x, surface); });
        restir::apply_visibility(reservoirs[i], surface, visibility);
    }
}

const Scene& scene() {
    static const Scene instance = [] {
        Scene s;
        s.lights = make_lights();
        std::vector<float> powers(kLightCount);
        for (std::uint32_t i = 0; i < kLightCount; ++i)
            powers[i] = s.lights[i].power;
        const restir::AliasTable table(powers);
        const restir::PowerLightSampler sampler{table.view()};
        render_initial(s, sampler, kPreviousFrame, s.previous_surfaces, s.previous_reservoirs);
        render_initial(s, sampler, kCurrentFrame, s.current_surfaces, s.current_reservoirs);
        return s;
    }();
    return instance;
}

// A pass's settings: where it looks, and how it weighs (visibility reuse with traced MIS rays).
template <class Params>
struct PassSettings {
    Params params;
    restir::ReuseParams reuse;
};

PassSettings<restir::TemporalParams> temporal_params(BiasCorrection mode) {
    return {restir::default_temporal_params(), {mode}};
}

template <bool Counting>
Reservoir<LightSampleRef> temporal_pixel(const Scene& s, std::uint32_t index,
                                         const PassSettings<restir::TemporalParams>& settings,
                                         const Bridge<Counting>& bridge) {
    restir::Pcg32 rng = restir::make_pixel_rng(index, kCurrentFrame, restir::RngStream::temporal);
    return restir::temporal_resample(pixel_at(index), s.current_reservoirs[index],
                                     s.current_surfaces[index], s.previous_reservoir_view(),
                                     s.previous_surface_view(), PanReprojection{}, settings.params,
                                     settings.reuse, kCurrentFrame, bridge, rng);
}

template <bool Counting>
Reservoir<LightSampleRef> spatial_pixel(const Scene& s, std::uint32_t index,
                                        const PassSettings<restir::SpatialParams>& settings,
                                        const Bridge<Counting>& bridge) {
    restir::Pcg32 rng = restir::make_pixel_rng(index, kCurrentFrame, restir::RngStream::spatial);
    return restir::spatial_resample(pixel_at(index), s.current_reservoir_view(),
                                    s.current_surface_view(), settings.params, settings.reuse,
                                    bridge, rng, s.offsets);
}

// Runs `pass(index, bridge)` once for every pixel with counting functors and reports the
// average calls per pixel.
template <class Pass>
void count_calls(benchmark::State& state, const Scene& s, const Pass& pass) {
    CallCounts counts;
    const Bridge<true> bridge = make_bridge<true>(s.lights.data(), &counts);
    for (std::uint32_t i = 0; i < kPixelCount; ++i) {
        auto result = pass(i, bridge);
        benchmark::DoNotOptimize(result);
    }
    state.counters["targets_per_pixel"] =
        static_cast<double>(counts.targets) / static_cast<double>(kPixelCount);
    state.counters["visibility_per_pixel"] =
        static_cast<double>(counts.visibility) / static_cast<double>(kPixelCount);
}

void BM_Temporal(benchmark::State& state, BiasCorrection mode) {
    const Scene& s = scene();
    const PassSettings<restir::TemporalParams> params = temporal_params(mode);
    const Bridge<false> bridge = make_bridge<false>(s.lights.data(), nullptr);
    std::uint32_t pixel = 0u;
    for (auto _ : state) {
        auto result = temporal_pixel(s, pixel & (kPixelCount - 1u), params, bridge);
        benchmark::DoNotOptimize(result);
        ++pixel;
    }
    state.SetItemsProcessed(state.iterations());
    count_calls(state, s, [&s, &params](std::uint32_t index, const Bridge<true>& b) {
        return temporal_pixel(s, index, params, b);
    });
}
BENCHMARK_CAPTURE(BM_Temporal, none, BiasCorrection::none);
BENCHMARK_CAPTURE(BM_Temporal, one_over_z, BiasCorrection::one_over_z);
BENCHMARK_CAPTURE(BM_Temporal, balance_heuristic, BiasCorrection::balance_heuristic);
BENCHMARK_CAPTURE(BM_Temporal, pairwise, BiasCorrection::pairwise);

// range(0) = k, the neighbours tried per pixel.
void BM_Spatial(benchmark::State& state, BiasCorrection mode) {
    const Scene& s = scene();
    PassSettings<restir::SpatialParams> params{restir::default_spatial_params(), {mode}};
    params.params.neighbour_count = static_cast<std::uint32_t>(state.range(0));
    const Bridge<false> bridge = make_bridge<false>(s.lights.data(), nullptr);
    std::uint32_t pixel = 0u;
    for (auto _ : state) {
        auto result = spatial_pixel(s, pixel & (kPixelCount - 1u), params, bridge);
        benchmark::DoNotOptimize(result);
        ++pixel;
    }
    state.SetItemsProcessed(state.iterations());
    count_calls(state, s, [&s, &params](std::uint32_t index, const Bridge<true>& b) {
        return spatial_pixel(s, index, params, b);
    });
}
BENCHMARK_CAPTURE(BM_Spatial, none, BiasCorrection::none)->ArgName("k")->Arg(3)->Arg(5);
BENCHMARK_CAPTURE(BM_Spatial, one_over_z, BiasCorrection::one_over_z)->ArgName("k")->Arg(3)->Arg(5);
BENCHMARK_CAPTURE(BM_Spatial, balance_heuristic, BiasCorrection::balance_heuristic)
    ->ArgName("k")
    ->Arg(3)
    ->Arg(5);
BENCHMARK_CAPTURE(BM_Spatial, pairwise, BiasCorrection::pairwise)->ArgName("k")->Arg(3)->Arg(5);

} // namespace
