// An analytic scene with closed-form answers, integrated with restir through its own types:
// a 24 x 24 patch of the ground plane z = 0 (normal +z) lit by 48 isotropic point lights, with
// one sphere floating between them that casts shadows. The irradiance at every texel is a
// finite sum over the lights it sees, computed exactly. The program renders the patch with
// RIS alone and with RIS + temporal + spatial reuse (pairwise MIS, visibility reuse), both
// through the library's frame recipe (restir::run_di_frame, one call per frame), in many
// independent runs, and checks that each estimator's image mean agrees with the exact one
// within 4 standard errors (measured across the runs), and that reuse lowers the per-pixel
// error.
// Exit status 0 when every check passes, 1 otherwise.
#include <restir/restir.hpp>

#include <glm/geometric.hpp>
#include <glm/vec4.hpp>

#include <cmath>
#include <cstdint>
#include <cstdio>
#include <utility>
#include <vector>

namespace scene {

// ---- The bridge: what restir needs from this application (37 lines of code) ----

// A G-buffer texel, known to restir through four free functions.
struct Texel {
    glm::vec3 position{0.0f};
};
glm::vec3 surface_position(const Texel& t) { return t.position; }
glm::vec3 surface_normal(const Texel&) { return {0.0f, 0.0f, 1.0f}; }
float surface_depth(const Texel& t) { return 2.0f - t.position.z; } // camera at z = 2
bool is_valid_surface(const Texel&) { return true; }

// Point lights as a light set: the same point for every uv, area_pdf 1, no normal (isotropic).
struct Lights {
    std::vector<glm::vec4> lights; // position, intensity
    std::uint32_t light_count() const { return static_cast<std::uint32_t>(lights.size()); }
    restir::LightSample sample_point(std::uint32_t id, glm::vec2) const {
        return {.position = glm::vec3(lights[id]),
                .normal = glm::vec3(0.0f),
                .radiance = glm::vec3(lights[id].w),
                .area_pdf = 1.0f,
                .is_delta = true};
    }
};

// The ray query: does the segment meet the sphere?
struct Sphere {
    glm::vec3 centre{0.5f, 0.5f, 0.3f};
    float radius = 0.15f;
    bool occluded(glm::vec3 from, glm::vec3 to) const {
        const glm::vec3 d = to - from, m = from - centre;
        const float a = glm::dot(d, d), b = glm::dot(m, d), c = glm::dot(m, m) - radius * radius;
        const float disc = b * b - a * c;
        if (c <= 0.0f || disc < 0.0f)
            return c <= 0.0f; // starts inside, or the line misses
        const float t = (-b - std::sqrt(disc)) / a;
        return t > 0.0f && t < 1.0f;
    }
};

// A random number generator of our own (SplitMix64), known to restir through next_float.
struct Random {
    std::uint64_t state;
};
float next_float(Random& r) {
    std::uint64_t z = (r.state += 0x9e3779b97f4a7c15ull);
    z = (z ^ (z >> 30)) * 0xbf58476d1ce4e5b9ull;
    z = (z ^ (z >> 27)) * 0x94d049bb133111ebull;
    return static_cast<float>((z ^ (z >> 31)) >> 40) * 0x1p-24f;
}
// ---- bridge end ----

constexpr std::uint32_t size = 24, pixels = size * size;

// Irradiance of one light point at a texel, without visibility: the integrand and p-hat.
float irradiance(const Lights& lights, const restir::LightSampleRef& s, const Texel& t) {
    return restir::unshadowed_irradiance(lights.sample_point(s.light_id, s.uv), t.position,
                                         surface_normal(t), restir::Falloff::exact())
        .x;
}

Lights make_lights() {
    Random r{12345u};
    Lights set;
    for (int i = 0; i < 48; ++i) { // braced lists evaluate left to right
        const glm::vec4 light{2.0f * next_float(r) - 0.5f, 2.0f * next_float(r) - 0.5f,
                              0.5f + next_float(r), 1.0f + 19.0f * next_float(r)};
        set.lights.push_back(light);
    }
    return set;
}

// ---- The scene, its exact answer, and its renders through the frame recipe ----

// The patch's texel centres, row by row.
std::vector<Texel> make_texels() {
    std::vector<Texel> texels(pixels);
    for (std::uint32_t i = 0; i < pixels; ++i)
        texels[i].position = {(float(i % size) + 0.5f) / size, (float(i / size) + 0.5f) / size,
                              0.0f};
    return texels;
}

// Everything a render reads: the lights, the sphere, the G-buffer, the lights' alias table.
struct Patch {
    Lights lights = make_lights();
    Sphere sphere{};
    std::vector<Texel> texels = make_texels();
    restir::AliasTable table{light_powers(lights)};

