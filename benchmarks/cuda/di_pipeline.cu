// The ReSTIR DI pipeline of restir-render as CUDA kernels over a 1920 x 1080 G-buffer of the
// Cornell box, with VPLs shot on the GPU. A frame is the G-buffer, the light tiles and the
// library's frame recipe (restir::DiFrame): one kernel per `frame.step(i)`, chosen by its stage,
// with the frame passed by value; the recipe decides the steps, their buffers and where rays
// are traced. Each pass and step is timed with CUDA events (median over the timed frames), the
// same ones run on the CPU (`run_pixel` over every pixel) with the same inputs, and their
// results compared pixel by pixel. Built by scripts/test.sh when nvcc is found; run it on a
// GPU with
//   bash scripts/gpu-benchmark.sh                 (or build/cuda/di_pipeline --help)
// Without a GPU, --cpu-only runs the CPU side alone (and writes the image).
//
// The table's rows are the stages (box::Pass). Before the recipe ran the frame, the visibility
// rays had rows of their own ("visibility", "final visibility") under ray-free reuse; they are
// now inside the initial and finish rows in both modes (ray-free: `ReuseVisibility::assumed`;
// --mis-rays: `traced`, where the reuse rows also hold the MIS rays), so those two rows include
// the analytic scene's shadow rays, and only the G-buffer row is left out of the sum.
#include "di_pipeline.hpp"

#include <cuda_runtime.h>

#include <algorithm>
#include <chrono>
#include <cmath>
#include <cstdint>
#include <cstdio>
#include <cstdlib>
#include <cstring>
#include <exception>
#include <initializer_list>
#include <new>
#include <string>
#include <thread>
#include <vector>

