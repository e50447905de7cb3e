// Receiver-dependent light points in RIS: candidates whose point is drawn from the receiver
// (`draw_receiver_light_candidate`, solid-angle sampling of triangles) and the re-drawn point
// of a presampled (area) candidate (`redraw_point_from_receiver` with the coverage of
// `triangle_area_fraction_above`), each unbiased against Lambert's polygon formula for a
// receiver a thousandth of a unit under a light, a light that straddles its horizon, a far
// light and a point light; the coverage formula against its Monte Carlo estimate; and the
// unified light set forwarding the receiver's points to its emitters.
#include <restir/restir.hpp>

#include "support/statistics.hpp"

#include <gtest/gtest.h>

#include <glm/geometric.hpp>

#include <array>
#include <cmath>
#include <cstddef>
#include <cstdint>
#include <vector>

namespace {

using restir::test::RunningStats;

constexpr float radiance = 2.0f;
constexpr float point_intensity = 0.5f;
const glm::vec3 receiver(0.0f);
const glm::vec3 receiver_normal(0.0f, 1.0f, 0.0f);

struct Triangle {
    glm::vec3 a, b, c;
    // The emitting side: the right-hand rule's normal.
    glm::vec3 normal() const { return glm::normalize(glm::cross(b - a, c - a)); }
};

// Light 0: a 0.2-unit triangle 1e-3 above the receiver, facing down. Light 1: a triangle
// facing the receiver whose lower third lies below its horizon. Light 2: a triangle 3 units
// up. Light 3: an isotropic point light.
const std::array<Triangle, 3> triangles{{
    {{-0.1f, 1e-3f, -0.1f}, {0.1f, 1e-3f, -0.1f}, {0.0f, 1e-3f, 0.1f}},
    {{-0.5f, -0.5f, 0.3f}, {0.0f, 1.0f, 0.3f}, {0.5f, -0.5f, 0.3f}},
    {{-1.0f, 3.0f, -1.0f}, {1.0f, 3.0f, -1.0f}, {0.0f, 3.0f, 1.0f}},
}};
const glm::vec3 point_light(0.3f, 1.5f, -0.4f);

// Triangles with area points (`LightSet`) and, with `from`, solid-angle points
// (`ReceiverLightSet`), and the point light as light 3.
struct Lights {
    std::uint32_t light_count() const { return 4u; }
    restir::LightSample sample_point(std::uint32_t id, glm::vec2 uv) const {
        if (id == 3u)
            return point();
        const Triangle& t = triangles[id];
        restir::LightSample s = emitting(t);
        s.position = restir::sample_triangle_area(t.a, t.b, t.c, uv);
        s.area_pdf = 2.0f / glm::length(glm::cross(t.b - t.a, t.c - t.a));
        return s;
    }
    restir::LightSample sample_point(std::uint32_t id, glm::vec2 uv, glm::vec3 from) const {
        if (id == 3u)
            return point();
        const Triangle& t = triangles[id];
        const restir::SolidAngleSample drawn =
            restir::sample_triangle_from(from, t.a, t.b, t.c, uv);
        restir::LightSample s = emitting(t);
        s.position = drawn.point;
        s.area_pdf = restir::solid_angle_to_area_pdf(drawn.pdf, from, drawn.point, t.normal());
        return s;
    }
    // The density of that map at a point of the triangle (`ReceiverLightDensity`).
    float point_pdf(std::uint32_t id, glm::vec3 on_light, glm::vec3 from) const {
        if (id == 3u)
            return 1.0f;
        const Triangle& t = triangles[id];
        return restir::solid_angle_to_area_pdf(
            restir::triangle_pdf_from(from, t.a, t.b, t.c, on_light), from, on_light, t.normal());
    }

private:
    static restir::LightSample emitting(const Triangle& t) {
        restir::LightSample s;
        s.normal = t.normal();
        s.radiance = glm::vec3(radiance);
        return s;
    }
    static restir::LightSample point() {
        restir::LightSample s;
        s.position = point_light;
        s.normal = glm::vec3(0.0f); // isotropic
        s.radiance = glm::vec3(point_intensity);
        s.area_pdf = 1.0f;
        s.is_delta = true;
        return s;
    }
};

static_assert(restir::ReceiverLightSet<Lights>);

// Lambert's formula for a polygon wholly above the receiver's horizon and facing it (the sign
// convention of tests/light/solid_angle_irradiance_test.cpp).
double polygon_irradiance(const std::vector<glm::dvec3>& vertices, glm::vec3 at) {
    double sum = 0.0;
    for (std::size_t i = 0; i < vertices.size(); ++i) {
        const glm::dvec3 v0 = vertices[i] - glm::dvec3(at);
        const glm::dvec3 v1 = vertices[(i + 1) % vertices.size()] - glm::dvec3(at);
        const double theta = std::atan2(glm::length(glm::cross(v0, v1)), glm::dot(v0, v1));
        sum += theta * glm::dot(glm::dvec3(receiver_normal), glm::normalize(glm::cross(v0, v1)));
    }
    return -0.5 * static_cast<double>(radiance) * sum;
}

// The triangle clipped to the receiver's upper half space (Sutherland-Hodgman), in order.
std::vector<glm::dvec3> clipped_above(const Triangle& t, glm::vec3 at) {
    const std::array<glm::dvec3, 3> v{glm::dvec3(t.a), glm::dvec3(t.b), glm::dvec3(t.c)};
    std::vector<glm::dvec3> out;
    for (std::size_t i = 0; i < 3; ++i) {
        const glm::dvec3 p = v[i], q = v[(i + 1) % 3];
        const double hp = glm::dot(p - glm::dvec3(at), glm::dvec3(receiver_normal));
        const double hq = glm::dot(q - glm::dvec3(at), glm::dvec3(receiver_normal));
        if (hp >= 0.0)
            out.push_back(p);
        if ((hp > 0.0) != (hq > 0.0) && hp != 0.0 && hq != 0.0)
            out.push_back(p + (q - p) * (hp / (hp - hq)));
    }
    return out;
}

// The exact irradiance summed over the channels: the triangles' parts above the horizon and
// the point light's I cos / d^2.
double exact_irradiance(glm::vec3 at = receiver) {
    double e = 0.0;
    for (const Triangle& t : triangles)
        e += polygon_irradiance(clipped_above(t, at), at);
    const glm::dvec3 x = glm::dvec3(point_light) - glm::dvec3(at);
    const double d2 = glm::dot(x, x);
    e += static_cast<double>(point_intensity) * glm::dot(glm::dvec3(receiver_normal), x) /
         (d2 * std::sqrt(d2));
    return 3.0 * e;
}

// p-hat: the irradiance at `at` summed over the channels.
struct Target {
    glm::vec3 at = receiver;
    float operator()(const restir::LightPointSample& s) const {
        const glm::vec3 e = restir::unshadowed_irradiance(s, at, receiver_normal);
        return e.x + e.y + e.z;
    }
};

float estimate(const restir::Reservoir<restir::LightPointSample>& r, Target target = {}) {
    return r.has_sample() ? target(r.sample) * r.contribution_weight : 0.0f;
}

constexpr std::uint32_t candidates = 8;
constexpr int trials = 200'000;

TEST(ReceiverLightCandidates, RisWithPointsFromTheReceiverIsUnbiasedNextToALight) {
    for (const Triangle& t : triangles) // every triangle faces the receiver
        ASSERT_GT(glm::dot(t.normal(), receiver - t.a), 0.0f);
    const Lights lights;
    const restir::UniformLightSampler sampler{lights.light_count()};
    const restir::Falloff falloff{};
    restir::Pcg32 rng = restir::make_pixel_rng(7u, 1u, 2u, 3u);
    RunningStats stats;
    float largest = 0.0f;
    for (int i = 0; i < trials; ++i) {
        const auto r = restir::resample_ris(
            rng, candidates,
            [&](restir::Pcg32& g) {
                return restir::draw_receiver_light_candidate(sampler, lights, receiver, falloff, g);
            },
            Target{});
        stats.add(static_cast<double>(estimate(r)));
        largest = std::fmax(largest, estimate(r));
    }
    EXPECT_TRUE(restir::test::agrees_with(stats, exact_irradiance()));
    // Bounded estimates: f(y) W = w_sum / M with w = p-hat / pmf, and a point drawn uniformly
    // in solid angle has p-hat = L cos(theta_r) (solid angle) <= 2 pi L per channel, so no
    // estimate exceeds N (2 pi L + I / d^2) 3 (N lights, pmf 1 / N). Area points 1e-3 under
    // light 0 reach 1e5 times that.
    const glm::vec3 x = point_light - receiver;
    const float bound =
        4.0f * 3.0f * (2.0f * restir::pi * radiance + point_intensity / glm::dot(x, x));
    EXPECT_LE(largest, 1.01f * bound);
}

// RIS over area candidates at `at`, then the chosen light's point drawn again from there.
RunningStats redrawn_estimates(glm::vec3 at, bool with_coverage) {
    const Target target{at};
    const Lights lights;
    const restir::UniformLightSampler sampler{lights.light_count()};
    const restir::Falloff falloff{};
    restir::Pcg32 rng = restir::make_pixel_rng(8u, 1u, 2u, 3u);
    RunningStats stats;
    for (int i = 0; i < trials; ++i) {
        const auto chosen = restir::resample_ris(
            rng, candidates,
            [&](restir::Pcg32& g) {
                const auto c = restir::draw_light_candidate(sampler, g);
                return restir::SourceSample<restir::LightPointSample>{
                    restir::make_light_point_sample(
                        c.sample.light_id, lights.sample_point(c.sample.light_id, c.sample.uv),
                        falloff),
                    c.pdf};
            },
            target);
        const std::uint32_t id = chosen.sample.light_id;
        const float coverage =
            id < 3u && with_coverage
                ? restir::triangle_area_fraction_above(triangles[id].a, triangles[id].b,
                                                       triangles[id].c, at, receiver_normal)
                : 1.0f;
        const float u = next_float(rng), v = next_float(rng);
        stats.add(static_cast<double>(
            estimate(restir::redraw_point_from_receiver(chosen, coverage, lights, glm::vec2(u, v),
                                                        at, falloff, target),
                     target)));
    }
    return stats;
}

// Next to light 0 the first RIS's area points make W heavy-tailed (its measured standard error
// is no guide there): the redrawn tests take a receiver 0.1 under light 0's plane.
const glm::vec3 lower_receiver(0.0f, -0.1f, 0.0f);

TEST(ReceiverLightCandidates, RedrawnPointWithCoverageIsUnbiased) {
    EXPECT_TRUE(restir::test::agrees_with(redrawn_estimates(lower_receiver, true),
                                          exact_irradiance(lower_receiver)));
}

// Light 1's part below the horizon is never chosen through an area point: without dividing W by
// the coverage (1.1^2 / 1.5^2 of its area lies above), its irradiance comes out short by that
// factor.
TEST(ReceiverLightCandidates, RedrawnPointWithoutCoverageIsBiased) {
    EXPECT_TRUE(restir::test::differs_from(redrawn_estimates(lower_receiver, false),
                                           exact_irradiance(lower_receiver)));
}

TEST(ReceiverLightCandidates, AreaFractionAboveAPlaneMatchesUniformAreaSamples) {
    const Triangle t{{0.0f, -1.0f, 0.0f}, {2.0f, 0.5f, 0.0f}, {-1.0f, 2.0f, 0.5f}};
    EXPECT_EQ(restir::triangle_area_fraction_above(t.a, t.b, t.c, glm::vec3(0.0f, -2.0f, 0.0f),
                                                   receiver_normal),
              1.0f);
    EXPECT_EQ(restir::triangle_area_fraction_above(t.a, t.b, t.c, glm::vec3(0.0f, 3.0f, 0.0f),
                                                   receiver_normal),
              0.0f);
    // The plane through vertex a alone: the rest of the triangle lies above it.
    EXPECT_EQ(restir::triangle_area_fraction_above(t.a, t.b, t.c, t.a, receiver_normal), 1.0f);
    const std::array<std::pair<glm::vec3, glm::vec3>, 4> planes{{
        {glm::vec3(0.0f, 0.2f, 0.0f), glm::vec3(0.0f, 1.0f, 0.0f)},  // one vertex above
        {glm::vec3(0.0f, 0.8f, 0.0f), glm::vec3(0.0f, -1.0f, 0.0f)}, // two above
        {glm::vec3(0.3f, 0.1f, 0.0f), glm::normalize(glm::vec3(1.0f, -0.5f, 0.3f))},
        {glm::vec3(0.0f, 0.5f, 0.0f), glm::normalize(glm::vec3(-1.0f, 1.0f, 2.0f))},
    }};
    for (const auto& [point, normal] : planes) {
        restir::Pcg32 rng = restir::make_pixel_rng(9u, 1u, 2u, 3u);
        RunningStats stats;
        for (int i = 0; i < 100'000; ++i) {
            const float u = next_float(rng), v = next_float(rng);
            const glm::vec3 x = restir::sample_triangle_area(t.a, t.b, t.c, glm::vec2(u, v));
            stats.add(glm::dot(normal, x - point) > 0.0f ? 1.0 : 0.0);
        }
        const float fraction = restir::triangle_area_fraction_above(t.a, t.b, t.c, point, normal);
        EXPECT_GT(fraction, 0.0f);
        EXPECT_LT(fraction, 1.0f);
        EXPECT_TRUE(restir::test::agrees_with(stats, static_cast<double>(fraction)));
    }
}

// Emitters with a receiver's map forward it through the unified set; VPLs stay points; a set
// whose emitters have none is no ReceiverLightSet.
TEST(ReceiverLightCandidates, UnifiedSetForwardsTheReceiverPointToEmitters) {
    struct AreaOnly {
        std::uint32_t light_count() const { return 1u; }
        restir::LightSample sample_point(std::uint32_t, glm::vec2) const { return {}; }
    };
    static_assert(!restir::ReceiverLightSet<restir::UnifiedLightSet<AreaOnly>>);
    static_assert(restir::ReceiverLightSet<restir::UnifiedLightSet<Lights>>);
    static_assert(restir::ReceiverLightDensity<restir::UnifiedLightSet<Lights>>);
    static_assert(!restir::ReceiverLightDensity<restir::UnifiedLightSet<AreaOnly>>);
    const Lights emitters;
    restir::Vpl vpl;
    vpl.position = glm::vec3(1.0f, 2.0f, 3.0f);
    vpl.flux = glm::vec3(1.0f);
    const restir::UnifiedLightSet<Lights> unified{&emitters, &vpl, 1u};
    const glm::vec3 from(0.05f, 0.0f, 0.02f);
    const glm::vec2 uv(0.3f, 0.7f);
    for (std::uint32_t id = 0; id < 3u; ++id) {
        const restir::LightSample direct = emitters.sample_point(id, uv, from);
        const restir::LightSample forwarded = unified.sample_point(id, uv, from);
        EXPECT_EQ(forwarded.position, direct.position);
        EXPECT_EQ(forwarded.area_pdf, direct.area_pdf);
        EXPECT_NE(forwarded.area_pdf, unified.sample_point(id, uv).area_pdf);
        // The density the set gives at the point it drew is the one the point carries.
        EXPECT_EQ(unified.point_pdf(id, forwarded.position, from),
                  emitters.point_pdf(id, direct.position, from));
        EXPECT_NEAR(unified.point_pdf(id, forwarded.position, from), forwarded.area_pdf,
                    1e-3f * forwarded.area_pdf);
    }
    const restir::LightSample v = unified.sample_point(4u, uv, from);
    EXPECT_TRUE(v.is_delta);
    EXPECT_EQ(v.position, vpl.position);
}

} // namespace
