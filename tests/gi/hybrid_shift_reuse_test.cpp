// ReSTIR PT's hybrid shift through the library's reuse (spatial; temporal then spatial under a
// moving camera) in each unbiased bias correction, on a glossy chain that reconnection alone
// cannot shift, with a known answer per pixel.
//
// The world: a polished tile (y = 0, normal +y, roughness 0.1) holds a 6 x 4 image of visible
// points x_1; a Lambertian panel at y = H = 2 faces down; a Lambertian carpet on the floor, away
// from the tile, faces up; a lamp, a rectangle of the panel, emits downwards (and reflects like
// the rest of it). The toy's path tracer makes the paths x_1 (tile) -> x_2 (panel) -> x_3
// (carpet) -> x_4 (lamp) and no others; their integral is the truth at a pixel. The panel is
// finite so that |x_2 - x_3|, and with it the reconnection's Jacobian, stays bounded: 1/Z's
// weights do not temper large Jacobians, and heavy tails would make its standard errors lie.
//
// The tile picks a lobe with u_lobe: with probability 0.7 a cosine-power lobe about the view's
// mirror direction (power 3 to 9 across the tile), else a cosine lobe; its f_s cos is rho_s p_s
// + rho_d p_d, so a lobe's posterior P_l p_l / p varies. The panel bounces by cosine sampling;
// light sampling (a point by area) and cosine sampling from x_3 reach the lamp, weighed by the
// balance heuristic. A path's numbers at a vertex depend on its seed and the vertex alone, so a
// replay from another visible point finds another direction (another axis and power); f and
// the densities are as docs/restir-pt.md says. Criterion (0.3, 0.5): every path reconnects at
// x_3 after one replayed glossy bounce (k = 3); (0.3, 100): none does (rc_index 0, whole replay).
//
// The truth per channel: the carpet's radiance is L_3 = rho_3 Le F(x_3), F the view factor to
// the lamp (closed form); the panel's L_2(x_2) = rho_2 / pi int_carpet L_3 H^2 / r^4 dA; the
// pixel's value the integral over the panel of (rho_s p_s + rho_d p_d)(w) L_2 cos_2 / d^2 dA,
// w and d the direction and distance from x_1. Gauss-Legendre rules do both rectangles: the
// integrands are smooth (the lobe's cut-off a.w = 0 a zero of order 3 or more) and the kernels'
// poles lie H off the plane. QuadratureHasConverged checks that doubling the nodes moves the
// truth by less than 1e-9 of it, where 4 standard errors are about 1e-2 of it.
#include <restir/restir.hpp>

#include "support/statistics.hpp"

#include <gtest/gtest.h>

#include <glm/geometric.hpp>
#include <glm/vec3.hpp>

#include <array>
#include <cmath>
#include <cstdint>
#include <cstdio>
#include <string>
#include <utility>
#include <vector>

