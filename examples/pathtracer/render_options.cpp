#include "render_options.hpp"

#include "environment.hpp"

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
             (uses_vpls(settings.gi) ? ", " + std::to_string(settings.vpls) + " VPLs"
                                     : std::string{}) +
             "), more than the limit of " + std::to_string(limit >> 20u) +
             " MB: make the image or --vpls smaller, or raise --max-memory");
}

// The flags of restir-render's enumerations: names to values, ignoring case.
template <class Enum>
CLI::Validator names(const std::map<std::string, Enum>& values) {
    return CLI::CheckedTransformer(values, CLI::ignore_case).description("");
}

// What is rendered: the scene, the method and the frames.
void add_scene_options(CLI::App& app, RenderOptions& options) {
    RenderSettings& settings = options.settings;
    app.add_option("--scene", options.scene,
                   "cornell (built in, diffuse), cornell-glossy (the same box with a polished "
                   "floor, a metal and a rough block), cornell-spheres (the box lit by three "
                   "emissive spheres), many-lights (procedural, see --lights), "
                   "sun-sky (an open courtyard under a generated sun and sky, --env replaces "
                   "it) or a Wavefront FILE.obj");
    app.add_option("--materials", options.materials,
                   "mtl: the materials as the scene defines them (an OBJ's MTL with its "
                   "specular lobes, docs/renderer.md); diffuse: every material Lambertian in its "
                   "base colour (metals too), as the study's comparisons assume")
        ->transform(
            names<MaterialMode>({{"mtl", MaterialMode::mtl}, {"diffuse", MaterialMode::diffuse}}))
        ->default_str("mtl");
    app.add_option("--lights", options.lights, "Emissive quads of the many-lights scene")
        ->check(CLI::Range(1u, 10'000'000u));
    app.add_option("--scene-seed", options.scene_seed,
                   "Seed of the many-lights scene's layout (apart from --seed, so that renders "
                   "with other pixel seeds see the same scene)");
    app.add_option("--method", settings.method,
                   "uniform: one uniformly chosen light per sample; ris: resampling from "
                   "--candidates; restir: RIS + temporal + spatial reuse; reference: path "
                   "tracer with next-event estimation and MIS")
        ->transform(names<Method>({{"uniform", Method::uniform},
                                   {"ris", Method::ris},
                                   {"restir", Method::restir},
                                   {"reference", Method::reference}}))
        ->default_str("restir");
    app.add_option("--gi", settings.gi,
                   "Indirect light: none, vpl (photon-mapped VPLs sampled with the emitters), "
                   "path (path-traced bounces), restir-gi (path samples reused over time and "
                   "space with the reconnection shift) or restir-pt (whole paths reused with the "
                   "hybrid shift), or vpl-unbiased (VPLs beyond a radius on Lambertian surfaces, "
                   "path samples for the rest: no bias); restir-gi, "
                   "restir-pt and vpl-unbiased: --method restir or reference")
        ->transform(names<GlobalIllumination>({{"none", GlobalIllumination::none},
                                               {"vpl", GlobalIllumination::vpl},
                                               {"path", GlobalIllumination::path},
                                               {"restir-gi", GlobalIllumination::restir_gi},
                                               {"restir-pt", GlobalIllumination::restir_pt},
                                               {"vpl-unbiased", GlobalIllumination::vpl_unbiased}}))
        ->default_str("vpl");
    app.add_option("--spp", settings.spp, "Samples per pixel per frame (restir: 1)")
        ->check(CLI::Range(1u, 65536u));
    app.add_option("--frames", options.frames, "Frames rendered and averaged")
        ->check(CLI::Range(1u, 100000u));
}

