// The hybrid shift of ReSTIR PT over a toy scene: the reconnection density, the Jacobian against
// finite differences, the inverse, the failures, the MIS weight at x_k, GlossyBsdf's lobes.
#include "bsdf/hemisphere_chi2.hpp"
#include "support/chi2.hpp"
#include "support/statistics.hpp"

#include <restir/bsdf/ggx.hpp>
#include <restir/bsdf/glossy_bsdf.hpp>
#include <restir/core/math.hpp>
#include <restir/core/rng.hpp>
#include <restir/gi/hybrid_shift.hpp>
#include <restir/gi/pt_sample.hpp>

#include <glm/geometric.hpp>
#include <glm/vec2.hpp>
#include <glm/vec3.hpp>

#include <gtest/gtest.h>

#include <algorithm>
#include <cmath>
#include <cstdint>
#include <numbers>
#include <optional>
#include <utility>

namespace {

using dvec3 = glm::dvec3;
using restir::GlossyBsdf;
using restir::HybridShift;
using restir::Pcg32;
using restir::PtSample;
using restir::ReconnectionCriterion;
using restir::ShiftedSample;
using restir::test::random_unit;

// A surface of the toy scene: position, normal, roughness, its sampler's cosine power.
struct Point {
    glm::vec3 position{0.0f};
    glm::vec3 normal{0.0f, 1.0f, 0.0f};
    float roughness = 1.0f;
    float exponent = 1.0f;
};
[[maybe_unused]] glm::vec3 surface_position(const Point& p) { return p.position; }
[[maybe_unused]] glm::vec3 surface_normal(const Point& p) { return p.normal; }
[[maybe_unused]] float surface_depth(const Point&) { return 1.0f; }
[[maybe_unused]] bool is_valid_surface(const Point&) { return true; }

// The toy material's sampler, the inverse CDF of the density (e + 1) / (2 pi) cos^e theta:
// cos theta = u0^(1 / (e + 1)) about n, phi = 2 pi u1 in a frame that depends on n alone.
template <class T>
glm::vec<3, T> lobe_direction(glm::vec<3, T> n, T exponent, T u0, T u1) {
    const T cos_t = std::pow(u0, T(1) / (exponent + T(1)));
    const T sin_t = std::sqrt(std::max(T(0), T(1) - cos_t * cos_t));
    const T phi = T(2) * std::numbers::pi_v<T> * u1;
    const bool x_small = std::abs(n.x) < T(0.9);
    const glm::vec<3, T> helper(x_small ? T(1) : T(0), x_small ? T(0) : T(1), T(0));
    const glm::vec<3, T> t = glm::normalize(glm::cross(n, helper));
    const glm::vec<3, T> b = glm::cross(n, t);
    return (sin_t * std::cos(phi)) * t + (sin_t * std::sin(phi)) * b + cos_t * n;
}

// A path's two numbers for its bounce at the visible point: 16 bits of the seed each, at the
// centre of their cell (exact in float and double).
glm::vec2 seed_numbers(std::uint32_t seed) {
    return {(static_cast<float>(seed & 0xffffu) + 0.5f) / 65536.0f,
            (static_cast<float>(seed >> 16u) + 0.5f) / 65536.0f};
}

// The toy scene's replayable path tracer (a `restir::PathReplay`): every bounce from a visible
// point reaches a ceiling at height 3. A path reconnecting at x_2 replays nothing; at x_3, one
// bounce; without reconnection vertex (rc_index 0, length 2) it ends on the ceiling's light.
struct ToyReplay {
    using Vertex = Point;
    static constexpr glm::vec3 albedo{0.7f, 0.5f, 0.3f};

