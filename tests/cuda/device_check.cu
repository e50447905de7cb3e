// Runs the core templates in a CUDA kernel and on the host with the same inputs and checks
// that both choose the same samples with the same weights. Needs a GPU: run by hand with
//   nvcc -std=c++20 -Iinclude -fmad=false -diag-suppress 20012 tests/cuda/device_check.cu
#include <restir/restir.hpp>

#include <cmath>
#include <cstdint>
#include <cstdio>
#include <vector>

namespace {

struct Candidate {
    std::uint32_t light;
};

struct PowerDraw {
    restir::PowerLightSampler sampler;
    RESTIR_HOST_DEVICE restir::SourceSample<Candidate> operator()(restir::Pcg32& rng) const {
        const restir::DiscreteSample c = restir::sample_light(sampler, rng);
        return {{c.index}, c.pmf};
    }
};

struct FalloffTarget {
    const float* light_x;
    float receiver_x;
    RESTIR_HOST_DEVICE float operator()(const Candidate& c) const {
        const float offset = light_x[c.light] - receiver_x;
        return restir::yuksel_falloff(offset < 0.0f ? -offset : offset, 0.05f);
    }
};

struct PixelResult {
    std::uint32_t light;
    float contribution_weight;
    std::uint32_t candidate_count;
};

RESTIR_HOST_DEVICE PixelResult shade(std::uint32_t pixel, const float* light_x,
                                     const restir::AliasEntry* entries, std::uint32_t count) {
    restir::Pcg32 rng = restir::make_pixel_rng(pixel, 3u, 1u, 2024u);
    const PowerDraw draw{restir::PowerLightSampler{restir::AliasTableView{entries, count}}};
    const FalloffTarget target{light_x, static_cast<float>(pixel % 97u) / 97.0f};
    auto reservoir = restir::resample_ris(rng, 32u, draw, target);
    auto neighbour = restir::resample_ris(rng, 32u, draw, target);
    neighbour.cap_candidate_count(20u);
    reservoir.merge(neighbour, target(neighbour.sample), next_float(rng));
    reservoir.finalize();
    return {reservoir.sample.light, reservoir.contribution_weight, reservoir.candidate_count};
}

// Reuse: a 64 x 64 image of points on a line under the same lights; each pixel's reservoir
// comes from `shade`'s RIS, then spatial reuse under the balance heuristic and pairwise MIS.
struct LinePoint {
    float x;
    bool valid;
};
RESTIR_HOST_DEVICE glm::vec3 surface_position(const LinePoint& p) { return {p.x, 0.0f, 0.0f}; }
RESTIR_HOST_DEVICE glm::vec3 surface_normal(const LinePoint&) { return {0.0f, 0.0f, 1.0f}; }
RESTIR_HOST_DEVICE float surface_depth(const LinePoint&) { return 1.0f; }
RESTIR_HOST_DEVICE bool is_valid_surface(const LinePoint& p) { return p.valid; }

struct LineTarget {
    const float* light_x;
    RESTIR_HOST_DEVICE float operator()(const Candidate& c, const LinePoint& p) const {
        return FalloffTarget{light_x, p.x}(c);
    }
};
struct HalfBlocked {
    RESTIR_HOST_DEVICE bool operator()(const Candidate& c, const LinePoint& p) const {
        return (c.light + static_cast<std::uint32_t>(surface_position(p).x * 64.0f)) % 4u != 0u;
    }
};

constexpr std::uint32_t image_side = 64;

RESTIR_HOST_DEVICE PixelResult reuse_pixel(std::uint32_t pixel, const float* light_x,
                                           const restir::Reservoir<Candidate>* reservoirs,
                                           const LinePoint* points, bool pairwise) {
    const restir::ImageView<const restir::Reservoir<Candidate>> view{reservoirs, image_side,
                                                                     image_side};
    const restir::ImageView<const LinePoint> surfaces{points, image_side, image_side};
    restir::SpatialParams params = restir::default_spatial_params();
    params.radius = 5.0f;
    params.neighbour_count = 4u;
    const restir::ReuseParams reuse{pairwise ? restir::BiasCorrection::pairwise
                                             : restir::BiasCorrection::balance_heuristic};
    const restir::ReuseBridge bridge{LineTarget{light_x}, HalfBlocked{}};
    restir::Pcg32 rng = restir::make_pixel_rng(pixel, 4u, 2u, 2024u);
    const restir::PixelCoord p{static_cast<std::int32_t>(pixel % image_side),
                               static_cast<std::int32_t>(pixel / image_side)};
    // The library's offset table: constant memory on the device, static storage on the host.
    const auto r = restir::spatial_resample(p, view, surfaces, params, reuse, bridge, rng);
    return {r.sample.light, r.contribution_weight, r.candidate_count};
}

__global__ void reuse_kernel(const float* light_x, const restir::Reservoir<Candidate>* reservoirs,
                             const LinePoint* points, bool pairwise, PixelResult* out) {
    const std::uint32_t pixel = blockIdx.x * blockDim.x + threadIdx.x;
    if (pixel < image_side * image_side)
        out[pixel] = reuse_pixel(pixel, light_x, reservoirs, points, pairwise);
}

__global__ void shade_kernel(const float* light_x, const restir::AliasEntry* entries,
                             std::uint32_t count, std::uint32_t pixels, PixelResult* out) {
    const std::uint32_t pixel = blockIdx.x * blockDim.x + threadIdx.x;
    if (pixel < pixels)
        out[pixel] = shade(pixel, light_x, entries, count);
}

// Photons: one square emitter over a floor of albedo 0.6, traced on the GPU and the CPU.
struct FloorHit {
    glm::vec3 position;
    bool found;
};
RESTIR_HOST_DEVICE glm::vec3 surface_position(const FloorHit& h) { return h.position; }
RESTIR_HOST_DEVICE glm::vec3 surface_normal(const FloorHit&) { return {0.0f, 1.0f, 0.0f}; }
[[maybe_unused]] RESTIR_HOST_DEVICE float surface_depth(const FloorHit&) { return 1.0f; }
RESTIR_HOST_DEVICE bool is_valid_surface(const FloorHit& h) { return h.found; }

struct Floor {
    RESTIR_HOST_DEVICE FloorHit closest_hit(glm::vec3 origin, glm::vec3 direction) const {
        const float t = -origin.y / direction.y;
        const glm::vec3 p = origin + t * direction;
        return {p, t > 0.0f && p.x * p.x < 4.0f && p.z * p.z < 4.0f};
    }
};

struct Matte {
    template <class Rng>
    RESTIR_HOST_DEVICE restir::Scattering operator()(const FloorHit& hit, glm::vec3,
                                                     Rng& rng) const {
        const float u0 = next_float(rng);
        const float u1 = next_float(rng);
        return {restir::sample_diffuse_direction(surface_normal(hit), u0, u1), glm::vec3(0.6f),
                glm::vec3(0.6f), true, false};
    }
};

struct SquareLight {
    RESTIR_HOST_DEVICE std::uint32_t light_count() const { return 1u; }
    RESTIR_HOST_DEVICE restir::LightSample sample_point(std::uint32_t, glm::vec2 uv) const {
        restir::LightSample s;
        s.position = {uv.x - 0.5f, 1.0f, uv.y - 0.5f};
        s.normal = {0.0f, -1.0f, 0.0f};
        s.radiance = glm::vec3(1.0f);
        s.area_pdf = 1.0f;
        return s;
    }
};

constexpr std::uint32_t photon_bounces = 3;

__global__ void photon_kernel(restir::PhotonSource source, restir::PhotonParams params,
                              restir::Vpl* out, std::uint32_t* counts) {
    const std::uint32_t photon = blockIdx.x * blockDim.x + threadIdx.x;
    if (photon < params.photon_count)
        counts[photon] = restir::trace_photon(photon, source, Floor{}, Matte{}, params,
                                              out + photon * photon_bounces);
}

// Light BVH: a draw at a shading point (a region for every fourth pixel) and `pmf` of the
// drawn light there, on the GPU and the CPU.
struct BvhResult {
    std::uint32_t light; // 0xffffffff: no light
    float draw_pmf;      // the pmf the descent returned
    float pmf;           // LightBvhView::pmf of the drawn light
};

RESTIR_HOST_DEVICE BvhResult bvh_pixel(std::uint32_t pixel, restir::LightBvhView bvh) {
    restir::Pcg32 rng = restir::make_pixel_rng(pixel, 5u, 1u, 2024u);
    const float x = static_cast<float>(pixel % 256u) / 256.0f;
    const float z = static_cast<float>(pixel / 256u % 256u) / 256.0f;
    const restir::ShadingPoint at{glm::vec3(x, 0.0f, z), glm::vec3(0.0f, 1.0f, 0.0f),
                                  pixel % 4u == 0u ? 0.05f : 0.0f};
    const float u0 = next_float(rng);
    const float u1 = next_float(rng);
    const restir::DiscreteSample c = bvh.sample(at, u0, u1);
    if (!(c.pmf > 0.0f))
        return {0xffffffffu, 0.0f, 0.0f};
    return {c.index, c.pmf, bvh.pmf(at, c.index)};
}

__global__ void bvh_kernel(restir::LightBvhView bvh, std::uint32_t pixels, BvhResult* out) {
    const std::uint32_t pixel = blockIdx.x * blockDim.x + threadIdx.x;
    if (pixel < pixels)
        out[pixel] = bvh_pixel(pixel, bvh);
}

// ReSTIR GI: a 64 x 64 floor of Lambertian points whose reservoirs hold path samples on a quad
// above it (some glossy, which the reconnection shift refuses to move, some above a ceiling
// that hides them), reused spatially through the reconnection shift with traced visibility,
// on the GPU and the CPU. A sample's origin pixel, plus one, rides in its source pdf.
struct GiPoint {
    glm::vec3 position;
    glm::vec3 albedo;
};
RESTIR_HOST_DEVICE glm::vec3 surface_position(const GiPoint& p) { return p.position; }
RESTIR_HOST_DEVICE glm::vec3 surface_normal(const GiPoint&) { return {0.0f, 1.0f, 0.0f}; }
RESTIR_HOST_DEVICE float surface_depth(const GiPoint&) { return 1.0f; }
RESTIR_HOST_DEVICE bool is_valid_surface(const GiPoint&) { return true; }

struct GiTarget {
    RESTIR_HOST_DEVICE float operator()(const restir::PathSample& x, const GiPoint& p) const {
        const restir::LambertianReceiver receiver{p.position, surface_normal(p), p.albedo};
        return restir::fold_channels<restir::ChannelNorm::sum>(
            restir::path_sample_radiance(x, receiver));
    }
};

struct BlockedAbove {
    float ceiling;
    RESTIR_HOST_DEVICE bool occluded(glm::vec3, glm::vec3 to) const { return to.y > ceiling; }
};

RESTIR_HOST_DEVICE PixelResult
gi_reuse_pixel(std::uint32_t pixel, const restir::Reservoir<restir::PathSample>* reservoirs,
               const GiPoint* points, restir::BiasCorrection mode) {
    const restir::ImageView<const restir::Reservoir<restir::PathSample>> view{
        reservoirs, image_side, image_side};
    const restir::ImageView<const GiPoint> surfaces{points, image_side, image_side};
    restir::SpatialParams params = restir::default_spatial_params();
    params.radius = 5.0f;
    params.neighbour_count = 4u;
    const BlockedAbove query{1.4f};
    const restir::ReuseBridge bridge{GiTarget{},
                                     restir::ReconnectionVisibility<BlockedAbove>{&query, 1e-4f},
                                     restir::AnyMaterial{}, restir::ReconnectionShift{}};
    restir::Pcg32 rng = restir::make_pixel_rng(pixel, 6u, 2u, 2024u);
    const restir::PixelCoord p{static_cast<std::int32_t>(pixel % image_side),
                               static_cast<std::int32_t>(pixel / image_side)};
    const auto r = restir::spatial_resample(
        p, view, surfaces, params, restir::ReuseParams{mode, restir::ReuseVisibility::traced},
        bridge, rng);
    return {r.has_sample() ? static_cast<std::uint32_t>(r.sample.source_pdf) : 0u,
            r.contribution_weight, r.candidate_count};
}

__global__ void gi_reuse_kernel(const restir::Reservoir<restir::PathSample>* reservoirs,
                                const GiPoint* points, restir::BiasCorrection mode,
                                PixelResult* out) {
    const std::uint32_t pixel = blockIdx.x * blockDim.x + threadIdx.x;
    if (pixel < image_side * image_side)
        out[pixel] = gi_reuse_pixel(pixel, reservoirs, points, mode);
}

// Compares GPU results with the same function run on the CPU; returns the mismatch count.
template <class CpuResult>
std::uint32_t compare(const char* name, const std::vector<PixelResult>& gpu, CpuResult&& cpu_at) {
    std::uint32_t mismatches = 0;
    double max_relative = 0.0;
    double count_sum = 0.0;
    for (std::uint32_t p = 0; p < gpu.size(); ++p) {
        const PixelResult cpu = cpu_at(p);
        count_sum += cpu.candidate_count;
        const double relative =
            std::abs(static_cast<double>(cpu.contribution_weight) - gpu[p].contribution_weight) /
            (1e-30 + std::abs(static_cast<double>(cpu.contribution_weight)));
        max_relative = relative > max_relative ? relative : max_relative;
        if (cpu.light != gpu[p].light || cpu.candidate_count != gpu[p].candidate_count ||
            relative > 1e-5) {
            if (mismatches < 3)
                std::printf("%s pixel %u: CPU light %u W %g M %u, GPU light %u W %g M %u\n", name,
                            p, cpu.light, static_cast<double>(cpu.contribution_weight),
                            cpu.candidate_count, gpu[p].light,
                            static_cast<double>(gpu[p].contribution_weight),
                            gpu[p].candidate_count);
            ++mismatches;
        }
    }
    std::printf("%s: %zu pixels (mean M %.1f), %u mismatches between GPU and CPU, max relative W "
                "difference %.3g\n",
                name, gpu.size(), count_sum / static_cast<double>(gpu.size()), mismatches,
                max_relative);
    return mismatches;
}

template <class T>
T* upload(const std::vector<T>& host) {
    T* device = nullptr;
    cudaMalloc(&device, host.size() * sizeof(T));
    cudaMemcpy(device, host.data(), host.size() * sizeof(T), cudaMemcpyHostToDevice);
    return device;
}

bool download(std::vector<PixelResult>& host, const PixelResult* device) {
    cudaError_t status = cudaGetLastError();
    if (status == cudaSuccess)
        status = cudaMemcpy(host.data(), device, host.size() * sizeof(PixelResult),
                            cudaMemcpyDeviceToHost);
    if (status != cudaSuccess)
        std::printf("CUDA error: %s\n", cudaGetErrorString(status));
    return status == cudaSuccess;
}

} // namespace

