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
// the analytic scene's shadow rays. The last row traces one such ray a pixel alone, after the
// frame, to tell what they cost; it and the G-buffer row are left out of the sum. With
// --shadow-rays none the rays find no triangle (the same kernels), and the frame times the
// library's work alone.
//
// This file holds the run (setup, reference, the frames of each layout, the table) and main; the
// rest, by job: options.hpp (command line), analytic_scene.hpp (scenes, cameras),
// di_pipeline.hpp (the frame and its collaborators), frame_work.hpp (kernels, launches, CPU
// loops), buffers.hpp (both sides' buffers, frame to frame), comparison.hpp (GPU against CPU),
// photons.hpp (VPLs on the GPU), reference_error.hpp (MSE against a reference), cuda_memory.hpp.
#include "buffers.hpp"
#include "comparison.hpp"
#include "cuda_memory.hpp"
#include "di_pipeline.hpp"
#include "frame_work.hpp"
#include "options.hpp"
#include "photons.hpp"
#include "reference_error.hpp"

#include <cuda_runtime.h>

#include <algorithm>
#include <chrono>
#include <cmath>
#include <cstdint>
#include <cstdio>
#include <cstdlib>
#include <exception>
#include <new>
#include <string>
#include <thread>
#include <vector>

namespace {

using namespace bench;
using box::Pass;

double median(std::vector<double> v) {
    if (v.empty())
        return 0.0;
    std::sort(v.begin(), v.end());
    const std::size_t n = v.size();
    return n % 2 == 1 ? v[n / 2] : 0.5 * (v[n / 2 - 1] + v[n / 2]);
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

// The VPLs of the Cornell box (none for the many-lights scene): a pilot of 4096 photons sets
// the count for about `vpls` VPLs (as restir-render), shot on the GPU where there is one.
std::vector<restir::Vpl> shoot_vpls(const Options& o, bool cornell, bool gpu,
                                    const box::Scene& scene, const box::Scene* device_scene,
                                    const box::Emitters& host_emitters, float extent) {
    restir::PhotonParams photons = restir::default_photon_params();
    photons.max_bounces = photon_bounces;
    photons.ray_offset = 1e-4f * extent;
    photons.seed = 1u;
    const restir::PhotonEmitters photon_emitters(host_emitters, photons.points_per_emitter,
                                                 photons.seed);
    float photon_ms = 0.0f;
    const auto shoot = [&](std::uint32_t count) {
        photons.photon_count = count;
        if (gpu)
            return shoot_on_gpu(photon_emitters, photons, device_scene, photon_ms);
        return restir::shoot_photons(host_emitters, scene, box::Lambertian{}, photons);
    };
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
                    o.lights, std::size_t{host_emitters.count});
    return vpls;
}

// The settings both sides share: the view, the size, the recipe's settings, the falloff and
// the light tiles' shape, the initial candidates.
Context base_context(const Options& o, bool cornell, restir::Falloff falloff, float extent) {
    Context base;
    base.view = cornell ? box::cornell_view : box::many_lights_view;
    base.width = o.width;
    base.height = o.height;
    base.params = box::recipe_params(o.height, o.radius, o.mis_rays);
    base.params.spatial_draw_span = o.draw_span;
    base.falloff = falloff;
    base.ray_offset = 1e-4f * extent;
    base.tiles.tile_count = box::tile_count;
    base.tiles.tile_size = box::tile_size;
    base.candidates = o.candidates;
    base.tile_group = o.tile_group;
    base.lanes = o.lanes;
    base.bvh_source = o.source == "bvh";
    if (!o.reuse) {
        base.params.temporal_reuse = false;
        base.params.spatial_passes = 0u;
    }
    return base;
}

// The bounds of the light BVH over the lights (emitters as area lights, VPLs as cosine
// emitters), for --source bvh.
std::vector<restir::LightBounds> light_bounds(const box::Lights& host_lights,
                                              const box::Emitters& host_emitters,
                                              const std::vector<restir::Vpl>& vpls) {
    std::vector<float> powers = restir::unified_light_powers(host_lights);
    std::vector<restir::LightBounds> bounds;
    for (std::uint32_t e = 0; e < host_emitters.count; ++e) {
        const box::Emitter& t = host_emitters.emitters[e];
        const glm::vec3 b = t.a + t.ab, c = t.a + t.ac;
        bounds.push_back(restir::area_light_bounds(
            glm::min(t.a, glm::min(b, c)), glm::max(t.a, glm::max(b, c)), t.normal, powers[e]));
    }
    for (std::size_t v = 0; v < vpls.size(); ++v)
        bounds.push_back(restir::point_light_bounds(vpls[v].position, vpls[v].normal,
                                                    powers[host_emitters.count + v]));
    return bounds;
}

// The reference image and its error buffer (device memory), or none.
struct Reference {
    glm::vec3* image = nullptr;
    double* squared_error = nullptr;
};

// The reference: the mean of `reference_frames` frames of RIS (32 candidates from the tiles,
// shadow-tested) under the static camera, with its own random numbers.
Reference make_reference(const Options& o, const Context& d, std::size_t pixels,
                         std::uint32_t threads) {
    Reference reference;
    Context r = d;
    r.params.temporal_reuse = false;
    r.params.spatial_passes = 0u;
    r.bvh_source = o.reference_source == "bvh";
    r.candidates = o.reference_candidates;
    r.seed = 7u;
    r.packed = false;
    reference.image = device_alloc<glm::vec3>(pixels);
    reference.squared_error = device_alloc<double>(1);
    check_cuda(cudaMemset(reference.image, 0, pixels * sizeof(glm::vec3)), "reference");
    for (std::uint32_t f = 0; f < o.reference_frames; ++f) {
        begin_frame(r, f, false);
        for (const Work& w : frame_work(r))
            run_work(w, r, true, threads);
        add_image<<<(static_cast<std::uint32_t>(pixels) + 255u) / 256u, 256u>>>(
            reference.image, r.image, static_cast<std::uint32_t>(pixels),
            1.0f / static_cast<float>(o.reference_frames));
    }
    check_cuda(cudaDeviceSynchronize(), "reference");
    std::printf("reference: the mean of %u frames of RIS (%u candidates from the %s)\n",
                o.reference_frames, o.reference_candidates,
                r.bvh_source ? "light BVH" : "light tiles");
    return reference;
}

// What the frames of one layout measured: per row, one time per frame (the sum of its steps in
// that frame), whether it ran, the per-frame errors and the CPU/GPU agreement.
struct Timings {
    std::vector<double> cpu_ms[box::pass_count], gpu_ms[box::pass_count], gpu_frame_ms;
    bool ran[box::pass_count] = {};
    std::vector<double> frame_errors;
    ErrorCorrelation correlation; // the last frame's, with a reference
    Comparison comparison;
};

// The frames of one layout: the checked frames on both sides (compared step by step), then the
// GPU's warm-up and timed frames (only the CPU's with --cpu-only).
Timings run_frames(const Options& o, Context& h, Context& d, bool gpu, std::uint32_t threads,
                   const Reference& reference, std::size_t pixels) {
    Timings t;
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
            t.ran[static_cast<std::uint32_t>(w.row)] = true;
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
                    t.comparison.work(w, h, d);
            }
        }
        // Frame 0 has no history and warms the caches: left out unless alone.
        if (on_cpu && (frame > 0u || cpu_frames == 1u))
            for (std::uint32_t r = 0; r < box::pass_count; ++r)
                if (cpu_frame[r] > 0.0)
                    t.cpu_ms[r].push_back(cpu_frame[r]);
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
                    t.gpu_ms[r].push_back(gpu_frame[r]);
            t.gpu_frame_ms.push_back(frame_ms);
            if (reference.image != nullptr) {
                t.frame_errors.push_back(
                    frame_mse(reference.squared_error, d.image, reference.image, pixels));
                if (frame + 1u == total)
                    t.correlation = error_correlation(d.image, reference.image, o.width, o.height);
            }
        }
        end_frame(h);
        end_frame(d);
    }
    for (cudaEvent_t& e : events)
        cudaEventDestroy(e);
    return t;
}

