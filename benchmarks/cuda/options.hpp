// The command-line options of di_pipeline (benchmarks/cuda/di_pipeline.cu): their defaults,
// the usage text (--help) and their parsing.
#pragma once

#include <cstdint>
#include <cstdio>
#include <cstdlib>
#include <cstring>
#include <initializer_list>
#include <string>

namespace bench {

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
    std::uint32_t tile_group = 16u;          // pixels per side of a group that shares a light tile
    std::uint32_t lanes = 4u;     // tile entries a pixel takes of each group of 8 that it reads
    std::uint32_t draw_span = 4u; // pixels along a row that take one spatial neighbour draw
    float radius = 20.0f; // spatial radius in pixels per 1080 rows (restir-render's default)
    std::string shadow_rays = "analytic"; // analytic | none (visible: the library's work alone)
};

[[noreturn]] inline void usage(const char* message) {
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
                 "                   [--lights N] [--tile-group N] [--radius PX]\n"
                 "                   [--shadow-rays analytic|none] [--lanes 4|8|2]\n"
                 "                   [--draw-span N]\n"
                 "--radius: the spatial pass's radius in pixels per 1080 rows (default 20,\n"
                 "restir-render's; the paper's is 30)\n"
                 "--shadow-rays none: every shadow ray finds the scene empty (each reads the\n"
                 "triangle count, 0), so that the frame times the library's work alone\n"
                 "--lanes N: each pixel takes N of the 8 entries of each group of the tile it\n"
                 "reads, and 8 / N pixels (2 x 1 for 4, 2 x 2 for 2) read the same groups\n"
                 "(default 4; 8 is restir-render's blocks of 8 entries a pixel)\n"
                 "--draw-span N: N pixels along a row reuse from the same neighbour offsets\n"
                 "(DiFrameParams::spatial_draw_span; default 4; 1: each pixel its own)\n");
    std::exit(message != nullptr ? 2 : 0);
}

inline std::uint32_t parse_count(const char* text, std::uint32_t low, std::uint32_t high) {
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
inline std::string choice(const std::string& option, const char* text,
                          std::initializer_list<const char*> allowed) {
    std::string names;
    for (const char* name : allowed) {
        if (std::strcmp(text, name) == 0)
            return text;
        names += names.empty() ? name : std::string(", ") + name;
    }
    usage((option + " takes one of " + names).c_str());
}

inline Options parse(int argc, char** argv) {
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
        else if (a == "--tile-group")
            o.tile_group = parse_count(value(), 1, 32);
        else if (a == "--radius")
            o.radius = static_cast<float>(parse_count(value(), 1, 1000));
        else if (a == "--shadow-rays")
            o.shadow_rays = choice(a, value(), {"analytic", "none"});
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
            if (o.block_x * o.block_y > 128)
                usage("--block: at most 128 threads (the step kernels' launch bounds)");
        } else if (a == "--draw-span") {
            o.draw_span = parse_count(value(), 1, 64);
        } else if (a == "--lanes") {
            o.lanes = parse_count(value(), 2, 8);
            if (o.lanes != 2u && o.lanes != 4u && o.lanes != 8u)
                usage("--lanes takes 8, 4 or 2");
        } else
            usage(("unknown option " + a).c_str());
    }
    return o;
}

} // namespace bench
