// The error against a reference on the GPU: the reference image as a running mean of frames,
// and a frame's mean squared error against it.
#pragma once

#include "cuda_memory.hpp"

#include <cuda_runtime.h>

#include <glm/vec3.hpp>

#include <array>
#include <cstddef>
#include <cstdint>
#include <vector>

namespace bench {

static __global__ void add_image(glm::vec3* sum, const glm::vec3* image, std::uint32_t pixels,
                                 float scale) {
    const std::uint32_t i = blockIdx.x * blockDim.x + threadIdx.x;
    if (i < pixels)
        sum[i] += scale * image[i];
}

// Adds the squared error of `image` against `reference`, averaged over the channels, to `*sum`.
static __global__ void add_squared_error(double* sum, const glm::vec3* image,
                                         const glm::vec3* reference, std::uint32_t pixels) {
    const std::uint32_t i = blockIdx.x * blockDim.x + threadIdx.x;
    double e = 0.0;
    if (i < pixels) {
        const glm::vec3 d = image[i] - reference[i];
        e = (static_cast<double>(d.x) * d.x + static_cast<double>(d.y) * d.y +
             static_cast<double>(d.z) * d.z) /
            3.0;
    }
    for (int offset = 16; offset > 0; offset /= 2)
        e += __shfl_down_sync(0xffffffffu, e, offset);
    if (threadIdx.x % 32u == 0u)
        atomicAdd(sum, e);
}

// The per-frame MSE of `image` against `reference`.
inline double frame_mse(double* sum, const glm::vec3* image, const glm::vec3* reference,
                        std::size_t pixels) {
    check_cuda(cudaMemset(sum, 0, sizeof(double)), "MSE");
    add_squared_error<<<(static_cast<std::uint32_t>(pixels) + 255u) / 256u, 256u>>>(
        sum, image, reference, static_cast<std::uint32_t>(pixels));
    double total = 0.0;
    download(&total, sum, 1);
    return total / static_cast<double>(pixels);
}

// The lags of `ErrorCorrelation`, in pixels.
inline constexpr std::array<std::uint32_t, 5> correlation_lags{1u, 2u, 4u, 8u, 16u};

// The normalised autocorrelation of a frame's error e = mean over channels of (image -
// reference) at each lag along x and along y: sum e(p) e(p + lag) / sum e(p)^2. Noise that
// pixels share (blotches) shows as large values at lags within the blotches.
struct ErrorCorrelation {
    std::array<double, correlation_lags.size()> x{}, y{};
};

inline ErrorCorrelation error_correlation(const glm::vec3* image, const glm::vec3* reference,
                                          std::uint32_t width, std::uint32_t height) {
    const std::size_t pixels = std::size_t{width} * height;
    std::vector<glm::vec3> a(pixels), b(pixels);
    download(a.data(), image, pixels);
    download(b.data(), reference, pixels);
    std::vector<double> e(pixels);
    double energy = 0.0;
    for (std::size_t i = 0; i < pixels; ++i) {
        const glm::vec3 d = a[i] - b[i];
        e[i] = (static_cast<double>(d.x) + d.y + d.z) / 3.0;
        energy += e[i] * e[i];
    }
    ErrorCorrelation c;
    if (!(energy > 0.0))
        return c;
    for (std::size_t k = 0; k < correlation_lags.size(); ++k) {
        const std::uint32_t lag = correlation_lags[k];
        double sx = 0.0, sy = 0.0;
        for (std::uint32_t y = 0; y < height; ++y)
            for (std::uint32_t x = 0; x < width; ++x) {
                const std::size_t i = std::size_t{y} * width + x;
                if (x + lag < width)
                    sx += e[i] * e[i + lag];
                if (y + lag < height)
                    sy += e[i] * e[i + std::size_t{lag} * width];
            }
        c.x[k] = sx / energy;
        c.y[k] = sy / energy;
    }
    return c;
}

} // namespace bench