// The environment light: a map file, its brightness and its rotation.
void add_environment_options(CLI::App& app, RenderOptions& options) {
    app.add_option("--env", options.environment,
                   "Environment map (.exr or .pfm, equirectangular, +Y up, the centre looking "
                   "down -Z, linear radiance, at most 8192x4096): lights the scene from "
                   "infinitely far and shows where camera rays leave it (any scene; every "
                   "method samples it)");
    app.add_option("--env-scale", options.environment_scale,
                   "Multiplies the environment's radiance (--env or sun-sky's sky)")
        ->check(finite_number & CLI::PositiveNumber);
    app.add_option("--env-rotate", options.environment_rotate,
                   "Turns the environment about +Y by this many degrees")
        ->check(finite_number);
    RenderSettings& settings = options.settings;
    app.add_option("--env-share", settings.environment_share,
                   "The environment's share of the light candidates, in (0, 1); 0 (default): "
                   "in proportion to its power into the scene's bounding sphere")
        ->check(finite_number & CLI::Range(0.0f, 0.99f));
    app.add_option("--env-sampling", settings.environment_sampling,
                   "How candidates find the environment: importance (its map's sampling, as one "
                   "light among the others) or bsdf (only BSDF-sampled candidates, at every "
                   "pixel; needs --bsdf-candidates)")
        ->transform(names<EnvironmentSampling>(
            {{"importance", EnvironmentSampling::importance}, {"bsdf", EnvironmentSampling::bsdf}}))
        ->default_str("importance");
}

// The image and the camera, and how the render runs.
void add_camera_options(CLI::App& app, RenderOptions& options) {
    RenderSettings& settings = options.settings;
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
    app.add_option("--camera-motion", settings.motion,
                   "none, or orbit: the camera turns about the look-at point a little every "
                   "frame, so temporal reuse goes through real reprojection")
        ->transform(
            names<CameraMotion>({{"none", CameraMotion::none}, {"orbit", CameraMotion::orbit}}))
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
}

// The images written and the measurements against a reference.
void add_output_options(CLI::App& app, RenderOptions& options) {
    app.add_option("--out", options.outs,
                   "Output image(s): .png (tone-mapped), .exr or .pfm (linear); repeat the flag "
                   "for several")
        ->multi_option_policy(CLI::MultiOptionPolicy::TakeAll);
    app.add_option("--out-frame", options.frame_outs,
                   "Image(s) of the last frame alone, as a real-time viewer sees it (.png, .exr "
                   "or .pfm; --out's exposure)")
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
}

// The reuse flags as given, made the library's parameters after parsing (`apply`).
struct ReuseFlags {
    std::optional<restir::BiasCorrection> bias_correction; // none given: the preset's
    bool visibility_reuse = true;
    bool mis_rays = true;
    void apply(restir::DiFrameParams& frame) const {
        if (bias_correction) {
            frame.temporal_bias_correction = *bias_correction;
            frame.spatial_bias_correction = *bias_correction;
        }
        frame.visibility = !visibility_reuse ? restir::ReuseVisibility::none
                           : mis_rays        ? restir::ReuseVisibility::traced
                                             : restir::ReuseVisibility::assumed;
    }
};

// --preset, the library's reuse presets, into `settings` and `flags`, then the reuse weights'
// flags. Defined before the other reuse flags: CLI11 stores the options' values in the order
// they are defined, so that a reuse flag given beside --preset changes the preset's value.
void add_reuse_options(CLI::App& app, RenderSettings& settings, ReuseFlags& flags) {
    app.add_option_function<restir::DiFramePreset>(
           "--preset",
           [&settings, &flags](restir::DiFramePreset preset) {
               settings.di_frame = RenderSettings::di_frame_settings(preset);
               settings.preset = preset;
               flags = ReuseFlags{};
               flags.mis_rays = preset != restir::DiFramePreset::fast;
           },
           "ReSTIR's reuse settings (docs/noise-and-bias.md, \"Presets\"): unbiased (the "
           "defaults: 5 neighbours, history cap 4 with permutation sampling), balanced "
           "(unbiased: 3 neighbours in half the radius, cap 20 without permutation, defensive "
           "pairwise MIS; less error a frame, a running mean that converges slower) or fast "
           "(balanced without MIS rays, biased); the reuse flags below change it")
        ->transform(names<restir::DiFramePreset>({{"unbiased", restir::DiFramePreset::unbiased},
                                                  {"balanced", restir::DiFramePreset::balanced},
                                                  {"fast", restir::DiFramePreset::fast}}))
        ->default_str("unbiased");
    app.add_option("--bias-correction", flags.bias_correction,
                   "Reuse weights: none (1/M, biased), one-over-z, balance-heuristic, pairwise, "
                   "defensive-pairwise (docs/noise-and-bias.md); default: the preset's")
        ->transform(names<restir::BiasCorrection>(
            {{"none", restir::BiasCorrection::none},
             {"one-over-z", restir::BiasCorrection::one_over_z},
             {"balance-heuristic", restir::BiasCorrection::balance_heuristic},
             {"pairwise", restir::BiasCorrection::pairwise},
             {"defensive-pairwise", restir::BiasCorrection::defensive_pairwise}}))
        ->default_str("pairwise");
    app.add_option("--visibility-reuse", flags.visibility_reuse,
                   "Zero W of occluded samples before reuse (true/false)");
    app.add_option("--mis-rays", flags.mis_rays,
                   "With visibility reuse, trace the shadow rays of the reuse MIS weights "
                   "(true/false); false assumes samples visible inside the weights (no rays in "
                   "reuse, slightly biased: docs/noise-and-bias.md)");
}

