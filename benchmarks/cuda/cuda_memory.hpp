// di_pipeline's CUDA helpers: an error check that ends the run, and device buffers allocated,
// uploaded from and downloaded to host memory.
#pragma once

#include <cuda_runtime.h>

#include <algorithm>
#include <cstddef>
#include <cstdio>
#include <cstdlib>
#include <vector>

namespace bench {

inline void check_cuda(cudaError_t status, const char* what) {
    if (status != cudaSuccess) {
        std::fprintf(stderr, "di_pipeline: %s: %s\n", what, cudaGetErrorString(status));
        std::exit(1);
    }
}

template <class T>
T* device_alloc(std::size_t n) {
    T* p = nullptr;
    check_cuda(cudaMalloc(&p, std::max<std::size_t>(n, 1) * sizeof(T)), "cudaMalloc");
    return p;
}
template <class T>
T* upload(const std::vector<T>& host) {
    T* p = device_alloc<T>(host.size());
    check_cuda(cudaMemcpy(p, host.data(), host.size() * sizeof(T), cudaMemcpyHostToDevice),
               "upload");
    return p;
}
template <class T>
void download(T* host, const T* device, std::size_t n) {
    check_cuda(cudaMemcpy(host, device, n * sizeof(T), cudaMemcpyDeviceToHost), "download");
}

} // namespace bench
