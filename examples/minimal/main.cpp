// Minimal integration of restir: a diffuse ground plane lit by 2000 small point lights, seen by
// an orthographic camera looking straight down. There is no ray tracer: nothing casts shadows.
// The application exposes its own types through the bridge (restir/concepts.hpp) and renders
// the scene three ways, one panel each, left to right:
//   uniform   - one light chosen uniformly per pixel, estimate f(x) / pmf(x);
//   RIS       - one light resampled from 32 power-sampled candidates, estimate f(y) * W;
//   reference - the exact sum over all lights.
// Usage: restir-minimal [OUTPUT.png]   (default out/minimal.png)
#include <restir/restir.hpp>

#pragma GCC diagnostic push
#pragma GCC diagnostic ignored "-Wconversion"
#pragma GCC diagnostic ignored "-Wold-style-cast"
#pragma GCC diagnostic ignored "-Wmissing-field-initializers"
#define STB_IMAGE_WRITE_IMPLEMENTATION
#include <stb/stb_image_write.h>
#pragma GCC diagnostic pop

#include <glm/geometric.hpp>

#include <algorithm>
#include <cmath>
#include <cstdint>
#include <cstdio>
#include <filesystem>
#include <numbers>
#include <vector>

namespace toy {

constexpr std::uint32_t kSize = 256; // Each panel is kSize x kSize pixels.
constexpr std::uint32_t kLightCount = 2000;
constexpr std::uint32_t kCandidates = 32; // RIS candidates per pixel.
constexpr std::uint64_t kSeed = 7;
constexpr float kAlbedo = 0.8f;
constexpr float kLightRadius = 0.005f; // Yuksel attenuation radius: no 1/d^2 singularity.

float luminance(glm::vec3 c) { return glm::dot(c, glm::vec3(0.2126f, 0.7152f, 0.0722f)); }

// Bridge, surface: a G-buffer texel. Every pixel sees the plane y = 0 from a camera at y = 2.
struct GroundPoint {
    glm::vec3 position;
};
glm::vec3 surface_position(const GroundPoint& p) { return p.position; }
glm::vec3 surface_normal(const GroundPoint&) { return {0.0f, 1.0f, 0.0f}; }
float surface_depth(const GroundPoint& p) { return 2.0f - p.position.y; }
bool is_valid_surface(const GroundPoint&) { return true; }

// Bridge, light set: point lights are the same point for every uv, with area_pdf 1.
struct PointLight {
    glm::vec3 position;
    glm::vec3 intensity;
};
struct PointLights {
    std::vector<PointLight> lights;
    std::uint32_t light_count() const { return static_cast<std::uint32_t>(lights.size()); }
    restir::LightSample sample_point(std::uint32_t id, glm::vec2 /*uv*/) const {
        return {.position = lights[id].position,
                .radiance = lights[id].intensity,
                .area_pdf = 1.0f,
                .is_delta = true};
    }
};

// Unshadowed contribution f of one light point: albedo / pi * I * cos(theta) * falloff(d).
template <restir::Surface S, restir::LightPoint P>
glm::vec3 shade(const S& surface, const P& light) {
    const glm::vec3 to_light = light.position - surface_position(surface);
    const float distance = glm::length(to_light);
    const float cosine = std::max(glm::dot(surface_normal(surface), to_light) / distance, 0.0f);
    return kAlbedo * std::numbers::inv_pi_v<float> * cosine *
           restir::yuksel_falloff(distance, kLightRadius) * light.radiance;
}

// Bridge, target function p-hat: the luminance of f.
struct TargetLuminance {
    const PointLights* lights;
    float operator()(const restir::LightSampleRef& ref, const GroundPoint& surface) const {
        return luminance(shade(surface, lights->sample_point(ref.light_id, ref.uv)));
    }
};

static_assert(restir::Surface<GroundPoint>);
static_assert(restir::LightSet<PointLights>);
static_assert(restir::TargetFunction<TargetLuminance, restir::LightSampleRef, GroundPoint>);

// Lights at random small heights, random tints, powers spanning three orders of magnitude.
PointLights make_lights() {
    restir::Pcg32 rng;
    rng.seed(kSeed, 0u);
    const auto u = [&] { return next_float(rng); };
    PointLights set;
    for (std::uint32_t i = 0; i < kLightCount; ++i) { // Braced lists evaluate left to right.
        const glm::vec3 position{2.2f * u() - 1.1f, 0.03f + 0.15f * u(), 2.2f * u() - 1.1f};
        const glm::vec3 tint{0.1f + u(), 0.1f + u(), 0.1f + u()};
        const float power = std::pow(10.0f, 3.0f * u()); // 1 to 1000
        set.lights.push_back({position, power * tint / (tint.r + tint.g + tint.b)});
    }
    return set;
}

// ---- The three panels ----

constexpr std::uint32_t kPixels = kSize * kSize;
using Panel = std::vector<glm::vec3>;

struct Panels {
    Panel uniform = Panel(kPixels);
    Panel ris = Panel(kPixels);
    Panel reference = Panel(kPixels);
};

// The ground point that pixel `pixel` of a panel sees.
GroundPoint ground_point(std::uint32_t pixel) {
    const float x = (2.0f * float(pixel % kSize) + 1.0f) / kSize - 1.0f; // [-1, 1]
    const float z = (2.0f * float(pixel / kSize) + 1.0f) / kSize - 1.0f;
    return {{x, 0.0f, z}};
}

// Every pixel by the three estimators, each with its own counter-based RNG pass.
Panels render(const PointLights& lights) {
    const TargetLuminance target{&lights};
    // Source distributions: uniform for the baseline, power (alias table) for RIS candidates.
    const restir::UniformLightSampler uniform{lights.light_count()};
    std::vector<float> powers;
    for (const PointLight& light : lights.lights)
        powers.push_back(luminance(light.intensity));
    const restir::AliasTable table(powers);
    const restir::PowerLightSampler power{table.view()};

    Panels panels;
    for (std::uint32_t pixel = 0; pixel < kPixels; ++pixel) {
        const GroundPoint surface = ground_point(pixel);

        // Uniform: one light, f / pmf.
        restir::Pcg32 rng = restir::make_pixel_rng(pixel, /*frame=*/0u, /*pass=*/0u, kSeed);
        const restir::DiscreteSample pick = restir::sample_light(uniform, rng);
        panels.uniform[pixel] = shade(surface, lights.sample_point(pick.index, {})) / pick.pmf;

        // RIS: candidates x_i from the power sampler with pdf p(x_i), kept in proportion to
        // p-hat(x_i) / p(x_i); W then makes f(y) * W an unbiased estimate of the full sum.
        rng = restir::make_pixel_rng(pixel, /*frame=*/0u, /*pass=*/1u, kSeed);
        const auto draw = [&](restir::Pcg32& r) { return restir::draw_light_candidate(power, r); };
        const auto p_hat = [&](const restir::LightSampleRef& ref) { return target(ref, surface); };
        const auto reservoir = restir::resample_ris(rng, kCandidates, draw, p_hat);
        const restir::LightSampleRef& y = reservoir.sample;
        panels.ris[pixel] = shade(surface, lights.sample_point(y.light_id, y.uv)) *
                            reservoir.contribution_weight; // W = 0 when nothing was kept.

        for (std::uint32_t id = 0; id < lights.light_count(); ++id)
            panels.reference[pixel] += shade(surface, lights.sample_point(id, {}));
    }
    return panels;
}

// ---- Error and output ----

double mean_luminance(const Panel& panel) {
    double mean = 0.0;
    for (const glm::vec3& c : panel)
        mean += double(luminance(c)) / kPixels;
    return mean;
}

// RMSE against the reference, relative to its mean luminance.
double relative_rmse(const Panel& image, const Panel& reference, double mean) {
    double sum = 0.0;
    for (std::uint32_t i = 0; i < kPixels; ++i)
        sum += double(glm::dot(image[i] - reference[i], image[i] - reference[i]));
    return std::sqrt(sum / (3.0 * kPixels)) / mean;
}

constexpr std::uint32_t kGap = 4, kWidth = 3 * kSize + 2 * kGap;

// The panels side by side, tone mapped: times `exposure`, clamped, sRGB curve.
std::vector<std::uint8_t> tone_map(const Panels& panels, float exposure) {
    std::vector<std::uint8_t> rgb(kWidth * kSize * 3, 24);
    const Panel* order[] = {&panels.uniform, &panels.ris, &panels.reference};
    for (std::uint32_t p = 0; p < 3; ++p)
        for (std::uint32_t i = 0; i < kPixels; ++i)
            for (int c = 0; c < 3; ++c) {
                const float v = std::clamp((*order[p])[i][c] * exposure, 0.0f, 1.0f);
                const float srgb =
                    v <= 0.0031308f ? 12.92f * v : 1.055f * std::pow(v, 1.0f / 2.4f) - 0.055f;
                const std::uint32_t x = p * (kSize + kGap) + i % kSize, row = i / kSize;
                rgb[(row * kWidth + x) * 3 + std::uint32_t(c)] = std::uint8_t(srgb * 255 + 0.5f);
            }
    return rgb;
}

bool write_png(const std::filesystem::path& output, const std::vector<std::uint8_t>& rgb) {
    std::error_code ignored; // A failure to create the directory shows up when writing.
    if (output.has_parent_path())
        std::filesystem::create_directories(output.parent_path(), ignored);
    return stbi_write_png(output.string().c_str(), int(kWidth), int(kSize), 3, rgb.data(),
                          int(kWidth * 3)) != 0;
}

} // namespace toy

int main(int argc, char** argv) {
    using namespace toy;
    const std::filesystem::path output = argc > 1 ? argv[1] : "out/minimal.png";
    const Panels panels = render(make_lights());
    const double mean = mean_luminance(panels.reference);
    std::printf("relative RMSE, 1 sample per pixel: uniform %.3f, RIS (%u candidates) %.3f\n",
                relative_rmse(panels.uniform, panels.reference, mean), kCandidates,
                relative_rmse(panels.ris, panels.reference, mean));
    // Exposure from the reference's mean.
    if (!write_png(output, tone_map(panels, 0.3f / float(mean)))) {
        std::fprintf(stderr, "restir-minimal: cannot write %s\n", output.string().c_str());
        return 1;
    }
    std::printf("wrote %s (%ux%u: uniform | RIS | reference)\n", output.string().c_str(), kWidth,
                kSize);
}