// The candidates and the ReSTIR frame's reuse, straight into the library's parameters.
void add_light_sampling_options(CLI::App& app, RenderSettings& settings) {
    restir::DiFrameParams& frame = settings.di_frame;
    app.add_option("--candidates", settings.candidates,
                   "RIS candidates per pixel (M; 0: 4 from the light BVH, 32 from tiles or grid)")
        ->check(CLI::Range(0u, 4096u));
    app.add_option("--neighbours", frame.spatial.neighbour_count, "Spatial reuse neighbours (k)")
        ->check(CLI::Range(0u, restir::max_reuse_inputs - 1u));
    app.add_option("--radius", frame.spatial.radius,
                   "Spatial reuse radius in pixels (0: two thirds of the preset's at 1080 rows, "
                   "scaled to the image height, at least 3: 20 px at 1080 rows for unbiased, 10 "
                   "for balanced and fast)")
        ->check(finite_number & CLI::Range(0.0f, 1000.0f));
    app.add_option("--spatial-passes", frame.spatial_passes, "Spatial reuse passes")
        ->check(CLI::Range(0u, 16u));
    app.add_option("--history-cap", frame.temporal.history_cap_multiplier,
                   "Temporal history M cap, as a multiple of the current M (0: no cap)");
    app.add_option("--permutation-sampling", frame.temporal.permutation_sampling,
                   "Temporal reuse reads the history of a pixel permuted per frame in 2x2 "
                   "blocks (true/false)");
    app.add_option("--permutation-min-roughness", frame.temporal.permutation_min_roughness,
                   "Permutation sampling only at surfaces at least this rough (perceptual "
                   "roughness; Lambertian surfaces count as 1); smoother ones read their own "
                   "pixel's history")
        ->check(finite_number & CLI::Range(0.0f, 1.0f));
    app.add_option("--spatial-min-roughness", frame.spatial.min_roughness,
                   "Surfaces smoother than this (perceptual roughness; Lambertian surfaces count "
                   "as 1) take no spatial neighbours")
        ->check(finite_number & CLI::Range(0.0f, 1.0f));
    app.add_option("--packed-history", settings.packed_history,
                   "Keep the temporal history packed, 28 bytes a pixel instead of 64, its light "
                   "points decoded from the light set when read: the same image, less memory, a "
                   "light lookup per pixel (true/false)");
    app.add_option("--boiling-filter", frame.boiling.threshold,
                   "Boiling filter after spatial reuse: empty reservoirs whose contribution "
                   "exceeds this multiple of their 9x9 neighbourhood's (0: off; biased)")
        ->check(finite_number & CLI::Range(0.0f, 1e30f));
    app.add_option("--source", settings.source,
                   "Candidate distribution of ris/restir: auto (default: bvh for scenes of 64 "
                   "or more emitters or with sphere lights drawn by solid angle, else power; "
                   "docs/performance.md), power or "
                   "uniform (from light tiles), bvh (by importance at the pixel's surface, a "
                   "light BVH drawn per pixel: far better candidates, each costing more; lower "
                   "--candidates) or grid (by "
                   "importance in the pixel's cell of a world-space grid, tiles per cell "
                   "resampled from power-proportional candidates every frame; --grid-cells)")
        ->transform(names<CandidateSource>({{"auto", CandidateSource::automatic},
                                            {"power", CandidateSource::power},
                                            {"uniform", CandidateSource::uniform},
                                            {"bvh", CandidateSource::bvh},
                                            {"grid", CandidateSource::grid}}))
        ->default_str("auto");
    app.add_option("--grid-cells", settings.grid_cells,
                   "--source grid: cells along the longest side of the scene's box (the other "
                   "sides in cells of about that size); 32 suits the many-lights scene, 8 the "
                   "Cornell boxes (docs/performance.md)")
        ->check(CLI::Range(1u, 256u));
}