// The table: per row, GPU median, CPU median, their ratio, bytes, agreement; then the frame
// without the G-buffer and the error against the reference. Whether GPU and CPU agree.
bool print_table(const Timings& t, const Context& h, bool packed, bool gpu, std::size_t pixels) {
    bool all_agree = true;
    std::printf("%-34s %10s %10s %8s %12s %12s %s\n", "pass", "GPU ms", "CPU ms", "CPU/GPU",
                "records B/px", "Gcand/s", "GPU = CPU");
    double gpu_sum = 0.0, cpu_sum = 0.0;
    for (std::uint32_t k = 0; k < box::pass_count; ++k) {
        const auto p = static_cast<Pass>(k);
        if (!t.ran[k])
            continue;
        const double g = median(t.gpu_ms[k]), c = median(t.cpu_ms[k]);
        if (!box::is_ray_pass(p)) {
            gpu_sum += g;
            cpu_sum += c;
        }
        char rate[32] = "";
        if (p == Pass::initial && g > 0.0)
            std::snprintf(rate, sizeof rate, "%.1f",
                          static_cast<double>(pixels) * h.candidates / (g * 1e6));
        const Agreement& a = t.comparison.passes[k];
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
    std::printf("%-34s %10s %10s %8s", "frame without the G-buffer",
                number(gpu_sum, "%.3f").c_str(), number(cpu_sum, "%.3f").c_str(),
                number(gpu_sum > 0.0 && cpu_sum > 0.0 ? cpu_sum / gpu_sum : 0.0, "%.1f").c_str());
    if (gpu)
        std::printf("   (median GPU frame without the G-buffer: %.3f ms)", median(t.gpu_frame_ms));
    std::printf("\n");
    if (!t.frame_errors.empty()) {
        double mean = 0.0;
        for (const double e : t.frame_errors)
            mean += e / static_cast<double>(t.frame_errors.size());
        std::printf("per-frame MSE against the reference: %.5g (mean of %zu frames)\n", mean,
                    t.frame_errors.size());
        std::printf("the last frame's error autocorrelation at");
        for (const std::uint32_t lag : correlation_lags)
            std::printf(" %u", lag);
        std::printf(" px:\n  along x");
        for (const double v : t.correlation.x)
            std::printf(" %.4f", v);
        std::printf("\n  along y");
        for (const double v : t.correlation.y)
            std::printf(" %.4f", v);
        std::printf("\n");
    }
    return all_agree;
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

    // --shadow-rays none: the shadow rays' scene holds no triangle, so every sample is visible
    // and the frame is the library's work (the kernels are the same; each ray reads the count).
    const bool shadow_rays = o.shadow_rays == "analytic";
    const box::Scene no_occluders{};
    box::Scene* device_scene = nullptr;
    box::Scene* device_occluders = nullptr;
    if (gpu) {
        device_scene = upload(std::vector<box::Scene>{scene});
        device_occluders =
            shadow_rays ? device_scene : upload(std::vector<box::Scene>{no_occluders});
    }
    const std::vector<restir::Vpl> vpls =
        shoot_vpls(o, cornell, gpu, scene, device_scene, host_emitters, extent);

    // The light set, its power table and its BVH.
    const box::Lights host_lights{&host_emitters, vpls.data(),
                                  static_cast<std::uint32_t>(vpls.size())};
    const restir::AliasTable table(restir::unified_light_powers(host_lights));
    const std::vector<restir::AliasEntry> table_entries(table.entries().begin(),
                                                        table.entries().end());
    const Context base = base_context(o, cornell, falloff, extent);
    const std::vector<restir::LightBounds> bounds = light_bounds(host_lights, host_emitters, vpls);
    const restir::LightBvh bvh(bounds);

    // The CPU side.
    HostBuffers host;
    host.allocate(pixels, entries);
    Context h = base;
    h.scene = &scene;
    h.occluders = shadow_rays ? &scene : &no_occluders;
    h.lights = host_lights;
    h.power = table.view();
    h.bvh = bvh.view();
    host.point(h);

    // The GPU side: the same inputs in device memory.
    Context d = base;
    if (gpu) {
        d.scene = device_scene;
        d.occluders = device_occluders;
        box::Emitters device_emitters{upload(emitters), host_emitters.count};
        d.lights = {upload(std::vector<box::Emitters>{device_emitters}), upload(vpls),
                    host_lights.vpl_count};
        d.power = {upload(table_entries), table.size()};
        d.bvh = bvh.view(); // the root's box with it
        d.bvh.groups = upload(bvh.groups());
        d.bvh.paths = upload(bvh.paths());
        point_device(d, pixels, entries);
    }

    const Reference reference =
        gpu && o.reference_frames > 0 ? make_reference(o, d, pixels, threads) : Reference{};

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
        if (!h.bvh_source)
            std::printf("light tiles: %u of %u entries, one per %ux%u pixels\n", box::tile_count,
                        box::tile_size, h.tile_group, h.tile_group);
        if (!h.bvh_source && o.lanes < 8u)
            std::printf("candidates: %u of the 8 entries of each group of the tile that %s pixels "
                        "read\n",
                        o.lanes, o.lanes == 4u ? "2 x 1" : "2 x 2");
        if (!shadow_rays)
            std::printf("shadow rays: none (every sample visible; the frame is the library's "
                        "work alone)\n");
        if (o.reuse)
            std::printf("spatial reuse: %u neighbours in %.1f px (%g px per 1080 rows), one draw "
                        "per %u pixel%s of a row\n",
                        h.params.spatial.neighbour_count, h.params.spatial.radius, o.radius,
                        o.draw_span, o.draw_span == 1u ? "" : "s");
        const Timings t = run_frames(o, h, d, gpu, threads, reference, pixels);
        all_agree = print_table(t, h, packed, gpu, pixels) && all_agree;
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
    const bench::Options o = bench::parse(argc, argv);
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
