// Reuse through a shift mapping (ReuseBridge::shift): ReSTIR GI path samples reused with the
// reconnection shift on a small synthetic GI problem with a known answer per pixel, shifts
// that fail, and the shift hook on light samples (the identity compiled away, and an identity
// that reuse cannot recognise).
//
// The GI world: a 6 x 4 image of visible points on a floor (y = 0, normal +y, Lambertian, an
// albedo per pixel) under a quad at height 1 that faces down and whose points s reflect a
// smooth, known Lo(s) (a Lambertian reflector, sample roughness 1 unless a case says
// otherwise); optionally a black square at height 0.5 between them (an occluder). A pixel's
// initial reservoir holds one cosine-sampled bounce direction (restir::sample_diffuse_direction)
// that reached the quad, W = 1 / pdf, or is empty with M = 1 where the bounce missed the quad
// or hit the occluder. The truth at the pixel at x is the integral over the quad's points
// visible from x of albedo / pi Lo(s) cos_x cos_s / d^2 dA, by the midpoint rule over the
// quad minus the occluder's shadow, which seen from x is a rectangle of the quad's plane too.
// The camera may move: in frame t the pixels see the floor shifted by t (0.11, 0, 0.05), so that
// temporal reuse at the same pixel reconnects from another visible point.
//
// Compiled with -ffp-contract=off (tests/CMakeLists.txt): two instantiations of the reuse step
// are compared to the last bit.
#include <restir/restir.hpp>

#include "reuse/synthetic_image.hpp"
#include "support/statistics.hpp"

#include <gtest/gtest.h>

#include <glm/geometric.hpp>
#include <glm/vec3.hpp>

#include <array>
#include <cmath>
#include <cstdint>
#include <cstdio>
#include <cstring>
#include <ostream>
#include <string>
#include <type_traits>
#include <vector>

namespace {

using restir::BiasCorrection;
using restir::PathSample;
using restir::PixelCoord;
using restir::Reservoir;
using restir::test::RunningStats;

constexpr std::int32_t width = 6;
constexpr std::int32_t height = 4;
constexpr std::uint32_t pixel_count = width * height;

// A visible point on the floor.
struct FloorPoint {
    glm::vec3 position{0.0f};
    glm::vec3 albedo{0.0f};
};
glm::vec3 surface_position(const FloorPoint& p) { return p.position; }
glm::vec3 surface_normal(const FloorPoint&) { return {0.0f, 1.0f, 0.0f}; }
float surface_depth(const FloorPoint&) { return 1.0f; }
bool is_valid_surface(const FloorPoint&) { return true; }

restir::LambertianReceiver receiver_of(const FloorPoint& p) {
    return {p.position, surface_normal(p), p.albedo};
}

// An axis-aligned rectangle in the horizontal plane at height y.
struct Rect {
    double x0, x1, z0, z1, y;
    bool contains(float x, float z) const {
        return static_cast<double>(x) >= x0 && static_cast<double>(x) <= x1 &&
               static_cast<double>(z) >= z0 && static_cast<double>(z) <= z1;
    }
};

constexpr Rect quad{-1.5, 1.1, -1.2, 1.4, 1.0};
constexpr Rect occluder{-0.4, 0.3, -0.3, 0.5, 0.5};

// Lo(s) towards any direction, per channel: smooth and positive.
glm::dvec3 quad_radiance(double x, double z) {
    return {1.0 + 0.5 * std::sin(2.0 * x), 0.8 + 0.4 * std::cos(1.5 * z),
            0.5 + 0.3 * std::sin(x + z)};
}

struct Scene {
    bool has_occluder = false;
    float roughness = 1.0f; // of the quad's points