// Sampling and reuse at glossy surfaces.
void add_glossy_options(CLI::App& app, RenderSettings& settings) {
    app.add_option("--bsdf-candidates", settings.bsdf_candidates,
                   "BSDF-sampled candidates per glossy pixel smoother than "
                   "--bsdf-max-roughness, combined by MIS with --candidates "
                   "light candidates from --source (power or uniform tiles, the BVH; drawn per "
                   "pixel by power with --source grid, or tiles with --light-points "
                   "solid-angle) (0: light candidates from --source alone)")
        ->check(CLI::Range(0u, 1024u));
    app.add_option("--bsdf-light-candidates", settings.bsdf_light_candidates,
                   "Light candidates beside BSDF candidates: at most this many of --candidates "
                   "(0: all of them)")
        ->check(CLI::Range(0u, 4096u));
    app.add_option("--bsdf-max-roughness", settings.bsdf_max_roughness,
                   "BSDF candidates only at glossy pixels smoother than this (perceptual "
                   "roughness): narrow lobes, which light candidates rarely hit; 1: every glossy "
                   "pixel")
        ->check(finite_number & CLI::Range(0.0f, 1.0f));
}

// How candidates' points on emitters are drawn.
void add_light_point_options(CLI::App& app, RenderSettings& settings) {
    app.add_option("--light-points", settings.light_points,
                   "Points on emitters of ris/restir candidates: area (uniform in area), "
                   "solid-angle (uniform in the solid angle seen from the pixel: no fireflies "
                   "next to lights; light tiles draw the chosen candidate's point on a triangle "
                   "again) or auto (default: solid-angle in scenes with sphere lights, else area)")
        ->transform(names<LightPoints>({{"area", LightPoints::area},
                                        {"solid-angle", LightPoints::solid_angle},
                                        {"auto", LightPoints::automatic}}))
        ->default_str("auto");
}

// Indirect light: the VPLs' photons and the path tracer's depth. The photons' seed is
// --vpl-seed, or --seed without it: `vpl_seed` holds it until parsing ends.
void add_indirect_light_options(CLI::App& app, RenderSettings& settings,
                                std::optional<std::uint64_t>& vpl_seed) {
    app.add_option("--vpls", settings.vpls, "About this many VPLs (gi vpl and vpl-unbiased)")
        ->check(CLI::Range(0u, 100'000'000u));
    app.add_option("--vpl-bounces", settings.photons.max_bounces,
                   "Photon bounce limit (gi vpl; vpl-unbiased takes --max-depth - 1)")
        ->check(CLI::Range(1u, 64u));
    app.add_option("--vpl-reshoot", settings.vpl_reshoot_interval,
                   "Shoot a new, independent VPL set every N frames (0: one set for the whole "
                   "render)")
        ->check(CLI::Range(0u, 1'000'000u));
    app.add_option("--vpl-seed", vpl_seed, "Seed of the photons (default: --seed)");
    app.add_option("--attenuation-radius", settings.attenuation_radius,
                   "Yuksel attenuation radius of VPLs in scene units (0: 2 % of the scene size)")
        ->check(finite_number & CLI::Range(0.0f, 1e30f));
    app.add_option("--partition-radius", settings.partition_radius,
                   "gi vpl-unbiased: the distance, as a share of the scene size, within which "
                   "path samples carry the light that VPLs carry beyond it")
        ->check(finite_number & CLI::Range(1e-4f, 10.0f));
    app.add_option("--vpl-path-part", settings.vpl_path_part,
                   "gi vpl-unbiased: the light that VPLs leave out from path samples reused by "
                   "ReSTIR GI's frame (reuse) or from one independent path sample a pixel "
                   "(independent)")
        ->transform(names<VplPathPart>(
            {{"reuse", VplPathPart::reuse}, {"independent", VplPathPart::independent}}))
        ->default_str("independent");
    app.add_option("--max-depth", settings.max_depth,
                   "Path length limit (reference, gi path, restir-gi and restir-pt)")
        ->check(CLI::Range(1u, 1024u));
    app.add_option("--gi-min-roughness", settings.reconnection.min_roughness,
                   "restir-gi: the roughness a sample point needs to be reused at another "
                   "visible point (Lambertian: 1; 0 reconnects every sample point, biased on "
                   "glossy ones)")
        ->check(finite_number & CLI::Range(0.0f, 1.0f));
    app.add_option("--pt-min-roughness", settings.pt_reconnection.min_roughness,
                   "restir-pt: the roughness both ends of a path's segment need for the hybrid "
                   "shift to reconnect there (the vertices before it are replayed)")
        ->check(finite_number & CLI::Range(0.0f, 1.0f));
    app.add_option("--pt-min-distance", settings.pt_reconnection.min_distance,
                   "restir-pt: the length, as a fraction of the scene's size, that a segment "
                   "needs for the hybrid shift to reconnect there")
        ->check(finite_number & CLI::Range(0.0f, 1.0f));
    app.add_flag("--indirect-only", settings.indirect_only,
                 "Frames hold indirect light only (gi path, restir-gi or restir-pt, and the "
                 "reference): to measure its error alone");
}