    // The bounce from `from` with the seed's numbers, as the prefix it makes: invalid where it
    // misses the ceiling or where (from, hit) meets `rule` (the path would reconnect there).
    restir::ReplayedPrefix<Point> bounce(std::uint32_t seed, const Point& from,
                                         const ReconnectionCriterion& rule) const {
        const glm::vec2 u = seed_numbers(seed);
        const glm::vec3 w = lobe_direction(from.normal, from.exponent, u.x, u.y);
        const glm::vec3 hit = from.position + ((3.0f - from.position.y) / w.y) * w;
        if (!(w.y > 0.0f) || rule(from.roughness, 0.8f, glm::distance(hit, from.position)))
            return {};
        const float density = (from.exponent + 1.0f) / restir::two_pi *
                              std::pow(glm::dot(from.normal, w), from.exponent);
        return {{hit, {0.0f, -1.0f, 0.0f}, 0.8f}, hit, 0.8f, albedo * w.y, density, density > 0.0f};
    }
    restir::ReplayedPrefix<Point> replay_prefix(const PtSample& x, const Point& from,
                                                const ReconnectionCriterion& rule) const {
        if (x.rc_index == 2u)
            return {from, from.position, from.roughness, glm::vec3(1.0f), 1.0f, true};
        return x.rc_index == 3u ? bounce(x.seed, from, rule) : restir::ReplayedPrefix<Point>{};
    }
    restir::ReplayedPath replay_path(const PtSample& x, const Point& from,
                                     const ReconnectionCriterion& rule) const {
        const restir::ReplayedPrefix<Point> b = bounce(x.seed, from, rule);
        if (x.rc_index != 0u || x.length != 2u || !b.valid)
            return {};
        return {b.throughput * glm::vec3(4.0f, 3.0f, 2.0f), b.density, true};
    }
    // Lambertian at both ends of the join: albedo / pi cos at v, 1 / pi cos at x_k towards
    // w_k with its MIS weight (the cosine lobe's density); nothing occludes.
    glm::vec3 reconnect(const Point& v, const PtSample& x) const {
        const glm::vec3 to_rc = glm::normalize(x.rc_position - v.position);
        const float cos_v = std::max(0.0f, glm::dot(v.normal, to_rc));
        const float cos_k = std::max(0.0f, glm::dot(x.rc_normal, x.rc_direction));
        return albedo * (cos_v / restir::pi) * (cos_k / restir::pi) *
               restir::rc_mis_weight(x, cos_k / restir::pi);
    }
};
static_assert(restir::PathReplay<ToyReplay, Point>);
static_assert(restir::ShiftMapping<HybridShift<ToyReplay>, PtSample, Point>);

// The sample the toy makes at `at` with `seed`, reconnecting at (s, n) (the path goes on past
// x_{k+1}) or, for rc_index 0, ending on the ceiling; D is 0 where it makes no such path.
PtSample make_sample(const ToyReplay& toy, const Point& at, glm::vec3 s, glm::vec3 n,
                     std::uint8_t rc_index, std::uint32_t seed) {
    const bool whole = rc_index == 0u;
    PtSample x{.visible_point = at.position,
               .rc_position = s,
               .rc_normal = n,
               .rc_direction = glm::normalize(n + glm::vec3(0.3f, -0.2f, 0.1f)),
               .suffix = {1.5f, 2.0f, 2.5f},
               .seed = seed,
               .rc_index = rc_index,
               .length = static_cast<std::uint8_t>(whole ? 2u : rc_index + 2u)};
    if (whole) {
        const restir::ReplayedPath path = toy.replay_path(x, at, {});
        x.contribution = path.contribution;
        x.density = path.valid ? path.density : 0.0f;
        return x;
    }
    const restir::ReplayedPrefix<Point> prefix = toy.replay_prefix(x, at, {});
    x.density =
        prefix.valid ? restir::reconnection_density(prefix.density, prefix.position, s, n) : 0.0f;
    x.contribution = prefix.throughput * toy.reconnect(prefix.last, x) * x.suffix;
    return x;
}

// Solid angle of triangle a, b, c seen from `from` (Van Oosterom and Strackee 1983; the triple
// product over the edges keeps small triangles precise).
double triangle_solid_angle(dvec3 from, dvec3 a, dvec3 b, dvec3 c) {
    const dvec3 ra = a - from, rb = b - from, rc = c - from;
    const double la = glm::length(ra), lb = glm::length(rb), lc = glm::length(rc);
    const double triple = std::abs(glm::dot(ra, glm::cross(b - a, c - a)));
    const double denominator =
        la * lb * lc + glm::dot(ra, rb) * lc + glm::dot(ra, rc) * lb + glm::dot(rb, rc) * la;
    return 2.0 * std::atan2(triple, denominator);
}

// Solid angle of the quad corner(-1/2, -1/2) .. corner(1/2, 1/2), two triangles, seen from o.
template <class Corner>
double quad_solid_angle(dvec3 o, const Corner& corner) {
    const dvec3 a = corner(-0.5, -0.5), b = corner(0.5, -0.5), c = corner(0.5, 0.5);
    return triangle_solid_angle(o, a, b, c) + triangle_solid_angle(o, a, c, corner(-0.5, 0.5));
}

// The ratio of the solid angles that a square of side 1e-3 min(d_q, d_r) around x_k (in its
// plane) subtends from r and from q: d omega_r / d omega_q, the reconnection's Jacobian. Each
// is A cos / d^2 within 3/8 (side / d)^2 (cos / d^2 expanded over the square to second
// order); the second number, the error allowed, is (side / d_q)^2 + (side / d_r)^2.
std::pair<double, double> patch_ratio(glm::vec3 q, glm::vec3 r, glm::vec3 s, glm::vec3 n) {
    const double d_q = glm::distance(dvec3(q), dvec3(s)), d_r = glm::distance(dvec3(r), dvec3(s));
    const double side = 1e-3 * std::min(d_q, d_r);
    const dvec3 normal = glm::normalize(dvec3(n));
    const dvec3 helper = std::abs(normal.x) < 0.9 ? dvec3(1.0, 0.0, 0.0) : dvec3(0.0, 1.0, 0.0);
    const dvec3 t = side * glm::normalize(glm::cross(normal, helper));
    const dvec3 b = side * glm::normalize(glm::cross(normal, t));
    const auto corner = [&](double i, double j) { return dvec3(s) + i * t + j * b; };
    return {quad_solid_angle(dvec3(r), corner) / quad_solid_angle(dvec3(q), corner),
            side * side / (d_q * d_q) + side * side / (d_r * d_r)};
}

// p_q(w_x) / p_r(w_y), the Jacobian d omega_y / d omega_x of a bounce replayed from q at r: the
// ratio of the solid angles of the directions that the square of numbers of side h = 1e-4
// around the seed's numbers maps to (corners joined by great circles). Each is h^2 / p within
// O(h^2) relative (midpoint rule; opposite arcs' bulges cancel to that order): below 1e-6 with
// u0 in [0.05, 0.95] and cosine powers up to 8.
double replay_ratio(const Point& q, const Point& r, std::uint32_t seed) {
    constexpr double h = 1e-4;
    const glm::dvec2 u(seed_numbers(seed));
    const auto patch = [&](const Point& p) {
        return quad_solid_angle(dvec3(0.0), [&](double i, double j) {
            return lobe_direction<double>(dvec3(p.normal), static_cast<double>(p.exponent),
                                          u.x + i * h, u.y + j * h);
        });
    };
    return patch(r) / patch(q);
}
constexpr double replay_fd_error = 1e-6;

// Relative float error of a reconnection Jacobian: coordinates below 8, distances >= 1 and
// cosines >= 0.3 keep each difference's rounding below 1e-6 of the distance and each cosine
// times distance's below 5e-6. Of a replayed bounce's density ratio: cos^e (e <= 8) errs by 8
// ulps, and the direction's rounding (a few 1e-7 rad) moves p by e tan(theta) <= 50 times it.
constexpr double float_jacobian_error = 1e-5;
constexpr double float_replay_error = 4e-5;

glm::vec3 random_box(Pcg32& rng, float half) {
    return half * (2.0f * glm::vec3{next_float(rng), next_float(rng), next_float(rng)} - 1.0f);
}

// A glossy visible point: position in [-1, 1]^3, normal within 20 degrees of up, power 1 to 8.
Point random_glossy_point(Pcg32& rng) {
    const glm::vec3 p = random_box(rng, 1.0f);
    const float tx = next_float(rng), tz = next_float(rng);
    const glm::vec3 n = glm::normalize(glm::vec3(0.5f * tx - 0.25f, 1.0f, 0.5f * tz - 0.25f));
    return {p, n, 0.1f, 1.0f + 7.0f * next_float(rng)};
}

// A reconnection vertex (s, n) that sees a and b from at least 1 away at cosines >= 0.3.
std::pair<glm::vec3, glm::vec3> random_rc_vertex(Pcg32& rng, glm::vec3 a, glm::vec3 b) {
    for (;;) {
        const glm::vec3 s = random_box(rng, 3.0f) * glm::vec3(1.0f, 0.5f, 1.0f);
        const glm::vec3 n = random_unit(rng), ta = a - s, tb = b - s;
        const float la = glm::length(ta), lb = glm::length(tb);
        if (la >= 1.0f && lb >= 1.0f && glm::dot(n, ta) >= 0.3f * la &&
            glm::dot(n, tb) >= 0.3f * lb)
            return {s, n};
    }
}

// Whether the seed's bounce from p is well conditioned: u0 in [0.05, 0.95], w_y >= 0.5.
bool well_conditioned(const Point& p, std::uint32_t seed) {
    const glm::vec2 u = seed_numbers(seed);
    return u.x >= 0.05f && u.x <= 0.95f && lobe_direction(p.normal, p.exponent, u.x, u.y).y >= 0.5f;
}

TEST(HybridShiftDensity, IsThePrefixTimesDistanceSquaredOverCosineAndZeroBehind) {
    const glm::vec3 rc(1.0f, -2.0f, 0.5f), from = rc + glm::vec3(0.0f, 3.0f, 4.0f); // 5 away
    const auto density = [&](float p, glm::vec3 at, glm::vec3 n) {
        return restir::reconnection_density(p, at, rc, n);
    };
    EXPECT_EQ(density(0.5f, from, {0.0f, 0.0f, 1.0f}), 15.625f); // 0.5 * 25 / 0.8
    EXPECT_FLOAT_EQ(density(0.5f, from, {0.0f, 1.0f, 0.0f}), 0.5f * 25.0f / 0.6f);
    EXPECT_FLOAT_EQ(density(2.0f, from, {0.0f, 0.6f, 0.8f}), 50.0f);
    EXPECT_EQ(density(0.5f, from, {0.0f, 0.0f, -1.0f}), 0.0f); // behind
    EXPECT_EQ(density(0.5f, from, {1.0f, 0.0f, 0.0f}), 0.0f);  // in the plane
    EXPECT_EQ(density(0.5f, rc, {0.0f, 0.0f, 1.0f}), 0.0f);    // at x_k
    EXPECT_EQ(density(0.0f, from, {0.0f, 0.0f, 1.0f}), 0.0f);
    EXPECT_EQ(density(std::nanf(""), from, {0.0f, 0.0f, 1.0f}), 0.0f);
    EXPECT_EQ(density(1e38f, from, {0.0f, 0.0f, 1.0f}), 0.0f); // overflows
}

// Reconnecting at x_2 (nothing replayed), the Jacobian is the reconnection's. At x_3 after one
// replayed bounce, it is the bounce's (d omega_y / d omega_x of the directions) times the
// reconnection's from the replayed vertex: the shift maps (w_1, w_2) triangularly, w_1 to w'_1
// alone, so its determinant is the product. Without reconnection vertex, the bounce's alone.
TEST(HybridShift, JacobianIsThatOfFiniteDifferences) {
    Pcg32 rng = restir::make_pixel_rng(1u, 0u, restir::RngStream::application, 2022u);
    const ToyReplay toy;
    const HybridShift<ToyReplay> shift{&toy};
    int checked = 0;
    for (int trial = 0; trial < 3000; ++trial) {
        const Point q = random_glossy_point(rng), r = random_glossy_point(rng);
        const Point rough_q{q.position, q.normal, 0.9f}, rough_r{r.position, r.normal, 0.9f};
        const std::uint32_t seed = rng.next_uint();
        const auto [s2, n2] = random_rc_vertex(rng, q.position, r.position);
        const PtSample x2 = make_sample(toy, rough_q, s2, n2, 2u, seed);
        const auto [reconnection, error2] = patch_ratio(q.position, r.position, s2, n2);
        ASSERT_NEAR(static_cast<double>(shift(x2, rough_q, rough_r).jacobian) / reconnection, 1.0,
                    error2 + float_jacobian_error)
            << "trial " << trial;
        if (!well_conditioned(q, seed) || !well_conditioned(r, seed))
            continue;
        const double replay = replay_ratio(q, r, seed);
        const PtSample whole = make_sample(toy, q, {}, {}, 0u, seed);
        ASSERT_NEAR(static_cast<double>(shift(whole, q, r).jacobian) / replay, 1.0,
                    replay_fd_error + float_replay_error)
            << "trial " << trial;
        const glm::vec3 q2 = toy.bounce(seed, q, {}).position,
                        r2 = toy.bounce(seed, r, {}).position;
        const auto [s3, n3] = random_rc_vertex(rng, q2, r2);
        const PtSample x3 = make_sample(toy, q, s3, n3, 3u, seed);
        const auto [geometric, error3] = patch_ratio(q2, r2, s3, n3);
        ASSERT_NEAR(static_cast<double>(shift(x3, q, r).jacobian) / (replay * geometric), 1.0,
                    error3 + replay_fd_error + float_jacobian_error + float_replay_error)
            << "trial " << trial;
        ++checked;
    }
    EXPECT_GT(checked, 500);
}

// Equal up to float rounding in f and D, exactly in the rest.
void expect_same_sample(const PtSample& actual, const PtSample& expected) {
    for (int c = 0; c < 3; ++c)
        EXPECT_NEAR(actual.contribution[c], expected.contribution[c],
                    1e-6f * expected.contribution[c]);
    EXPECT_NEAR(actual.density, expected.density, 1e-6f * expected.density);
    PtSample rest = actual;
    rest.contribution = expected.contribution;
    rest.density = expected.density;
    EXPECT_EQ(rest, expected);
}

// The shifted sample is the one the toy's path tracer makes at the receiver with the same
// numbers, and shifting it back gives the original and the inverse Jacobian.
TEST(HybridShift, ShiftingBackGivesTheSampleAndTheInverseJacobian) {
    Pcg32 rng = restir::make_pixel_rng(3u, 0u, restir::RngStream::application, 2022u);
    const ToyReplay toy;
    const HybridShift<ToyReplay> shift{&toy};
    int inverted[4] = {};
    for (int trial = 0; trial < 3000 && !::testing::Test::HasFailure(); ++trial) {
        const auto rc_index = static_cast<std::uint8_t>(trial % 3 == 0 ? 0 : trial % 3 + 1);
        Point a = random_glossy_point(rng), b = random_glossy_point(rng);
        if (rc_index == 2u)
            a.roughness = b.roughness = 0.9f;
        const glm::vec3 s = random_box(rng, 3.0f), n = random_unit(rng);
        const std::uint32_t seed = rng.next_uint();
        const PtSample x = make_sample(toy, a, s, n, rc_index, seed);
        const ShiftedSample<PtSample> y = shift(x, a, b);
        if (!(x.density > 0.0f) || !(y.jacobian > 0.0f))
            continue;
        expect_same_sample(y.sample, make_sample(toy, b, s, n, rc_index, seed));
        const ShiftedSample<PtSample> back = shift(y.sample, b, a);
        expect_same_sample(back.sample, x);
        EXPECT_NEAR(static_cast<double>(y.jacobian) * static_cast<double>(back.jacobian), 1.0, 1e-5)
            << "trial " << trial;
        ++inverted[rc_index];
    }
    EXPECT_GT(inverted[0], 200);
    EXPECT_GT(inverted[2], 100);
    EXPECT_GT(inverted[3], 100);
}

// Rough points below an x_2 facing down, glossy ones below the ceiling, a steep bounce's seed.
const Point rough_a{{0.0f, 0.0f, 0.0f}, {0.0f, 1.0f, 0.0f}, 0.9f, 2.0f};
const Point rough_b{{0.6f, 0.1f, -0.4f}, {0.0f, 1.0f, 0.0f}, 0.9f, 3.0f};
const glm::vec3 rc_s{0.3f, 2.0f, 0.2f}, rc_down{0.0f, -1.0f, 0.0f};
const Point glossy_a{{0.0f, 0.0f, 0.0f}, {0.0f, 1.0f, 0.0f}, 0.1f, 2.0f};
const Point glossy_b{{0.6f, 0.1f, -0.4f}, {0.0f, 1.0f, 0.0f}, 0.1f, 5.0f};
const glm::vec3 ceiling_rc_s{0.2f, 0.5f, -0.1f}, rc_up{0.0f, 1.0f, 0.0f};
constexpr std::uint32_t steep_seed = 0x8000c000u; // u = (0.75, 0.5)

void expect_failed(const ShiftedSample<PtSample>& y, const Point& to, const char* why) {
    EXPECT_EQ(y.jacobian, 0.0f) << why;
    EXPECT_EQ(y.sample.visible_point, to.position) << why;
}

TEST(HybridShift, FailsWhereTheReconnectionOrTheReplayFails) {
    const ToyReplay toy;
    const HybridShift<ToyReplay> shift{&toy};
    const PtSample x = make_sample(toy, rough_a, rc_s, rc_down, 2u, steep_seed);
    ASSERT_GT(shift(x, rough_a, rough_b).jacobian, 0.0f);
    const Point glossy{rough_b.position, rough_b.normal, 0.29f}, above{{0.6f, 2.5f, -0.4f}},
        level{{0.6f, rc_s.y, -0.4f}};
    expect_failed(shift(x, rough_a, glossy), glossy, "y_{k-1} too smooth");
    expect_failed(shift(x, rough_a, above), above, "behind x_k");
    expect_failed(shift(x, rough_a, level), level, "in x_k's plane");
    PtSample smooth_rc = x, empty = x, no_density = x;
    smooth_rc.rc_roughness = 0.29f;
    empty.length = 0u;
    no_density.density = 0.0f;
    expect_failed(shift(smooth_rc, rough_a, rough_b), rough_b, "x_k too smooth");
    expect_failed(shift(empty, rough_a, rough_b), rough_b, "no sample");
    expect_failed(shift(empty, rough_a, rough_a), rough_a, "no sample, same surface");
    expect_failed(shift(no_density, rough_a, rough_b), rough_b, "no density");
    const HybridShift<ToyReplay> far{&toy, {0.3f, 2.5f}}; // |y_1 - x_k| is about 2.0
    expect_failed(far(x, rough_a, rough_b), rough_b, "too close");
    EXPECT_GT((HybridShift<ToyReplay>{&toy, {0.3f, 1.5f}}(x, rough_a, rough_b).jacobian), 0.0f);
    Point facing_down = glossy_b, rough = glossy_b;
    facing_down.normal = -facing_down.normal; // the bounce misses the ceiling
    rough.roughness = 0.9f; // (y_1, y_2) meets the criterion: the path would reconnect at y_2
    for (const std::uint8_t rc_index : {std::uint8_t{0u}, std::uint8_t{3u}}) {
        const PtSample y = make_sample(toy, glossy_a, ceiling_rc_s, rc_up, rc_index, steep_seed);
        ASSERT_GT(shift(y, glossy_a, glossy_b).jacobian, 0.0f);
        expect_failed(shift(y, glossy_a, facing_down), facing_down, "missed");
        expect_failed(shift(y, glossy_a, rough), rough, "reconnects earlier");
    }
}

TEST(HybridShift, KeepsTheSampleBetweenSurfacesAtTheSamePositionAndNormal) {
    const ToyReplay toy;
    const HybridShift<ToyReplay> shift{&toy};
    const PtSample x = make_sample(toy, glossy_a, ceiling_rc_s, rc_up, 3u, steep_seed);
    // Another material at the same place, where the replay would fail: the sample is kept,
    // and its own visible point plays no part (it becomes the receiver's).
    const Point same{glossy_a.position, glossy_a.normal, 0.9f, 7.0f};
    PtSample elsewhere = x;
    elsewhere.visible_point = glm::vec3(5.0f);
    EXPECT_EQ(shift(elsewhere, glossy_a, same).jacobian, 1.0f);
    EXPECT_EQ(shift(elsewhere, glossy_a, same).sample, x);
    // Another normal at the same place is a shift: the bounce is replayed about it.
    const Point tilted{glossy_a.position, glm::normalize(glm::vec3(0.2f, 1.0f, 0.0f)), 0.1f, 2.0f};
    const ShiftedSample<PtSample> turned = shift(x, glossy_a, tilted);
    EXPECT_TRUE(turned.jacobian > 0.0f && turned.jacobian != 1.0f) << turned.jacobian;
    expect_same_sample(turned.sample,
                       make_sample(toy, tilted, ceiling_rc_s, rc_up, 3u, steep_seed));
}

TEST(HybridShiftMis, WeighsTheLastSegmentsTechniqueAndNothingBefore) {
    PtSample x{.rc_light_pdf = 0.6f, .rc_index = 3u, .length = 4u}; // light-sampled end
    EXPECT_FLOAT_EQ(restir::rc_mis_weight(x, 0.2f), 0.75f);
    EXPECT_EQ(restir::rc_mis_weight(x, 0.0f), 1.0f); // BSDF sampling cannot draw w_k
    x.end = restir::PathEnd::bsdf_sampled;
    EXPECT_FLOAT_EQ(restir::rc_mis_weight(x, 0.2f), 0.25f);
    EXPECT_EQ(restir::rc_mis_weight(x, 0.0f), 0.0f);
    // x_k before the last segment: no light density, weight 1 whichever way the path ended.
    x = {.rc_light_pdf = 0.0f, .rc_index = 2u, .length = 5u};
    for (const auto end : {restir::PathEnd::light_sampled, restir::PathEnd::bsdf_sampled}) {
        x.end = end;
        EXPECT_EQ(restir::rc_mis_weight(x, 0.37f), 1.0f);
    }
}

struct LobeMaterial {
    const char* name;
    GlossyBsdf bsdf;
};
const LobeMaterial lobe_materials[] = {
    {"dielectric 0.12", GlossyBsdf::from_metallic_roughness({0.8f, 0.5f, 0.3f}, 0.0f, 0.12f)},
    {"dielectric 0.6", GlossyBsdf::from_metallic_roughness({0.8f, 0.5f, 0.3f}, 0.0f, 0.6f)},
    {"metal 0.4", GlossyBsdf::from_metallic_roughness({0.9f, 0.6f, 0.3f}, 1.0f, 0.4f)},
};
constexpr glm::vec3 up{0.0f, 0.0f, 1.0f};

// The two branches sum to `pdf` (0 where it is), up to the rounding of n.wo and n.wi, which a
// compiler may fuse differently in the two functions: two roundings of a cosine differ by at
// most 7.2e-7, which moves the diffuse lobe by 7.2e-7 / cos and the specular's D by 4 times it.
TEST(GlossyBsdfLobe, BranchDensitiesSumToThePdf) {
    Pcg32 rng = restir::make_pixel_rng(5u, 0u, restir::RngStream::application, 2022u);
    for (const LobeMaterial& m : lobe_materials)
        for (int i = 0; i < 40000; ++i) {
            const glm::vec3 n = random_unit(rng), wo = random_unit(rng), wi = random_unit(rng);
            const float pdf = m.bsdf.pdf(n, wo, wi);
            const float specular = m.bsdf.lobe_pdf(n, wo, wi, true);
            const float diffuse = m.bsdf.lobe_pdf(n, wo, wi, false);
            ASSERT_TRUE(specular >= 0.0f && diffuse >= 0.0f) << m.name << " " << i;
            const float cos_min = std::max(std::min(glm::dot(n, wo), glm::dot(n, wi)), 1e-20f);
            ASSERT_NEAR(specular + diffuse, pdf, (1e-5f + 3e-6f / cos_min) * pdf)
                << m.name << " " << i;
        }
}

// The directions that `sample` draws on one branch (u_lobe drawn until it picks it) fit the
// branch's density lobe_pdf / P, P its probability; the draws that give no direction fill
// what that density leaves of 1.
TEST(GlossyBsdfLobe, EachBranchDrawsItsDensityOverItsProbability) {
    constexpr int chi2_tests = 10;
    const double alpha = restir::test::sidak_significance(0.01, chi2_tests);
    Pcg32 rng = restir::make_pixel_rng(6u, 0u, restir::RngStream::application, 2022u);
    for (const LobeMaterial& m : lobe_materials)
        for (const float degrees : {30.0f, 75.0f})
            for (const bool specular : {true, false}) {
                const glm::vec3 wo = restir::test::view_at(degrees);
                const float p = m.bsdf.specular_probability(up, wo);
                const float branch = specular ? p : 1.0f - p;
                if (branch == 0.0f)
                    continue; // a metal's diffuse branch is never drawn
                const auto draw = [&]() -> std::optional<glm::vec3> {
                    float u_lobe = next_float(rng);
                    while (m.bsdf.samples_specular(up, wo, u_lobe) != specular)
                        u_lobe = next_float(rng);
                    const float u0 = next_float(rng), u1 = next_float(rng);
                    const restir::BsdfSample s = m.bsdf.sample(up, wo, u_lobe, u0, u1);
                    return s.pdf > 0.0f ? std::optional<glm::vec3>(s.wi) : std::nullopt;
                };
                const auto density = [&](glm::vec3 wi) {
                    return m.bsdf.lobe_pdf(up, wo, wi, specular) / branch;
                };
                const glm::vec3 peak = specular ? glm::vec3(-wo.x, -wo.y, wo.z) : up;
                EXPECT_TRUE(restir::test::samples_fit_density(
                    draw, density, peak, specular ? restir::ggx_alpha(m.bsdf.roughness) : 1.0f,
                    200000, alpha))
                    << m.name << ", view " << degrees << ", specular " << specular;
            }
}

// The branch is picked with probability P_s, and the posterior lobe_pdf(specular) / pdf of a
// drawn direction is the probability that the specular branch drew it: over draws with a
// uniform u_lobe, [specular branch] - posterior has mean 0 (0 where no direction is drawn).
TEST(GlossyBsdfLobe, SpecularPosteriorIsTheBranchesFrequency) {
    Pcg32 rng = restir::make_pixel_rng(7u, 0u, restir::RngStream::application, 2022u);
    for (const LobeMaterial& m : lobe_materials)
        for (const float degrees : {0.0f, 45.0f, 80.0f}) {
            const glm::vec3 wo = restir::test::view_at(degrees);
            restir::test::RunningStats frequency, gap;
            for (int i = 0; i < 200000; ++i) {
                const float u_lobe = next_float(rng), u0 = next_float(rng), u1 = next_float(rng);
                const bool specular = m.bsdf.samples_specular(up, wo, u_lobe);
                const restir::BsdfSample s = m.bsdf.sample(up, wo, u_lobe, u0, u1);
                const double posterior =
                    s.pdf > 0.0f ? static_cast<double>(m.bsdf.lobe_pdf(up, wo, s.wi, true)) /
                                       static_cast<double>(m.bsdf.pdf(up, wo, s.wi))
                                 : (specular ? 1.0 : 0.0);
                frequency.add(specular ? 1.0 : 0.0);
                gap.add((specular ? 1.0 : 0.0) - posterior);
            }
            const double p = static_cast<double>(m.bsdf.specular_probability(up, wo));
            EXPECT_TRUE(restir::test::agrees_with(frequency, p)) << m.name << ", view " << degrees;
            EXPECT_TRUE(restir::test::agrees_with(gap, 0.0)) << m.name << ", view " << degrees;
        }
}

} // namespace