    // Whether the segment between two points crosses the occluder.
    bool occluded(glm::vec3 from, glm::vec3 to) const {
        if (!has_occluder)
            return false;
        const float t = (static_cast<float>(occluder.y) - from.y) / (to.y - from.y);
        if (!(t > 0.0f && t < 1.0f))
            return false;
        const glm::vec3 p = from + t * (to - from);
        return occluder.contains(p.x, p.z);
    }
};

// The scene as a RayQuery, for restir::ReconnectionVisibility.
struct SceneQuery {
    const Scene* scene = nullptr;
    bool occluded(glm::vec3 from, glm::vec3 to) const { return scene->occluded(from, to); }
};
using SceneVisibility = restir::ReconnectionVisibility<SceneQuery>;

// p-hat: the sum of the channels of f cos Lo at the receiver; with `visibility` also the
// reconnection's visibility (Ouyang et al. 2021, Alg. 4), else unshadowed.
template <class Visibility>
struct GiTargetOf {
    const Visibility* visibility = nullptr;
    float operator()(const PathSample& x, const FloorPoint& p) const {
        const float t = restir::fold_channels<restir::ChannelNorm::sum>(
            restir::path_sample_radiance(x, receiver_of(p)));
        return visibility != nullptr && t > 0.0f && !(*visibility)(x, p) ? 0.0f : t;
    }
};
using GiTarget = GiTargetOf<SceneVisibility>;

// The integral over rectangle r of albedo / pi Lo(s) cos_x cos_s / d^2 = albedo / pi Lo(s)
// h^2 / d^4 (h the height of r above x), midpoint rule on n x n cells.
glm::dvec3 integrate_over(const Rect& r, const FloorPoint& p, int n) {
    glm::dvec3 sum(0.0);
    if (!(r.x1 > r.x0) || !(r.z1 > r.z0))
        return sum;
    const double dx = (r.x1 - r.x0) / n, dz = (r.z1 - r.z0) / n;
    const double h = r.y - static_cast<double>(p.position.y);
    for (int i = 0; i < n; ++i)
        for (int j = 0; j < n; ++j) {
            const double x = r.x0 + (i + 0.5) * dx, z = r.z0 + (j + 0.5) * dz;
            const double ex = x - static_cast<double>(p.position.x);
            const double ez = z - static_cast<double>(p.position.z);
            const double d2 = ex * ex + h * h + ez * ez;
            sum += quad_radiance(x, z) * (h * h / (d2 * d2));
        }
    return sum * (dx * dz / 3.14159265358979323846) * glm::dvec3(p.albedo);
}

// The truth at a visible point: the quad, less the part of it behind the occluder (the
// occluder's projection from p onto the quad's plane, clipped to the quad).
glm::dvec3 truth_at(const FloorPoint& p, bool has_occluder) {
    constexpr int n = 500;
    glm::dvec3 total = integrate_over(quad, p, n);
    if (has_occluder) {
        const double scale = (quad.y - static_cast<double>(p.position.y)) /
                             (occluder.y - static_cast<double>(p.position.y));
        const auto project = [&](double v, float origin) {
            return static_cast<double>(origin) + (v - static_cast<double>(origin)) * scale;
        };
        const Rect shadow{std::fmax(quad.x0, project(occluder.x0, p.position.x)),
                          std::fmin(quad.x1, project(occluder.x1, p.position.x)),
                          std::fmax(quad.z0, project(occluder.z0, p.position.z)),
                          std::fmin(quad.z1, project(occluder.z1, p.position.z)), quad.y};
        total -= integrate_over(shadow, p, n);
    }
    return total;
}

struct GiSetup {
    BiasCorrection mode;
    bool occluder = false;
    bool temporal = false;       // four frames of temporal then spatial reuse, the camera moving
    float roughness = 1.0f;      // of the quad's points (the shift's minimum is 0.5)
    bool visible_target = false; // p-hat with the reconnection's visibility
};

std::string name_of(const GiSetup& s) {
    const char* modes[] = {"none", "one_over_z", "balance_heuristic", "pairwise",
                           "defensive_pairwise"};
    return std::string(modes[static_cast<int>(s.mode)]) + (s.temporal ? "/temporal" : "/spatial") +
           (s.occluder ? "/occluder" : "") + (s.roughness < 0.5f ? "/glossy" : "") +
           (s.visible_target ? "/visible-target" : "");
}

void PrintTo(const GiSetup& setup, std::ostream* os) { *os << name_of(setup); }

std::uint64_t seed_of(const GiSetup& setup) { return restir::test::seed_of_name(name_of(setup)); }

struct SamePixel {
    PixelCoord operator()(PixelCoord p) const { return p; }
};

// Per pixel: the estimate f(y) W per channel and summed, and f(y) W M per channel.
struct PixelStats {
    std::array<RunningStats, 3> channels, times_m;
    RunningStats sum;
};

// Frames of initial candidates, temporal reuse (with `temporal`) and one spatial pass, with
// the final visibility test; the estimates of the last frame per pixel.
class GiPipeline {
public:
    explicit GiPipeline(const GiSetup& setup) : setup_(setup), seed_(seed_of(setup)) {
        scene_.has_occluder = setup.occluder;
        scene_.roughness = setup.roughness;
        reuse_.bias_correction = setup.mode;
        reuse_.visibility =
            setup.occluder ? restir::ReuseVisibility::traced : restir::ReuseVisibility::none;
        spatial_.neighbour_count = 5u;
        spatial_.radius = 2.5f;
    }
    GiPipeline(const GiPipeline&) = delete; // the bridge points into it
    GiPipeline& operator=(const GiPipeline&) = delete;

