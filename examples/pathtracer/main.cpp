// restir-render: the Embree example renderer. Renders a scene with uniform light sampling,
// RIS, ReSTIR or a reference path tracer, with optional VPL or path-traced global
// illumination, over several frames, and measures the error against a reference image.
// `restir-render --help` lists every flag.
#include "camera.hpp"
#include "command_line.hpp"
#include "error_metrics.hpp"
#include "image_io.hpp"
#include "renderer.hpp"
#include "scene.hpp"

#include <CLI/CLI.hpp>

#include <algorithm>
#include <cmath>
#include <cstdio>
#include <cstdlib>
#include <filesystem>
#include <fstream>
#include <iostream>
#include <map>
#include <optional>
#include <string>
#include <unistd.h>
#include <utility>
#include <vector>

namespace {

struct Options {
    std::string scene = "cornell";
    std::uint32_t lights = 1000;
    std::uint64_t scene_seed = 0;
    std::uint64_t max_memory_mb = 0;
    std::vector<float> look_from, look_at;
    std::optional<float> fov;
    std::uint32_t frames = 16;
    std::vector<std::string> outs{"out/render.png"};
    std::optional<float> exposure;
    std::string reference;
    std::string csv;
};

[[noreturn]] void fail(const std::string& message) { pt::fail("restir-render", message); }

// CLI11's Range lets NaN through (every comparison with it is false): the float flags check
// for a finite number first.
const CLI::Validator finite_number(
    [](std::string& text) -> std::string {
        char* end = nullptr;
        const float value = std::strtof(text.c_str(), &end);
        if (end == text.c_str())
            return {}; // not a number at all: CLI11's conversion reports it
        return std::isfinite(value) ? std::string{} : "'" + text + "' is not a finite number";
    },
    "", "finite");

// Refuses a render whose estimated memory (pt::estimated_memory_bytes) exceeds `limit_mb`, or
// without a limit three quarters of the physical memory, before any work starts.
void check_memory(const pt::RenderSettings& settings, bool with_reference, std::uint64_t limit_mb) {
    std::uint64_t limit = limit_mb << 20u;
    if (limit == 0u) {
        const long pages = sysconf(_SC_PHYS_PAGES);
        const long page_size = sysconf(_SC_PAGE_SIZE);
        if (pages <= 0 || page_size <= 0)
            return; // unknown: no limit
        limit = static_cast<std::uint64_t>(pages) / 4u * 3u * static_cast<std::uint64_t>(page_size);
    }
    const std::uint64_t needed = pt::estimated_memory_bytes(settings, with_reference);
    if (needed > limit)
        fail("this render needs about " + std::to_string(needed >> 20u) + " MB (" +
             std::to_string(settings.width) + "x" + std::to_string(settings.height) +
             (settings.gi == pt::GlobalIllumination::vpl
                  ? ", " + std::to_string(settings.vpls) + " VPLs"
                  : std::string{}) +
             "), more than the limit of " + std::to_string(limit >> 20u) +
             " MB: make the image or --vpls smaller, or raise --max-memory");
}

void progress(std::uint32_t done, std::uint32_t total, double frame_ms) {
    constexpr std::size_t width = 30;
    const std::size_t filled = width * done / total;
    std::fprintf(stderr, "\r[%s%s] frame %u/%u, %.1f ms", std::string(filled, '#').c_str(),
                 std::string(width - filled, '.').c_str(), done, total, frame_ms);
    if (done == total)
        std::fputc('\n', stderr);
    std::fflush(stderr);
}

// The CSV's error measures of the accumulated image, after the bias columns: relMSE,
// fireflies, row structure of the error and its autocorrelation at lags 1 to 8.
constexpr std::uint32_t csv_lags = 8;

std::string error_header() {
    std::string header = "rel_mse,fireflies,p999,row_ratio,column_ratio";
    for (const char* axis : {"acf_x", "acf_y"})
        for (std::uint32_t lag = 1; lag <= csv_lags; ++lag)
            header += "," + std::string(axis) + std::to_string(lag);
    return header;
}

std::string number(double value) {
    char text[32];
    std::snprintf(text, sizeof text, "%.6g", value);
    return text;
}

// The values of error_header()'s columns; empty ones without a reference.
std::string error_columns(const pt::Image& image, const std::optional<pt::Image>& reference) {
    if (!reference)
        return std::string(5 + 2 * csv_lags - 1, ',');
    const pt::FireflyMeasure fireflies = pt::firefly_measure(image, *reference);
    const pt::RowStructure rows = pt::row_structure_of_error(image, *reference);
    const pt::ErrorAutocorrelation acf = pt::error_autocorrelation(image, *reference, csv_lags);
    std::string columns = number(pt::relative_mse(image, *reference)) + "," +
                          std::to_string(fireflies.count) + "," + number(fireflies.p999) + "," +
                          number(rows.row_ratio) + "," + number(rows.column_ratio);
    for (const std::vector<double>* values : {&acf.acf_x, &acf.acf_y})
        for (std::uint32_t lag = 1; lag <= csv_lags; ++lag)
            columns += "," + number((*values)[lag]);
    return columns;
}

} // namespace

