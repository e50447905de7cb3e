// restir-render: the Embree example renderer. Renders a scene with uniform light sampling,
// RIS, ReSTIR or a reference path tracer, with optional VPL or path-traced global
// illumination, over several frames, and measures the error against a reference image.
// `restir-render --help` lists every flag.
#include "camera.hpp"
#include "command_line.hpp"
#include "environment.hpp"
#include "error_metrics.hpp"
#include "image_io.hpp"
#include "render_options.hpp"
#include "renderer.hpp"
#include "scene.hpp"

#include <algorithm>
#include <cmath>
#include <cstdio>
#include <cstdlib>
#include <filesystem>
#include <fstream>
#include <iostream>
#include <optional>
#include <string>
#include <utility>
#include <vector>

namespace {

[[noreturn]] void fail(const std::string& message) { pt::fail("restir-render", message); }

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

// The CSV's glossy and flicker columns: over the glossy pixels, the MSE of the accumulated
// image and of the frame alone against the reference (empty without one), and the flicker, the
// mean squared difference between this frame and the last over every pixel and over the glossy
// ones (static camera: twice the per-pixel frame-to-frame variance; empty in the first frame).
constexpr const char* glossy_header = "mse_glossy,frame_mse_glossy,flicker,flicker_glossy";

std::string glossy_columns(const pt::Renderer& renderer, const std::optional<pt::Image>& reference,
                           const std::optional<pt::Image>& previous_frame) {
    const std::vector<std::uint8_t> glossy = renderer.glossy_pixels();
    std::string columns;
    if (reference)
        columns = number(pt::masked_mse(renderer.accumulated(), *reference, glossy)) + "," +
                  number(pt::masked_mse(renderer.last_frame(), *reference, glossy));
    else
        columns = ",";
    columns += ",";
    if (previous_frame)
        columns += number(pt::masked_mse(renderer.last_frame(), *previous_frame, {})) + "," +
                   number(pt::masked_mse(renderer.last_frame(), *previous_frame, glossy));
    else
        columns += ",";
    return columns;
}

// --- The camera ------------------------------------------------------------------------------

// The scene's camera (or one framing its bounds) with the flags' changes, checked.
pt::CameraSetup camera_of(const pt::Scene& scene, const pt::RenderOptions& options) {
    const pt::RenderSettings& settings = options.settings;
    pt::CameraSetup camera = scene.camera
                                 ? *scene.camera
                                 : pt::frame_bounds(scene, static_cast<float>(settings.width) /
                                                               static_cast<float>(settings.height));
    if (!options.look_from.empty())
        camera.look_from = {options.look_from[0], options.look_from[1], options.look_from[2]};
    if (!options.look_at.empty())
        camera.look_at = {options.look_at[0], options.look_at[1], options.look_at[2]};
    if (options.fov)
        camera.fov_degrees = *options.fov;
    pt::check_camera(camera);
    return camera;
}

// --- Measurement -----------------------------------------------------------------------------

// The reference image, if any: exactly the image's size (nothing larger is read), every pixel
// finite.
std::optional<pt::Image> read_reference(const pt::RenderOptions& options) {
    if (options.reference.empty())
        return std::nullopt;
    const pt::RenderSettings& settings = options.settings;
    pt::Image reference =
        pt::read_image(options.reference, {std::uint64_t{settings.width} * settings.height});
    if (reference.width != settings.width || reference.height != settings.height)
        fail("the reference " + options.reference + " is " + std::to_string(reference.width) + "x" +
             std::to_string(reference.height) + " but the image is " +
             std::to_string(settings.width) + "x" + std::to_string(settings.height));
    if (const std::size_t bad = pt::non_finite_pixels(reference); bad > 0)
        fail("the reference " + options.reference + " has " + std::to_string(bad) +
             " pixel(s) that are not finite");
    return reference;
}

// The CSV file (its directory created) with its header row; closed without --csv.
std::ofstream open_csv(const std::string& path) {
    std::ofstream csv;
    if (path.empty())
        return csv;
    const std::filesystem::path parent = std::filesystem::path(path).parent_path();
    std::error_code error;
    if (!parent.empty())
        std::filesystem::create_directories(parent, error);
    if (error)
        fail("cannot create the directory " + parent.string() + " for " + path + ": " +
             error.message());
    csv.open(path);
    if (!csv)
        fail("cannot write " + path);
    csv << "frame,rmse,frame_rmse,frame_ms,elapsed_ms,primary_ms,photons_ms,candidates_ms,"
           "temporal_ms,spatial_ms,shading_ms,tiles_ms,indirect_ms,bias,frame_bias,"
        << error_header() << ',' << glossy_header << '\n';
    return csv;
}

// One frame's line on stdout and row of the CSV: timings and, with a reference, the error of
// the accumulated image and of the frame alone.
void report_frame(std::uint32_t frame, const pt::FrameTimings& t, double elapsed,
                  const pt::Renderer& renderer, const std::optional<pt::Image>& reference,
                  const std::optional<pt::Image>& previous_frame, std::ofstream& csv) {
    std::string error, frame_error, bias, frame_bias;
    if (reference) {
        error = std::to_string(pt::rmse(renderer.accumulated(), *reference));
        frame_error = std::to_string(pt::rmse(renderer.last_frame(), *reference));
        bias = std::to_string(pt::relative_mean_difference(renderer.accumulated(), *reference));
        frame_bias =
            std::to_string(pt::relative_mean_difference(renderer.last_frame(), *reference));
    }
    char indirect[32] = ""; // the ReSTIR GI frame's phase, where it runs
    if (t.indirect > 0.0)
        std::snprintf(indirect, sizeof indirect, ", indirect %.1f", t.indirect);
    std::printf("frame %u: %.1f ms (primary %.1f, photons %.1f, tiles %.1f, candidates %.1f, "
                "temporal %.1f, spatial %.1f, shading %.1f%s)%s%s\n",
                frame, t.total, t.primary, t.photons, t.tiles, t.candidates, t.temporal, t.spatial,
                t.shading, indirect, reference ? " rmse " : "", error.c_str());
    std::fflush(stdout);
    if (csv)
        csv << frame << ',' << error << ',' << frame_error << ',' << t.total << ',' << elapsed
            << ',' << t.primary << ',' << t.photons << ',' << t.candidates << ',' << t.temporal
            << ',' << t.spatial << ',' << t.shading << ',' << t.tiles << ',' << t.indirect << ','
            << bias << ',' << frame_bias << ',' << error_columns(renderer.accumulated(), reference)
            << ',' << glossy_columns(renderer, reference, previous_frame) << '\n';
}

// --- The frames ------------------------------------------------------------------------------

// Renders and reports every frame, with a progress bar on a terminal.
void render_frames(pt::Renderer& renderer, const pt::RenderOptions& options,
                   const std::optional<pt::Image>& reference, std::ofstream& csv) {
    const bool interactive = isatty(fileno(stderr)) != 0;
    double elapsed = 0.0;
    std::optional<pt::Image> previous_frame; // for the flicker columns
    for (std::uint32_t f = 0; f < options.frames; ++f) {
        const pt::FrameTimings t = renderer.render_frame();
        elapsed += t.total;
        report_frame(f + 1, t, elapsed, renderer, reference, previous_frame, csv);
        if (csv)
            previous_frame = renderer.last_frame();
        if (interactive)
            progress(f + 1, options.frames, t.total);
    }
}

// --- Image output ----------------------------------------------------------------------------

bool is_black(const pt::Image& image) {
    return std::none_of(image.pixels.begin(), image.pixels.end(),
                        [](const glm::vec3& p) { return p.x > 0.0f || p.y > 0.0f || p.z > 0.0f; });
}

// The accumulated image in every --out file, a warning if it is black, and a summary.
void write_outputs(const pt::Renderer& renderer, const pt::RenderOptions& options) {
    const pt::Image& image = renderer.accumulated();
    const float exposure = options.exposure ? *options.exposure : pt::auto_exposure(image);
    for (const std::string& out : options.outs)
        pt::write_image(out, image, exposure);
    for (const std::string& out : options.frame_outs)
        pt::write_image(out, renderer.last_frame(), exposure);
    if (is_black(image))
        std::cerr << "restir-render: warning: the image is black: does the camera see the "
                     "lit scene (--look-from, --look-at)?\n";
    std::printf("pixels with a surface: %zu of %zu\n", renderer.surface_pixel_count(),
                image.pixels.size());
    for (const auto* outs : {&options.outs, &options.frame_outs})
        for (const std::string& out : *outs)
            std::printf("wrote %s (exposure %.2f)\n", out.c_str(), static_cast<double>(exposure));
}

// ", environment NAME WxH" for a scene with an environment, else nothing.
std::string environment_summary(const pt::Scene& scene) {
    if (!scene.environment)
        return {};
    return ", environment " + scene.environment->name + " " +
           std::to_string(scene.environment->map.width()) + "x" +
           std::to_string(scene.environment->map.height());
}

// "; 32 candidates by power" for the RIS methods: the source and count the render resolved.
std::string candidates_summary(const pt::RenderSettings& settings) {
    if (settings.method != pt::Method::ris && settings.method != pt::Method::restir)
        return {};
    const char* source = "by power";
    switch (settings.source) {
    case pt::CandidateSource::uniform:
        source = "uniformly";
        break;
    case pt::CandidateSource::bvh:
        source = "from the light BVH";
        break;
    case pt::CandidateSource::grid:
        source = "from the light grid";
        break;
    case pt::CandidateSource::power:
    case pt::CandidateSource::automatic:
        break;
    }
    return "; " + std::to_string(settings.candidates) + " candidates " + source;
}

// The scene's light shapes after its triangle count ("+ 3 light shapes"), nothing without any.
std::string shapes_summary(const pt::Scene& scene) {
    const std::uint32_t count = scene.shapes.count();
    return count == 0u ? std::string() : " + " + std::to_string(count) + " light shapes";
}

// Loads the scene, checks everything that can be checked before the render, renders, measures
// and writes the image.
void run(pt::RenderOptions& options) {
    pt::RenderSettings& settings = options.settings;
    const pt::Scene scene = pt::load_scene(options);
    settings.camera = camera_of(scene, options);
    for (const auto* outs : {&options.outs, &options.frame_outs})
        for (const std::string& out : *outs)
            pt::check_output_format(out); // before the render, not after it
    const std::optional<pt::Image> reference = read_reference(options);
    std::ofstream csv = open_csv(options.csv);

    pt::Renderer renderer(scene, settings);
    std::printf("scene %s: %u triangles%s, %u emitters, %zu VPLs%s; %ux%u, %u frame(s)%s\n",
                scene.name.c_str(), scene.triangle_count(), shapes_summary(scene).c_str(),
                renderer.emitter_count(), renderer.vpl_count(), environment_summary(scene).c_str(),
                settings.width, settings.height, options.frames,
                candidates_summary(renderer.settings()).c_str());
    const bool unbiased = settings.gi == pt::GlobalIllumination::vpl_unbiased;
    const bool vpl_bounces = !unbiased || settings.max_depth > 1; // unbiased: max-depth - 1
    if (pt::uses_vpls(settings.gi) && settings.vpls > 0 && vpl_bounces && renderer.vpl_count() == 0)
        std::cerr << (unbiased ? "restir-render: warning: no photon left a VPL (they lie on "
                                 "Lambertian surfaces alone): path samples carry all the "
                                 "indirect light\n"
                               : "restir-render: warning: no photon left a VPL (no surface "
                                 "reflects light): the indirect light is black\n");
    render_frames(renderer, options, reference, csv);
    write_outputs(renderer, options);
}

} // namespace

int main(int argc, char** argv) {
    std::string help;
    std::optional<pt::RenderOptions> options;
    try {
        options = pt::parse_render_options(argc, argv, help);
    } catch (const pt::UsageError& e) {
        fail(e.what());
    }
    if (!options) {
        std::cout << help;
        return 0;
    }
    try {
        run(*options);
    } catch (const std::exception& e) {
        fail(e.what());
    }
    return 0;
}