    std::uint32_t frames() const { return setup_.temporal ? 4u : 1u; }

    std::vector<PixelStats> run(std::uint32_t trials) {
        std::vector<PixelStats> stats(pixel_count);
        for (std::uint32_t trial = 0; trial < trials; ++trial) {
            for (std::uint32_t frame = 0; frame < frames(); ++frame)
                render_frame(frame, trial);
            for (std::uint32_t i = 0; i < pixel_count; ++i) {
                const Reservoir<PathSample>& r = history_[i];
                const glm::vec3 f =
                    r.has_sample()
                        ? restir::path_sample_radiance(r.sample, receiver_of(surfaces_[i])) *
                              r.contribution_weight
                        : glm::vec3(0.0f);
                const auto m = static_cast<double>(r.candidate_count);
                for (int c = 0; c < 3; ++c) {
                    const auto k = static_cast<std::size_t>(c);
                    stats[i].channels[k].add(static_cast<double>(f[c]));
                    stats[i].times_m[k].add(static_cast<double>(f[c]) * m);
                }
                stats[i].sum.add(static_cast<double>(f.x) + static_cast<double>(f.y) +
                                 static_cast<double>(f.z));
            }
        }
        return stats;
    }

    glm::dvec3 truth(std::uint32_t pixel) const {
        return truth_at(surface(pixel, frames() - 1u), setup_.occluder);
    }

    static FloorPoint surface(std::uint32_t pixel, std::uint32_t frame) {
        const auto i = static_cast<float>(pixel % width), j = static_cast<float>(pixel / width);
        const auto t = static_cast<float>(frame);
        return {{-1.0f + 0.4f * i + 0.11f * t, 0.0f, -0.6f + 0.4f * j + 0.05f * t},
                {0.3f + 0.1f * static_cast<float>(pixel % 3u), 0.5f + 0.1f * j, 0.7f - 0.05f * i}};
    }

private:
    // One cosine-sampled bounce: a path sample where it reaches the quad unblocked, W = 1 / pdf;
    // otherwise an empty reservoir that counts one candidate.
    Reservoir<PathSample> initial(const FloorPoint& p, restir::Pcg32& rng) const {
        const glm::vec3 n = surface_normal(p);
        const float u0 = next_float(rng), u1 = next_float(rng), u = next_float(rng);
        const glm::vec3 wi = restir::sample_diffuse_direction(n, u0, u1);
        const float pdf = restir::diffuse_direction_pdf(n, wi);
        Reservoir<PathSample> r;
        const float t = (static_cast<float>(quad.y) - p.position.y) / wi.y;
        const glm::vec3 s = p.position + t * wi;
        if (!(pdf > 0.0f) || !(t > 0.0f) || !quad.contains(s.x, s.z) ||
            scene_.occluded(p.position, s)) {
            r.stream(PathSample{}, 0.0f, 0.0f, u);
            r.finalize();
            return r;
        }
        PathSample x;
        x.visible_point = p.position;
        x.sample_point = s;
        x.sample_normal = glm::vec3(0.0f, -1.0f, 0.0f);
        x.radiance = glm::vec3(quad_radiance(static_cast<double>(s.x), static_cast<double>(s.z)));
        x.source_pdf = pdf;
        x.sample_roughness = scene_.roughness;
        const float target = target_()(x, p);
        r.stream(x, target / pdf, target, u);
        r.finalize();
        return r;
    }

    GiTarget target_() const { return {setup_.visible_target ? &visibility_ : nullptr}; }

