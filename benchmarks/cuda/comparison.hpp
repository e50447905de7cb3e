// The CPU/GPU comparison of di_pipeline: per pass, how many of the GPU's outputs are
// bit-identical to the CPU's and how many differ by more than the float tolerance; each pass's
// output is then copied over so that the next pass starts from the same input on both sides.
#pragma once

#include "cuda_memory.hpp"
#include "di_pipeline.hpp"
#include "frame_work.hpp"

#include <glm/vec3.hpp>

#include <algorithm>
#include <cmath>
#include <cstddef>
#include <cstdint>
#include <cstring>
#include <vector>

namespace bench {

using box::Context;
using box::Pass;

// Mismatches between the CPU's and the GPU's output of one pass.
struct Agreement {
    std::uint64_t items = 0, mismatches = 0, identical = 0;
    double max_relative = 0.0;
    void add(bool same_bits, bool agrees, double relative) {
        ++items;
        identical += same_bits ? 1u : 0u;
        mismatches += agrees ? 0u : 1u;
        max_relative = std::max(max_relative, relative);
    }
};

// Float tolerance: relative 1e-5 (above `floor`, absolute 1e-5 floor).
inline constexpr double tolerance = 1e-5;
inline double relative_difference(float a, float b, double floor = 0.0) {
    const double d = std::fabs(static_cast<double>(a) - static_cast<double>(b));
    const double scale = std::max(
        {std::fabs(static_cast<double>(a)), std::fabs(static_cast<double>(b)), floor, 1e-30});
    return d == 0.0 ? 0.0 : d / scale;
}
inline double relative_difference(glm::vec3 a, glm::vec3 b, double floor = 0.0) {
    return std::max({relative_difference(a.x, b.x, floor), relative_difference(a.y, b.y, floor),
                     relative_difference(a.z, b.z, floor)});
}

inline bool same_bits(float a, float b) { return std::memcmp(&a, &b, sizeof a) == 0; }
inline bool same_bits(glm::vec3 a, glm::vec3 b) { return std::memcmp(&a, &b, sizeof a) == 0; }

inline void compare_item(Agreement& agreement, const box::Reservoir& cpu,
                         const box::Reservoir& gpu) {
    // Field by field: the sample's padding bytes are not part of the result.
    const bool same = cpu.sample.light_id == gpu.sample.light_id &&
                      same_bits(cpu.sample.position, gpu.sample.position) &&
                      same_bits(cpu.sample.normal, gpu.sample.normal) &&
                      same_bits(cpu.sample.intensity, gpu.sample.intensity) &&
                      same_bits(cpu.sample.falloff, gpu.sample.falloff) &&
                      same_bits(cpu.weight_sum, gpu.weight_sum) &&
                      same_bits(cpu.target_value, gpu.target_value) &&
                      same_bits(cpu.contribution_weight, gpu.contribution_weight) &&
                      cpu.candidate_count == gpu.candidate_count;
    const double relative =
        std::max({relative_difference(cpu.contribution_weight, gpu.contribution_weight),
                  relative_difference(cpu.target_value, gpu.target_value),
                  relative_difference(cpu.weight_sum, gpu.weight_sum),
                  relative_difference(cpu.sample.position, gpu.sample.position, 1.0)});
    agreement.add(same,
                  cpu.sample.light_id == gpu.sample.light_id &&
                      cpu.candidate_count == gpu.candidate_count && relative <= tolerance,
                  relative);
}
inline void compare_item(Agreement& agreement, const box::Texel& cpu, const box::Texel& gpu) {
    const double relative = std::max({relative_difference(cpu.position, gpu.position, 1.0),
                                      relative_difference(cpu.normal, gpu.normal, 1.0),
                                      relative_difference(cpu.depth, gpu.depth, 1.0)});
    agreement.add(std::memcmp(&cpu, &gpu, sizeof(cpu)) == 0,
                  cpu.material == gpu.material && relative <= tolerance, relative);
}
inline void compare_item(Agreement& agreement, std::uint8_t cpu, std::uint8_t gpu) {
    agreement.add(cpu == gpu, cpu == gpu, cpu == gpu ? 0.0 : 1.0);
}
inline void compare_item(Agreement& agreement, glm::vec3 cpu, glm::vec3 gpu) {
    const double relative = relative_difference(cpu, gpu, 1e-3);
    agreement.add(std::memcmp(&cpu, &gpu, sizeof(cpu)) == 0, relative <= tolerance, relative);
}
inline void compare_item(Agreement& agreement, const box::Packed& cpu, const box::Packed& gpu) {
    const double relative =
        std::max({relative_difference(cpu.contribution_weight, gpu.contribution_weight),
                  relative_difference(cpu.target_value, gpu.target_value),
                  relative_difference(cpu.position, gpu.position, 1.0)});
    agreement.add(std::memcmp(&cpu, &gpu, sizeof(cpu)) == 0,
                  cpu.light_id == gpu.light_id && cpu.candidate_count == gpu.candidate_count &&
                      relative <= tolerance,
                  relative);
}

// Downloads the GPU's `device` buffer, compares it with the CPU's `host`, then makes the CPU's
// copy the GPU's (so that the next pass starts from the same input on both).
template <class T>
void settle(Agreement& agreement, T* host, const T* device, std::size_t n,
            std::vector<T>& scratch) {
    scratch.resize(n);
    download(scratch.data(), device, n);
    for (std::size_t i = 0; i < n; ++i)
        compare_item(agreement, host[i], scratch[i]);
    std::copy(scratch.begin(), scratch.end(), host);
}

struct Comparison {
    Agreement passes[box::pass_count]; // by row
    std::vector<box::Texel> texels;
    std::vector<box::Reservoir> reservoirs;
    std::vector<box::Packed> packed;
    std::vector<glm::vec3> colors;
    std::vector<std::uint8_t> answers; // the shadow rays'
    std::vector<float> planes;

