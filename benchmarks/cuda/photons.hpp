// The Cornell box's VPLs shot on the GPU: restir::trace_photon per thread, collected in photon
// order as restir::shoot_photons returns them on the CPU.
#pragma once

#include "cuda_memory.hpp"
#include "di_pipeline.hpp"

#include <cuda_runtime.h>

#include <cstddef>
#include <cstdint>
#include <vector>

namespace bench {

inline constexpr std::uint32_t photon_bounces = 8; // restir-render's

static __global__ void photon_kernel(restir::PhotonSource source, restir::PhotonParams params,
                                     const box::Scene* scene, restir::Vpl* out,
                                     std::uint32_t* counts) {
    const std::uint32_t photon = blockIdx.x * blockDim.x + threadIdx.x;
    if (photon < params.photon_count)
        counts[photon] = restir::trace_photon(photon, source, *scene, box::Lambertian{}, params,
                                              out + std::size_t{photon} * params.max_bounces);
}

// VPLs of `params.photon_count` photons shot on the GPU, in photon order (as shoot_photons
// returns them); `ms` gets the kernel's time.
inline std::vector<restir::Vpl> shoot_on_gpu(const restir::PhotonEmitters& emitters,
                                             restir::PhotonParams params, const box::Scene* scene,
                                             float& ms) {
    const std::vector<restir::AliasEntry> entries(emitters.table().entries().begin(),
                                                  emitters.table().entries().end());
    restir::EmitterPoint* points = upload(emitters.points());
    restir::AliasEntry* table = upload(entries);
    restir::Vpl* slots =
        device_alloc<restir::Vpl>(std::size_t{params.photon_count} * params.max_bounces);
    std::uint32_t* counts = device_alloc<std::uint32_t>(params.photon_count);
    cudaEvent_t start, stop;
    cudaEventCreate(&start);
    cudaEventCreate(&stop);
    cudaEventRecord(start);
    photon_kernel<<<(params.photon_count + 127) / 128, 128>>>(
        {points, {table, emitters.table().size()}}, params, scene, slots, counts);
    cudaEventRecord(stop);
    check_cuda(cudaEventSynchronize(stop), "photon kernel");
    cudaEventElapsedTime(&ms, start, stop);
    std::vector<restir::Vpl> all(std::size_t{params.photon_count} * params.max_bounces);
    std::vector<std::uint32_t> n(params.photon_count);
    download(all.data(), slots, all.size());
    download(n.data(), counts, n.size());
    std::vector<restir::Vpl> vpls;
    for (std::uint32_t p = 0; p < params.photon_count; ++p)
        for (std::uint32_t b = 0; b < n[p]; ++b)
            vpls.push_back(all[std::size_t{p} * params.max_bounces + b]);
    cudaFree(points);
    cudaFree(table);
    cudaFree(slots);
    cudaFree(counts);
    cudaEventDestroy(start);
    cudaEventDestroy(stop);
    return vpls;
}

} // namespace bench