namespace {

using restir::BiasCorrection;
using restir::PathEnd;
using restir::PixelCoord;
using restir::PtSample;
using restir::ReconnectionCriterion;
using restir::Reservoir;

constexpr std::int32_t width = 6, height = 4;
constexpr std::uint32_t pixel_count = width * height;

constexpr float panel_height = 2.0f, tile_roughness = 0.1f, specular_probability = 0.7f;
constexpr glm::vec3 camera{-4.0f, 2.5f, 0.3f}, up{0.0f, 1.0f, 0.0f};
constexpr glm::vec3 tile_specular{0.55f, 0.45f, 0.3f}, tile_diffuse{0.25f, 0.35f, 0.5f};
constexpr glm::vec3 panel_albedo{0.8f, 0.7f, 0.6f}, carpet_albedo{0.5f, 0.7f, 0.9f};
constexpr glm::vec3 lamp_radiance{6.0f, 5.0f, 4.0f};
constexpr double pi = 3.14159265358979323846;

constexpr ReconnectionCriterion reconnect_at_x3{0.3f, 0.5f}, no_reconnection{0.3f, 100.0f};
static_assert(tile_roughness < reconnect_at_x3.min_roughness &&
              tile_roughness < no_reconnection.min_roughness); // (x_1, x_2) never reconnects

// An axis-aligned rectangle of a horizontal plane.
struct Rect {
    double x0, x1, z0, z1;
    bool contains(glm::vec3 p) const {
        const auto x = static_cast<double>(p.x), z = static_cast<double>(p.z);
        return x >= x0 && x <= x1 && z >= z0 && z <= z1;
    }
};
constexpr Rect panel{-0.5, 5.5, -2.5, 2.5}; // at y = panel_height
constexpr Rect carpet{1.5, 4.5, -1.5, 1.5}; // at y = 0
constexpr Rect lamp{2.0, 3.0, -0.6, 0.6};   // at y = panel_height
constexpr float lamp_area = static_cast<float>((lamp.x1 - lamp.x0) * (lamp.z1 - lamp.z0));

// A visible point on the tile.
struct Tile {
    glm::vec3 position{0.0f};
};
glm::vec3 surface_position(const Tile& t) { return t.position; }
glm::vec3 surface_normal(const Tile&) { return up; }
float surface_depth(const Tile&) { return 1.0f; }
bool is_valid_surface(const Tile&) { return true; }

// The tile's glossy lobe at p: its axis, the mirror direction of the view, and its power.
std::pair<glm::vec3, float> lobe_at(glm::vec3 p) {
    const glm::vec3 view = glm::normalize(camera - p);
    return {{-view.x, view.y, -view.z}, 6.0f + 3.0f * std::sin(1.7f * p.x + 1.1f * p.z)};
}

// The density (e + 1) / (2 pi) max(0, a.w)^e of the cosine-power lobe about unit a.
template <class T>
T power_pdf(glm::vec<3, T> a, T e, glm::vec<3, T> w) {
    const T c = glm::dot(a, w);
    return c > T(0) ? (e + T(1)) / (T(2) * static_cast<T>(pi)) * std::pow(c, e) : T(0);
}

// Its sampler, the inverse CDF: cos = u0^(1 / (e + 1)) about n, phi = 2 pi u1 in a frame of n.
glm::vec3 lobe_direction(glm::vec3 n, float e, float u0, float u1) {
    const float cos_t = std::pow(u0, 1.0f / (e + 1.0f));
    const float sin_t = std::sqrt(std::fmax(0.0f, 1.0f - cos_t * cos_t));
    const float phi = restir::two_pi * u1;
    const glm::vec3 helper = std::abs(n.x) < 0.9f ? glm::vec3(1, 0, 0) : glm::vec3(0, 1, 0);
    const glm::vec3 t = glm::normalize(glm::cross(n, helper));
    const glm::vec3 b = glm::cross(n, t);
    return (sin_t * std::cos(phi)) * t + (sin_t * std::sin(phi)) * b + cos_t * n;
}

// A path's three numbers at a vertex for a purpose: a function of its seed and the vertex.
enum Purpose : std::uint32_t { draw_bounce = 1u, draw_light = 2u, draw_pick = 3u };
glm::vec3 numbers(std::uint32_t seed, std::uint32_t vertex, Purpose purpose) {
    restir::Pcg32 rng = restir::make_pixel_rng(seed, vertex, purpose);
    return {next_float(rng), next_float(rng), next_float(rng)}; // u_lobe, u0, u1, in order
}

// A bounce: the point it reaches, f_s cos (times the lobe's posterior) and the density.
struct Bounce {
    glm::vec3 hit{0.0f}, weighted_f{0.0f};
    float density = 0.0f;
    bool valid = false;
};

// The bounce at a visible point, to the panel: f_s cos P_l p_l / p, density P_l p_l.
Bounce tile_bounce(glm::vec3 p, std::uint32_t seed) {
    const glm::vec3 u = numbers(seed, 1u, draw_bounce);
    const auto [axis, exponent] = lobe_at(p);
    const bool specular = u.x < specular_probability;
    const glm::vec3 w =
        specular ? lobe_direction(axis, exponent, u.y, u.z) : lobe_direction(up, 1.0f, u.y, u.z);
    if (!(w.y > 0.0f))
        return {};
    const float p_s = power_pdf(axis, exponent, w), p_d = power_pdf(up, 1.0f, w);
    const glm::vec3 f_cos = tile_specular * p_s + tile_diffuse * p_d;
    const float branch =
        specular ? specular_probability * p_s : (1.0f - specular_probability) * p_d;
    const float mixture = specular_probability * p_s + (1.0f - specular_probability) * p_d;
    const glm::vec3 hit = p + ((panel_height - p.y) / w.y) * w;
    return {hit, f_cos * (branch / mixture), branch, branch > 0.0f && panel.contains(hit)};
}

// The panel's cosine-sampled bounce from x_2 to x_3, valid on the carpet.
Bounce panel_bounce(glm::vec3 x2, std::uint32_t seed) {
    const glm::vec3 u = numbers(seed, 2u, draw_bounce);
    const glm::vec3 w = lobe_direction(-up, 1.0f, u.y, u.z);
    if (!(w.y < 0.0f))
        return {};
    const glm::vec3 hit = x2 + (x2.y / -w.y) * w;
    const float density = -w.y * restir::inv_pi;
    return {hit, panel_albedo * density, density, carpet.contains(hit)};
}

// The lamp reached from x_3 by `end`'s technique with the path's numbers at vertex 3: the unit
// direction and both techniques' densities of it (solid angle), found where it is the lamp.
struct Connection {
    glm::vec3 direction{0.0f};
    float light_pdf = 0.0f, bsdf_pdf = 0.0f;
    bool found = false;
    float pdf(PathEnd end) const { return end == PathEnd::light_sampled ? light_pdf : bsdf_pdf; }
};
Connection connect(glm::vec3 x3, std::uint32_t seed, PathEnd end) {
    glm::vec3 point{0.0f, panel_height, 0.0f}, w{0.0f};
    if (end == PathEnd::light_sampled) {
        const glm::vec3 u = numbers(seed, 3u, draw_light);
        point.x = static_cast<float>(lamp.x0 + (lamp.x1 - lamp.x0) * static_cast<double>(u.y));
        point.z = static_cast<float>(lamp.z0 + (lamp.z1 - lamp.z0) * static_cast<double>(u.z));
        w = glm::normalize(point - x3);
    } else {
        const glm::vec3 u = numbers(seed, 3u, draw_bounce);
        w = lobe_direction(up, 1.0f, u.y, u.z);
        if (!(w.y > 0.0f))
            return {};
        point = x3 + ((panel_height - x3.y) / w.y) * w;
        if (!lamp.contains(point))
            return {};
    }
    const glm::vec3 d = point - x3; // the lamp faces down: its cosine is w.y, as is x_3's
    return {w, glm::dot(d, d) / (w.y * lamp_area), w.y * restir::inv_pi, w.y > 0.0f};
}

// The path that `seed` draws from visible point p, its light found by `end`'s technique.
struct ToyPath {
    Bounce first, second;
    Connection light;
    // The density of drawing it (the lobe's at x_1, the end's technique's at x_3).
    float density(PathEnd end) const { return first.density * second.density * light.pdf(end); }
};
ToyPath trace(glm::vec3 p, std::uint32_t seed, PathEnd end) {
    ToyPath path{tile_bounce(p, seed), {}, {}};
    path.second = path.first.valid ? panel_bounce(path.first.hit, seed) : Bounce{};
    path.light = path.second.valid ? connect(path.second.hit, seed, end) : Connection{};
    return path;
}

// The toy's path tracer, replayable (a restir::PathReplay).
struct ToyPathTracer {
    using Vertex = glm::vec3; // y_{k-1} = y_2, a point of the panel