// The checks that involve several flags, and the memory estimate.
void check_consistent(const RenderOptions& options) {
    const RenderSettings& settings = options.settings;
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
    // A packed history decodes a point's 1 / area_pdf from the light set by area; a point drawn
    // from the pixel carries its own, which the stored W belongs to.
    if (settings.packed_history && settings.light_points == LightPoints::solid_angle)
        fail("--packed-history decodes light points as area samples: use --light-points area "
             "with it");
    if (reuses_paths(settings.gi) && settings.method != Method::restir &&
        settings.method != Method::reference)
        fail("--gi restir-gi, restir-pt and vpl-unbiased reuse path samples across frames: use "
             "--method restir (or reference for their converged image)");
    if (settings.indirect_only && settings.gi == GlobalIllumination::vpl_unbiased &&
        settings.method == Method::restir)
        fail("--indirect-only cannot part the VPLs of --gi vpl-unbiased from the emitters' "
             "direct light: compare whole images");
    if (settings.indirect_only && !traces_indirect_paths(settings.gi) &&
        settings.gi != GlobalIllumination::vpl_unbiased)
        fail("--indirect-only keeps the indirect light of --gi path, restir-gi or restir-pt: "
             "give one");
    if (settings.environment_sampling == EnvironmentSampling::bsdf && settings.bsdf_candidates == 0)
        fail("--env-sampling bsdf finds the environment through BSDF candidates only: give "
             "--bsdf-candidates N");
}

} // namespace

Scene load_scene(const RenderOptions& options) {
    Scene scene = options.scene == "cornell"           ? make_cornell_box()
                  : options.scene == "cornell-glossy"  ? make_glossy_cornell_box()
                  : options.scene == "cornell-spheres" ? make_cornell_spheres()
                  : options.scene == "many-lights"
                      ? make_many_lights(options.lights, options.scene_seed)
                  : options.scene == "sun-sky" ? make_sun_sky_scene(nullptr)
                                               : load_obj(options.scene);
    if (options.materials == MaterialMode::diffuse)
        make_materials_diffuse(scene);
    if (!options.environment.empty())
        scene.environment = load_environment(options.environment, options.environment_scale,
                                             options.environment_rotate);
    else if (options.scene == "sun-sky")
        scene.environment = make_sun_sky_environment(SunSkyParams{}, options.environment_scale,
                                                     options.environment_rotate);
    return scene;
}

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
    std::optional<std::uint64_t> vpl_seed;
    add_scene_options(app, options);
    add_environment_options(app, options);
    add_camera_options(app, options);
    add_output_options(app, options);
    ReuseFlags reuse_flags;
    add_reuse_options(app, settings, reuse_flags);
    add_light_sampling_options(app, settings);
    add_light_point_options(app, settings);
    add_glossy_options(app, settings);
    add_indirect_light_options(app, settings, vpl_seed);
    try {
        app.parse(argc, argv);
    } catch (const CLI::CallForHelp&) {
        help = app.help();
        return std::nullopt;
    } catch (const CLI::ParseError& e) {
        fail(std::string(e.what()) + " (see --help)");
    }
    settings.photons.seed = vpl_seed.value_or(settings.seed);
    settings.di_frame.boiling_filter = settings.di_frame.boiling.threshold > 0.0f;
    reuse_flags.apply(settings.di_frame);
    check_consistent(options);
    return options;
}

} // namespace pt
