// The integration guide's bridge (docs/integration.md: quad lights, a target function on
// unshadowed_irradiance, LightVisibility with the offset scaled to the scene) in a scene
// hundreds of units wide: a sloping floor quad lit by a quad light, seen through primary rays
// from a camera 800 units away, with a ray query that intersects both quads in float as a ray
// tracer does. One RIS estimate per pixel and frame; the image's mean irradiance
// must match the closed form within 4 standard errors (measured over the frames). With a fixed
// offset of 1e-4 world units (the old default) the floor shadows itself where rounding puts a
// shadow ray's origin below it, and the same test finds the image darker by many standard
// errors: the trap is real.
#include <restir/restir.hpp>

#include <glm/geometric.hpp>
#include <gtest/gtest.h>

#include <cmath>
#include <cstdint>
#include <cstdio>
#include <optional>
#include <vector>

namespace integration_guide {

struct Texel { // the guide's G-buffer texel, without what these checks do not need
    glm::vec3 position{0.0f}, normal{0.0f, 1.0f, 0.0f};
    bool valid = false;
};
glm::vec3 surface_position(const Texel& t) { return t.position; }
glm::vec3 surface_normal(const Texel& t) { return t.normal; }
float surface_depth(const Texel&) { return 1.0f; }
bool is_valid_surface(const Texel& t) { return t.valid; }

} // namespace integration_guide

