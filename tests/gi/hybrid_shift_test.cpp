// The hybrid shift of ReSTIR PT over a toy scene whose paths it replays: the reconnection
// density, the shift's Jacobian against finite differences (the solid angles of a small patch
// around the reconnection vertex, and of the directions that a small square of random numbers
// maps to under a replayed bounce), its inverse, its failures, the MIS weight at the
// reconnection vertex, and the lobe densities of GlossyBsdf of which a replayed path's density
// is made.
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
using restir::HybridShift;
using restir::Pcg32;
using restir::PtSample;
using restir::ReconnectionCriterion;
using restir::test::random_unit;

// A surface of the toy scene: its position, normal, perceptual roughness (the criterion's) and
// the cosine power of its material's direction sampler.
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

// The toy scene and its replayable path tracer (a `restir::PathReplay`): a ceiling at height
// `ceiling` facing down, which every bounce from a visible point (below it) aims at. A path
// reconnecting at x_2 replays nothing; at x_3, one bounce from x_1 to the ceiling; a path
// without reconnection vertex (rc_index 0, length 2) ends on the ceiling's emission.
struct ToyReplay {
    using Vertex = Point;
    float ceiling = 3.0f;
    float ceiling_roughness = 0.8f;
    glm::vec3 albedo{0.7f, 0.5f, 0.3f};
    glm::vec3 emission{4.0f, 3.0f, 2.0f};

