// Streaks in the example renderer's images. A VPL whose shadow ray ended exactly on the surface
// the VPL lies on was occluded or not as rounding decided, which drew full-width bright and
// dark rows on the Cornell box's back wall, in the reference and, through reuse, in ReSTIR's
// error. Here: the back wall of a VPL reference has no more row structure than its noise, and
// the error of RIS and ReSTIR is no more correlated along rows than along columns.
#include "error_metrics.hpp"
#include "image_io.hpp"
#include "renderer.hpp"
#include "scene.hpp"

#include <gtest/gtest.h>

#include <cmath>
#include <cstdint>
#include <cstdio>
#include <vector>

namespace {

using pt::GlobalIllumination;
using pt::Method;

// The size and frame counts: the row ratio of independent noise on the back wall region
// (x in [0.25, 0.75), y in [0.25, 0.39)) is sqrt(0.9 / region width), measured over the
// region's rows with a relative standard error of sqrt(1.22 / (2 rows)) (the high-pass
// correlates neighbouring rows). At 384 x 384 (192 x 54 pixels) that is 0.068 +- 11 %: a
// renderer without streaks stays below 0.1, 4.3 standard errors above, at any frame count;
// streaks, fixed per pixel, stand out more with every frame (32 frames: 0.31). A Debug build
// (sanitizers, many times slower) renders fewer frames: it checks the same noise-only bound,
// but tells streaks apart less surely.
#ifdef NDEBUG
constexpr std::uint32_t reference_frames = 32;
constexpr std::uint32_t frames = 8;
#else
constexpr std::uint32_t reference_frames = 8;
constexpr std::uint32_t frames = 4;
#endif
constexpr std::uint32_t size = 384;

pt::RenderSettings settings(const pt::Scene& scene, Method method) {
    pt::RenderSettings s;
    s.width = size;
    s.height = size;
    s.camera = *scene.camera;
    s.method = method;
    s.gi = GlobalIllumination::vpl;
    s.threads = 2;
    return s;
}

pt::Image render(const pt::Scene& scene, Method method, std::uint32_t frame_count) {
    pt::Renderer renderer(scene, settings(scene, method));
    for (std::uint32_t f = 0; f < frame_count; ++f)
        renderer.render_frame();
    return renderer.accumulated();
}

// The Cornell box and its VPL reference, rendered once for every test here.
struct Shared {
    pt::Scene scene = pt::make_cornell_box();
    pt::Image reference = render(scene, Method::reference, reference_frames);
};

const Shared& shared() {
    static const Shared instance;
    return instance;
}

// Standard error of error_autocorrelation's estimate at lag (dx, dy), for errors independent
// between pixels but of any variance per pixel: sqrt(sum of e_i^2 e_j^2 over the pairs) / pairs,
// divided by the variance (e the channel-summed error, its mean removed).
double autocorrelation_standard_error(const pt::Image& image, const pt::Image& reference,
                                      std::uint32_t dx, std::uint32_t dy) {
    std::vector<double> e(image.pixels.size());
    double mean = 0.0;
    for (std::size_t i = 0; i < e.size(); ++i) {
        const glm::vec3 d = image.pixels[i] - reference.pixels[i];
        e[i] = static_cast<double>(d.x) + static_cast<double>(d.y) + static_cast<double>(d.z);
        mean += e[i] / static_cast<double>(e.size());
    }
    double variance = 0.0;
    for (double& v : e) {
        v -= mean;
        variance += v * v / static_cast<double>(e.size());
    }
    double squares = 0.0;
    double pairs = 0.0;
    for (std::uint32_t y = 0; y + dy < image.height; ++y)
        for (std::uint32_t x = 0; x + dx < image.width; ++x) {
            const double a = e[x + std::size_t{y} * image.width];
            const double b = e[x + dx + std::size_t{y + dy} * image.width];
            squares += a * a * b * b;
            pairs += 1.0;
        }
    return std::sqrt(squares) / pairs / variance;
}

TEST(ImageStructure, VplReferenceHasNoStreaksOnTheBackWall) {
    const pt::Region wall = pt::cornell_back_wall_region(size, size);
    const pt::RowStructure rows = pt::row_structure(shared().reference, wall);
    const double noise_only = std::sqrt(0.9 / (wall.x1 - wall.x0));
    std::printf("back wall of the VPL reference, %u frames: row ratio %.4f (noise alone %.4f), "
                "column ratio %.4f\n",
                reference_frames, rows.row_ratio, noise_only, rows.column_ratio);
    EXPECT_LT(rows.row_ratio, 0.1);
}

TEST(ImageStructure, ErrorIsAsCorrelatedAlongRowsAsAlongColumns) {
    const Shared& s = shared();
    for (Method method : {Method::ris, Method::restir}) {
        const pt::Image image = render(s.scene, method, frames);
        const pt::ErrorAutocorrelation acf = pt::error_autocorrelation(image, s.reference);
        const char* name = method == Method::ris ? "ris" : "restir";
        for (std::uint32_t lag = 1; lag <= 8; ++lag) {
            const double se_x = autocorrelation_standard_error(image, s.reference, lag, 0);
            const double se_y = autocorrelation_standard_error(image, s.reference, 0, lag);
            const double bound = 4.0 * std::sqrt(se_x * se_x + se_y * se_y);
            std::printf("%s lag %u: acf x %+.4f, y %+.4f, difference %+.4f (bound %.4f)\n", name,
                        lag, acf.acf_x[lag], acf.acf_y[lag], acf.acf_x[lag] - acf.acf_y[lag],
                        bound);
            EXPECT_LT(std::abs(acf.acf_x[lag] - acf.acf_y[lag]), bound) << name << " lag " << lag;
        }
    }
}

} // namespace