    restir::ReplayedPrefix<glm::vec3> replay_prefix(const PtSample& x, const Tile& from,
                                                    const ReconnectionCriterion& rule) const {
        const Bounce b = tile_bounce(from.position, x.seed);
        if (x.rc_index != 3u || !b.valid ||
            rule(tile_roughness, 1.0f, glm::distance(from.position, b.hit)))
            return {};
        return {b.hit, b.hit, 1.0f, b.weighted_f, b.density, true};
    }
    restir::ReplayedPath replay_path(const PtSample& x, const Tile& from,
                                     const ReconnectionCriterion& rule) const {
        const ToyPath y = trace(from.position, x.seed, x.end);
        const float branch = y.light.pdf(x.end);
        if (x.rc_index != 0u || x.length != 4u || !y.light.found || !(branch > 0.0f) ||
            rule(tile_roughness, 1.0f, glm::distance(from.position, y.first.hit)) ||
            rule(1.0f, 1.0f, glm::distance(y.first.hit, y.second.hit)))
            return {};
        const glm::vec3 f = y.first.weighted_f * y.second.weighted_f * carpet_albedo *
                            (y.light.direction.y * restir::inv_pi) * lamp_radiance *
                            (branch / (y.light.light_pdf + y.light.bsdf_pdf));
        return {f, y.density(x.end), true};
    }
    // f_s cos at the panel towards x_3 and at x_3 towards w_3 (MIS-weighted); nothing occludes.
    glm::vec3 reconnect(const glm::vec3& v, const PtSample& x) const {
        const float cos_v = std::fmax(0.0f, -glm::normalize(x.rc_position - v).y);
        const float cos_k = std::fmax(0.0f, glm::dot(x.rc_normal, x.rc_direction));
        return panel_albedo * (cos_v * restir::inv_pi) * carpet_albedo * (cos_k * restir::inv_pi) *
               restir::rc_mis_weight(x, cos_k * restir::inv_pi);
    }
};
static_assert(restir::PathReplay<ToyPathTracer, Tile>);
constexpr ToyPathTracer toy;

// A visible point's initial reservoir: the path of `seed`, reconnecting at x_3 where the rule
// allows (else replayed whole), its two light connections streamed with weight p-hat / density
// (p-hat the sum of f's channels); W = w_sum / p-hat, M = 1 (also where the path ends early).
Reservoir<PtSample> initial_reservoir(const Tile& t, std::uint32_t seed,
                                      const ReconnectionCriterion& rule) {
    Reservoir<PtSample> r;
    restir::Pcg32 pick = restir::make_pixel_rng(seed, 0u, draw_pick);
    for (const PathEnd end : {PathEnd::light_sampled, PathEnd::bsdf_sampled}) {
        const float u = next_float(pick);
        const ToyPath path = trace(t.position, seed, end);
        PtSample x{.visible_point = t.position, .seed = seed, .length = 4u, .end = end};
        if (path.light.found && rule(1.0f, 1.0f, glm::distance(path.first.hit, path.second.hit))) {
            x.rc_index = 3u;
            x.rc_position = path.second.hit;
            x.rc_normal = up;
            x.rc_direction = path.light.direction;
            x.suffix = lamp_radiance; // w_3 ends the path
            x.rc_light_pdf = path.light.light_pdf;
            x.density =
                restir::reconnection_density(path.first.density, path.first.hit, x.rc_position, up);
            x.contribution = path.first.weighted_f * toy.reconnect(path.first.hit, x) * x.suffix;
        } else if (path.light.found) {
            const restir::ReplayedPath whole = toy.replay_path(x, t, rule);
            x.contribution = whole.contribution;
            x.density = whole.valid ? whole.density : 0.0f;
        }
        const float target = restir::fold_channels<restir::ChannelNorm::sum>(x.contribution);
        if (target > 0.0f && x.density > 0.0f)
            r.stream(x, target / path.density(end), target, u);
    }
    r.finalize_normalized();
    r.candidate_count = 1u;
    return r;
}

// Gauss-Legendre nodes and weights on [a, b] (Newton's method on the Legendre polynomial).
std::vector<std::pair<double, double>> gauss_legendre(int n, double a, double b) {
    std::vector<std::pair<double, double>> nodes;
    for (int i = 0; i < n; ++i) {
        double x = std::cos(pi * (i + 0.75) / (n + 0.5)), derivative = 1.0, step = 1.0;
        for (int iteration = 0; iteration < 100 && std::abs(step) > 1e-15; ++iteration) {
            double p0 = 1.0, p1 = x;
            for (int k = 2; k <= n; ++k)
                p0 = std::exchange(p1, ((2 * k - 1) * x * p1 - (k - 1) * p0) / k);
            derivative = n * (x * p1 - p0) / (x * x - 1.0);
            step = p1 / derivative;
            x -= step;
        }
        nodes.emplace_back(0.5 * (a + b + (b - a) * x),
                           (b - a) / ((1.0 - x * x) * derivative * derivative));
    }
    return nodes;
}

// The view factor from a point of the carpet to the lamp (parallel, H above): the rectangle with
// a corner above the point (odd in both sides), over the lamp's corners with signs.
double lamp_view_factor(double x, double z) {
    const auto corner = [](double a, double b) {
        const double h = static_cast<double>(panel_height), ha = std::hypot(h, a),
                     hb = std::hypot(h, b);
        return (a / ha * std::atan(b / ha) + b / hb * std::atan(a / hb)) / (2.0 * pi);
    };
    return corner(lamp.x1 - x, lamp.z1 - z) - corner(lamp.x0 - x, lamp.z1 - z) -
           corner(lamp.x1 - x, lamp.z0 - z) + corner(lamp.x0 - x, lamp.z0 - z);
}

// The truth at visible point p: n x n nodes on the panel, n / 2 x n / 2 on the carpet.
glm::dvec3 truth_at(glm::vec3 p, int n) {
    std::vector<glm::dvec3> carpet_nodes; // x, z, the weight times F
    for (const auto& [x, wx] : gauss_legendre(n / 2, carpet.x0, carpet.x1))
        for (const auto& [z, wz] : gauss_legendre(n / 2, carpet.z0, carpet.z1))
            carpet_nodes.emplace_back(x, z, wx * wz * lamp_view_factor(x, z));
    const auto h = static_cast<double>(panel_height);
    const auto [axis, exponent] = lobe_at(p);
    double specular = 0.0, diffuse = 0.0;
    for (const auto& [x2, wx] : gauss_legendre(n, panel.x0, panel.x1))
        for (const auto& [z2, wz] : gauss_legendre(n, panel.z0, panel.z1)) {
            double radiance = 0.0; // L_2(x_2) / (rho_2 rho_3 Le / pi)
            for (const glm::dvec3& c : carpet_nodes) {
                const double r2 = (x2 - c.x) * (x2 - c.x) + h * h + (z2 - c.y) * (z2 - c.y);
                radiance += c.z * h * h / (r2 * r2);
            }
            const glm::dvec3 d = glm::dvec3(x2, h, z2) - glm::dvec3(p);
            const double r2 = glm::dot(d, d);
            const glm::dvec3 w = d / std::sqrt(r2);
            const double d_omega = wx * wz * w.y / r2; // the panel's cosine over r^2
            specular +=
                power_pdf(glm::dvec3(axis), static_cast<double>(exponent), w) * radiance * d_omega;
            diffuse += w.y / pi * radiance * d_omega;
        }
    const glm::dvec3 chain =
        glm::dvec3(panel_albedo) * glm::dvec3(carpet_albedo) * glm::dvec3(lamp_radiance) / pi;
    return chain * (glm::dvec3(tile_specular) * specular + glm::dvec3(tile_diffuse) * diffuse);
}
constexpr int truth_nodes = 32;

struct PtSetup {
    BiasCorrection mode;
    bool replay_whole = false; // under the criterion that no segment meets
    bool temporal = false;     // four frames of temporal then spatial reuse, the camera moving
};

std::string name_of(const PtSetup& s) {
    const char* modes[] = {"none", "one_over_z", "balance_heuristic", "pairwise",
                           "defensive_pairwise"};
    return std::string(modes[static_cast<int>(s.mode)]) +
           (s.replay_whole ? "_replay" : "_reconnect") + (s.temporal ? "_temporal" : "_spatial");
}

std::uint64_t seed_of(const PtSetup& setup) { return restir::test::seed_of_name(name_of(setup)); }

// Per pixel: f(y) W after reuse per channel and summed; the last frame's initial one summed.
struct PixelStats {
    std::array<restir::test::RunningStats, 3> channels;
    restir::test::RunningStats sum, initial_sum;
};

double channel_sum(glm::dvec3 v) { return v.x + v.y + v.z; }

// p-hat: the sum of f's channels at the sample's own visible point; visibility is in f.
float pt_target(const PtSample& x, const Tile& t) {
    return restir::fold_channels<restir::ChannelNorm::sum>(
        restir::pt_sample_contribution(x, t.position));
}
bool in_f(const PtSample&, const Tile&) { return true; }

// Frames of initial paths, temporal reuse (with `temporal`) and one spatial pass through
// restir::HybridShift; the estimates of the last frame per pixel.
class PtPipeline {
public:
    explicit PtPipeline(const PtSetup& setup) : setup_(setup) {}
    std::uint32_t frames() const { return setup_.temporal ? 4u : 1u; }