    // The bounce from `from` with the seed's numbers, as the prefix it makes: invalid where it
    // misses the ceiling or where (from, hit) meets `rule` (the path would reconnect there).
    restir::ReplayedPrefix<Point> bounce(std::uint32_t seed, const Point& from,
                                         const ReconnectionCriterion& rule) const {
        const glm::vec2 u = seed_numbers(seed);
        const glm::vec3 w = lobe_direction(from.normal, from.exponent, u.x, u.y);
        const Point hit{from.position + ((ceiling - from.position.y) / w.y) * w,
                        {0.0f, -1.0f, 0.0f},
                        ceiling_roughness,
                        1.0f};
        if (!(w.y > 0.0f) ||
            rule(from.roughness, hit.roughness, glm::distance(hit.position, from.position)))
            return {};
        const float density = (from.exponent + 1.0f) / restir::two_pi *
                              std::pow(glm::dot(from.normal, w), from.exponent);
        return {hit, hit.position, hit.roughness, albedo * w.y, density, density > 0.0f};
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
        return {b.throughput * emission, b.density, true};
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

// The sample that the toy's path tracer makes at `at` with `seed`: reconnecting at (s, n) for
// rc_index 2 or 3 (the path going on past x_{k+1}), ending on the ceiling for rc_index 0; f and
// D as its own sampler computes them (0 density where it makes no such path).
PtSample make_sample(const ToyReplay& toy, const Point& at, glm::vec3 s, glm::vec3 n,
                     std::uint8_t rc_index, std::uint32_t seed) {
    PtSample x;
    x.visible_point = at.position;
    x.seed = seed;
    x.rc_index = rc_index;
    if (rc_index == 0u) {
        x.length = 2u;
        x.end = restir::PathEnd::bsdf_sampled;
        const restir::ReplayedPath path = toy.replay_path(x, at, {});
        x.contribution = path.contribution;
        x.density = path.valid ? path.density : 0.0f;
        return x;
    }
    x.length = static_cast<std::uint8_t>(rc_index + 2u);
    x.rc_position = s;
    x.rc_normal = n;
    x.rc_direction = glm::normalize(n + glm::vec3(0.3f, -0.2f, 0.1f));
    x.suffix = {1.5f, 2.0f, 2.5f};
    x.rc_roughness = 0.9f;
    x.rc_material = 5u;
    const restir::ReplayedPrefix<Point> prefix = toy.replay_prefix(x, at, {});
    x.density =
        prefix.valid ? restir::reconnection_density(prefix.density, prefix.position, s, n) : 0.0f;
    x.contribution = prefix.throughput * toy.reconnect(prefix.last, x) * x.suffix;
    return x;
}

// Solid angle of triangle a, b, c seen from `from` (Van Oosterom and Strackee 1983, the triple
// product over the triangle's edges, which keeps small triangles precise).
double triangle_solid_angle(dvec3 from, dvec3 a, dvec3 b, dvec3 c) {
    const dvec3 ra = a - from, rb = b - from, rc = c - from;
    const double la = glm::length(ra), lb = glm::length(rb), lc = glm::length(rc);
    const double triple = std::abs(glm::dot(ra, glm::cross(b - a, c - a)));
    const double denominator =
        la * lb * lc + glm::dot(ra, rb) * lc + glm::dot(ra, rc) * lb + glm::dot(rb, rc) * la;
    return 2.0 * std::atan2(triple, denominator);
}

// Solid angle of the square of side `side` centred on `s` in the plane of normal `n`, seen
// from `from`.
double square_solid_angle(glm::vec3 from, glm::vec3 s, glm::vec3 n, double side) {
    const dvec3 normal = glm::normalize(dvec3(n)), centre(s);
    const dvec3 helper = std::abs(normal.x) < 0.9 ? dvec3(1.0, 0.0, 0.0) : dvec3(0.0, 1.0, 0.0);
    const dvec3 t = (0.5 * side) * glm::normalize(glm::cross(normal, helper));
    const dvec3 b = (0.5 * side) * glm::normalize(glm::cross(normal, t));
    const dvec3 c00 = centre - t - b, c10 = centre + t - b, c11 = centre + t + b,
                c01 = centre - t + b;
    return triangle_solid_angle(dvec3(from), c00, c10, c11) +
           triangle_solid_angle(dvec3(from), c00, c11, c01);
}

// The ratio of the solid angles that a patch of side 1e-3 min(d_q, d_r) around x_k subtends
// from r and from q: d omega_r / d omega_q, the reconnection's Jacobian. Expanding cos / d^2
// over the patch to second order, each solid angle is A cos / d^2 within 3/8 (side / d)^2;
// the second number, the error allowed, is (side / d_q)^2 + (side / d_r)^2.
std::pair<double, double> patch_ratio(glm::vec3 q, glm::vec3 r, glm::vec3 s, glm::vec3 n) {
    const double d_q = glm::distance(dvec3(q), dvec3(s)), d_r = glm::distance(dvec3(r), dvec3(s));
    const double side = 1e-3 * std::min(d_q, d_r);
    return {square_solid_angle(r, s, n, side) / square_solid_angle(q, s, n, side),
            side * side / (d_q * d_q) + side * side / (d_r * d_r)};
}

// p_q(w_x) / p_r(w_y), the Jacobian d omega_y / d omega_x of a bounce replayed from q at r: the
// ratio of the solid angles of the directions that the square of numbers of side 1e-4 around
// the seed's numbers maps to (its corners' directions joined by great circles). Both are
// h^2 / p within O(h^2) relative (midpoint rule; the arcs' bulges cancel to that order): with
// u0 in [0.05, 0.95] and cosine powers up to 8, below 1e-6.
double replay_ratio(const Point& q, const Point& r, std::uint32_t seed) {
    constexpr double h = 1e-4;
    const glm::dvec2 u(seed_numbers(seed));
    const auto patch = [&](const Point& p) {
        const auto w = [&](double du0, double du1) {
            return lobe_direction<double>(dvec3(p.normal), static_cast<double>(p.exponent),
                                          u.x + du0 * h, u.y + du1 * h);
        };
        const dvec3 o(0.0), a = w(-0.5, -0.5), b = w(0.5, -0.5), c = w(0.5, 0.5), d = w(-0.5, 0.5);
        return triangle_solid_angle(o, a, b, c) + triangle_solid_angle(o, a, c, d);
    };
    return patch(r) / patch(q);
}
constexpr double replay_fd_error = 1e-6;

// Relative float error of one reconnection Jacobian (two reconnection densities): coordinates
// below 8, distances at least 0.5 and cosines at least 0.2 keep each difference's rounding
// below 1e-6 of the distance and each cosine-times-distance's below 5e-6.
constexpr double float_jacobian_error = 1e-5;
// And of a replayed bounce's density ratio: a float cosine to the power e <= 8 errs by 8 ulps,
// and the float direction's rounding (a few 1e-7 rad) moves p by e tan(theta) <= 50 times it.
constexpr double float_replay_error = 4e-5;

glm::vec3 random_box(Pcg32& rng, float half) {
    const float x = next_float(rng), y = next_float(rng), z = next_float(rng);
    return half * (2.0f * glm::vec3(x, y, z) - 1.0f);
}

// A glossy visible point below the ceiling: position in [-1, 1]^3, normal within 20 degrees
// of up, cosine power in [1, 8].
Point random_glossy_point(Pcg32& rng) {
    const glm::vec3 p = random_box(rng, 1.0f);
    const float tx = next_float(rng), tz = next_float(rng);
    const glm::vec3 n = glm::normalize(glm::vec3(0.5f * tx - 0.25f, 1.0f, 0.5f * tz - 0.25f));
    return {p, n, 0.1f, 1.0f + 7.0f * next_float(rng)};
}

// A reconnection vertex (s, n) that sees both a and b from at least 1 away at a cosine of at
// least 0.3.
std::pair<glm::vec3, glm::vec3> random_rc_vertex(Pcg32& rng, glm::vec3 a, glm::vec3 b) {
    for (;;) {
        const glm::vec3 s = random_box(rng, 3.0f) * glm::vec3(1.0f, 0.5f, 1.0f);
        const glm::vec3 n = random_unit(rng);
        const glm::vec3 ta = a - s, tb = b - s;
        const float la = glm::length(ta), lb = glm::length(tb);
        if (la >= 1.0f && lb >= 1.0f && glm::dot(n, ta) >= 0.3f * la &&
            glm::dot(n, tb) >= 0.3f * lb)
            return {s, n};
    }
}

// Whether the seed's bounce from p is well conditioned: u0 in [0.05, 0.95], the direction at
// least 30 degrees above the horizontal.
bool well_conditioned(const Point& p, std::uint32_t seed) {
    const glm::vec2 u = seed_numbers(seed);
    return u.x >= 0.05f && u.x <= 0.95f && lobe_direction(p.normal, p.exponent, u.x, u.y).y >= 0.5f;
}

TEST(HybridShiftDensity, IsThePrefixTimesDistanceSquaredOverCosineAndZeroBehind) {
    const glm::vec3 rc(1.0f, -2.0f, 0.5f), from = rc + glm::vec3(0.0f, 3.0f, 4.0f); // 5 away
    const auto density = [&](float prefix, glm::vec3 at, glm::vec3 n) {
        return restir::reconnection_density(prefix, at, rc, n);
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

// Reconnecting at x_2 (nothing replayed), the Jacobian is the reconnection's.
TEST(HybridShift, ReconnectionJacobianIsTheRatioOfSolidAnglesOfASmallPatch) {
    Pcg32 rng = restir::make_pixel_rng(0u, 0u, restir::RngStream::application, 2022u);
    const ToyReplay toy;
    const HybridShift<ToyReplay> shift{&toy};
    for (int trial = 0; trial < 2000; ++trial) {
        const Point q{random_box(rng, 2.0f), random_unit(rng), 0.9f};
        const Point r{random_box(rng, 2.0f), random_unit(rng), 0.9f};
        const auto [s, n] = random_rc_vertex(rng, q.position, r.position);
        const PtSample x = make_sample(toy, q, s, n, 2u, rng.next_uint());
        const float jacobian = shift(x, q, r).jacobian;
        const auto [expected, error] = patch_ratio(q.position, r.position, s, n);
        ASSERT_NEAR(static_cast<double>(jacobian) / expected, 1.0, error + float_jacobian_error)
            << "trial " << trial;
    }
}

// Reconnecting at x_3 after one replayed bounce, the Jacobian is the bounce's (d omega_y /
// d omega_x of the directions) times the reconnection's from the replayed vertex: the shift maps
// (w_1, w_2) triangularly, w_1 to w'_1 alone, so its determinant is the product. Without
// reconnection vertex the path is replayed whole: the bounce's alone.
TEST(HybridShift, ReplayAndReconnectionJacobiansAreThoseOfFiniteDifferences) {
    Pcg32 rng = restir::make_pixel_rng(1u, 0u, restir::RngStream::application, 2022u);
    const ToyReplay toy;
    const HybridShift<ToyReplay> shift{&toy};
    int checked = 0;
    for (int trial = 0; trial < 2000; ++trial) {
        const Point q = random_glossy_point(rng), r = random_glossy_point(rng);
        const std::uint32_t seed = rng.next_uint();
        if (!well_conditioned(q, seed) || !well_conditioned(r, seed))
            continue;
        const double replay = replay_ratio(q, r, seed);
        const PtSample whole = make_sample(toy, q, {}, {}, 0u, seed);
        ASSERT_NEAR(static_cast<double>(shift(whole, q, r).jacobian) / replay, 1.0,
                    replay_fd_error + float_replay_error)
            << "trial " << trial;
        const glm::vec3 x2 = toy.bounce(seed, q, {}).position,
                        y2 = toy.bounce(seed, r, {}).position;
        const auto [s, n] = random_rc_vertex(rng, x2, y2);
        const PtSample x = make_sample(toy, q, s, n, 3u, seed);
        const auto [geometric, error] = patch_ratio(x2, y2, s, n);
        ASSERT_NEAR(static_cast<double>(shift(x, q, r).jacobian) / (replay * geometric), 1.0,
                    error + replay_fd_error + float_jacobian_error + float_replay_error)
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
        const restir::ShiftedSample<PtSample> y = shift(x, a, b);
        if (!(x.density > 0.0f) || !(y.jacobian > 0.0f))
            continue;
        expect_same_sample(y.sample, make_sample(toy, b, s, n, rc_index, seed));
        const restir::ShiftedSample<PtSample> back = shift(y.sample, b, a);
        expect_same_sample(back.sample, x);
        EXPECT_NEAR(static_cast<double>(y.jacobian) * static_cast<double>(back.jacobian), 1.0, 1e-5)
            << "trial " << trial;
        ++inverted[rc_index];
    }
    EXPECT_GT(inverted[0], 200);
    EXPECT_GT(inverted[2], 100);
    EXPECT_GT(inverted[3], 100);
}

// Two rough visible points below a reconnection vertex facing down (reconnecting at x_2), two
// glossy ones below the ceiling (replaying a bounce), and a seed whose bounce rises steeply.
const Point rough_a{{0.0f, 0.0f, 0.0f}, {0.0f, 1.0f, 0.0f}, 0.9f, 2.0f};
const Point rough_b{{0.6f, 0.1f, -0.4f}, {0.0f, 1.0f, 0.0f}, 0.9f, 3.0f};
const glm::vec3 rc_s{0.3f, 2.0f, 0.2f}, rc_down{0.0f, -1.0f, 0.0f};
const Point glossy_a{{0.0f, 0.0f, 0.0f}, {0.0f, 1.0f, 0.0f}, 0.1f, 2.0f};
const Point glossy_b{{0.6f, 0.1f, -0.4f}, {0.0f, 1.0f, 0.0f}, 0.1f, 5.0f};
const glm::vec3 ceiling_rc_s{0.2f, 0.5f, -0.1f}, rc_up{0.0f, 1.0f, 0.0f};
constexpr std::uint32_t steep_seed = 0x8000c000u; // u = (0.75, 0.5)

void expect_failed(const restir::ShiftedSample<PtSample>& y, const Point& to, const char* why) {
    EXPECT_EQ(y.jacobian, 0.0f) << why;
    EXPECT_EQ(y.sample.visible_point, to.position) << why;
}

TEST(HybridShift, FailsWhereTheReconnectionFails) {
    const ToyReplay toy;
    const HybridShift<ToyReplay> shift{&toy};
    const PtSample x = make_sample(toy, rough_a, rc_s, rc_down, 2u, steep_seed);
    ASSERT_GT(x.density, 0.0f);
    EXPECT_GT(shift(x, rough_a, rough_b).jacobian, 0.0f);
    Point glossy = rough_b, above = rough_b, level = rough_b;
    glossy.roughness = 0.29f;
    above.position.y = 2.5f;
    level.position.y = rc_s.y;
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
}

TEST(HybridShift, FailsWhereTheReplayFails) {
    const ToyReplay toy;
    const HybridShift<ToyReplay> shift{&toy};
    Point facing_down = glossy_b, rough = glossy_b;
    facing_down.normal = -facing_down.normal; // the bounce misses the ceiling
    rough.roughness = 0.9f; // (y_1, y_2) meets the criterion: the path would reconnect at y_2
    for (const std::uint8_t rc_index : {std::uint8_t{0u}, std::uint8_t{3u}}) {
        const PtSample x = make_sample(toy, glossy_a, ceiling_rc_s, rc_up, rc_index, steep_seed);
        ASSERT_GT(x.density, 0.0f);
        EXPECT_GT(shift(x, glossy_a, glossy_b).jacobian, 0.0f);
        expect_failed(shift(x, glossy_a, facing_down), facing_down, "missed");
        expect_failed(shift(x, glossy_a, rough), rough, "reconnects earlier");
    }
}

TEST(HybridShift, KeepsTheSampleBetweenSurfacesAtTheSamePositionAndNormal) {
    const ToyReplay toy;
    const HybridShift<ToyReplay> shift{&toy};
    const PtSample x = make_sample(toy, glossy_a, ceiling_rc_s, rc_up, 3u, steep_seed);
    // Another material at the same place, where the replay would fail: the sample is kept.
    Point same = glossy_a;
    same.roughness = 0.9f;
    same.exponent = 7.0f;
    const restir::ShiftedSample<PtSample> kept = shift(x, glossy_a, same);
    EXPECT_EQ(kept.jacobian, 1.0f);
    EXPECT_EQ(kept.sample, x);
    // The sample's own visible point plays no part: it becomes the receiver's.
    PtSample elsewhere = x;
    elsewhere.visible_point = glm::vec3(5.0f);
    EXPECT_EQ(shift(elsewhere, glossy_a, same).sample, x);
    // Another normal at the same place is a shift: the bounce is replayed about it.
    Point tilted = glossy_a;
    tilted.normal = glm::normalize(glm::vec3(0.2f, 1.0f, 0.0f));
    const restir::ShiftedSample<PtSample> turned = shift(x, glossy_a, tilted);
    EXPECT_GT(turned.jacobian, 0.0f);
    EXPECT_NE(turned.jacobian, 1.0f);
    expect_same_sample(turned.sample,
                       make_sample(toy, tilted, ceiling_rc_s, rc_up, 3u, steep_seed));
}

TEST(HybridShiftMis, WeighsTheLastSegmentsTechniqueAndNothingBefore) {
    PtSample x;
    x.rc_index = 3u;
    x.length = 4u;
    x.rc_light_pdf = 0.6f;
    x.end = restir::PathEnd::light_sampled;
    EXPECT_FLOAT_EQ(restir::rc_mis_weight(x, 0.2f), 0.75f);
    EXPECT_EQ(restir::rc_mis_weight(x, 0.0f), 1.0f); // BSDF sampling cannot draw w_k
    x.end = restir::PathEnd::bsdf_sampled;
    EXPECT_FLOAT_EQ(restir::rc_mis_weight(x, 0.2f), 0.25f);
    EXPECT_EQ(restir::rc_mis_weight(x, 0.0f), 0.0f);
    // x_k before the last segment: no light density, weight 1 whichever way the path ended.
    x.rc_index = 2u;
    x.length = 5u;
    x.rc_light_pdf = 0.0f;
    for (const auto end : {restir::PathEnd::light_sampled, restir::PathEnd::bsdf_sampled}) {
        x.end = end;
        EXPECT_EQ(restir::rc_mis_weight(x, 0.37f), 1.0f);
    }
}

struct LobeMaterial {
    const char* name;
    restir::GlossyBsdf bsdf;
};
const LobeMaterial lobe_materials[] = {
    {"dielectric 0.12",
     restir::GlossyBsdf::from_metallic_roughness({0.8f, 0.5f, 0.3f}, 0.0f, 0.12f)},
    {"dielectric 0.6", restir::GlossyBsdf::from_metallic_roughness({0.8f, 0.5f, 0.3f}, 0.0f, 0.6f)},
    {"metal 0.4", restir::GlossyBsdf::from_metallic_roughness({0.9f, 0.6f, 0.3f}, 1.0f, 0.4f)},
};
constexpr glm::vec3 up{0.0f, 0.0f, 1.0f};

TEST(GlossyBsdfLobe, BranchDensitiesSumToThePdf) {
    Pcg32 rng = restir::make_pixel_rng(5u, 0u, restir::RngStream::application, 2022u);
    for (const LobeMaterial& m : lobe_materials)
        for (int i = 0; i < 40000; ++i) {
            const glm::vec3 n = random_unit(rng), wo = random_unit(rng), wi = random_unit(rng);
            const float pdf = m.bsdf.pdf(n, wo, wi);
            const float specular = m.bsdf.lobe_pdf(n, wo, wi, true);
            const float diffuse = m.bsdf.lobe_pdf(n, wo, wi, false);
            ASSERT_GE(specular, 0.0f) << m.name << " " << i;
            ASSERT_GE(diffuse, 0.0f) << m.name << " " << i;
            ASSERT_NEAR(specular + diffuse, pdf, 1e-5f * pdf) << m.name << " " << i;
        }
}

// The directions that `sample` draws on one branch (u_lobe drawn until it picks it) fit the
// branch's density lobe_pdf / P, P its probability; the draws that give no direction fill
// what that density leaves of 1.
TEST(GlossyBsdfLobe, EachBranchDrawsItsDensityOverItsProbability) {
    constexpr int chi2_tests = 10;
    const double alpha = restir::test::sidak_significance(0.01, chi2_tests);
    Pcg32 rng = restir::make_pixel_rng(6u, 0u, restir::RngStream::application, 2022u);
    int tests = 0;
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
                const float scale = specular ? restir::ggx_alpha(m.bsdf.roughness) : 1.0f;
                EXPECT_TRUE(
                    restir::test::samples_fit_density(draw, density, peak, scale, 200000, alpha))
                    << m.name << ", view " << degrees << ", specular " << specular;
                ++tests;
            }
    EXPECT_EQ(tests, chi2_tests);
}

// The branch is picked with probability P_s, and the posterior lobe_pdf(specular) / pdf of a
// drawn direction is the probability that the specular branch drew it: over draws with a
// uniform u_lobe, [specular branch] - posterior has mean 0.
TEST(GlossyBsdfLobe, SpecularPosteriorIsTheBranchesFrequency) {
    Pcg32 rng = restir::make_pixel_rng(7u, 0u, restir::RngStream::application, 2022u);
    for (const LobeMaterial& m : lobe_materials)
        for (const float degrees : {0.0f, 45.0f, 80.0f}) {
            const glm::vec3 wo = restir::test::view_at(degrees);
            restir::test::RunningStats frequency, gap;
            for (int i = 0; i < 200000; ++i) {
                const float u_lobe = next_float(rng), u0 = next_float(rng), u1 = next_float(rng);
                const bool specular = m.bsdf.samples_specular(up, wo, u_lobe);
                frequency.add(specular ? 1.0 : 0.0);
                const restir::BsdfSample s = m.bsdf.sample(up, wo, u_lobe, u0, u1);
                if (!(s.pdf > 0.0f)) {
                    gap.add(0.0);
                    continue;
                }
                const double posterior = static_cast<double>(m.bsdf.lobe_pdf(up, wo, s.wi, true)) /
                                         static_cast<double>(m.bsdf.pdf(up, wo, s.wi));
                gap.add((specular ? 1.0 : 0.0) - posterior);
            }
            const double p = static_cast<double>(m.bsdf.specular_probability(up, wo));
            EXPECT_TRUE(restir::test::agrees_with(frequency, p)) << m.name << ", view " << degrees;
            EXPECT_TRUE(restir::test::agrees_with(gap, 0.0)) << m.name << ", view " << degrees;
        }
}

} // namespace
