// The reconnection shift of ReSTIR GI and its path samples: the Jacobian against the ratio of
// solid angles that a small patch around the sample point subtends (computed exactly), the
// shift's rules, the Jacobian's composition, a path sample's contribution at a Lambertian
// receiver, and the storage form's round trip.
#include <restir/core/rng.hpp>
#include <restir/gi/path_sample.hpp>
#include <restir/gi/reconnection_shift.hpp>
#include <restir/light/receiver.hpp>

#include <gtest/gtest.h>

#include <glm/geometric.hpp>
#include <glm/vec3.hpp>

#include <algorithm>
#include <cmath>
#include <cstdint>
#include <cstdio>
#include <limits>
#include <utility>

namespace {

using restir::PathSample;

// A surface known by its position (the shift reads nothing else).
struct Point {
    glm::vec3 position{0.0f};
    glm::vec3 normal{0.0f, 1.0f, 0.0f};
};
glm::vec3 surface_position(const Point& p) { return p.position; }
[[maybe_unused]] glm::vec3 surface_normal(const Point& p) { return p.normal; }
[[maybe_unused]] float surface_depth(const Point&) { return 1.0f; }
[[maybe_unused]] bool is_valid_surface(const Point&) { return true; }

struct Vec3d {
    double x, y, z;
};
Vec3d to_double(glm::vec3 v) {
    return {static_cast<double>(v.x), static_cast<double>(v.y), static_cast<double>(v.z)};
}
Vec3d operator+(Vec3d a, Vec3d b) { return {a.x + b.x, a.y + b.y, a.z + b.z}; }
Vec3d operator-(Vec3d a, Vec3d b) { return {a.x - b.x, a.y - b.y, a.z - b.z}; }
Vec3d operator*(double s, Vec3d a) { return {s * a.x, s * a.y, s * a.z}; }
double dot(Vec3d a, Vec3d b) { return a.x * b.x + a.y * b.y + a.z * b.z; }
Vec3d cross(Vec3d a, Vec3d b) {
    return {a.y * b.z - a.z * b.y, a.z * b.x - a.x * b.z, a.x * b.y - a.y * b.x};
}
double length(Vec3d a) { return std::sqrt(dot(a, a)); }
Vec3d normalize(Vec3d a) { return (1.0 / length(a)) * a; }

// Solid angle of triangle a, b, c seen from `from`, in double (Van Oosterom and Strackee 1983,
// with the triple product taken over the triangle's edges, which keeps small distant triangles
// precise).
double triangle_solid_angle(Vec3d from, Vec3d a, Vec3d b, Vec3d c) {
    const Vec3d ra = a - from, rb = b - from, rc = c - from;
    const double la = length(ra), lb = length(rb), lc = length(rc);
    const double triple = std::fabs(dot(ra, cross(b - a, c - a)));
    const double denominator =
        la * lb * lc + dot(ra, rb) * lc + dot(ra, rc) * lb + dot(rb, rc) * la;
    return 2.0 * std::atan2(triple, denominator);
}

// Solid angle of the square of side `side` centred on `centre` in the plane of unit `normal`,
// seen from `from`.
double square_solid_angle(Vec3d from, Vec3d centre, Vec3d normal, double side) {
    const Vec3d helper = std::fabs(normal.x) < 0.9 ? Vec3d{1.0, 0.0, 0.0} : Vec3d{0.0, 1.0, 0.0};
    const Vec3d t = (0.5 * side) * normalize(cross(normal, helper));
    const Vec3d b = (0.5 * side) * normalize(cross(normal, t));
    const Vec3d c00 = centre - t - b, c10 = centre + t - b, c11 = centre + t + b,
                c01 = centre - t + b;
    return triangle_solid_angle(from, c00, c10, c11) + triangle_solid_angle(from, c00, c11, c01);
}

glm::vec3 random_unit(restir::Pcg32& rng) {
    const float z = 1.0f - 2.0f * next_float(rng);
    const float phi = 2.0f * restir::pi * next_float(rng);
    const float r = std::sqrt(std::max(0.0f, 1.0f - z * z));
    return {r * std::cos(phi), r * std::sin(phi), z};
}

// A point in front of the surface (s, n) at distance [0.5, 4) whose direction makes a cosine of
// at least 0.2 with n.
glm::vec3 random_point_in_front(restir::Pcg32& rng, glm::vec3 s, glm::vec3 n) {
    for (;;) {
        const glm::vec3 w = random_unit(rng);
        if (glm::dot(w, n) >= 0.2f)
            return s + (0.5f + 3.5f * next_float(rng)) * w;
    }
}

// Relative error budget of one float Jacobian: coordinates below 6 in magnitude, distances
// at least 0.5 and cosines at least 0.2 put each difference's rounding below 1e-6 of the
// distance and each cosine-times-distance's below 5e-6 relative; the rest of the formula adds
// a few ulps.
constexpr double float_jacobian_error = 1e-5;

// J(q -> r) = Omega_r / Omega_q for a patch of side eps around s in s's tangent plane, up to
// the patch's own size: expanding cos / d^2 over a square of side eps to second order, each
// solid angle is A cos / d^2 (1 + (eps / d)^2 (5/8 sin^2 - 1/4)), within 3/8 (eps / d)^2; the
// check allows (eps / d_q)^2 + (eps / d_r)^2 for that (higher orders included) plus the float
// rounding of J.
TEST(ReconnectionJacobian, IsTheRatioOfSolidAnglesOfASmallPatch) {
    restir::Pcg32 rng = restir::make_pixel_rng(0u, 0u, restir::RngStream::application, 2021u);
    for (int trial = 0; trial < 2000; ++trial) {
        const glm::vec3 s(4.0f * next_float(rng) - 2.0f, 4.0f * next_float(rng) - 2.0f,
                          4.0f * next_float(rng) - 2.0f);
        const glm::vec3 n = random_unit(rng);
        const glm::vec3 q = random_point_in_front(rng, s, n);
        const glm::vec3 r = random_point_in_front(rng, s, n);
        const double d_q = length(to_double(q) - to_double(s));
        const double d_r = length(to_double(r) - to_double(s));
        const double side = 1e-3 * std::min(d_q, d_r);
        const Vec3d nd = normalize(to_double(n));
        const double omega_q = square_solid_angle(to_double(q), to_double(s), nd, side);
        const double omega_r = square_solid_angle(to_double(r), to_double(s), nd, side);
        const double expected = omega_r / omega_q;
        const double tolerance =
            (side * side / (d_q * d_q) + side * side / (d_r * d_r)) + float_jacobian_error;
        const float jacobian = restir::reconnection_jacobian(q, r, s, n);
        ASSERT_NEAR(static_cast<double>(jacobian) / expected, 1.0, tolerance) << "trial " << trial;
    }
}

TEST(ReconnectionJacobian, IsZeroWhereEitherPointIsBehindOrOnTheSurface) {
    const glm::vec3 s(0.0f, 1.0f, 0.0f), n(0.0f, -1.0f, 0.0f);
    const glm::vec3 front(0.3f, 0.0f, 0.2f), other_front(-0.5f, -0.5f, 0.1f);
    const glm::vec3 behind(0.3f, 2.0f, 0.2f), in_plane(2.0f, 1.0f, 0.0f);
    EXPECT_GT(restir::reconnection_jacobian(front, other_front, s, n), 0.0f);
    EXPECT_EQ(restir::reconnection_jacobian(behind, front, s, n), 0.0f);
    EXPECT_EQ(restir::reconnection_jacobian(front, behind, s, n), 0.0f);
    EXPECT_EQ(restir::reconnection_jacobian(in_plane, front, s, n), 0.0f);
    EXPECT_EQ(restir::reconnection_jacobian(front, in_plane, s, n), 0.0f);
    EXPECT_EQ(restir::reconnection_jacobian(s, front, s, n), 0.0f);
    EXPECT_EQ(restir::reconnection_jacobian(front, s, s, n), 0.0f);
    // The same normal the other way round: both points now behind.
    EXPECT_EQ(restir::reconnection_jacobian(front, other_front, s, -n), 0.0f);
    const float nan = std::numeric_limits<float>::quiet_NaN();
    EXPECT_EQ(restir::reconnection_jacobian(glm::vec3(nan), front, s, n), 0.0f);
}

// Shifting q -> r -> t is shifting q -> t, and r -> q undoes q -> r, up to float rounding (the
// budget of each Jacobian involved).
TEST(ReconnectionJacobian, ComposesAndInverts) {
    restir::Pcg32 rng = restir::make_pixel_rng(1u, 0u, restir::RngStream::application, 2021u);
    for (int trial = 0; trial < 2000; ++trial) {
        const glm::vec3 s(4.0f * next_float(rng) - 2.0f, 4.0f * next_float(rng) - 2.0f,
                          4.0f * next_float(rng) - 2.0f);
        const glm::vec3 n = random_unit(rng);
        const glm::vec3 q = random_point_in_front(rng, s, n);
        const glm::vec3 r = random_point_in_front(rng, s, n);
        const glm::vec3 t = random_point_in_front(rng, s, n);
        const auto q_r = static_cast<double>(restir::reconnection_jacobian(q, r, s, n));
        const auto r_t = static_cast<double>(restir::reconnection_jacobian(r, t, s, n));
        const auto q_t = static_cast<double>(restir::reconnection_jacobian(q, t, s, n));
        const auto r_q = static_cast<double>(restir::reconnection_jacobian(r, q, s, n));
        ASSERT_NEAR(q_r * r_t / q_t, 1.0, 3.0 * float_jacobian_error) << "trial " << trial;
        ASSERT_NEAR(q_r * r_q, 1.0, 2.0 * float_jacobian_error) << "trial " << trial;
        ASSERT_EQ(restir::reconnection_jacobian(q, q, s, n), 1.0f) << "trial " << trial;
    }
}

PathSample sample_at(glm::vec3 visible_point, float roughness) {
    PathSample x;
    x.visible_point = visible_point;
    x.sample_point = glm::vec3(0.2f, 1.5f, -0.1f);
    x.sample_normal = glm::normalize(glm::vec3(0.1f, -1.0f, 0.2f));
    x.radiance = glm::vec3(0.7f, 1.1f, 2.0f);
    x.source_pdf = 0.27f;
    x.sample_roughness = roughness;
    return x;
}

// The shifted sample is the original with its visible point moved to the receiver's position.
void expect_moved_only(const PathSample& shifted, const PathSample& original, glm::vec3 r) {
    PathSample expected = original;
    expected.visible_point = r;
    EXPECT_EQ(shifted, expected);
}

TEST(ReconnectionShift, KeepsTheSamplePointAndMovesTheVisiblePoint) {
    const Point from{{0.0f, 0.0f, 0.0f}}, to{{0.6f, 0.1f, -0.3f}};
    const PathSample x = sample_at(from.position, 1.0f);
    const restir::ShiftedSample<PathSample> y = restir::ReconnectionShift{}(x, from, to);
    expect_moved_only(y.sample, x, to.position);
    EXPECT_FLOAT_EQ(y.jacobian, restir::reconnection_jacobian(from.position, to.position,
                                                              x.sample_point, x.sample_normal));
    EXPECT_GT(y.jacobian, 0.0f);
    EXPECT_NE(y.jacobian, 1.0f);
    static_assert(restir::ShiftMapping<restir::ReconnectionShift, PathSample, Point>);
    static_assert(!restir::is_identity_shift<restir::ReconnectionShift>);
    static_assert(restir::is_identity_shift<const restir::IdentityShift&>);
}

TEST(ReconnectionShift, SamePositionIsTheIdentityWhateverTheRoughness) {
    const Point from{{0.3f, 0.0f, 0.2f}, {0.0f, 1.0f, 0.0f}};
    const Point same{{0.3f, 0.0f, 0.2f}, {0.0f, 0.0f, 1.0f}}; // another normal, same place
    for (float roughness : {0.0f, 0.2f, 0.5f, 1.0f}) {
        const PathSample x = sample_at(from.position, roughness);
        const restir::ShiftedSample<PathSample> y = restir::ReconnectionShift{}(x, from, same);
        EXPECT_EQ(y.jacobian, 1.0f) << roughness;
        expect_moved_only(y.sample, x, same.position);
    }
    // Even a sample that the point lies behind: the same pixel keeps its own sample.
    PathSample behind = sample_at(from.position, 0.0f);
    behind.sample_normal = -behind.sample_normal;
    EXPECT_EQ(restir::ReconnectionShift{}(behind, from, same).jacobian, 1.0f);
}

TEST(ReconnectionShift, FailsBelowTheMinimumRoughnessElsewhere) {
    const Point from{{0.0f, 0.0f, 0.0f}}, to{{0.6f, 0.1f, -0.3f}};
    const float full = restir::reconnection_jacobian(from.position, to.position,
                                                     sample_at(from.position, 1.0f).sample_point,
                                                     sample_at(from.position, 1.0f).sample_normal);
    const struct {
        float min_roughness, roughness;
        bool shifts;
    } cases[] = {
        {0.5f, 0.49f, false}, {0.5f, 0.5f, true}, {0.5f, 0.0f, false}, {0.5f, 1.0f, true},
        {1.0f, 0.99f, false}, {1.0f, 1.0f, true}, {0.0f, 0.0f, true},  {0.0f, 0.3f, true},
        {0.5f, -1.0f, false}, {0.5f, 2.0f, true},
    };
    for (const auto& c : cases) {
        const PathSample x = sample_at(from.position, c.roughness);
        const restir::ShiftedSample<PathSample> y =
            restir::ReconnectionShift{c.min_roughness}(x, from, to);
        if (c.shifts)
            EXPECT_FLOAT_EQ(y.jacobian, full)
                << "min " << c.min_roughness << ", roughness " << c.roughness;
        else
            EXPECT_EQ(y.jacobian, 0.0f)
                << "min " << c.min_roughness << ", roughness " << c.roughness;
        expect_moved_only(y.sample, x, to.position);
    }
    PathSample nan_roughness = sample_at(from.position, std::nanf(""));
    EXPECT_EQ(restir::ReconnectionShift{}(nan_roughness, from, to).jacobian, 0.0f);
    // Behind the sample point's surface: fails though rough.
    PathSample back = sample_at(from.position, 1.0f);
    back.sample_normal = -back.sample_normal;
    EXPECT_EQ(restir::ReconnectionShift{}(back, from, to).jacobian, 0.0f);
}

TEST(PathSampleRadiance, IsTheLambertianIntegrandTowardsTheSamplePoint) {
    const restir::LambertianReceiver receiver{
        {0.1f, 0.0f, -0.2f}, glm::normalize(glm::vec3(0.2f, 1.0f, 0.1f)), {0.8f, 0.5f, 0.3f}};
    PathSample x = sample_at(receiver.position, 1.0f);
    const glm::vec3 wi = glm::normalize(x.sample_point - receiver.position);
    const glm::vec3 expected =
        receiver.albedo * (glm::dot(receiver.normal, wi) / restir::pi) * x.radiance;
    const glm::vec3 value = restir::path_sample_radiance(x, receiver);
    for (int c = 0; c < 3; ++c)
        EXPECT_NEAR(value[c], expected[c], 1e-6f * expected[c]) << c;
    // The visible point stored in the sample plays no part: only the receiver's position.
    x.visible_point = glm::vec3(5.0f);
    EXPECT_EQ(restir::path_sample_radiance(x, receiver), value);
}

TEST(PathSampleRadiance, IsZeroBehindEitherSurface) {
    const restir::LambertianReceiver receiver{
        {0.1f, 0.0f, -0.2f}, {0.0f, 1.0f, 0.0f}, {0.8f, 0.5f, 0.3f}};
    PathSample x = sample_at(receiver.position, 1.0f);
    PathSample back = x; // the receiver behind the sample point's surface
    back.sample_normal = -x.sample_normal;
    EXPECT_EQ(restir::path_sample_radiance(back, receiver), glm::vec3(0.0f));
    PathSample in_plane = x; // the receiver in the sample point's tangent plane
    in_plane.sample_point = receiver.position + glm::vec3(0.0f, 1.5f, 0.0f);
    in_plane.sample_normal = glm::vec3(1.0f, 0.0f, 0.0f);
    EXPECT_EQ(restir::path_sample_radiance(in_plane, receiver), glm::vec3(0.0f));
    restir::LambertianReceiver flipped = receiver; // the sample point below the receiver
    flipped.normal = -receiver.normal;
    EXPECT_EQ(restir::path_sample_radiance(x, flipped), glm::vec3(0.0f));
    PathSample at_receiver = x; // no direction at all
    at_receiver.sample_point = receiver.position;
    EXPECT_EQ(restir::path_sample_radiance(at_receiver, receiver), glm::vec3(0.0f));
}

double angle_between(glm::vec3 a, glm::vec3 b) {
    const Vec3d x = to_double(a), y = to_double(b);
    return std::atan2(length(cross(x, y)), dot(x, y));
}

// Octahedral normals, 16 bits a coordinate, rounded to the nearest code: each coordinate errs by
// at most h = 1 / 65535 (half a step of 2 / 65535); at a face centre of the octahedron (the
// worst place: farthest from the sphere, 1 / sqrt(3) from the origin) a move (h, h) in the
// square moves the point on the face by sqrt(6) h, which turns the direction by sqrt(3) sqrt(6) h
// = 3 sqrt(2) / 65535 = 6.47e-5 rad; float decoding adds about 1e-7.
constexpr double octahedral_bound = 3.0 * 1.41421356237 / 65535.0 + 1e-6;

TEST(PackedPathSample, KeepsPointsAndPdfExactlyAndNormalsWithinTheirBound) {
    restir::Pcg32 rng = restir::make_pixel_rng(2u, 0u, restir::RngStream::application, 2021u);
    double worst_angle = 0.0;
    for (int i = 0; i < 200000; ++i) {
        PathSample x;
        x.visible_point = glm::vec3(next_float(rng) * 1e3f, -next_float(rng), next_float(rng));
        x.sample_point = glm::vec3(-next_float(rng) * 1e-3f, next_float(rng), 7.0f);
        x.sample_normal = random_unit(rng);
        x.radiance = glm::vec3(1.0f);
        x.source_pdf = next_float(rng) * 100.0f;
        x.sample_roughness = next_float(rng);
        const PathSample y = restir::unpack_path_sample(restir::pack_path_sample(x));
        ASSERT_EQ(y.visible_point, x.visible_point);
        ASSERT_EQ(y.sample_point, x.sample_point);
        ASSERT_EQ(y.source_pdf, x.source_pdf);
        ASSERT_NEAR(y.sample_roughness, x.sample_roughness, 1.0f / 65535.0f);
        ASSERT_NEAR(glm::length(y.sample_normal), 1.0f, 1e-6f);
        worst_angle = std::max(worst_angle, angle_between(x.sample_normal, y.sample_normal));
    }
    // The axes, the octant boundaries and the folded lower half's edges.
    for (glm::vec3 n :
         {glm::vec3(1, 0, 0), glm::vec3(-1, 0, 0), glm::vec3(0, 1, 0), glm::vec3(0, -1, 0),
          glm::vec3(0, 0, 1), glm::vec3(0, 0, -1), glm::vec3(1, 1, 0), glm::vec3(-1, 1, 0),
          glm::vec3(1, -1, -1e-7f), glm::vec3(-1, -1, -1), glm::vec3(1e-7f, -1e-7f, -1)}) {
        PathSample x;
        x.sample_normal = glm::normalize(n);
        const PathSample y = restir::unpack_path_sample(restir::pack_path_sample(x));
        worst_angle = std::max(worst_angle, angle_between(x.sample_normal, y.sample_normal));
    }
    EXPECT_LT(worst_angle, octahedral_bound);
    EXPECT_LT(worst_angle, 1e-4);
    std::printf("octahedral normals: worst angle %.3g rad\n", worst_angle);
}

glm::vec3 round_trip_radiance(glm::vec3 radiance) {
    PathSample x;
    x.radiance = radiance;
    return restir::unpack_path_sample(restir::pack_path_sample(x)).radiance;
}

// RGB9E5: mantissas in units of 2^(e - 9) with the largest channel below 2^e, so rounding errs
// by at most half a unit, 2^-9 of the largest channel. Where that channel rounds up to 2^e,
// the exponent grows by one and so does the unit: half of it is then at most 1 / 511.5 of the
// largest channel (which is at least 511.5 old units), the exact bound used here.
TEST(PackedPathSample, KeepsRadianceWithinItsSharedExponentBound) {
    restir::Pcg32 rng = restir::make_pixel_rng(3u, 0u, restir::RngStream::application, 2021u);
    for (int i = 0; i < 200000; ++i) {
        glm::vec3 c;
        for (int k = 0; k < 3; ++k) // magnitudes from 2^-15 to 2^15, channels up to 2^30 apart
            c[k] =
                std::ldexp(1.0f + next_float(rng), static_cast<int>(next_float(rng) * 30.0f) - 15);
        const float top = std::max(c.x, std::max(c.y, c.z));
        const glm::vec3 y = round_trip_radiance(c);
        for (int k = 0; k < 3; ++k)
            ASSERT_LE(std::fabs(y[k] - c[k]), top / 511.5f) << i << " channel " << k;
    }
    // A largest channel that rounds up to the next power of two, and a channel halfway between
    // two of the new units: the error is 2^-9, just over 2^-9 of the largest channel.
    const glm::vec3 edge(511.75f / 512.0f, 100.5f / 256.0f, 0.0f);
    const glm::vec3 y = round_trip_radiance(edge);
    EXPECT_EQ(y.x, 1.0f);
    EXPECT_LE(std::fabs(y.y - edge.y), edge.x / 511.5f);
    EXPECT_GT(std::fabs(y.y - edge.y), edge.x / 512.0f);
    // Below 2^-16 the exponent stops at -15: units of 2^-24, errors below 2^-25.
    const glm::vec3 tiny(3e-6f, 1e-7f, 0.0f);
    const glm::vec3 t = round_trip_radiance(tiny);
    for (int k = 0; k < 3; ++k)
        EXPECT_LE(std::fabs(t[k] - tiny[k]), 0x1p-25f) << k;
}

TEST(PackedPathSample, ClampsHostileRadianceAndRoughness) {
    const float inf = std::numeric_limits<float>::infinity();
    const float nan = std::numeric_limits<float>::quiet_NaN();
    EXPECT_EQ(round_trip_radiance({nan, -2.0f, -inf}), glm::vec3(0.0f));
    EXPECT_EQ(round_trip_radiance({1e6f, inf, 70000.0f}), glm::vec3(65408.0f));
    EXPECT_EQ(round_trip_radiance({65408.0f, 0.0f, 0.0f}), glm::vec3(65408.0f, 0.0f, 0.0f));
    const glm::vec3 mixed = round_trip_radiance({nan, 1.0f, -1.0f});
    EXPECT_EQ(mixed, glm::vec3(0.0f, 1.0f, 0.0f));
    for (const auto& [roughness, expected] :
         {std::pair{nan, 0.0f}, std::pair{-1.0f, 0.0f}, std::pair{2.0f, 1.0f}, std::pair{inf, 1.0f},
          std::pair{1.0f, 1.0f}, std::pair{0.0f, 0.0f}}) {
        PathSample x;
        x.sample_roughness = roughness;
        EXPECT_EQ(restir::unpack_path_sample(restir::pack_path_sample(x)).sample_roughness,
                  expected)
            << roughness;
    }
}

} // namespace