    void render_frame(std::uint32_t frame, std::uint32_t trial) {
        const restir::ReuseBridge bridge{target_(), visibility_, restir::AnyMaterial{},
                                         restir::ReconnectionShift{}};
        std::vector<FloorPoint> surfaces(pixel_count);
        std::vector<Reservoir<PathSample>> current(pixel_count);
        for (std::uint32_t i = 0; i < pixel_count; ++i) {
            surfaces[i] = surface(i, frame);
            restir::Pcg32 rng =
                restir::make_pixel_rng(i, frame, restir::RngStream::initial, seed_ + trial);
            current[i] = initial(surfaces[i], rng);
        }
        const restir::ImageView<const FloorPoint> surface_view{surfaces.data(), width, height};
        if (frame > 0) {
            const restir::ImageView<const Reservoir<PathSample>> previous{history_.data(), width,
                                                                          height};
            const restir::ImageView<const FloorPoint> previous_surfaces{surfaces_.data(), width,
                                                                        height};
            for (std::uint32_t i = 0; i < pixel_count; ++i) {
                const PixelCoord p{static_cast<std::int32_t>(i % width),
                                   static_cast<std::int32_t>(i / width)};
                restir::Pcg32 rng =
                    restir::make_pixel_rng(i, frame, restir::RngStream::temporal, seed_ + trial);
                current[i] = restir::temporal_resample(p, current[i], surfaces[i], previous,
                                                       previous_surfaces, SamePixel{}, temporal_,
                                                       reuse_, frame, bridge, rng);
            }
        }
        const restir::ImageView<const Reservoir<PathSample>> input{current.data(), width, height};
        std::vector<Reservoir<PathSample>> spatial(pixel_count);
        for (std::uint32_t i = 0; i < pixel_count; ++i) {
            const PixelCoord p{static_cast<std::int32_t>(i % width),
                               static_cast<std::int32_t>(i / width)};
            restir::Pcg32 rng =
                restir::make_pixel_rng(i, frame, restir::RngStream::spatial, seed_ + trial);
            spatial[i] =
                restir::spatial_resample(p, input, surface_view, spatial_, reuse_, bridge, rng);
            // The shading ray; under visibility reuse it also zeroes W for the next frame.
            restir::apply_visibility(spatial[i], surfaces[i], visibility_);
        }
        history_ = spatial;
        surfaces_ = surfaces;
    }