    std::vector<PixelStats> run(std::uint32_t trials) {
        std::vector<PixelStats> stats(pixel_count);
        const auto estimate = [&](const Reservoir<PtSample>& r, std::uint32_t i) {
            return glm::dvec3(restir::pt_sample_contribution(r.sample, surfaces_[i].position) *
                              r.contribution_weight);
        };
        for (std::uint32_t trial = 0; trial < trials; ++trial) {
            for (std::uint32_t frame = 0; frame < frames(); ++frame)
                render_frame(frame, seed_ + trial);
            for (std::uint32_t i = 0; i < pixel_count; ++i) {
                const glm::dvec3 f = estimate(history_[i], i);
                for (std::size_t c = 0; c < 3u; ++c)
                    stats[i].channels[c].add(f[static_cast<int>(c)]);
                stats[i].sum.add(channel_sum(f));
                stats[i].initial_sum.add(channel_sum(estimate(initial_[i], i)));
            }
        }
        return stats;
    }

    glm::dvec3 truth(std::uint32_t pixel) const {
        return truth_at(surface(pixel, frames() - 1u).position, truth_nodes);
    }

    static Tile surface(std::uint32_t pixel, std::uint32_t frame) {
        const auto i = static_cast<float>(pixel % width), j = static_cast<float>(pixel / width);
        const auto t = static_cast<float>(frame);
        return {{-1.0f + 0.4f * i + 0.11f * t, 0.0f, -0.6f + 0.4f * j + 0.05f * t}};
    }

private:
    void render_frame(std::uint32_t frame, std::uint64_t seed) {
        const ReconnectionCriterion rule = setup_.replay_whole ? no_reconnection : reconnect_at_x3;
        const restir::ReuseBridge bridge{pt_target, in_f, restir::AnyMaterial{},
                                         restir::HybridShift<ToyPathTracer>{&toy, rule}};
        const auto pixel = [](std::uint32_t i) {
            return PixelCoord{static_cast<std::int32_t>(i % width),
                              static_cast<std::int32_t>(i / width)};
        };
        std::vector<Tile> surfaces(pixel_count);
        initial_.resize(pixel_count);
        for (std::uint32_t i = 0; i < pixel_count; ++i) {
            surfaces[i] = surface(i, frame);
            restir::Pcg32 rng = restir::make_pixel_rng(i, frame, restir::RngStream::initial, seed);
            initial_[i] = initial_reservoir(surfaces[i], rng.next_uint(), rule);
        }
        std::vector<Reservoir<PtSample>> current = initial_;
        for (std::uint32_t i = 0; i < pixel_count && frame > 0; ++i) {
            restir::Pcg32 rng = restir::make_pixel_rng(i, frame, restir::RngStream::temporal, seed);
            current[i] = restir::temporal_resample(
                pixel(i), current[i], surfaces[i], {history_.data(), width, height},
                {surfaces_.data(), width, height}, [](PixelCoord p) { return p; }, temporal_,
                reuse_, frame, bridge, rng);
        }
        const restir::ImageView<const Reservoir<PtSample>> input{current.data(), width, height};
        const restir::ImageView<const Tile> surface_view{surfaces.data(), width, height};
        history_.resize(pixel_count);
        for (std::uint32_t i = 0; i < pixel_count; ++i) {
            restir::Pcg32 rng = restir::make_pixel_rng(i, frame, restir::RngStream::spatial, seed);
            history_[i] = restir::spatial_resample(pixel(i), input, surface_view, spatial_, reuse_,
                                                   bridge, rng);
        }
        surfaces_ = surfaces;
    }

