// The error against a reference on the GPU: the reference image as a running mean of frames,
// and a frame's mean squared error against it.
#pragma once

#include "cuda_memory.hpp"

#include <cuda_runtime.h>

#include <glm/vec3.hpp>

#include <cstddef>
#include <cstdint>

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

} // namespace bench
