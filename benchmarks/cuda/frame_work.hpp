// The work of a frame on both sides: the passes that are not the recipe's (G-buffer, light
// tiles) and the recipe's steps as CUDA kernels and launches (one kernel per stage) and as CPU
// loops over threads, and the list of a frame's work (`frame_work`) with `run_work` running an
// item of it on either side.
#pragma once

#include "cuda_memory.hpp"
#include "di_pipeline.hpp"

#include <cuda_runtime.h>

#include <algorithm>
#include <cstdint>
#include <thread>
#include <vector>

namespace bench {

using box::Context;
using box::Pass;
using restir::DiStage;
using restir::DiStep;

// The items a pass that is not the recipe's covers: pixels, or the light tiles' entries as one
// row.
RESTIR_HOST_DEVICE inline std::uint32_t items_x(Pass p, const Context& c) {
    return p == Pass::tiles ? c.tiles.tile_count * c.tiles.tile_size : c.width;
}
RESTIR_HOST_DEVICE inline std::uint32_t items_y(Pass p, const Context& c) {
    return p == Pass::tiles ? 1u : c.height;
}

template <Pass P>
__global__ void pass_kernel(Context c) {
    const std::uint32_t x = blockIdx.x * blockDim.x + threadIdx.x;
    const std::uint32_t y = blockIdx.y * blockDim.y + threadIdx.y;
    if (x < items_x(P, c) && y < items_y(P, c))
        box::run_item<P>(c, x, y);
}

// At most this many threads a block of a step kernel (--block), and at least this many such
// blocks an SM can hold: the register budget (96 a thread) that keeps 20 warps resident, not
// the 16 that the candidates and spatial kernels' own register counts would leave
// (docs/performance.md, "GPU").
inline constexpr std::uint32_t step_block_threads = 128u;
inline constexpr std::uint32_t step_blocks_per_sm = 5u;

// One step of the recipe over the pixels, compiled for stage `Stage` only; the frame by value
// (a kernel parameter: no copy in local memory).
// (The initial stage's kernel also for the candidates' `Lanes`, `Context::lanes`.)
template <DiStage Stage, std::uint32_t Lanes, class Frame>
__global__ void __launch_bounds__(step_block_threads, step_blocks_per_sm)
    step_kernel(Frame frame, DiStep step, Context c) {
    const std::uint32_t x = blockIdx.x * blockDim.x + threadIdx.x;
    const std::uint32_t y = blockIdx.y * blockDim.y + threadIdx.y;
    if (x < c.width && y < c.height)
        box::run_step<Stage, Lanes>(frame, step, c, x, y);
}

// `f.template operator()<L>()` with L = c.lanes (8, 4 or 2) as a constant.
template <class F>
decltype(auto) with_lanes(const Context& c, F&& f) {
    switch (c.lanes) {
    case 2u:
        return f.template operator()<2u>();
    case 4u:
        return f.template operator()<4u>();
    default:
        return f.template operator()<restir::tile_group_size>();
    }
}

inline dim3 pixel_block(16, 8); // --block

template <Pass P>
void launch(const Context& c) {
    const dim3 block = P == Pass::tiles ? dim3(256, 1) : pixel_block;
    const dim3 grid((items_x(P, c) + block.x - 1) / block.x,
                    (items_y(P, c) + block.y - 1) / block.y);
    pass_kernel<P><<<grid, block>>>(c);
}

template <class Frame>
void launch_step(const Frame& frame, const DiStep& step, const Context& c) {
    const dim3 grid((c.width + pixel_block.x - 1) / pixel_block.x,
                    (c.height + pixel_block.y - 1) / pixel_block.y);
    restir::visit_stage(step.stage, [&](auto stage) {
        constexpr DiStage Stage = decltype(stage)::value;
        if constexpr (Stage == DiStage::initial) // the candidates' kernel for each lane count
            with_lanes(c, [&]<std::uint32_t Lanes>() {
                step_kernel<Stage, Lanes><<<grid, pixel_block>>>(frame, step, c);
            });
        else
            step_kernel<Stage, restir::tile_group_size><<<grid, pixel_block>>>(frame, step, c);
    });
}

// `body(x, y)` for every item of a w x h grid on `threads` CPU threads: rows (pixels) or runs
// of 256 entries (a single row, the tiles), interleaved over the threads.
template <class Body>
void for_each_item(std::uint32_t w, std::uint32_t h, std::uint32_t threads, const Body& body) {
    const std::uint32_t chunks = h > 1u ? h : (w + 255u) / 256u;
    std::vector<std::thread> pool;
    for (std::uint32_t t = 0; t < threads; ++t)
        pool.emplace_back([&, t] {
            for (std::uint32_t k = t; k < chunks; k += threads) {
                if (h > 1u) {
                    for (std::uint32_t x = 0; x < w; ++x)
                        body(x, k);
                } else {
                    for (std::uint32_t x = k * 256u; x < std::min(w, k * 256u + 256u); ++x)
                        body(x, 0u);
                }
            }
        });
    for (std::thread& t : pool)
        t.join();
}

// The work of a frame: the G-buffer, the light tiles (for candidates drawn from them), then the
// recipe's steps as `frame.step(i)` lists them (none is spelled out here).
struct Work {
    Pass row = Pass::gbuffer;
    DiStep step{}; // for the recipe's rows
};
template <class Frame>
std::vector<Work> frame_work(const Context& c) {
    std::vector<Work> work = {{Pass::gbuffer}};
    if (!c.bvh_source)
        work.push_back({Pass::tiles});
    const Frame frame = c.recipe<Frame>();
    for (std::uint32_t i = 0; i < frame.step_count(); ++i) {
        const DiStep step = frame.step(i);
        work.push_back({box::row_of(step.stage), step});
    }
    work.push_back({Pass::shadow_rays});
    return work;
}
inline std::vector<Work> frame_work(const Context& c) {
    return c.packed ? frame_work<box::PackedFrame>(c) : frame_work<box::PlainFrame>(c);
}

// `w` on the GPU (a launch) or the CPU, for the layout of `c`.
template <class Frame>
void run_work(const Work& w, const Context& c, bool gpu, std::uint32_t threads) {
    if (w.row == Pass::gbuffer)
        return gpu ? launch<Pass::gbuffer>(c)
                   : for_each_item(c.width, c.height, threads,
                                   [&](std::uint32_t x, std::uint32_t y) {
                                       box::run_item<Pass::gbuffer>(c, x, y);
                                   });
    if (w.row == Pass::shadow_rays)
        return gpu ? launch<Pass::shadow_rays>(c)
                   : for_each_item(c.width, c.height, threads,
                                   [&](std::uint32_t x, std::uint32_t y) {
                                       box::run_item<Pass::shadow_rays>(c, x, y);
                                   });
    if (w.row == Pass::tiles)
        return gpu ? launch<Pass::tiles>(c)
                   : for_each_item(items_x(Pass::tiles, c), 1u, threads,
                                   [&](std::uint32_t x, std::uint32_t y) {
                                       box::run_item<Pass::tiles>(c, x, y);
                                   });
    const Frame frame = c.recipe<Frame>();
    if (gpu)
        return launch_step(frame, w.step, c);
    const restir::DiBuffers<restir::LightPointSample> buffers = c.buffers();
    with_lanes(c, [&]<std::uint32_t Lanes>() {
        for_each_item(c.width, c.height, threads, [&](std::uint32_t x, std::uint32_t y) {
            frame.run_pixel(w.step, c.pixel(x, y), buffers, box::frame_bridge<Lanes>(c));
        });
    });
}
inline void run_work(const Work& w, const Context& c, bool gpu, std::uint32_t threads) {
    if (c.packed)
        run_work<box::PackedFrame>(w, c, gpu, threads);
    else
        run_work<box::PlainFrame>(w, c, gpu, threads);
}

} // namespace bench