int main() {
    constexpr std::uint32_t light_count = 4096, pixels = 1 << 16;
    std::vector<float> light_x(light_count), power(light_count);
    restir::Pcg32 setup = restir::make_pixel_rng(0u, 0u, 0u, 1u);
    for (std::uint32_t i = 0; i < light_count; ++i) {
        light_x[i] = next_float(setup);
        power[i] = 0.01f + next_float(setup);
    }
    const restir::AliasTable table(power);
    const std::vector<restir::AliasEntry> entries(table.entries().begin(), table.entries().end());
    float* device_x = upload(light_x);
    restir::AliasEntry* device_entries = upload(entries);

    // RIS and a merge, per pixel.
    std::vector<PixelResult> gpu(pixels);
    PixelResult* device_out = nullptr;
    cudaMalloc(&device_out, pixels * sizeof(PixelResult));
    shade_kernel<<<(pixels + 255) / 256, 256>>>(device_x, device_entries, light_count, pixels,
                                                device_out);
    if (!download(gpu, device_out))
        return 1;
    std::uint32_t mismatches = compare("RIS", gpu, [&](std::uint32_t p) {
        return shade(p, light_x.data(), entries.data(), light_count);
    });

    // Spatial reuse over reservoirs made on the host.
    constexpr std::uint32_t image_pixels = image_side * image_side;
    std::vector<LinePoint> points(image_pixels);
    std::vector<restir::Reservoir<Candidate>> reservoirs(image_pixels);
    const PowerDraw draw{restir::PowerLightSampler{table.view()}};
    for (std::uint32_t p = 0; p < image_pixels; ++p) {
        points[p] = {static_cast<float>(p % 97u) / 97.0f, p % 13u != 0u};
        restir::Pcg32 rng = restir::make_pixel_rng(p, 4u, 1u, 2024u);
        reservoirs[p] =
            restir::resample_ris(rng, 8u, draw, FalloffTarget{light_x.data(), points[p].x});
        restir::apply_visibility(reservoirs[p], points[p], HalfBlocked{});
    }
    const restir::Reservoir<Candidate>* device_reservoirs = upload(reservoirs);
    const LinePoint* device_points = upload(points);
    for (const bool pairwise : {false, true}) {
        std::vector<PixelResult> reused(image_pixels);
        reuse_kernel<<<(image_pixels + 127) / 128, 128>>>(device_x, device_reservoirs,
                                                          device_points, pairwise, device_out);
        if (!download(reused, device_out))
            return 1;
        mismatches += compare(
            pairwise ? "spatial reuse, pairwise" : "spatial reuse, balance heuristic", reused,
            [&](std::uint32_t p) {
                return reuse_pixel(p, light_x.data(), reservoirs.data(), points.data(), pairwise);
            });
    }

    // ReSTIR GI: path samples reused through the reconnection shift, every bias correction.
    std::vector<GiPoint> gi_points(image_pixels);
    std::vector<restir::Reservoir<restir::PathSample>> gi_reservoirs(image_pixels);
    for (std::uint32_t p = 0; p < image_pixels; ++p) {
        restir::Pcg32 rng = restir::make_pixel_rng(p, 6u, 1u, 2024u);
        gi_points[p] = {glm::vec3(static_cast<float>(p % image_side) / 32.0f - 1.0f, 0.0f,
                                  static_cast<float>(p / image_side) / 32.0f - 1.0f),
                        glm::vec3(0.3f + 0.5f * next_float(rng), 0.6f, 0.4f)};
        restir::Reservoir<restir::PathSample>& r = gi_reservoirs[p];
        r.candidate_count = 1u + restir::uniform_index(next_float(rng), 4u);
        if (p % 11u == 0u)
            continue; // the bounce found nothing
        restir::PathSample& x = r.sample;
        x.visible_point = gi_points[p].position;
        x.sample_point = glm::vec3(4.0f * next_float(rng) - 2.0f, p % 5u == 0u ? 1.5f : 1.0f,
                                   4.0f * next_float(rng) - 2.0f);
        x.sample_normal = glm::vec3(0.0f, -1.0f, 0.0f);
        x.radiance = glm::vec3(next_float(rng), next_float(rng), 1.0f);
        x.source_pdf = static_cast<float>(p + 1u);
        x.sample_roughness = p % 7u == 0u ? 0.3f : 1.0f;
        r.target_value = GiTarget{}(x, gi_points[p]);
        r.contribution_weight = 0.5f + next_float(rng);
        r.weight_sum =
            r.contribution_weight * r.target_value * static_cast<float>(r.candidate_count);
    }
    const restir::Reservoir<restir::PathSample>* device_gi_reservoirs = upload(gi_reservoirs);
    const GiPoint* device_gi_points = upload(gi_points);
    for (const restir::BiasCorrection mode :
         {restir::BiasCorrection::none, restir::BiasCorrection::one_over_z,
          restir::BiasCorrection::balance_heuristic, restir::BiasCorrection::pairwise}) {
        const char* names[] = {"GI reuse, 1/M", "GI reuse, 1/Z", "GI reuse, balance heuristic",
                               "GI reuse, pairwise"};
        std::vector<PixelResult> reused(image_pixels);
        gi_reuse_kernel<<<(image_pixels + 127) / 128, 128>>>(device_gi_reservoirs, device_gi_points,
                                                             mode, device_out);
        if (!download(reused, device_out))
            return 1;
        mismatches += compare(names[static_cast<int>(mode)], reused, [&](std::uint32_t p) {
            return gi_reuse_pixel(p, gi_reservoirs.data(), gi_points.data(), mode);
        });
    }

    // Light BVH over 4096 point lights above the unit square, facing down or isotropic.
    std::vector<restir::LightBounds> bounds(light_count);
    for (std::uint32_t i = 0; i < light_count; ++i) {
        const glm::vec3 position(next_float(setup), 0.05f + next_float(setup), next_float(setup));
        bounds[i] = restir::point_light_bounds(
            position, i % 3u == 0u ? glm::vec3(0.0f) : glm::vec3(0.0f, -1.0f, 0.0f), power[i]);
    }
    const restir::LightBvh bvh(bounds);
    restir::LightBvhView device_bvh = bvh.view(); // the root's box with it
    device_bvh.groups = upload(bvh.groups());
    device_bvh.paths = upload(bvh.paths());
    BvhResult* device_bvh_out = nullptr;
    cudaMalloc(&device_bvh_out, pixels * sizeof(BvhResult));
    bvh_kernel<<<(pixels + 127) / 128, 128>>>(device_bvh, pixels, device_bvh_out);
    std::vector<BvhResult> bvh_gpu(pixels);
    if (cudaMemcpy(bvh_gpu.data(), device_bvh_out, pixels * sizeof(BvhResult),
                   cudaMemcpyDeviceToHost) != cudaSuccess) {
        std::printf("CUDA error: %s\n", cudaGetErrorString(cudaGetLastError()));
        return 1;
    }
    std::uint32_t bvh_mismatches = 0, drawn = 0;
    for (std::uint32_t p = 0; p < pixels; ++p) {
        const BvhResult cpu = bvh_pixel(p, bvh.view());
        const BvhResult& g = bvh_gpu[p];
        drawn += cpu.light != 0xffffffffu ? 1u : 0u;
        // The same light, and both pmfs equal to the CPU's to 1e-5.
        const auto close = [](float a, float b) {
            return std::abs(static_cast<double>(a) - b) <= 1e-5 * std::abs(static_cast<double>(a));
        };
        if (cpu.light != g.light || !close(cpu.draw_pmf, g.draw_pmf) || !close(cpu.pmf, g.pmf)) {
            if (bvh_mismatches < 3)
                std::printf("light BVH pixel %u: CPU light %u pmf %g / %g, GPU light %u pmf %g / "
                            "%g\n",
                            p, cpu.light, static_cast<double>(cpu.draw_pmf),
                            static_cast<double>(cpu.pmf), g.light, static_cast<double>(g.draw_pmf),
                            static_cast<double>(g.pmf));
            ++bvh_mismatches;
        }
    }
    std::printf("light BVH: %u shading points (%u drew a light), %u mismatches between GPU and "
                "CPU\n",
                pixels, drawn, bvh_mismatches);
    mismatches += bvh_mismatches;

    // Photons: GPU VPLs against shoot_photons on the CPU. Only sin, cos and sqrt may differ
    // in their last bits between the two, so positions and fluxes agree to 1e-4.
    restir::PhotonParams params = restir::default_photon_params();
    params.photon_count = 1u << 16u;
    params.max_bounces = photon_bounces;
    params.seed = 3u;
    const SquareLight square;
    const std::vector<restir::Vpl> cpu_vpls =
        restir::shoot_photons(square, Floor{}, Matte{}, params);
    const restir::PhotonEmitters emitters(square, params.points_per_emitter, params.seed);
    const std::vector<restir::AliasEntry> photon_entries(emitters.table().entries().begin(),
                                                         emitters.table().entries().end());
    const restir::EmitterPoint* device_emitter_points = upload(emitters.points());
    const restir::AliasEntry* device_photon_entries = upload(photon_entries);
    restir::Vpl* device_vpls = nullptr;
    std::uint32_t* device_counts = nullptr;
    cudaMalloc(&device_vpls, params.photon_count * photon_bounces * sizeof(restir::Vpl));
    cudaMalloc(&device_counts, params.photon_count * sizeof(std::uint32_t));
    const restir::PhotonSource device_source{device_emitter_points,
                                             {device_photon_entries, emitters.table().size()}};
    photon_kernel<<<params.photon_count / 256, 256>>>(device_source, params, device_vpls,
                                                      device_counts);
    std::vector<restir::Vpl> slots(params.photon_count * photon_bounces);
    std::vector<std::uint32_t> counts(params.photon_count);
    if (cudaMemcpy(slots.data(), device_vpls, slots.size() * sizeof(restir::Vpl),
                   cudaMemcpyDeviceToHost) != cudaSuccess ||
        cudaMemcpy(counts.data(), device_counts, counts.size() * sizeof(std::uint32_t),
                   cudaMemcpyDeviceToHost) != cudaSuccess) {
        std::printf("CUDA error: %s\n", cudaGetErrorString(cudaGetLastError()));
        return 1;
    }
    std::vector<restir::Vpl> gpu_vpls;
    for (std::uint32_t p = 0; p < params.photon_count; ++p)
        for (std::uint32_t b = 0; b < counts[p]; ++b)
            gpu_vpls.push_back(slots[p * photon_bounces + b]);
    std::uint32_t vpl_mismatches = cpu_vpls.size() == gpu_vpls.size() ? 0u : 1u;
    double max_difference = 0.0;
    for (std::size_t i = 0; i < cpu_vpls.size() && i < gpu_vpls.size(); ++i)
        for (int c = 0; c < 3; ++c) {
            const double dp = std::abs(static_cast<double>(cpu_vpls[i].position[c]) -
                                       static_cast<double>(gpu_vpls[i].position[c]));
            const double df = std::abs(static_cast<double>(cpu_vpls[i].flux[c]) -
                                       static_cast<double>(gpu_vpls[i].flux[c])) /
                              static_cast<double>(cpu_vpls[i].flux[c]);
            max_difference = std::fmax(max_difference, std::fmax(dp, df));
            if (dp > 1e-4 || df > 1e-4)
                ++vpl_mismatches;
        }
    std::printf("photons: %u photons, %zu VPLs on the CPU, %zu on the GPU, %u mismatches, max "
                "difference %.3g\n",
                params.photon_count, cpu_vpls.size(), gpu_vpls.size(), vpl_mismatches,
                max_difference);
    mismatches += vpl_mismatches;
    return mismatches == 0 ? 0 : 1;
}