    // The outputs of `w`: CPU's in `h`, GPU's in `d`.
    void work(const Work& w, const Context& h, const Context& d) {
        Agreement& a = passes[static_cast<std::uint32_t>(w.row)];
        const std::size_t pixels = std::size_t{h.width} * h.height;
        switch (w.row) {
        case Pass::gbuffer:
            settle(a, h.surfaces, d.surfaces, pixels, texels);
            break;
        case Pass::tiles: {
            const std::size_t floats = h.tiles.plane_float_count();
            planes.resize(floats);
            download(planes.data(), d.tiles.planes, floats);
            for (std::size_t i = 0; i < floats; ++i) {
                const double r = relative_difference(h.tiles.planes[i], planes[i], 1e-3);
                a.add(std::memcmp(&h.tiles.planes[i], &planes[i], 4) == 0, r <= tolerance, r);
            }
            std::copy(planes.begin(), planes.end(), h.tiles.planes);
            std::vector<restir::LightSampleRef> refs(h.tiles.tile_count * h.tiles.tile_size);
            download(refs.data(), d.tiles.references, refs.size());
            for (std::size_t i = 0; i < refs.size(); ++i) {
                const bool same = refs[i].light_id == h.tiles.references[i].light_id &&
                                  refs[i].uv == h.tiles.references[i].uv;
                a.add(same, same, same ? 0.0 : 1.0);
            }
            std::copy(refs.begin(), refs.end(), h.tiles.references);
            break;
        }
        case Pass::shadow_rays:
            settle(a, h.visible, d.visible, pixels, answers);
            break;
        default:
            // The buffer the step wrote (finish: `out`, in place), and the shading's outputs.
            settle(a, h.buffers()[w.step.output].data, d.buffers()[w.step.output].data, pixels,
                   reservoirs);
            if (w.row == Pass::finish) {
                settle(a, h.image, d.image, pixels, colors);
                if (h.packed)
                    settle(a, h.packed_history, d.packed_history, pixels, packed);
            }
            break;
        }
    }
};

} // namespace bench