    GiSetup setup_;
    std::uint64_t seed_;
    Scene scene_;
    SceneQuery query_{&scene_};
    SceneVisibility visibility_{&query_, 1e-4f};
    restir::TemporalParams temporal_ = restir::default_temporal_params();
    restir::SpatialParams spatial_ = restir::default_spatial_params();
    restir::ReuseParams reuse_{};
    std::vector<Reservoir<PathSample>> history_;
    std::vector<FloorPoint> surfaces_;
};

std::uint32_t trials_for(const GiSetup& s) { return s.temporal ? 8'000u : 20'000u; }

// Prints the pixel-averaged relative bias and relative standard deviation of the channel sum.
void report(const GiSetup& setup, const GiPipeline& pipeline,
            const std::vector<PixelStats>& stats) {
    double bias_sum = 0.0, deviation_sum = 0.0;
    for (std::uint32_t p = 0; p < pixel_count; ++p) {
        const glm::dvec3 truth = pipeline.truth(p);
        const double total = truth.x + truth.y + truth.z;
        bias_sum += (stats[p].sum.mean() - total) / total;
        deviation_sum += std::sqrt(stats[p].sum.variance()) / total;
    }
    std::printf("%-50s relative bias %+.4f, relative standard deviation %.3f\n",
                name_of(setup).c_str(), bias_sum / pixel_count, deviation_sum / pixel_count);
}

class UnbiasedShiftReuse : public ::testing::TestWithParam<GiSetup> {};

TEST_P(UnbiasedShiftReuse, MeanMatchesTruthAtEveryPixel) {
    const GiSetup setup = GetParam();
    GiPipeline pipeline(setup);
    const std::vector<PixelStats> stats = pipeline.run(trials_for(setup));
    report(setup, pipeline, stats);
    for (std::uint32_t p = 0; p < pixel_count; ++p) {
        const glm::dvec3 truth = pipeline.truth(p);
        for (int c = 0; c < 3; ++c)
            EXPECT_TRUE(
                restir::test::agrees_with(stats[p].channels[static_cast<std::size_t>(c)], truth[c]))
                << name_of(setup) << ", pixel " << p << ", channel " << c;
    }
}

std::vector<GiSetup> unbiased_setups() {
    std::vector<GiSetup> setups;
    constexpr BiasCorrection unbiased[] = {
        BiasCorrection::one_over_z, BiasCorrection::balance_heuristic, BiasCorrection::pairwise,
        BiasCorrection::defensive_pairwise};
    for (BiasCorrection mode : unbiased)
        for (bool occluded : {false, true})
            for (bool temporal : {false, true})
                setups.push_back({mode, occluded, temporal});
    // Every shift succeeds (nothing occluded, a Lambertian quad, every floor point in front of
    // it): 1/M is unbiased too, with the Jacobians.
    for (bool temporal : {false, true})
        setups.push_back({BiasCorrection::none, false, temporal});
    // Every shift to another visible point fails (the quad's points below the minimum
    // roughness): the unbiased modes fall back on the pixel's own samples.
    for (BiasCorrection mode : unbiased)
        setups.push_back({mode, false, true, 0.3f});
    // p-hat with the reconnection's visibility (Ouyang et al. 2021, Alg. 4).
    for (BiasCorrection mode : unbiased)
        setups.push_back({mode, true, false, 1.0f, true});
    return setups;
}

INSTANTIATE_TEST_SUITE_P(Modes, UnbiasedShiftReuse, ::testing::ValuesIn(unbiased_setups()),
                         [](const ::testing::TestParamInfo<GiSetup>& param_info) {
                             std::string name = name_of(param_info.param);
                             for (char& c : name)
                                 if (c == '/' || c == '-')
                                     c = '_';
                             return name;
                         });

// 1/M gives a neighbour its share M_i / sum M whether or not its samples can shift to the
// receiver. Where none can (the quad's points below the shift's minimum roughness, so every
// reconnection to another visible point fails), a pixel keeps only its own sample, with the
// share 1 / M of the result (its own M is 1): darker, and exactly so, since f W M is then
// the pixel's own unbiased estimate.
TEST(BiasedShiftReuse, OneOverMDarkensWhereNoNeighbourCanShift) {
    const GiSetup setup{BiasCorrection::none, false, false, 0.3f};
    GiPipeline pipeline(setup);
    const std::vector<PixelStats> stats = pipeline.run(trials_for(setup));
    report(setup, pipeline, stats);
    for (std::uint32_t p = 0; p < pixel_count; ++p) {
        const glm::dvec3 truth = pipeline.truth(p);
        for (int c = 0; c < 3; ++c) {
            const auto k = static_cast<std::size_t>(c);
            const RunningStats& s = stats[p].channels[k];
            EXPECT_TRUE(restir::test::differs_from(s, truth[c]))
                << "pixel " << p << ", channel " << c;
            EXPECT_LT(s.mean(), truth[c]) << "pixel " << p << ", channel " << c;
            EXPECT_TRUE(restir::test::agrees_with(stats[p].times_m[k], truth[c]))
                << "f W M, pixel " << p << ", channel " << c;
        }
    }
}

// What a neighbour lends in the failed-shift checks: a sample that shifts to the receiver, or
// one that cannot reach it.
enum class Lender {
    good,                 // Lambertian, in front of both, visible from both
    glossy,               // below the shift's minimum roughness: J = 0
    back_facing,          // the receiver behind the sample point's surface: J = 0
    occluded_at_home,     // hidden from the neighbour itself (a history that became occluded)
    occluded_at_receiver, // hidden from the receiver only
};

// Sample points above y = 1.75 are hidden from everywhere, those above y = 1.25 from the
// receiver only.
struct HidingQuery {
    glm::vec3 receiver{0.0f};
    bool occluded(glm::vec3 from, glm::vec3 to) const {
        return to.y > 1.75f || (to.y > 1.25f && glm::distance(from, receiver) < 0.01f);
    }
};
using HidingVisibility = restir::ReconnectionVisibility<HidingQuery>;

glm::vec3 random_colour(restir::Pcg32& rng) {
    return {0.2f + next_float(rng), 0.2f + next_float(rng), 0.2f + next_float(rng)};
}

// A sample of kind `kind` made at `at`, for receiver `q`.
PathSample lender_sample(Lender kind, const FloorPoint& q, const FloorPoint& at,
                         restir::Pcg32& rng) {
    PathSample x;
    x.visible_point = at.position;
    x.sample_point = 0.5f * (q.position + at.position) +
                     glm::vec3(0.4f * next_float(rng) - 0.2f, 1.0f, 0.4f * next_float(rng) - 0.2f);
    x.sample_normal = glm::vec3(0.0f, -1.0f, 0.0f);
    x.radiance = random_colour(rng);
    x.source_pdf = 1.0f;
    x.sample_roughness = 1.0f;
    switch (kind) {
    case Lender::good:
        break;
    case Lender::glossy:
        x.sample_roughness = 0.3f;
        break;
    case Lender::back_facing: { // tilted towards the neighbour, away from the receiver
        const glm::vec3 away = at.position - q.position;
        x.sample_normal = glm::normalize(glm::normalize(glm::vec3(away.x, 0.0f, away.z)) -
                                         glm::vec3(0.0f, 0.2f, 0.0f));
        x.sample_point = 0.5f * (q.position + at.position) + glm::vec3(0.0f, 1.0f, 0.0f);
        break;
    }
    case Lender::occluded_at_home:
        x.sample_point.y = 2.0f;
        break;
    case Lender::occluded_at_receiver:
        x.sample_point.y = 1.5f;
        break;
    }
    return x;
}

// A finalised reservoir holding `x` with p-hat at `at`, a random W and M.
Reservoir<PathSample> lent_reservoir(const PathSample& x, const FloorPoint& at,
                                     restir::Pcg32& rng) {
    Reservoir<PathSample> r;
    r.sample = x;
    r.target_value = GiTargetOf<HidingVisibility>{}(x, at);
    r.contribution_weight = 0.2f + 2.0f * next_float(rng);
    r.candidate_count = 1u + restir::uniform_index(next_float(rng), 5u);
    r.weight_sum = r.contribution_weight * r.target_value * static_cast<float>(r.candidate_count);
    return r;
}

struct FailedShiftCase {
    const char* name;
    std::vector<Lender> failing; // the kinds that must never be the result's sample
    restir::ReuseVisibility visibility;
    bool visible_target;
    std::vector<BiasCorrection> modes;
};

// Over many random receivers, each with a canonical reservoir (empty a quarter of the time)
// and five neighbours lending good samples or samples of the failing kinds, the result's
// sample is never one of the failing ones: it is the canonical one or a good one, moved to
// the receiver.
void check_failed_shifts_never_selected(const FailedShiftCase& c) {
    constexpr std::uint32_t neighbours = 5u;
    std::uint32_t from_neighbours = 0u, from_canonical = 0u, results = 0u;
    for (std::uint32_t seed = 0; seed < 3000u; ++seed) {
        restir::Pcg32 rng = restir::make_pixel_rng(seed, 0u, restir::RngStream::application, 7u);
        const FloorPoint q{{2.0f * next_float(rng) - 1.0f, 0.0f, 2.0f * next_float(rng) - 1.0f},
                           random_colour(rng)};
        const HidingQuery query{q.position};
        const HidingVisibility visibility{&query, 1e-4f};
        Reservoir<PathSample> canonical;
        canonical.candidate_count = 1u;
        if (next_float(rng) >= 0.25f)
            canonical = lent_reservoir(lender_sample(Lender::good, q, q, rng), q, rng);
        std::array<FloorPoint, neighbours> surfaces;
        std::array<Reservoir<PathSample>, neighbours> reservoirs;
        std::array<bool, neighbours> failing{};
        std::array<restir::ReuseInput<PathSample, FloorPoint>, neighbours> inputs;
        for (std::uint32_t i = 0; i < neighbours; ++i) {
            const float angle = 2.0f * restir::pi * next_float(rng);
            const float distance = 0.5f + next_float(rng);
            surfaces[i] = {q.position +
                               distance * glm::vec3(std::cos(angle), 0.0f, std::sin(angle)),
                           random_colour(rng)};
            failing[i] = next_float(rng) < 0.6f;
            const Lender kind =
                failing[i] ? c.failing[restir::uniform_index(
                                 next_float(rng), static_cast<std::uint32_t>(c.failing.size()))]
                           : Lender::good;
            reservoirs[i] =
                lent_reservoir(lender_sample(kind, q, surfaces[i], rng), surfaces[i], rng);
            ASSERT_GT(reservoirs[i].target_value, 0.0f) << c.name << ", seed " << seed;
            inputs[i] = {&reservoirs[i], &surfaces[i]};
        }
        const GiTargetOf<HidingVisibility> target{c.visible_target ? &visibility : nullptr};
        const restir::ReuseBridge bridge{target, visibility, restir::AnyMaterial{},
                                         restir::ReconnectionShift{}};
        for (BiasCorrection mode : c.modes) {
            restir::Pcg32 reuse_rng =
                restir::make_pixel_rng(seed, static_cast<std::uint32_t>(mode), 0u, 8u);
            const Reservoir<PathSample> result = restir::combine_inputs(
                canonical, q,
                restir::ReuseInputSpan<PathSample, FloorPoint>{inputs.data(), neighbours},
                restir::ReuseParams{mode, c.visibility}, bridge, reuse_rng);
            ++results;
            if (!result.has_sample())
                continue;
            ASSERT_EQ(result.sample.visible_point, q.position) << c.name << ", seed " << seed;
            for (std::uint32_t i = 0; i < neighbours; ++i) {
                const bool same = result.sample.sample_point == reservoirs[i].sample.sample_point;
                ASSERT_FALSE(same && failing[i])
                    << c.name << ", seed " << seed << ", mode " << static_cast<int>(mode)
                    << ": neighbour " << i << "'s sample, which cannot shift to the receiver";
                from_neighbours += same ? 1u : 0u;
            }
            from_canonical += canonical.has_sample() &&
                                      result.sample.sample_point == canonical.sample.sample_point
                                  ? 1u
                                  : 0u;
        }
    }
    // The check is not vacuous: good neighbours' samples and the canonical ones were chosen.
    EXPECT_GT(from_neighbours, results / 10u) << c.name;
    EXPECT_GT(from_canonical, results / 10u) << c.name;
}

constexpr BiasCorrection every_mode[] = {BiasCorrection::none, BiasCorrection::one_over_z,
                                         BiasCorrection::balance_heuristic,
                                         BiasCorrection::pairwise};

TEST(FailedShift, ZeroJacobianIsNeverSelected) {
    for (restir::ReuseVisibility visibility :
         {restir::ReuseVisibility::none, restir::ReuseVisibility::traced})
        check_failed_shifts_never_selected({"J = 0 (glossy or back-facing sample point)",
                                            {Lender::glossy, Lender::back_facing},
                                            visibility,
                                            false,
                                            {std::begin(every_mode), std::end(every_mode)}});
}

// Under traced visibility reuse the unbiased modes retest each input's own sample at its own
// surface: a sample hidden from the neighbour that lends it has no MIS weight (1/Z: it is not
// lent), whatever its W says.
TEST(FailedShift, SampleOccludedAtItsOwnSurfaceIsNeverSelectedUnderTracedVisibility) {
    check_failed_shifts_never_selected(
        {"occluded at the lending surface",
         {Lender::occluded_at_home, Lender::glossy},
         restir::ReuseVisibility::traced,
         false,
         {BiasCorrection::one_over_z, BiasCorrection::balance_heuristic,
          BiasCorrection::pairwise}});
}

// A p-hat that includes the reconnection's visibility from the receiver (Ouyang et al. 2021,
// Alg. 4: p-hat_q = 0 where the sample point is hidden from q) never selects a reconnection
// that is occluded at the receiver, in any mode. (With an unshadowed p-hat, the library's
// default for light samples too, such a sample may be selected; the shading ray then gives
// it no contribution, which is what the statistical tests check.)
TEST(FailedShift, ReconnectionOccludedAtTheReceiverIsNeverSelectedWithAVisibleTarget) {
    for (restir::ReuseVisibility visibility :
         {restir::ReuseVisibility::none, restir::ReuseVisibility::traced})
        check_failed_shifts_never_selected({"occluded at the receiver, p-hat with visibility",
                                            {Lender::occluded_at_receiver, Lender::back_facing},
                                            visibility,
                                            true,
                                            {std::begin(every_mode), std::end(every_mode)}});
}

} // namespace