namespace {

using box::Context;
using box::Pass;
using restir::DiStage;
using restir::DiStep;

// --- Options --------------------------------------------------------------------------------

struct Options {
    std::uint32_t width = 1920, height = 1080;
    std::uint32_t frames = 100;     // timed GPU frames
    std::uint32_t warmup = 10;      // GPU frames before them
    std::uint32_t check_frames = 4; // first frames, run on both and compared pass by pass
    std::uint32_t vpls = 100'000;   // about this many VPLs
    std::uint32_t threads = 0;      // CPU threads (0: all)
    std::string layout = "both";    // plain | packed | both
    bool mis_rays = false;          // traced MIS rays in reuse (ReuseVisibility::traced, as
                                    // restir-render); without: assumed (ray-free reuse)
    bool cpu_only = false;
    std::string scene = "cornell";          // cornell | many-lights
    std::uint32_t lights = 100'000;         // many-lights: light quads
    std::string reference_source = "tiles"; // the reference's RIS candidates: tiles | bvh
    std::uint32_t reference_candidates = 32;
    std::string source = "tiles";            // tiles | bvh (initial candidates)
    std::uint32_t candidates = 32;           // initial candidates per pixel
    bool reuse = true;                       // false: RIS alone (no temporal or spatial reuse)
    bool static_camera = false;              // the camera of frame 0 in every frame
    std::uint32_t reference_frames = 0;      // > 0: per-frame MSE against this many frames of RIS
    std::string image;                       // PPM of the last frame
    std::uint32_t block_x = 16, block_y = 8; // threads per CUDA block of the pixel passes
};

[[noreturn]] void usage(const char* message) {
    if (message != nullptr)
        std::fprintf(stderr, "di_pipeline: %s\n", message);
    std::fprintf(stderr,
                 "usage: di_pipeline [--width N] [--height N] [--frames N] [--warmup N]\n"
                 "                   [--check-frames N] [--vpls N] [--threads N]\n"
                 "                   [--layout plain|packed|both] [--mis-rays] [--cpu-only]\n"
                 "                   [--image FILE.ppm] [--block WxH] [--source tiles|bvh]\n"
                 "                   [--candidates N] [--no-reuse] [--static-camera]\n"
                 "                   [--reference-frames N] [--reference-source tiles|bvh]\n"
                 "                   [--reference-candidates N] [--scene cornell|many-lights]\n"
                 "                   [--lights N]\n");
    std::exit(message != nullptr ? 2 : 0);
}

std::uint32_t parse_count(const char* text, std::uint32_t low, std::uint32_t high) {
    char* end = nullptr;
    const unsigned long long v = std::strtoull(text, &end, 10);
    if (end == text || *end != '\0' || v < low || v > high) {
        static std::string message;
        message = std::string("'") + text + "' is not a whole number in [" + std::to_string(low) +
                  ", " + std::to_string(high) + "]";
        usage(message.c_str());
    }
    return static_cast<std::uint32_t>(v);
}

// `text` when it is one of `allowed`; otherwise the usage, naming them.
std::string choice(const std::string& option, const char* text,
                   std::initializer_list<const char*> allowed) {
    std::string names;
    for (const char* name : allowed) {
        if (std::strcmp(text, name) == 0)
            return text;
        names += names.empty() ? name : std::string(", ") + name;
    }
    usage((option + " takes one of " + names).c_str());
}

Options parse(int argc, char** argv) {
    Options o;
    for (int i = 1; i < argc; ++i) {
        const std::string a = argv[i];
        const auto value = [&]() -> const char* {
            if (i + 1 >= argc)
                usage((a + " needs a value").c_str());
            return argv[++i];
        };
        if (a == "--help" || a == "-h")
            usage(nullptr);
        else if (a == "--width")
            o.width = parse_count(value(), 8, 8192);
        else if (a == "--height")
            o.height = parse_count(value(), 8, 8192);
        else if (a == "--frames")
            o.frames = parse_count(value(), 1, 100000);
        else if (a == "--warmup")
            o.warmup = parse_count(value(), 0, 100000);
        else if (a == "--check-frames")
            o.check_frames = parse_count(value(), 0, 1000);
        else if (a == "--vpls")
            o.vpls = parse_count(value(), 0, 10'000'000);
        else if (a == "--threads")
            o.threads = parse_count(value(), 1, 1024);
        else if (a == "--layout")
            o.layout = choice(a, value(), {"plain", "packed", "both"});
        else if (a == "--mis-rays")
            o.mis_rays = true;
        else if (a == "--source")
            o.source = choice(a, value(), {"tiles", "bvh"});
        else if (a == "--candidates")
            o.candidates = parse_count(value(), 1, 4096);
        else if (a == "--scene")
            o.scene = choice(a, value(), {"cornell", "many-lights"});
        else if (a == "--lights")
            o.lights = parse_count(value(), 1, 10'000'000);
        else if (a == "--reference-source")
            o.reference_source = choice(a, value(), {"tiles", "bvh"});
        else if (a == "--reference-candidates")
            o.reference_candidates = parse_count(value(), 1, 4096);
        else if (a == "--no-reuse")
            o.reuse = false;
        else if (a == "--static-camera")
            o.static_camera = true;
        else if (a == "--reference-frames")
            o.reference_frames = parse_count(value(), 1, 1'000'000);
        else if (a == "--cpu-only")
            o.cpu_only = true;
        else if (a == "--image")
            o.image = value();
        else if (a == "--block") {
            const std::string v = value();
            const std::size_t x = v.find('x');
            if (x == std::string::npos)
                usage("--block takes WxH, for example 8x8");
            o.block_x = parse_count(v.substr(0, x).c_str(), 1, 1024);
            o.block_y = parse_count(v.substr(x + 1).c_str(), 1, 1024);
            if (o.block_x * o.block_y > 1024)
                usage("--block: at most 1024 threads");
        } else
            usage(("unknown option " + a).c_str());
    }
    return o;
}

// --- CUDA helpers ---------------------------------------------------------------------------

void check_cuda(cudaError_t status, const char* what) {
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

double median(std::vector<double> v) {
    if (v.empty())
        return 0.0;
    std::sort(v.begin(), v.end());
    const std::size_t n = v.size();
    return n % 2 == 1 ? v[n / 2] : 0.5 * (v[n / 2 - 1] + v[n / 2]);
}

// --- Passes and steps on both sides ----------------------------------------------------------

// The items a pass that is not the recipe's covers: pixels, or the light tiles' entries as one
// row.
RESTIR_HOST_DEVICE std::uint32_t items_x(Pass p, const Context& c) {
    return p == Pass::tiles ? c.tiles.tile_count * c.tiles.tile_size : c.width;
}
RESTIR_HOST_DEVICE std::uint32_t items_y(Pass p, const Context& c) {
    return p == Pass::tiles ? 1u : c.height;
}

template <Pass P>
__global__ void pass_kernel(Context c) {
    const std::uint32_t x = blockIdx.x * blockDim.x + threadIdx.x;
    const std::uint32_t y = blockIdx.y * blockDim.y + threadIdx.y;
    if (x < items_x(P, c) && y < items_y(P, c))
        box::run_item<P>(c, x, y);
}

// One step of the recipe over the pixels, compiled for stage `Stage` only; the frame by value
// (a kernel parameter: no copy in local memory).
template <DiStage Stage, class Frame>
__global__ void step_kernel(Frame frame, DiStep step, Context c) {
    const std::uint32_t x = blockIdx.x * blockDim.x + threadIdx.x;
    const std::uint32_t y = blockIdx.y * blockDim.y + threadIdx.y;
    if (x < c.width && y < c.height)
        box::run_step<Stage>(frame, step, c, x, y);
}

dim3 pixel_block(16, 8); // --block

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
    switch (step.stage) {
    case DiStage::initial:
        return step_kernel<DiStage::initial><<<grid, pixel_block>>>(frame, step, c);
    case DiStage::temporal:
        return step_kernel<DiStage::temporal><<<grid, pixel_block>>>(frame, step, c);
    case DiStage::spatial:
        return step_kernel<DiStage::spatial><<<grid, pixel_block>>>(frame, step, c);
    case DiStage::boiling:
        return step_kernel<DiStage::boiling><<<grid, pixel_block>>>(frame, step, c);
    case DiStage::finish:
        return step_kernel<DiStage::finish><<<grid, pixel_block>>>(frame, step, c);
    }
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
    return work;
}
std::vector<Work> frame_work(const Context& c) {
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
    for_each_item(c.width, c.height, threads, [&](std::uint32_t x, std::uint32_t y) {
        frame.run_pixel(w.step, c.pixel(x, y), buffers, box::InitialCandidates{c}, c.bridge(),
                        box::PixelRngs{c}, box::Shading{c});
    });
}
void run_work(const Work& w, const Context& c, bool gpu, std::uint32_t threads) {
    if (c.packed)
        run_work<box::PackedFrame>(w, c, gpu, threads);
    else
        run_work<box::PlainFrame>(w, c, gpu, threads);
}

// --- Buffers --------------------------------------------------------------------------------

// The per-frame buffers of one side, and the context pointing at them.
struct HostBuffers {
    std::vector<box::Texel> surfaces, previous_surfaces;
    std::vector<box::Reservoir> out, scratch, history;
    std::vector<box::Packed> packed_history;
    std::vector<glm::vec3> image;
    std::vector<float> planes;
    std::vector<restir::LightSampleRef> references;
    void allocate(std::size_t pixels, std::size_t entries) {
        surfaces.assign(pixels, {});
        previous_surfaces.assign(pixels, {});
        out.assign(pixels, {});
        scratch.assign(pixels, {});
        history.assign(pixels, {});
        packed_history.assign(pixels, {});
        image.assign(pixels, glm::vec3(0.0f));
        planes.assign(entries * restir::tile_plane_count, 0.0f);
        references.assign(entries, {});
    }
    void point(Context& c) {
        c.surfaces = surfaces.data();
        c.previous_surfaces = previous_surfaces.data();
        c.out = out.data();
        c.scratch = scratch.data();
        c.history = history.data();
        c.packed_history = packed_history.data();
        c.image = image.data();
        c.tiles.planes = planes.data();
        c.tiles.references = references.data();
    }
};

void point_device(Context& c, std::size_t pixels, std::size_t entries) {
    c.surfaces = device_alloc<box::Texel>(pixels);
    c.previous_surfaces = device_alloc<box::Texel>(pixels);
    c.out = device_alloc<box::Reservoir>(pixels);
    c.scratch = device_alloc<box::Reservoir>(pixels);
    c.history = device_alloc<box::Reservoir>(pixels);
    c.packed_history = device_alloc<box::Packed>(pixels);
    c.image = device_alloc<glm::vec3>(pixels);
    c.tiles.planes = device_alloc<float>(entries * restir::tile_plane_count);
    c.tiles.references = device_alloc<restir::LightSampleRef>(entries);
}

// Next frame's view of the buffers: this frame's G-buffer becomes last frame's, and (plain
// layout) the final reservoirs in `out` the history.
void end_frame(Context& c) {
    std::swap(c.surfaces, c.previous_surfaces);
    if (!c.packed)
        std::swap(c.out, c.history);
}
void begin_frame(Context& c, std::uint32_t frame, bool moving_camera) {
    c.frame = frame;
    c.has_history = frame > 0u;
    const std::uint32_t shown = moving_camera ? frame : 0u;
    c.camera = box::camera_of_frame(c.view, shown, c.width, c.height);
    c.previous_camera =
        box::camera_of_frame(c.view, shown > 0u ? shown - 1u : 0u, c.width, c.height);
}

// --- Comparison -----------------------------------------------------------------------------

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
constexpr double tolerance = 1e-5;
double relative_difference(float a, float b, double floor = 0.0) {
    const double d = std::fabs(static_cast<double>(a) - static_cast<double>(b));
    const double scale = std::max(
        {std::fabs(static_cast<double>(a)), std::fabs(static_cast<double>(b)), floor, 1e-30});
    return d == 0.0 ? 0.0 : d / scale;
}
double relative_difference(glm::vec3 a, glm::vec3 b, double floor = 0.0) {
    return std::max({relative_difference(a.x, b.x, floor), relative_difference(a.y, b.y, floor),
                     relative_difference(a.z, b.z, floor)});
}

bool same_bits(float a, float b) { return std::memcmp(&a, &b, sizeof a) == 0; }
bool same_bits(glm::vec3 a, glm::vec3 b) { return std::memcmp(&a, &b, sizeof a) == 0; }

void compare_item(Agreement& agreement, const box::Reservoir& cpu, const box::Reservoir& gpu) {
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
void compare_item(Agreement& agreement, const box::Texel& cpu, const box::Texel& gpu) {
    const double relative = std::max({relative_difference(cpu.position, gpu.position, 1.0),
                                      relative_difference(cpu.normal, gpu.normal, 1.0),
                                      relative_difference(cpu.depth, gpu.depth, 1.0)});
    agreement.add(std::memcmp(&cpu, &gpu, sizeof(cpu)) == 0,
                  cpu.material == gpu.material && relative <= tolerance, relative);
}
void compare_item(Agreement& agreement, glm::vec3 cpu, glm::vec3 gpu) {
    const double relative = relative_difference(cpu, gpu, 1e-3);
    agreement.add(std::memcmp(&cpu, &gpu, sizeof(cpu)) == 0, relative <= tolerance, relative);
}
void compare_item(Agreement& agreement, const box::Packed& cpu, const box::Packed& gpu) {
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

// --- Photons --------------------------------------------------------------------------------

constexpr std::uint32_t photon_bounces = 8; // restir-render's

__global__ void photon_kernel(restir::PhotonSource source, restir::PhotonParams params,
                              const box::Scene* scene, restir::Vpl* out, std::uint32_t* counts) {
    const std::uint32_t photon = blockIdx.x * blockDim.x + threadIdx.x;
    if (photon < params.photon_count)
        counts[photon] = restir::trace_photon(photon, source, *scene, box::Lambertian{}, params,
                                              out + std::size_t{photon} * params.max_bounces);
}

// VPLs of `params.photon_count` photons shot on the GPU, in photon order (as shoot_photons
// returns them); `ms` gets the kernel's time.
std::vector<restir::Vpl> shoot_on_gpu(const restir::PhotonEmitters& emitters,
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

// --- Error against a reference ------------------------------------------------------------

__global__ void add_image(glm::vec3* sum, const glm::vec3* image, std::uint32_t pixels,
                          float scale) {
    const std::uint32_t i = blockIdx.x * blockDim.x + threadIdx.x;
    if (i < pixels)
        sum[i] += scale * image[i];
}

// Adds the squared error of `image` against `reference`, averaged over the channels, to `*sum`.
__global__ void add_squared_error(double* sum, const glm::vec3* image, const glm::vec3* reference,
                                  std::uint32_t pixels) {
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
double frame_mse(double* sum, const glm::vec3* image, const glm::vec3* reference,
                 std::size_t pixels) {
    check_cuda(cudaMemset(sum, 0, sizeof(double)), "MSE");
    add_squared_error<<<(static_cast<std::uint32_t>(pixels) + 255u) / 256u, 256u>>>(
        sum, image, reference, static_cast<std::uint32_t>(pixels));
    double total = 0.0;
    download(&total, sum, 1);
    return total / static_cast<double>(pixels);
}

// --- Output ---------------------------------------------------------------------------------

void write_ppm(const std::string& path, const std::vector<glm::vec3>& image, std::uint32_t w,
               std::uint32_t h) {
    std::FILE* f = std::fopen(path.c_str(), "wb");
    if (f == nullptr) {
        std::fprintf(stderr, "di_pipeline: cannot write %s\n", path.c_str());
        std::exit(1);
    }
    std::fprintf(f, "P6\n%u %u\n255\n", w, h);
    std::vector<unsigned char> row(std::size_t{w} * 3);
    for (std::uint32_t y = 0; y < h; ++y) {
        for (std::uint32_t x = 0; x < w; ++x)
            for (int k = 0; k < 3; ++k) {
                const float v = std::pow(std::clamp(image[x + y * w][k], 0.0f, 1.0f), 1.0f / 2.2f);
                row[x * 3 + static_cast<std::uint32_t>(k)] =
                    static_cast<unsigned char>(std::lround(255.0f * v));
            }
        std::fwrite(row.data(), 1, row.size(), f);
    }
    std::fclose(f);
    std::printf("wrote %s\n", path.c_str());
}

// `v` in `format`, or "-" where nothing was measured (0).
std::string number(double v, const char* format) {
    if (!(v > 0.0))
        return "-";
    char text[32];
    std::snprintf(text, sizeof text, format, v);
    return text;
}

// Bytes a pass reads and writes per pixel at the least (each record once), by layout.
double record_bytes(Pass p, bool packed, restir::ReuseVisibility visibility) {
    const double texel = sizeof(box::Texel), reservoir = sizeof(box::Reservoir);
    const double stored = packed ? sizeof(box::Packed) : reservoir;
    switch (p) {
    case Pass::gbuffer:
        return texel;
    case Pass::initial:
        return texel + reservoir;
    case Pass::temporal:
        return 2 * texel + 2 * reservoir + stored; // here + history
    case Pass::spatial:
        return texel + 2 * reservoir;
    case Pass::boiling:
        return 2 * reservoir;
    case Pass::finish: // written back when it carries visibility
        return texel + (restir::carries_visibility(visibility) ? 2 : 1) * reservoir +
               sizeof(glm::vec3) + (packed ? stored : 0.0);
    default:
        return 0.0;
    }
}

int run_benchmark(const Options& o) {
    pixel_block = dim3(o.block_x, o.block_y);
    const std::uint32_t threads =
        o.threads > 0 ? o.threads : std::max(1u, std::thread::hardware_concurrency());
    const std::size_t pixels = std::size_t{o.width} * o.height;
    const std::size_t entries = std::size_t{box::tile_count} * box::tile_size;

    // The scene, its emitters and its extent (the diagonal of its box), on the host.
    const bool cornell = o.scene == "cornell";
    std::vector<box::Emitter> emitters;
    const box::Scene scene =
        cornell ? box::make_cornell_box() : box::make_many_lights(o.lights, 1u, emitters);
    if (cornell)
        emitters = box::make_emitters(scene);
    const box::Emitters host_emitters{emitters.data(), static_cast<std::uint32_t>(emitters.size())};
    const float extent = cornell ? glm::length(box::to_vec3(cornell::box().extent))
                                 : glm::length(glm::vec3(100.0f, 3.0f, 100.0f));
    const restir::Falloff falloff = restir::Falloff::yuksel(0.02f * extent);

    int devices = 0;
    const bool gpu = !o.cpu_only && cudaGetDeviceCount(&devices) == cudaSuccess && devices > 0;
    if (!o.cpu_only && !gpu) {
        std::fprintf(stderr, "di_pipeline: no CUDA device (use --cpu-only to run the CPU passes "
                             "alone)\n");
        return 1;
    }
    if (gpu) {
        cudaDeviceProp prop{};
        cudaGetDeviceProperties(&prop, 0);
        std::printf("device: %s, %d SMs; CPU: %u threads\n", prop.name, prop.multiProcessorCount,
                    threads);
    }

    // Photons: a pilot of 4096 photons sets the count for about `vpls` VPLs (as restir-render).
    restir::PhotonParams photons = restir::default_photon_params();
    photons.max_bounces = photon_bounces;
    photons.ray_offset = 1e-4f * extent;
    photons.seed = 1u;
    const restir::PhotonEmitters photon_emitters(host_emitters, photons.points_per_emitter,
                                                 photons.seed);
    box::Scene* device_scene = nullptr;
    float photon_ms = 0.0f;
    const auto shoot = [&](std::uint32_t count) {
        photons.photon_count = count;
        if (gpu)
            return shoot_on_gpu(photon_emitters, photons, device_scene, photon_ms);
        return restir::shoot_photons(host_emitters, scene, box::Lambertian{}, photons);
    };
    if (gpu)
        device_scene = upload(std::vector<box::Scene>{scene});
    std::vector<restir::Vpl> vpls;
    if (cornell && o.vpls > 0) {
        const double per_photon = static_cast<double>(shoot(4096).size()) / 4096.0;
        vpls = shoot(static_cast<std::uint32_t>(std::ceil(o.vpls / std::max(per_photon, 1e-3))));
    }
    if (cornell)
        std::printf("VPLs: %zu from %u photons (%.3f ms on the %s)\n", vpls.size(),
                    photons.photon_count, static_cast<double>(photon_ms), gpu ? "GPU" : "CPU");
    else
        std::printf("many-lights: %u light quads (%zu emitter triangles), direct light only\n",
                    o.lights, emitters.size());

    // The light set and its power table.
    const box::Lights host_lights{&host_emitters, vpls.data(),
                                  static_cast<std::uint32_t>(vpls.size())};
    const restir::AliasTable table(restir::unified_light_powers(host_lights));
    const std::vector<restir::AliasEntry> table_entries(table.entries().begin(),
                                                        table.entries().end());

    Context base;
    base.view = cornell ? box::cornell_view : box::many_lights_view;
    base.width = o.width;
    base.height = o.height;
    base.params = box::recipe_params(o.height, o.mis_rays);
    base.falloff = falloff;
    base.ray_offset = 1e-4f * extent;
    base.tiles.tile_count = box::tile_count;
    base.tiles.tile_size = box::tile_size;
    base.candidates = o.candidates;
    base.bvh_source = o.source == "bvh";
    if (!o.reuse) {
        base.params.temporal_reuse = false;
        base.params.spatial_passes = 0u;
    }

    // The light BVH over the same lights (emitters as area lights, VPLs as cosine emitters),
    // for --source bvh.
    std::vector<float> powers = restir::unified_light_powers(host_lights);
    std::vector<restir::LightBounds> bounds;
    for (std::uint32_t e = 0; e < host_emitters.count; ++e) {
        const box::Emitter& t = emitters[e];
        const glm::vec3 b = t.a + t.ab, c = t.a + t.ac;
        bounds.push_back(restir::area_light_bounds(
            glm::min(t.a, glm::min(b, c)), glm::max(t.a, glm::max(b, c)), t.normal, powers[e]));
    }
    for (std::size_t v = 0; v < vpls.size(); ++v)
        bounds.push_back(restir::point_light_bounds(vpls[v].position, vpls[v].normal,
                                                    powers[host_emitters.count + v]));
    const restir::LightBvh bvh(bounds);

    // The CPU side.
    HostBuffers host;
    host.allocate(pixels, entries);
    Context h = base;
    h.scene = &scene;
    h.lights = host_lights;
    h.power = table.view();
    h.bvh = bvh.view();
    host.point(h);

    // The GPU side: the same inputs in device memory.
    Context d = base;
    if (gpu) {
        d.scene = device_scene;
        box::Emitters device_emitters{upload(emitters), host_emitters.count};
        d.lights = {upload(std::vector<box::Emitters>{device_emitters}), upload(vpls),
                    host_lights.vpl_count};
        d.power = {upload(table_entries), table.size()};
        d.bvh = {upload(bvh.groups()), upload(bvh.paths()), bvh.view().count};
        point_device(d, pixels, entries);
    }

    // The reference: the mean of `reference_frames` frames of RIS (32 candidates from the tiles,
    // shadow-tested) under the static camera, with its own random numbers.
    glm::vec3* reference = nullptr;
    double* squared_error = nullptr;
    if (gpu && o.reference_frames > 0) {
        Context r = d;
        r.params.temporal_reuse = false;
        r.params.spatial_passes = 0u;
        r.bvh_source = o.reference_source == "bvh";
        r.candidates = o.reference_candidates;
        r.seed = 7u;
        r.packed = false;
        reference = device_alloc<glm::vec3>(pixels);
        squared_error = device_alloc<double>(1);
        check_cuda(cudaMemset(reference, 0, pixels * sizeof(glm::vec3)), "reference");
        for (std::uint32_t f = 0; f < o.reference_frames; ++f) {
            begin_frame(r, f, false);
            for (const Work& w : frame_work(r))
                run_work(w, r, true, threads);
            add_image<<<(static_cast<std::uint32_t>(pixels) + 255u) / 256u, 256u>>>(
                reference, r.image, static_cast<std::uint32_t>(pixels),
                1.0f / static_cast<float>(o.reference_frames));
        }
        check_cuda(cudaDeviceSynchronize(), "reference");
        std::printf("reference: the mean of %u frames of RIS (%u candidates from the %s)\n",
                    o.reference_frames, o.reference_candidates,
                    r.bvh_source ? "light BVH" : "light tiles");
    }

    std::vector<std::string> layouts;
    if (o.layout != "packed")
        layouts.push_back("plain");
    if (o.layout != "plain")
        layouts.push_back("packed");

    bool all_agree = true;
    for (const std::string& layout : layouts) {
        const bool packed = layout == "packed";
        h.packed = d.packed = packed;
        std::printf(
            "\n== %s history (%zu B a pixel), %s, %ux%u, %u candidates from the %s, %zu "
            "lights%s\n",
            packed ? "packed" : "plain", packed ? sizeof(box::Packed) : sizeof(box::Reservoir),
            !o.reuse     ? "RIS alone (no reuse)"
            : o.mis_rays ? "pairwise MIS with traced visibility in reuse"
                         : "pairwise MIS, ray-free reuse",
            o.width, o.height, h.candidates, h.bvh_source ? "light BVH" : "light tiles",
            host_lights.light_count() + std::size_t{0}, o.static_camera ? ", static camera" : "");

        // Per row, one time per frame (the sum of its steps in that frame).
        std::vector<double> cpu_ms[box::pass_count], gpu_ms[box::pass_count], gpu_frame_ms;
        bool ran[box::pass_count] = {};
        std::vector<double> frame_errors;
        Comparison comparison;
        const std::uint32_t cpu_frames = o.cpu_only ? o.frames : (gpu ? o.check_frames : 0u);
        const std::uint32_t total = gpu ? o.check_frames + o.warmup + o.frames : o.frames;
        std::vector<cudaEvent_t> events;
        for (std::uint32_t frame = 0; frame < total; ++frame) {
            begin_frame(h, frame, !o.static_camera);
            begin_frame(d, frame, !o.static_camera);
            // The same steps on both sides: the same settings and history.
            const std::vector<Work> work = frame_work(h);
            const bool on_cpu = frame < cpu_frames;
            const bool timed_gpu = gpu && frame >= o.check_frames + o.warmup;
            while (gpu && events.size() < work.size() + 1) {
                events.emplace_back();
                cudaEventCreate(&events.back());
            }
            double cpu_frame[box::pass_count] = {};
            for (std::size_t k = 0; k < work.size(); ++k) {
                const Work& w = work[k];
                ran[static_cast<std::uint32_t>(w.row)] = true;
                if (gpu) {
                    if (timed_gpu)
                        cudaEventRecord(events[k]);
                    run_work(w, d, true, threads);
                    if (!timed_gpu)
                        check_cuda(cudaDeviceSynchronize(), box::pass_name(w.row));
                }
                if (on_cpu) {
                    const auto start = std::chrono::steady_clock::now();
                    run_work(w, h, false, threads);
                    cpu_frame[static_cast<std::uint32_t>(w.row)] +=
                        std::chrono::duration<double, std::milli>(std::chrono::steady_clock::now() -
                                                                  start)
                            .count();
                    if (gpu)
                        comparison.work(w, h, d);
                }
            }
            // Frame 0 has no history and warms the caches: left out unless alone.
            if (on_cpu && (frame > 0u || cpu_frames == 1u))
                for (std::uint32_t r = 0; r < box::pass_count; ++r)
                    if (cpu_frame[r] > 0.0)
                        cpu_ms[r].push_back(cpu_frame[r]);
            if (timed_gpu) {
                cudaEventRecord(events[work.size()]);
                check_cuda(cudaEventSynchronize(events[work.size()]), "frame");
                double gpu_frame[box::pass_count] = {};
                double frame_ms = 0.0;
                for (std::size_t k = 0; k < work.size(); ++k) {
                    float ms = 0.0f;
                    cudaEventElapsedTime(&ms, events[k], events[k + 1]);
                    gpu_frame[static_cast<std::uint32_t>(work[k].row)] += ms;
                    if (!box::is_ray_pass(work[k].row))
                        frame_ms += ms;
                }
                for (std::uint32_t r = 0; r < box::pass_count; ++r)
                    if (gpu_frame[r] > 0.0)
                        gpu_ms[r].push_back(gpu_frame[r]);
                gpu_frame_ms.push_back(frame_ms);
                if (reference != nullptr)
                    frame_errors.push_back(frame_mse(squared_error, d.image, reference, pixels));
            }
            end_frame(h);
            end_frame(d);
        }

        // The table: per row, GPU median, CPU median, their ratio, bytes, agreement.
        std::printf("%-34s %10s %10s %8s %12s %12s %s\n", "pass", "GPU ms", "CPU ms", "CPU/GPU",
                    "records B/px", "Gcand/s", "GPU = CPU");
        double gpu_sum = 0.0, cpu_sum = 0.0;
        for (std::uint32_t k = 0; k < box::pass_count; ++k) {
            const auto p = static_cast<Pass>(k);
            if (!ran[k])
                continue;
            const double g = median(gpu_ms[k]), c = median(cpu_ms[k]);
            if (!box::is_ray_pass(p)) {
                gpu_sum += g;
                cpu_sum += c;
            }
            char rate[32] = "";
            if (p == Pass::initial && g > 0.0)
                std::snprintf(rate, sizeof rate, "%.1f",
                              static_cast<double>(pixels) * h.candidates / (g * 1e6));
            const Agreement& a = comparison.passes[k];
            char agree[96] = "-";
            if (a.items > 0) {
                std::snprintf(agree, sizeof agree, "%llu/%llu bit-identical, %llu over 1e-5",
                              static_cast<unsigned long long>(a.identical),
                              static_cast<unsigned long long>(a.items),
                              static_cast<unsigned long long>(a.mismatches));
                all_agree = all_agree && a.mismatches == 0;
            }
            std::printf("%-34s %10s %10s %8s %12.0f %12s %s\n", box::pass_name(p),
                        number(g, "%.3f").c_str(), number(c, "%.3f").c_str(),
                        number(g > 0.0 && c > 0.0 ? c / g : 0.0, "%.1f").c_str(),
                        record_bytes(p, packed, h.params.visibility), rate, agree);
        }
        // The frame but its G-buffer: the tiles and the recipe's steps, with their shadow rays.
        std::printf(
            "%-34s %10s %10s %8s", "frame without the G-buffer", number(gpu_sum, "%.3f").c_str(),
            number(cpu_sum, "%.3f").c_str(),
            number(gpu_sum > 0.0 && cpu_sum > 0.0 ? cpu_sum / gpu_sum : 0.0, "%.1f").c_str());
        if (gpu)
            std::printf("   (median GPU frame without the G-buffer: %.3f ms)",
                        median(gpu_frame_ms));
        std::printf("\n");
        if (!frame_errors.empty()) {
            double mean = 0.0;
            for (const double e : frame_errors)
                mean += e / static_cast<double>(frame_errors.size());
            std::printf("per-frame MSE against the reference: %.5g (mean of %zu frames)\n", mean,
                        frame_errors.size());
        }
        for (cudaEvent_t& e : events)
            cudaEventDestroy(e);
        if (!o.image.empty() && layout == layouts.back()) {
            if (gpu)
                download(host.image.data(), d.image, pixels);
            write_ppm(o.image, host.image, o.width, o.height);
        }
    }
    if (gpu) {
        std::printf("\nGPU and CPU %s (relative tolerance %.0e per float)\n",
                    all_agree ? "agree on every checked item" : "DISAGREE", tolerance);
        if (!all_agree)
            return 1;
    }
    return 0;
}

} // namespace

int main(int argc, char** argv) {
    const Options o = parse(argc, argv);
    try {
        return run_benchmark(o);
    } catch (const std::bad_alloc&) {
        std::fprintf(stderr, "di_pipeline: out of host memory (try a smaller --width, --height, "
                             "--vpls or --lights)\n");
    } catch (const std::exception& e) {
        std::fprintf(stderr, "di_pipeline: %s\n", e.what());
    }
    return 1;
}