    static std::vector<float> light_powers(const Lights& lights) {
        std::vector<float> powers;
        for (const glm::vec4& l : lights.lights)
            powers.push_back(l.w);
        return powers;
    }
    restir::LightVisibility<Lights, Sphere> visibility() const { return {&lights, &sphere, 1e-4f}; }
};

// The exact irradiance of every texel: the sum over the lights it sees (the segment test
// restir uses), and the image mean.
struct Exact {
    std::vector<double> pixels;
    double mean = 0.0;
};

Exact exact_irradiance(const Patch& patch) {
    const restir::LightVisibility<Lights, Sphere> visibility = patch.visibility();
    Exact exact{std::vector<double>(pixels, 0.0)};
    for (std::uint32_t i = 0; i < pixels; ++i) {
        for (std::uint32_t id = 0; id < patch.lights.light_count(); ++id)
            if (visibility({id, {}}, patch.texels[i]))
                exact.pixels[i] += double(irradiance(patch.lights, {id, {}}, patch.texels[i]));
        exact.mean += exact.pixels[i] / pixels;
    }
    return exact;
}

// One run of `frames` frames through the frame recipe (restir::run_di_frame): RIS alone, or
// with temporal and spatial reuse. Returns the last frame's image.
std::vector<double> render(const Patch& patch, std::uint64_t seed, std::uint32_t frames,
                           bool reuse) {
    const restir::PowerLightSampler sampler{patch.table.view()};
    const auto target_at = [&](const restir::LightSampleRef& s, const Texel& t) {
        return irradiance(patch.lights, s, t);
    };
    const auto same_pixel = [](restir::PixelCoord p) { return p; }; // a still camera
    const auto for_each_pixel = [](const auto& stage) { // a parallel loop in a real renderer
        for (std::uint32_t i = 0; i < pixels; ++i)
            stage(restir::PixelCoord{int(i % size), int(i / size)});
    };
    std::uint32_t f = 0; // the frame's index, which the pixels' random streams depend on
    // The application's side of the frame: initial candidates, p-hat and visibility for
    // reuse, each pixel's random streams (no shading callback: the image is read from `out`).
    const restir::DiBridge bridge{
        [&](restir::PixelCoord, const Texel& texel, Random& rng) {
            return restir::resample_ris(
                rng, 8u, [&](Random& g) { return restir::draw_light_candidate(sampler, g); },
                target_at, texel);
        },
        restir::ReuseBridge{target_at, patch.visibility()},
        [&](restir::PixelCoord p, std::uint32_t stream) {
            return Random{seed * 0x100000001b3ull + (f * 7919u + stream) * pixels +
                          std::uint64_t(p.x + p.y * int(size))};
        }};
    using Reservoir = restir::Reservoir<restir::LightSampleRef>;
    std::vector<Reservoir> history(pixels), out(pixels), scratch(pixels);
    restir::DiFrame<restir::LightSampleRef, Texel, decltype(same_pixel)> frame{
        .params = restir::default_di_frame_params(),
        .surfaces = {patch.texels.data(), size, size},
        .reproject = same_pixel};
    frame.params.spatial.radius = 4.0f;
    frame.params.temporal_reuse = reuse;
    frame.params.spatial_passes = reuse ? 1u : 0u;
    for (; f < frames; ++f) {
        frame.frame_index = f;
        if (f > 0) { // frame 0 (and a camera cut) has no history
            std::swap(history, out);
            frame.history = {history.data(), size, size};
            frame.previous_surfaces = frame.surfaces; // a still scene
        }
        const restir::DiBuffers<restir::LightSampleRef> buffers{{out.data(), size, size},
                                                                {scratch.data(), size, size}};
        restir::run_di_frame(frame, buffers, bridge, for_each_pixel);
    }
    std::vector<double> image(pixels);
    for (std::uint32_t i = 0; i < pixels; ++i) // shading: W is 0 where occluded
        image[i] = double(target_at(out[i].sample, patch.texels[i]) * out[i].contribution_weight);
    return image;
}

// One estimator over many independent runs of 4 frames: the average image mean and its
// standard error, and the per-pixel RMSE relative to the exact mean.
struct Measured {
    double mean = 0.0;
    double standard_error = 0.0;
    double pixel_rmse = 0.0;
};

Measured measure(const Patch& patch, const Exact& exact, bool reuse) {
    constexpr int runs = 400;
    double sum = 0.0, sum_squares = 0.0, squared_error = 0.0;
    for (int k = 0; k < runs; ++k) {
        const std::vector<double> image = render(patch, 1000u + std::uint64_t(k), 4u, reuse);
        double mean = 0.0;
        for (std::uint32_t i = 0; i < pixels; ++i) {
            mean += image[i] / pixels;
            squared_error += (image[i] - exact.pixels[i]) * (image[i] - exact.pixels[i]);
        }
        sum += mean;
        sum_squares += mean * mean;
    }
    Measured m;
    m.mean = sum / runs;
    m.standard_error = std::sqrt((sum_squares / runs - m.mean * m.mean) / (runs - 1));
    m.pixel_rmse = std::sqrt(squared_error / (runs * double(pixels))) / exact.mean;
    return m;
}

// Prints whether the estimator's image mean agrees with the exact one within 4 standard
// errors, and returns it.
bool agrees(const char* name, const Measured& m, double truth) {
    const bool ok = std::abs(m.mean - truth) < 4.0 * m.standard_error;
    std::printf("%-22s image mean %.5f, exact %.5f, difference %+.5f (%.1f standard errors) %s\n",
                name, m.mean, truth, m.mean - truth, std::abs(m.mean - truth) / m.standard_error,
                ok ? "ok" : "FAILED");
    return ok;
}

} // namespace scene

int main() {
    using namespace scene;
    const Patch patch;
    const Exact exact = exact_irradiance(patch);
    const Measured ris = measure(patch, exact, false);
    const bool ris_agrees = agrees("RIS", ris, exact.mean);
    const Measured reuse = measure(patch, exact, true);
    const bool reuse_agrees = agrees("RIS + temporal/spatial", reuse, exact.mean);
    const bool better = reuse.pixel_rmse < ris.pixel_rmse;
    std::printf("relative RMSE per pixel at frame 4: RIS %.3f, with reuse %.3f %s\n",
                ris.pixel_rmse, reuse.pixel_rmse, better ? "ok" : "FAILED");
    return ris_agrees && reuse_agrees && better ? 0 : 1;
}