namespace {

using integration_guide::Texel;

constexpr std::uint32_t width = 24, height = 16, frames = 96, candidates = 4;

struct Quad { // a corner, two edges, radiance
    glm::vec3 corner, edge_u, edge_v, radiance;
    glm::vec3 normal() const { return glm::normalize(glm::cross(edge_u, edge_v)); }
};

struct Lights { // the guide's MyLights
    std::vector<Quad> quads;
    std::uint32_t light_count() const { return static_cast<std::uint32_t>(quads.size()); }
    restir::LightSample sample_point(std::uint32_t id, glm::vec2 uv) const {
        const Quad& q = quads[id];
        const glm::vec3 n = glm::cross(q.edge_u, q.edge_v);
        const float area = glm::length(n);
        restir::LightSample s;
        s.position = q.corner + uv.x * q.edge_u + uv.y * q.edge_v;
        s.normal = n / area;
        s.radiance = q.radiance;
        s.area_pdf = 1.0f / area;
        s.is_delta = false;
        return s;
    }
};

// Where the ray o + t d meets the quad, as a ray tracer computes it: the quad as two
// triangles, each tested in float by Moller and Trumbore's method; nullopt when it misses.
std::optional<float> hit_triangle(glm::vec3 v0, glm::vec3 e1, glm::vec3 e2, glm::vec3 o,
                                  glm::vec3 d) {
    const glm::vec3 p = glm::cross(d, e2);
    const float det = glm::dot(e1, p);
    if (det == 0.0f)
        return std::nullopt;
    const float inv_det = 1.0f / det;
    const glm::vec3 s = o - v0;
    const float u = glm::dot(s, p) * inv_det;
    if (u < 0.0f || u > 1.0f)
        return std::nullopt;
    const glm::vec3 q = glm::cross(s, e1);
    const float v = glm::dot(d, q) * inv_det;
    if (v < 0.0f || u + v > 1.0f)
        return std::nullopt;
    return glm::dot(e2, q) * inv_det;
}
std::optional<float> hit(const Quad& q, glm::vec3 o, glm::vec3 d) {
    if (const auto t = hit_triangle(q.corner, q.edge_u, q.edge_v, o, d))
        return t;
    const glm::vec3 far = q.corner + q.edge_u + q.edge_v;
    return hit_triangle(far, -q.edge_u, -q.edge_v, o, d);
}

struct Rays { // the guide's MyRays: whether the open segment from -> to meets a quad
    const std::vector<Quad>* quads;
    bool occluded(glm::vec3 from, glm::vec3 to) const {
        for (const Quad& q : *quads) {
            const std::optional<float> t = hit(q, from, to - from);
            if (t && *t > 0.0f && *t < 1.0f)
                return true;
        }
        return false;
    }
};

// The scene: a sloping floor 550 units wide (it rises 500 units across), in a room whose
// corner lies 1000 units from the world's origin, as a room of a larger model does, and a
// light of 130 x 105 units above it, facing down. Hit points there carry rounding errors of
// about 1e-4 along the floor's normal.
const Quad floor_quad{{1000.0f, 0.0f, 1000.0f}, {0.0f, 300.0f, 555.0f}, {550.0f, 200.0f, 0.0f}, {}};
const Quad light_quad{
    {1213.0f, 748.0f, 1227.0f}, {130.0f, 0.0f, 0.0f}, {0.0f, 0.0f, 105.0f}, glm::vec3(15.0f)};
// The diagonal of the scene's bounding box.
const float scene_extent = glm::length(glm::vec3(550.0f, 748.0f, 555.0f));

// Irradiance at p (normal n) from a one-sided Lambertian quad of radiance L, in closed form
// (Lambert's polygon formula): E = L / 2 sum_i angle_i n . unit(r_i x r_i+1).
double exact_irradiance(const Quad& q, glm::dvec3 p, glm::dvec3 n) {
    const glm::dvec3 c(q.corner), a(q.edge_u), b(q.edge_v);
    const glm::dvec3 vertices[4] = {c, c + b, c + a + b, c + a};
    double sum = 0.0;
    for (int i = 0; i < 4; ++i) {
        const glm::dvec3 r0 = glm::normalize(vertices[i] - p);
        const glm::dvec3 r1 = glm::normalize(vertices[(i + 1) % 4] - p);
        sum += std::acos(glm::clamp(glm::dot(r0, r1), -1.0, 1.0)) *
               glm::dot(n, glm::normalize(glm::cross(r0, r1)));
    }
    return 0.5 * std::abs(sum) * static_cast<double>(q.radiance.x);
}

// The G-buffer: primary rays from a camera 800 units in front of the scene, hitting the floor.
std::vector<Texel> render_gbuffer() {
    std::vector<Texel> gbuffer(std::size_t{width} * height);
    const glm::vec3 eye{1278.0f, 273.0f, 200.0f};
    const glm::vec3 look_at{1278.0f, 200.0f, 1330.0f};
    const glm::vec3 forward = glm::normalize(look_at - eye);
    const glm::vec3 right = glm::normalize(glm::cross(forward, glm::vec3(0.0f, 1.0f, 0.0f)));
    const glm::vec3 up = glm::cross(right, forward);
    for (std::uint32_t y = 0; y < height; ++y)
        for (std::uint32_t x = 0; x < width; ++x) {
            const float sx = (static_cast<float>(x) + 0.5f) / width - 0.5f;
            const float sy = (static_cast<float>(y) + 0.5f) / height - 0.5f;
            const glm::vec3 d = glm::normalize(forward + 0.4f * sx * right + 0.25f * sy * up);
            const std::optional<float> t = hit(floor_quad, eye, d);
            Texel& texel = gbuffer[x + y * width];
            if (!t)
                continue;
            texel.position = eye + *t * d;
            texel.normal = floor_quad.normal();
            texel.valid = true;
        }
    return gbuffer;
}

struct Result {
    double mean_error = 0.0;     // image mean of (estimate - exact), averaged over frames
    double standard_error = 0.0; // of that average, from the frames' spread
    double exact_mean = 0.0;     // image mean of the exact irradiance
};

// One RIS estimate of the irradiance per pixel and frame (the guide's candidates, target and
// shading), with shadow rays offset by `visible`.
Result render(const Lights& lights, const restir::LightVisibility<Lights, Rays>& visible) {
    const std::vector<Texel> gbuffer = render_gbuffer();
    const float power[] = {1.0f};
    const restir::AliasTable table(power);
    const restir::PowerLightSampler sampler{table.view()};
    const auto contribution = [&](const restir::LightSampleRef& s, const Texel& t) {
        return restir::unshadowed_irradiance(lights.sample_point(s.light_id, s.uv), t.position,
                                             t.normal, restir::Falloff::exact());
    };
    const auto target = [&](const restir::LightSampleRef& s, const Texel& t) {
        return contribution(s, t).x;
    };
    Result result;
    std::uint32_t valid = 0;
    for (const Texel& t : gbuffer)
        if (t.valid) {
            result.exact_mean += exact_irradiance(lights.quads[0], t.position, t.normal);
            ++valid;
        }
    EXPECT_GT(valid, width * height / 2u);
    result.exact_mean /= valid;
    double sum = 0.0, sum_squares = 0.0;
    for (std::uint32_t f = 0; f < frames; ++f) {
        double error = 0.0;
        for (std::uint32_t i = 0; i < gbuffer.size(); ++i) {
            const Texel& t = gbuffer[i];
            if (!t.valid)
                continue;
            restir::Pcg32 rng = restir::make_pixel_rng(i, f, restir::RngStream::application);
            const auto r = restir::resample_ris(
                rng, candidates,
                [&](restir::Pcg32& g) { return restir::draw_light_candidate(sampler, g); }, target,
                t);
            const double estimate =
                r.has_sample() && visible(r.sample, t)
                    ? static_cast<double>(contribution(r.sample, t).x * r.contribution_weight)
                    : 0.0;
            error += estimate - exact_irradiance(lights.quads[0], t.position, t.normal);
        }
        error /= valid;
        sum += error;
        sum_squares += error * error;
    }
    result.mean_error = sum / frames;
    const double variance = (sum_squares - sum * sum / frames) / (frames - 1);
    result.standard_error = std::sqrt(variance / frames);
    return result;
}

TEST(IntegrationGuide, SceneScaledOffsetIsUnbiasedInALargeScene) {
    const Lights lights{{light_quad}};
    const std::vector<Quad> occluders{floor_quad, light_quad};
    const Rays rays{&occluders};
    const Result r = render(
        lights, restir::LightVisibility<Lights, Rays>::for_scene(lights, rays, scene_extent));
    EXPECT_GT(r.standard_error, 0.0);
    std::printf("scene-scaled offset: mean error %.3g +- %.3g of %.4g\n", r.mean_error,
                r.standard_error, r.exact_mean);
    EXPECT_LT(std::abs(r.mean_error), 4.0 * r.standard_error)
        << "mean error " << r.mean_error << " of " << r.exact_mean;
}

TEST(IntegrationGuide, FixedTinyOffsetShadowsALargeSceneItself) {
    const Lights lights{{light_quad}};
    const std::vector<Quad> occluders{floor_quad, light_quad};
    const Rays rays{&occluders};
    const Result r = render(lights, restir::LightVisibility<Lights, Rays>{&lights, &rays, 1e-4f});
    std::printf("offset 1e-4: mean error %.3g +- %.3g of %.4g\n", r.mean_error, r.standard_error,
                r.exact_mean);
    EXPECT_LT(r.mean_error, -10.0 * r.standard_error)
        << "mean error " << r.mean_error << " of " << r.exact_mean;
    EXPECT_LT(r.mean_error, -0.005 * r.exact_mean) << "at least 0.5 % darker";
}

} // namespace