namespace {

namespace synthetic = restir::test::synthetic;

// Bridge types of this file alone: the reuse functions instantiated for them are compiled here,
// without contraction, and not taken at link time from another test's instantiation.
struct ShiftTestTarget : synthetic::Target {};
struct ShiftTestVisibility : synthetic::Visibility {};

// The identity under a name that reuse does not recognise: the shifted code path (a copy of
// each lent reservoir, the Jacobians multiplied in) with J = 1.
struct UnrecognisedIdentity {
    template <class Sample, class S>
    restir::ShiftedSample<Sample> operator()(const Sample& x, const S&, const S&) const {
        return {x, 1.0f};
    }
};
static_assert(!restir::is_identity_shift<UnrecognisedIdentity>);
static_assert(restir::ShiftMapping<UnrecognisedIdentity, synthetic::LightId, synthetic::Patch>);

// One spatial pass over the synthetic DI image (synthetic_image.hpp) for every pixel and
// trial, under `bridge`: the results, in order.
template <class Bridge>
std::vector<Reservoir<synthetic::LightId>> spatial_pass(const Bridge& bridge, BiasCorrection mode) {
    using namespace synthetic;
    std::vector<Reservoir<LightId>> results;
    std::vector<Patch> patches(synthetic::pixel_count);
    for (std::uint32_t i = 0; i < synthetic::pixel_count; ++i)
        patches[i] = patch_seen(pixel_of(i), 0u);
    const restir::UniformLightSampler sampler{light_count};
    restir::SpatialParams spatial = restir::default_spatial_params();
    spatial.neighbour_count = 5u;
    spatial.radius = 2.5f;
    const restir::ReuseParams reuse{mode, restir::ReuseVisibility::traced};
    for (std::uint32_t trial = 0; trial < 300u; ++trial) {
        std::vector<Reservoir<LightId>> initial(synthetic::pixel_count);
        for (std::uint32_t i = 0; i < synthetic::pixel_count; ++i) {
            restir::Pcg32 rng = restir::make_pixel_rng(i, 0u, restir::RngStream::initial, trial);
            const auto uniform = [&](restir::Pcg32& g) {
                const restir::DiscreteSample c = restir::sample_light(sampler, g);
                return restir::SourceSample<LightId>{{c.index}, c.pmf};
            };
            initial[i] =
                restir::resample_ris(rng, initial_candidates, uniform, [&](const LightId& x) {
                    return bridge.target(x, patches[i]);
                });
            restir::apply_visibility(initial[i], patches[i], bridge.visibility);
        }
        const restir::ImageView<const Reservoir<LightId>> input{initial.data(), synthetic::width,
                                                                synthetic::height};
        const restir::ImageView<const Patch> surfaces{patches.data(), synthetic::width,
                                                      synthetic::height};
        for (std::uint32_t i = 0; i < synthetic::pixel_count; ++i) {
            restir::Pcg32 rng = restir::make_pixel_rng(i, 0u, restir::RngStream::spatial, trial);
            results.push_back(restir::spatial_resample(pixel_of(i), input, surfaces, spatial, reuse,
                                                       bridge, rng));
        }
    }
    return results;
}

// `ReuseBridge{t, v}` is the bridge with the identity shift, which reuse compiles away: the
// same type, so the same reservoirs to the last bit.
TEST(IdentityShift, IsTheDefaultShiftToTheLastBit) {
    const ShiftTestTarget target;
    const ShiftTestVisibility visibility;
    const restir::ReuseBridge plain{target, visibility};
    const restir::ReuseBridge explicit_identity{target, visibility, restir::AnyMaterial{},
                                                restir::IdentityShift{}};
    static_assert(std::is_same_v<decltype(plain), decltype(explicit_identity)>);
    for (BiasCorrection mode : every_mode) {
        const auto a = spatial_pass(plain, mode);
        const auto b = spatial_pass(explicit_identity, mode);
        ASSERT_EQ(a.size(), b.size());
        for (std::size_t i = 0; i < a.size(); ++i)
            ASSERT_EQ(std::memcmp(&a[i], &b[i], sizeof(a[i])), 0)
                << "mode " << static_cast<int>(mode) << ", result " << i;
    }
}

// The shifted code path with J = 1 on light samples gives the unshifted path's reservoirs: the
// same samples and M, and W, the weight sum and p-hat within float rounding (the balance
// heuristic sums its MIS denominator in another order; its terms, at most 16, each round by
// 2^-24). A differing selection would need a uniform number within that rounding of a
// threshold: about 1e-6 per merge, none expected in these 5400 results.
TEST(IdentityShift, AnUnrecognisedIdentityGivesTheSameReservoirs) {
    const ShiftTestTarget target;
    const ShiftTestVisibility visibility;
    const restir::ReuseBridge plain{target, visibility};
    const restir::ReuseBridge shifted{target, visibility, restir::AnyMaterial{},
                                      UnrecognisedIdentity{}};
    for (BiasCorrection mode : every_mode) {
        const auto a = spatial_pass(plain, mode);
        const auto b = spatial_pass(shifted, mode);
        ASSERT_EQ(a.size(), b.size());
        std::uint32_t with_sample = 0u;
        for (std::size_t i = 0; i < a.size(); ++i) {
            ASSERT_EQ(a[i].sample, b[i].sample) << "mode " << static_cast<int>(mode) << ", " << i;
            ASSERT_EQ(a[i].candidate_count, b[i].candidate_count) << i;
            for (const auto& [x, y] :
                 {std::pair{a[i].contribution_weight, b[i].contribution_weight},
                  std::pair{a[i].weight_sum, b[i].weight_sum},
                  std::pair{a[i].target_value, b[i].target_value}})
                ASSERT_NEAR(x, y, 1e-5f * x) << "mode " << static_cast<int>(mode) << ", " << i;
            with_sample += a[i].has_sample() ? 1u : 0u;
        }
        EXPECT_GT(with_sample, a.size() / 2u);
    }
}

} // namespace
