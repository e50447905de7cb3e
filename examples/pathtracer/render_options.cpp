#include "render_options.hpp"

#include <CLI/CLI.hpp>

#include <unistd.h>

#include <cmath>
#include <cstdlib>
#include <map>
#include <string>
#include <utility>

namespace pt {
namespace {

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

// The limit a render's estimated memory is checked against: `max_memory_mb`, or without one
// three quarters of the physical memory (0 when unknown: no limit).
std::uint64_t memory_limit_bytes(std::uint64_t max_memory_mb) {
    if (max_memory_mb != 0u) // in bytes, saturating
        return max_memory_mb > (~std::uint64_t{0} >> 20u) ? ~std::uint64_t{0}
                                                          : max_memory_mb << 20u;
    const long pages = sysconf(_SC_PHYS_PAGES);
    const long page_size = sysconf(_SC_PAGE_SIZE);
    if (pages <= 0 || page_size <= 0)
        return 0u; // unknown: no limit
    return static_cast<std::uint64_t>(pages) / 4u * 3u * static_cast<std::uint64_t>(page_size);
}

[[noreturn]] void fail(const std::string& message) { throw UsageError(message); }

// Refuses a render whose estimated memory (estimated_memory_bytes) exceeds the limit, before
// any work starts.
void check_memory(const RenderSettings& settings, bool with_reference, std::uint64_t limit_mb) {
    const std::uint64_t limit = memory_limit_bytes(limit_mb);
    if (limit == 0u)
        return;
    const std::uint64_t needed = estimated_memory_bytes(settings, with_reference);
    if (needed > limit)
        fail("this render needs about " + std::to_string(needed >> 20u) + " MB (" +
             std::to_string(settings.width) + "x" + std::to_string(settings.height) +
             (settings.gi == GlobalIllumination::vpl
                  ? ", " + std::to_string(settings.vpls) + " VPLs"
                  : std::string{}) +
             "), more than the limit of " + std::to_string(limit >> 20u) +
             " MB: make the image or --vpls smaller, or raise --max-memory");
}

} // namespace

std::optional<RenderOptions> parse_render_options(int argc, const char* const* argv,
                                                  std::string& help) {
    RenderOptions options;
    RenderSettings& settings = options.settings;

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
    const std::map<std::string, Method> methods{{"uniform", Method::uniform},
                                                {"ris", Method::ris},
                                                {"restir", Method::restir},
                                                {"reference", Method::reference}};
    app.add_option("--method", settings.method,
                   "uniform: one uniformly chosen light per sample; ris: resampling from "
                   "--candidates; restir: RIS + temporal + spatial reuse; reference: path "
                   "tracer with next-event estimation and MIS")
        ->transform(CLI::CheckedTransformer(methods, CLI::ignore_case).description(""))
        ->default_str("restir");
    const std::map<std::string, GlobalIllumination> gis{{"none", GlobalIllumination::none},
                                                        {"vpl", GlobalIllumination::vpl},
                                                        {"path", GlobalIllumination::path}};
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
    const std::map<std::string, CameraMotion> motions{{"none", CameraMotion::none},
                                                      {"orbit", CameraMotion::orbit}};
    app.add_option("--camera-motion", settings.motion,
                   "none, or orbit: the camera turns about the look-at point a little every "
                   "frame, so temporal reuse goes through real reprojection")
        ->transform(CLI::CheckedTransformer(motions, CLI::ignore_case).description(""))
        ->default_str("none");
    app.add_option("--antialias", settings.antialias,
                   "Jitter primary rays inside the pixel (true/false); off, every method sees "
                   "pixel centres and the RMSE measures lighting noise only");
    app.add_option("--seed", settings.seed, "Seed of every random number");
    app.add_option("--threads", settings.threads, "Worker threads (0: all cores)")
        ->check(CLI::Range(0u, 4096u));
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
    const std::map<std::string, CandidateSource> sources{{"power", CandidateSource::power},
                                                         {"uniform", CandidateSource::uniform}};
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

    try {
        app.parse(argc, argv);
    } catch (const CLI::CallForHelp&) {
        help = app.help();
        return std::nullopt;
    } catch (const CLI::ParseError& e) {
        fail(std::string(e.what()) + " (see --help)");
    }
    settings.vpl_seed = vpl_seed.value_or(settings.seed);
    check_memory(settings, !options.reference.empty(), options.max_memory_mb);
    for (const auto& [name, values] :
         {std::pair{"--look-from", &options.look_from}, std::pair{"--look-at", &options.look_at}})
        if (!values->empty() && values->size() != 3)
            fail(std::string(name) + " needs three numbers x,y,z, got " +
                 std::to_string(values->size()));
    if (settings.method == Method::restir && settings.spp != 1)
        fail("restir renders one sample per pixel per frame: use --frames instead of --spp");
    if (!options.reference.empty() && settings.motion != CameraMotion::none)
        fail("--reference needs a still camera (--camera-motion none)");
    return options;
}

} // namespace pt