int main(int argc, char** argv) {
    pt::RenderSettings settings;
    settings.width = 512;
    settings.height = 512;
    Options options;

    CLI::App app{"restir-render: ReSTIR, RIS, uniform light sampling and VPL global illumination "
                 "on Embree, with error measurement against a reference"};
    // A flag given twice keeps its last value, so that wrappers can set defaults that the
    // user's arguments override (scripts/render.sh).
    app.option_defaults()->always_capture_default()->multi_option_policy(
        CLI::MultiOptionPolicy::TakeLast);
    app.add_option("--scene", options.scene,
                   "cornell (built in), many-lights (procedural, see --lights) or a Wavefront "
                   "FILE.obj");
    app.add_option("--lights", options.lights, "Emissive quads of the many-lights scene")
        ->check(CLI::Range(1u, 10'000'000u));
    app.add_option("--scene-seed", options.scene_seed,
                   "Seed of the many-lights scene's layout (apart from --seed, so that renders "
                   "with other pixel seeds see the same scene)");
    const std::map<std::string, pt::Method> methods{{"uniform", pt::Method::uniform},
                                                    {"ris", pt::Method::ris},
                                                    {"restir", pt::Method::restir},
                                                    {"reference", pt::Method::reference}};
    app.add_option("--method", settings.method,
                   "uniform: one uniformly chosen light per sample; ris: resampling from "
                   "--candidates; restir: RIS + temporal + spatial reuse; reference: path "
                   "tracer with next-event estimation and MIS")
        ->transform(CLI::CheckedTransformer(methods, CLI::ignore_case).description(""))
        ->default_str("restir");
    const std::map<std::string, pt::GlobalIllumination> gis{{"none", pt::GlobalIllumination::none},
                                                            {"vpl", pt::GlobalIllumination::vpl},
                                                            {"path", pt::GlobalIllumination::path}};
    app.add_option("--gi", settings.gi,
                   "Indirect light: none, vpl (photon-mapped VPLs sampled with the emitters) or "
                   "path (path-traced bounces)")
        ->transform(CLI::CheckedTransformer(gis, CLI::ignore_case).description(""))
        ->default_str("vpl");
    app.add_option("--spp", settings.spp, "Samples per pixel per frame (restir: 1)")
        ->check(CLI::Range(1u, 65536u));
    app.add_option("--frames", options.frames, "Frames rendered and averaged")
        ->check(CLI::Range(1u, 100000u));
    app.add_option("--width", settings.width, "Image width")->check(CLI::Range(1u, 16384u));
    app.add_option("--height", settings.height, "Image height")->check(CLI::Range(1u, 16384u));
    app.add_option("--look-from", options.look_from, "Camera position x,y,z")
        ->delimiter(',')
        ->expected(3)
        ->check(finite_number);
    app.add_option("--look-at", options.look_at, "Point the camera looks at, x,y,z")
        ->delimiter(',')
        ->expected(3)
        ->check(finite_number);
    app.add_option("--fov", options.fov, "Vertical field of view in degrees")
        ->check(finite_number & CLI::Range(1.0f, 179.0f));
    const std::map<std::string, pt::CameraMotion> motions{{"none", pt::CameraMotion::none},
                                                          {"orbit", pt::CameraMotion::orbit}};
    app.add_option("--camera-motion", settings.motion,
                   "none, or orbit: the camera turns about the look-at point a little every "
                   "frame, so temporal reuse goes through real reprojection")
        ->transform(CLI::CheckedTransformer(motions, CLI::ignore_case).description(""))
        ->default_str("none");
    app.add_option("--antialias", settings.antialias,
                   "Jitter primary rays inside the pixel (true/false); off, every method sees "
                   "pixel centres and the RMSE measures lighting noise only");
    app.add_option("--seed", settings.seed, "Seed of every random number");
    app.add_option("--threads", settings.threads, "Worker threads (0: all cores)");
    app.add_option("--max-memory", options.max_memory_mb,
                   "Refuse renders whose estimated memory exceeds this many MB (0: three "
                   "quarters of the machine's physical memory)");
    app.add_option("--out", options.outs,
                   "Output image(s): .png (tone-mapped), .exr or .pfm (linear); repeat the flag "
                   "for several")
        ->multi_option_policy(CLI::MultiOptionPolicy::TakeAll);
    app.add_option("--exposure", options.exposure,
                   "PNG exposure in stops (default: automatic, average luminance to 0.18)")
        ->check(finite_number);
    app.add_option("--reference", options.reference,
                   "Reference image (.exr or .pfm) for the RMSE after every frame");
    app.add_option("--csv", options.csv,
                   "CSV per frame: rmse (accumulated image), frame_rmse (last frame alone), "
                   "frame_ms, elapsed_ms, the phase timings, bias, and the error measures of "
                   "docs/renderer.md (rel_mse, fireflies, p999, row/column ratio, "
                   "autocorrelation)");
    // The library's parameters.
    app.add_option("--candidates", settings.candidates, "RIS candidates per pixel (M)")
        ->check(CLI::Range(1u, 4096u));
    app.add_option("--neighbours", settings.neighbours, "Spatial reuse neighbours (k)")
        ->check(CLI::Range(0u, restir::max_reuse_inputs - 1u));
    app.add_option("--radius", settings.radius,
                   "Spatial reuse radius in pixels (0: the paper's 30 px at 1080 rows, scaled "
                   "to the image height, at least 3)")
        ->check(finite_number & CLI::Range(0.0f, 1000.0f));
    app.add_option("--spatial-passes", settings.spatial_passes, "Spatial reuse passes")
        ->check(CLI::Range(0u, 16u));
    app.add_option("--history-cap", settings.history_cap,
                   "Temporal history M cap, as a multiple of the current M (0: no cap)");
    app.add_option("--permutation-sampling", settings.permutation_sampling,
                   "Temporal reuse reads the history of a pixel permuted per frame in 2x2 "
                   "blocks (true/false)");
    app.add_option("--boiling-filter", settings.boiling_threshold,
                   "Boiling filter after spatial reuse: empty reservoirs whose contribution "
                   "exceeds this multiple of their 9x9 neighbourhood's (0: off; biased)")
        ->check(finite_number & CLI::Range(0.0f, 1e30f));
    const std::map<std::string, restir::BiasCorrection> corrections{
        {"none", restir::BiasCorrection::none},
        {"one-over-z", restir::BiasCorrection::one_over_z},
        {"balance-heuristic", restir::BiasCorrection::balance_heuristic},
        {"pairwise", restir::BiasCorrection::pairwise}};
    app.add_option("--bias-correction", settings.bias_correction,
                   "Reuse weights: none (1/M, biased), one-over-z, balance-heuristic, pairwise")
        ->transform(CLI::CheckedTransformer(corrections, CLI::ignore_case).description(""))
        ->default_str("pairwise");
    app.add_option("--visibility-reuse", settings.visibility_reuse,
                   "Zero W of occluded samples before reuse (true/false)");
    app.add_option("--mis-rays", settings.mis_rays,
                   "With visibility reuse, trace the shadow rays of the reuse MIS weights "
                   "(true/false); false assumes samples visible inside the weights (no rays in "
                   "reuse, slightly biased: docs/noise-and-bias.md)");
    const std::map<std::string, pt::CandidateSource> sources{
        {"power", pt::CandidateSource::power}, {"uniform", pt::CandidateSource::uniform}};
    app.add_option("--source", settings.source,
                   "Candidate distribution of ris/restir: power or uniform")
        ->transform(CLI::CheckedTransformer(sources, CLI::ignore_case).description(""))
        ->default_str("power");
    app.add_option("--vpls", settings.vpls, "About this many VPLs (gi vpl)")
        ->check(CLI::Range(0u, 100'000'000u));
    app.add_option("--vpl-bounces", settings.vpl_bounces, "Photon bounce limit")
        ->check(CLI::Range(1u, 64u));
    app.add_option("--vpl-reshoot", settings.vpl_reshoot_interval,
                   "Shoot a new, independent VPL set every N frames (0: one set for the whole "
                   "render)")
        ->check(CLI::Range(0u, 1'000'000u));
    std::optional<std::uint64_t> vpl_seed;
    app.add_option("--vpl-seed", vpl_seed, "Seed of the photons (default: --seed)");
    app.add_option("--attenuation-radius", settings.attenuation_radius,
                   "Yuksel attenuation radius of VPLs in scene units (0: 2 % of the scene size)")
        ->check(finite_number & CLI::Range(0.0f, 1e30f));
    app.add_option("--max-depth", settings.max_depth, "Path length limit (reference, gi path)")
        ->check(CLI::Range(1u, 1024u));

    pt::parse_command_line(app, argc, argv, "restir-render");
    settings.vpl_seed = vpl_seed.value_or(settings.seed);
    check_memory(settings, !options.reference.empty(), options.max_memory_mb);
    for (const auto& [name, values] :
         {std::pair{"--look-from", &options.look_from}, std::pair{"--look-at", &options.look_at}})
        if (!values->empty() && values->size() != 3)
            fail(std::string(name) + " needs three numbers x,y,z, got " +
                 std::to_string(values->size()));
    if (settings.method == pt::Method::restir && settings.spp != 1)
        fail("restir renders one sample per pixel per frame: use --frames instead of --spp");
    if (!options.reference.empty() && settings.motion != pt::CameraMotion::none)
        fail("--reference needs a still camera (--camera-motion none)");

    try {
        pt::Scene scene;
        if (options.scene == "cornell")
            scene = pt::make_cornell_box();
        else if (options.scene == "many-lights")
            scene = pt::make_many_lights(options.lights, options.scene_seed);
        else
            scene = pt::load_obj(options.scene);

        settings.camera = scene.camera
                              ? *scene.camera
                              : pt::frame_bounds(scene, static_cast<float>(settings.width) /
                                                            static_cast<float>(settings.height));
        if (!options.look_from.empty())
            settings.camera.look_from = {options.look_from[0], options.look_from[1],
                                         options.look_from[2]};
        if (!options.look_at.empty())
            settings.camera.look_at = {options.look_at[0], options.look_at[1], options.look_at[2]};
        if (options.fov)
            settings.camera.fov_degrees = *options.fov;
        pt::check_camera(settings.camera);
        for (const std::string& out : options.outs)
            pt::check_output_format(out); // before the render, not after it

        std::optional<pt::Image> reference;
        if (!options.reference.empty()) {
            // It must match the image: nothing larger is read.
            reference = pt::read_image(options.reference,
                                       {std::uint64_t{settings.width} * settings.height});
            if (reference->width != settings.width || reference->height != settings.height)
                fail("the reference " + options.reference + " is " +
                     std::to_string(reference->width) + "x" + std::to_string(reference->height) +
                     " but the image is " + std::to_string(settings.width) + "x" +
                     std::to_string(settings.height));
            const auto bad = std::count_if(
                reference->pixels.begin(), reference->pixels.end(), [](const glm::vec3& p) {
                    return !(std::isfinite(p.x) && std::isfinite(p.y) && std::isfinite(p.z));
                });
            if (bad > 0) // every error measure would be NaN
                fail("the reference " + options.reference + " has " + std::to_string(bad) +
                     " pixel(s) that are not finite");
        }
        std::ofstream csv;
        if (!options.csv.empty()) {
            const std::filesystem::path parent = std::filesystem::path(options.csv).parent_path();
            std::error_code error;
            if (!parent.empty())
                std::filesystem::create_directories(parent, error);
            if (error)
                fail("cannot create the directory " + parent.string() + " for " + options.csv +
                     ": " + error.message());
            csv.open(options.csv);
            if (!csv)
                fail("cannot write " + options.csv);
            csv << "frame,rmse,frame_rmse,frame_ms,elapsed_ms,primary_ms,photons_ms,candidates_ms,"
                   "temporal_ms,spatial_ms,shading_ms,tiles_ms,bias,frame_bias,"
                << error_header() << '\n';
        }

        pt::Renderer renderer(scene, settings);
        std::printf("scene %s: %u triangles, %u emitters, %zu VPLs; %ux%u, %u frame(s)\n",
                    scene.name.c_str(), scene.triangle_count(), renderer.emitter_count(),
                    renderer.vpl_count(), settings.width, settings.height, options.frames);
        if (settings.gi == pt::GlobalIllumination::vpl && settings.vpls > 0 &&
            renderer.vpl_count() == 0)
            std::cerr << "restir-render: warning: no photon left a VPL (no surface reflects "
                         "light): the indirect light is black\n";
        const bool interactive = isatty(fileno(stderr)) != 0;
        double elapsed = 0.0;
        for (std::uint32_t f = 0; f < options.frames; ++f) {
            const pt::FrameTimings t = renderer.render_frame();
            elapsed += t.total;
            std::string error, frame_error, bias, frame_bias;
            if (reference) {
                error = std::to_string(pt::rmse(renderer.accumulated(), *reference));
                frame_error = std::to_string(pt::rmse(renderer.last_frame(), *reference));
                bias = std::to_string(
                    pt::relative_mean_difference(renderer.accumulated(), *reference));
                frame_bias =
                    std::to_string(pt::relative_mean_difference(renderer.last_frame(), *reference));
            }
            std::printf(
                "frame %u: %.1f ms (primary %.1f, photons %.1f, tiles %.1f, candidates %.1f, "
                "temporal %.1f, spatial %.1f, shading %.1f)%s%s\n",
                f + 1, t.total, t.primary, t.photons, t.tiles, t.candidates, t.temporal, t.spatial,
                t.shading, reference ? " rmse " : "", error.c_str());
            std::fflush(stdout);
            if (csv)
                csv << f + 1 << ',' << error << ',' << frame_error << ',' << t.total << ','
                    << elapsed << ',' << t.primary << ',' << t.photons << ',' << t.candidates << ','
                    << t.temporal << ',' << t.spatial << ',' << t.shading << ',' << t.tiles << ','
                    << bias << ',' << frame_bias << ','
                    << error_columns(renderer.accumulated(), reference) << '\n';
            if (interactive)
                progress(f + 1, options.frames, t.total);
        }

        const pt::Image& image = renderer.accumulated();
        const float exposure = options.exposure ? *options.exposure : pt::auto_exposure(image);
        for (const std::string& out : options.outs)
            pt::write_image(out, image, exposure);
        bool black = true;
        for (const glm::vec3& p : image.pixels)
            if (p.x > 0.0f || p.y > 0.0f || p.z > 0.0f) {
                black = false;
                break;
            }
        if (black)
            std::cerr << "restir-render: warning: the image is black: does the camera see the "
                         "lit scene (--look-from, --look-at)?\n";
        std::printf("pixels with a surface: %zu of %zu\n", renderer.surface_pixel_count(),
                    image.pixels.size());
        for (const std::string& out : options.outs)
            std::printf("wrote %s (exposure %.2f)\n", out.c_str(), static_cast<double>(exposure));
    } catch (const pt::SceneError& e) {
        fail(e.what());
    } catch (const pt::ImageError& e) {
        fail(e.what());
    } catch (const std::exception& e) {
        fail(e.what());
    }
    return 0;
}
