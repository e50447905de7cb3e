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
        return restir::yuksel_attenuation(offset < 0.0f ? -offset : offset, 0.05f);
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

__global__ void shade_kernel(const float* light_x, const restir::AliasEntry* entries,
                             std::uint32_t count, std::uint32_t pixels, PixelResult* out) {
    const std::uint32_t pixel = blockIdx.x * blockDim.x + threadIdx.x;
    if (pixel < pixels)
        out[pixel] = shade(pixel, light_x, entries, count);
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

    float* device_x = nullptr;
    restir::AliasEntry* device_entries = nullptr;
    PixelResult* device_out = nullptr;
    cudaMalloc(&device_x, light_count * sizeof(float));
    cudaMalloc(&device_entries, light_count * sizeof(restir::AliasEntry));
    cudaMalloc(&device_out, pixels * sizeof(PixelResult));
    cudaMemcpy(device_x, light_x.data(), light_count * sizeof(float), cudaMemcpyHostToDevice);
    cudaMemcpy(device_entries, table.entries().data(), light_count * sizeof(restir::AliasEntry),
               cudaMemcpyHostToDevice);
    shade_kernel<<<(pixels + 255) / 256, 256>>>(device_x, device_entries, light_count, pixels,
                                                device_out);
    std::vector<PixelResult> gpu(pixels);
    cudaError_t status = cudaGetLastError();
    if (status == cudaSuccess)
        status = cudaMemcpy(gpu.data(), device_out, pixels * sizeof(PixelResult),
                            cudaMemcpyDeviceToHost);
    if (status != cudaSuccess) {
        std::printf("CUDA error: %s\n", cudaGetErrorString(status));
        return 1;
    }

    std::uint32_t mismatches = 0;
    double max_relative = 0.0;
    for (std::uint32_t p = 0; p < pixels; ++p) {
        const PixelResult cpu = shade(p, light_x.data(), table.entries().data(), light_count);
        const double relative =
            std::abs(static_cast<double>(cpu.contribution_weight) - gpu[p].contribution_weight) /
            (1e-30 + std::abs(static_cast<double>(cpu.contribution_weight)));
        max_relative = relative > max_relative ? relative : max_relative;
        if (cpu.light != gpu[p].light || cpu.candidate_count != gpu[p].candidate_count ||
            relative > 1e-5) {
            if (mismatches < 3)
                std::printf(
                    "pixel %u: CPU light %u W %g M %u, GPU light %u W %g M %u\n", p, cpu.light,
                    static_cast<double>(cpu.contribution_weight), cpu.candidate_count, gpu[p].light,
                    static_cast<double>(gpu[p].contribution_weight), gpu[p].candidate_count);
            ++mismatches;
        }
    }
    std::printf("%u pixels, %u mismatches between GPU and CPU, max relative W difference %.3g\n",
                pixels, mismatches, max_relative);
    return mismatches == 0 ? 0 : 1;
}