    PtSetup setup_;
    std::uint64_t seed_ = seed_of(setup_);
    restir::TemporalParams temporal_{};
    restir::SpatialParams spatial_{.neighbour_count = 5u, .radius = 2.5f};
    restir::ReuseParams reuse_{setup_.mode, restir::ReuseVisibility::none};
    std::vector<Reservoir<PtSample>> initial_, history_;
    std::vector<Tile> surfaces_;
};

class HybridShiftReuse : public ::testing::TestWithParam<PtSetup> {};

// Every pixel's mean after reuse agrees with the truth per channel, as the initial paths' does
// (the sampler and the truth without the shift). Reuse lowers the variance (0.1 to 0.7 of it):
// where every shift fails, each pixel keeps its own initial sample, a ratio of exactly 1.
TEST_P(HybridShiftReuse, MeanMatchesTruthAtEveryPixel) {
    const PtSetup setup = GetParam();
    PtPipeline pipeline(setup);
    const std::vector<PixelStats> stats = pipeline.run(setup.temporal ? 3'000u : 8'000u);
    double initial_variance = 0.0, reused_variance = 0.0, bias = 0.0;
    for (std::uint32_t p = 0; p < pixel_count; ++p) {
        const glm::dvec3 truth = pipeline.truth(p);
        for (int c = 0; c < 3; ++c)
            EXPECT_TRUE(
                restir::test::agrees_with(stats[p].channels[static_cast<std::size_t>(c)], truth[c]))
                << name_of(setup) << ", pixel " << p << ", channel " << c;
        EXPECT_TRUE(restir::test::agrees_with(stats[p].initial_sum, channel_sum(truth)))
            << name_of(setup) << ", pixel " << p << ", initial paths";
        initial_variance += stats[p].initial_sum.variance();
        reused_variance += stats[p].sum.variance();
        bias += (stats[p].sum.mean() - channel_sum(truth)) / channel_sum(truth);
    }
    std::printf("%-40s relative bias %+.4f, variance after reuse / before %.3f\n",
                name_of(setup).c_str(), bias / pixel_count, reused_variance / initial_variance);
    EXPECT_LT(reused_variance, 0.8 * initial_variance) << name_of(setup);
}

std::vector<PtSetup> setups() {
    std::vector<PtSetup> all;
    for (const BiasCorrection mode :
         {BiasCorrection::one_over_z, BiasCorrection::balance_heuristic, BiasCorrection::pairwise})
        for (const bool replay_whole : {false, true})
            for (const bool temporal : {false, true})
                all.push_back({mode, replay_whole, temporal});
    return all;
}

INSTANTIATE_TEST_SUITE_P(Modes, HybridShiftReuse, ::testing::ValuesIn(setups()),
                         [](const auto& param_info) { return name_of(param_info.param); });

TEST(HybridShiftReuseTruth, QuadratureHasConverged) {
    for (const std::uint32_t pixel : {0u, 5u, 9u, pixel_count - 1u}) {
        const glm::vec3 p = PtPipeline::surface(pixel, 3u).position;
        const glm::dvec3 coarse = truth_at(p, truth_nodes), fine = truth_at(p, 2 * truth_nodes);
        for (int c = 0; c < 3; ++c)
            EXPECT_NEAR(coarse[c], fine[c], 1e-9 * fine[c]) << "pixel " << pixel << ", " << c;
    }
}

} // namespace
