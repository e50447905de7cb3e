// End-to-end tests of the example renderer on tiny images: every method and GI mode runs,
// ReSTIR beats RIS beats uniform sampling against a reference rendered here, the reference
// path tracer converges to the analytic radiance of a furnace, and images do not depend on
// the thread count or on how the temporal history is stored.
#include "error_metrics.hpp"
#include "gbuffer.hpp"
#include "renderer.hpp"
#include "scene.hpp"

#include "pathtracer/directional_albedo.hpp"
#include "pathtracer/image_sums.hpp"
#include "support/statistics.hpp"

#include <glm/geometric.hpp>
#include <gtest/gtest.h>

#include <array>
#include <cmath>
#include <cstdio>
#include <cstring>
#include <iterator>
#include <string>
#include <utility>
#include <vector>

namespace {

using pt::GlobalIllumination;
using pt::Method;

pt::RenderSettings tiny(const pt::Scene& scene, std::uint32_t size) {
    pt::RenderSettings s;
    s.width = size;
    s.height = size;
    s.camera = *scene.camera;
    s.vpls = 4000;
    s.di_frame.spatial.radius = 4.0f; // neighbours within a few pixels of these tiny images
    s.threads = 2;
    return s;
}

// Bit for bit the same pixels.
bool same_pixels(const pt::Image& a, const pt::Image& b) {
    return a.pixels.size() == b.pixels.size() &&
           std::memcmp(a.pixels.data(), b.pixels.data(), a.pixels.size() * sizeof(glm::vec3)) == 0;
}

pt::Image render(const pt::Scene& scene, const pt::RenderSettings& settings, std::uint32_t frames) {
    pt::Renderer renderer(scene, settings);
    for (std::uint32_t f = 0; f < frames; ++f)
        renderer.render_frame();
    return renderer.accumulated();
}

TEST(Renderer, EveryMethodAndIndirectModeGivesAFiniteLitImage) {
    const pt::Scene scene = pt::make_cornell_box();
    for (Method method : {Method::uniform, Method::ris, Method::restir, Method::reference})
        for (GlobalIllumination gi :
             {GlobalIllumination::none, GlobalIllumination::vpl, GlobalIllumination::path}) {
            pt::RenderSettings s = tiny(scene, 16);
            s.method = method;
            s.gi = gi;
            const pt::Image image = render(scene, s, 2);
            double sum = 0.0;
            for (const glm::vec3& p : image.pixels)
                for (int c = 0; c < 3; ++c) {
                    ASSERT_TRUE(std::isfinite(p[c]) && p[c] >= 0.0f)
                        << static_cast<int>(method) << "/" << static_cast<int>(gi);
                    sum += static_cast<double>(p[c]);
                }
            EXPECT_GT(sum, 0.0) << static_cast<int>(method) << "/" << static_cast<int>(gi);
        }
}

// The reference study's comparison in miniature: Cornell box, direct + VPL light, RMSE against
// a converged reference after a few frames: of the accumulated image (RIS beats uniform
// sampling) and of the last frame alone, the image a real-time user sees (ReSTIR beats RIS:
// reuse makes single frames less noisy; after only three frames of this 40 x 40 image the
// accumulated RMSE of the two is within a few per cent either way, depending on the seed).
TEST(Renderer, RestirBeatsRisBeatsUniformSampling) {
    const pt::Scene scene = pt::make_cornell_box();
    pt::RenderSettings s = tiny(scene, 40);
    s.method = Method::reference;
    s.spp = 1024;
    const pt::Image reference = render(scene, s, 1);
    s.spp = 1;
    double error[3] = {0.0, 0.0, 0.0};
    double frame_error[3] = {0.0, 0.0, 0.0};
    const Method methods[3] = {Method::uniform, Method::ris, Method::restir};
    for (int m = 0; m < 3; ++m) {
        s.method = methods[m];
        pt::Renderer renderer(scene, s);
        for (int f = 0; f < 3; ++f)
            renderer.render_frame();
        error[m] = pt::rmse(renderer.accumulated(), reference);
        frame_error[m] = pt::rmse(renderer.last_frame(), reference);
    }
    std::printf("RMSE after 3 frames: uniform %.4f, ris %.4f, restir %.4f; of frame 3 alone: "
                "uniform %.4f, ris %.4f, restir %.4f\n",
                error[0], error[1], error[2], frame_error[0], frame_error[1], frame_error[2]);
    EXPECT_LT(frame_error[2], frame_error[1]);
    EXPECT_LT(frame_error[1], frame_error[0]);
    EXPECT_LT(error[1], error[0]);
}

// A closed box whose walls are all `walls`: emitting and reflecting.
pt::Scene furnace_of(const pt::Material& walls) {
    pt::Scene scene;
    scene.name = "furnace";
    for (float x : {-1.0f, 1.0f})
        for (float y : {-1.0f, 1.0f})
            for (float z : {-1.0f, 1.0f})
                scene.positions.push_back({x, y, z});
    // Vertex index = 4 * (x > 0) + 2 * (y > 0) + (z > 0); quads in cyclic order, then each
    // triangle wound so that its normal points into the box (towards the origin).
    const std::uint32_t faces[6][4] = {{0, 1, 3, 2}, {4, 6, 7, 5}, {0, 4, 5, 1},
                                       {2, 3, 7, 6}, {0, 2, 6, 4}, {1, 5, 7, 3}};
    for (const auto& f : faces) {
        for (const std::uint32_t* t : {&f[0], &f[1]}) {
            std::uint32_t a = f[0], b = t[1], c = t[2];
            const glm::vec3 pa = scene.positions[a], pb = scene.positions[b],
                            pc = scene.positions[c];
            if (glm::dot(glm::cross(pb - pa, pc - pa), -(pa + pb + pc)) < 0.0f)
                std::swap(b, c);
            for (std::uint32_t v : {a, b, c})
                scene.indices.push_back(v);
        }
        scene.triangle_materials.push_back(0u);
        scene.triangle_materials.push_back(0u);
    }
    scene.materials.push_back(walls);
    scene.camera = pt::CameraSetup{{0.1f, 0.2f, 0.3f}, {0.0f, 0.0f, -1.0f}, {0, 1, 0}, 90.0f};
    return scene;
}

// A closed box whose walls all emit Le and reflect with albedo a: the radiance everywhere is
// Le (1 + a) with direct light only, and Le / (1 - a) with all bounces.
pt::Scene furnace(float albedo) {
    return furnace_of(
        {.name = "glowing", .albedo = glm::vec3(albedo), .emission = glm::vec3(1.0f)});
}

TEST(Renderer, ReferenceConvergesToTheFurnaceRadiance) {
    const float albedo = 0.5f;
    const pt::Scene scene = furnace(albedo);
    for (GlobalIllumination gi : {GlobalIllumination::none, GlobalIllumination::path}) {
        pt::RenderSettings s = tiny(scene, 24);
        s.method = Method::reference;
        s.gi = gi;
        s.max_depth = 64;
        pt::Renderer renderer(scene, s);
        const restir::test::RunningStats radiance = pt::test::pixel_means(renderer, 8);
        const double expected = gi == GlobalIllumination::none
                                    ? 1.0 + static_cast<double>(albedo)
                                    : 1.0 / (1.0 - static_cast<double>(albedo));
        std::printf("furnace, gi %d: mean %.5f +- %.5f, expected %.5f\n", static_cast<int>(gi),
                    radiance.mean(), radiance.standard_error(), expected);
        EXPECT_TRUE(restir::test::agrees_with(radiance, expected)) << static_cast<int>(gi);
    }
}

// Direct light in a furnace of glossy walls that emit Le = 1: L = Le (1 + A(wo)), A(wo) the
// directional albedo, integral of f cos over the hemisphere. The reference path tracer
// estimates the reflected part with emitter NEE and BSDF sampling under MIS; here A(wo) comes
// from BSDF sampling alone (the mean of GlossyBsdf::sample's weights), so that a wrong density
// in either MIS weight, or a wrong f cos in NEE, shows as a difference.
TEST(Renderer, ReferenceMatchesTheGlossyFurnacesDirectionalAlbedo) {
    const pt::Material materials[] = {
        {.name = "dielectric", .albedo = glm::vec3(0.5f), .specular = 0.04f, .roughness = 0.3f},
        {.name = "copper", .albedo = {0.95f, 0.64f, 0.54f}, .roughness = 0.15f, .metallic = 1.0f},
        {.name = "half-metal",
         .albedo = {0.2f, 0.6f, 0.9f},
         .specular = 0.08f,
         .roughness = 0.5f,
         .metallic = 0.5f}};
    // One pixel at the camera's centre sees the wall z = -1 at (-0.9, 0, -1), 66 degrees off
    // its normal.
    const glm::vec3 eye{0.9f, 0.0f, -0.2f}, seen{-0.9f, 0.0f, -1.0f}, normal{0.0f, 0.0f, 1.0f};
    const glm::vec3 wo = glm::normalize(eye - seen);
    for (pt::Material walls : materials) {
        walls.emission = glm::vec3(1.0f);
        const restir::GlossyBsdf bsdf = walls.bsdf();
        restir::Pcg32 rng;
        rng.seed(7u, 11u);
        const pt::test::ChannelStats albedo =
            pt::test::directional_albedo(bsdf, normal, wo, 1 << 22, rng);
        pt::Scene scene = furnace_of(walls);
        scene.camera = pt::CameraSetup{eye, seen, {0.0f, 1.0f, 0.0f}, 30.0f};
        pt::RenderSettings s = tiny(scene, 1);
        s.method = Method::reference;
        s.gi = GlobalIllumination::none;
        s.spp = 64;
        pt::Renderer renderer(scene, s);
        const pt::test::ChannelStats radiance = pt::test::pixel_radiance(renderer, 400);
        for (int c = 0; c < 3; ++c) {
            const double error = std::abs(radiance[c].mean() - (1.0 + albedo[c].mean()));
            const double se = std::hypot(radiance[c].standard_error(), albedo[c].standard_error());
            std::printf("glossy furnace (metallic %.1f), channel %d: %.5f, expected %.5f +- %.5f\n",
                        static_cast<double>(walls.metallic), c, radiance[c].mean(),
                        1.0 + albedo[c].mean(), se);
            EXPECT_LT(error, 4.0 * se) << "metallic " << walls.metallic << ", channel " << c;
        }
    }
}

TEST(Renderer, FurnaceWallsFaceInwards) {
    // Guards the test above: with outward walls the camera would see no emission at all.
    const pt::Scene scene = furnace(0.5f);
    pt::RenderSettings s = tiny(scene, 8);
    s.method = Method::uniform;
    s.gi = GlobalIllumination::none;
    for (const glm::vec3& p : render(scene, s, 1).pixels)
        EXPECT_GE(p.x, 1.0f);
}

TEST(Renderer, ImagesDoNotDependOnTheThreadCount) {
    const pt::Scene scene = pt::make_cornell_box();
    for (Method method : {Method::restir, Method::ris, Method::reference}) {
        pt::RenderSettings s = tiny(scene, 24);
        s.method = method;
        s.threads = 1;
        const pt::Image one = render(scene, s, 3);
        s.threads = 3;
        const pt::Image three = render(scene, s, 3);
        EXPECT_TRUE(same_pixels(one, three)) << static_cast<int>(method);
    }
}

// The packed history (restir::PackedPointHistory) decodes every stored light point back to the
// sample it was: ReSTIR's images are bit-identical with it and without it, with emitters and
// VPLs, a moving camera, every bias correction, and a VPL set reshot mid-render.
TEST(Renderer, PackedHistoryGivesTheSameImages) {
    const pt::Scene scene = pt::make_cornell_box();
    for (const restir::BiasCorrection mode :
         {restir::BiasCorrection::none, restir::BiasCorrection::one_over_z,
          restir::BiasCorrection::balance_heuristic, restir::BiasCorrection::pairwise}) {
        pt::RenderSettings s = tiny(scene, 24);
        s.method = Method::restir;
        s.motion = pt::CameraMotion::orbit;
        s.vpl_reshoot_interval = 3;
        s.di_frame.temporal_bias_correction = mode;
        s.di_frame.spatial_bias_correction = mode;
        const pt::Image viewed = render(scene, s, 5);
        s.packed_history = true;
        const pt::Image packed = render(scene, s, 5);
        EXPECT_TRUE(same_pixels(viewed, packed)) << static_cast<int>(mode);
    }
}

// Candidates drawn from the light BVH by their importance at each pixel (--source bvh), from
// tiles per grid cell drawn from it (--source grid), and in proportion to power from light
// tiles estimate the same image: the mean brightness agrees within 4 standard errors measured
// over seeds, for RIS and ReSTIR, on the many-lights scene (direct light) and in the Cornell
// box with VPLs.
TEST(Renderer, BvhAndGridCandidatesEstimateTheSameImage) {
    const pt::Scene scenes[2] = {pt::make_many_lights(300, 3u), pt::make_cornell_box()};
    struct Run {
        Method method;
        pt::CandidateSource source;
        const char* name;
    };
    const Run runs[5] = {{Method::ris, pt::CandidateSource::power, "ris power"},
                         {Method::ris, pt::CandidateSource::bvh, "ris bvh"},
                         {Method::ris, pt::CandidateSource::grid, "ris grid"},
                         {Method::restir, pt::CandidateSource::bvh, "restir bvh"},
                         {Method::restir, pt::CandidateSource::grid, "restir grid"}};
    for (const pt::Scene& scene : scenes) {
        pt::RenderSettings s = tiny(scene, 32);
        s.gi = scene.name == "cornell" ? GlobalIllumination::vpl : GlobalIllumination::none;
        s.candidates = 16;
        restir::test::RunningStats brightness[5];
        for (std::uint64_t seed = 1; seed <= 8; ++seed)
            for (int k = 0; k < 5; ++k) {
                s.method = runs[k].method;
                s.source = runs[k].source;
                s.seed = seed;
                double sum = 0.0;
                for (const glm::vec3& p : render(scene, s, 4).pixels)
                    sum += static_cast<double>(p.x + p.y + p.z);
                brightness[k].add(sum);
            }
        for (int k = 1; k < 5; ++k) {
            const double difference = std::abs(brightness[k].mean() - brightness[0].mean());
            const double error =
                std::sqrt(brightness[0].variance() / 8.0 + brightness[k].variance() / 8.0);
            EXPECT_LT(difference, 4.0 * error)
                << scene.name << ": power " << brightness[0].mean() << ", " << runs[k].name << " "
                << brightness[k].mean();
        }
    }
}

// Points on emitters drawn uniformly in solid angle from each pixel (--light-points
// solid-angle: per candidate with --source bvh and --method uniform; for light tiles, the chosen
// candidate's point drawn again where TriangleEmitters::redraw_pays_off, which it rarely does
// in these scenes: the redraw's own test is tests/sampling/receiver_light_candidates_test.cpp)
// estimate the same image as area points: the mean brightness over 8 seeds agrees within 4
// standard errors, on the many-lights scene and in the Cornell box with VPLs (which keep their
// points).
TEST(Renderer, SolidAngleLightPointsEstimateTheSameImage) {
    const pt::Scene scenes[2] = {pt::make_many_lights(300, 3u), pt::make_cornell_box()};
    struct Run {
        Method method;
        pt::CandidateSource source;
        pt::LightPoints points;
        const char* name;
    };
    constexpr int run_count = 5;
    const Run runs[run_count] = {
        {Method::ris, pt::CandidateSource::power, pt::LightPoints::area, "ris power area"},
        {Method::ris, pt::CandidateSource::power, pt::LightPoints::solid_angle, "ris power"},
        {Method::ris, pt::CandidateSource::bvh, pt::LightPoints::solid_angle, "ris bvh"},
        {Method::restir, pt::CandidateSource::power, pt::LightPoints::solid_angle, "restir power"},
        {Method::uniform, pt::CandidateSource::power, pt::LightPoints::solid_angle, "uniform"}};
    for (const pt::Scene& scene : scenes) {
        pt::RenderSettings s = tiny(scene, 32);
        s.gi = scene.name == "cornell" ? GlobalIllumination::vpl : GlobalIllumination::none;
        s.candidates = 16;
        restir::test::RunningStats brightness[run_count];
        for (std::uint64_t seed = 1; seed <= 8; ++seed)
            for (int k = 0; k < run_count; ++k) {
                s.method = runs[k].method;
                s.source = runs[k].source;
                s.light_points = runs[k].points;
                s.seed = seed;
                double sum = 0.0;
                for (const glm::vec3& p : render(scene, s, 4).pixels)
                    sum += static_cast<double>(p.x + p.y + p.z);
                brightness[k].add(sum);
            }
        for (int k = 1; k < run_count; ++k) {
            const double difference = std::abs(brightness[k].mean() - brightness[0].mean());
            const double error =
                std::sqrt(brightness[0].variance() / 8.0 + brightness[k].variance() / 8.0);
            EXPECT_LT(difference, 4.0 * error)
                << scene.name << ": area " << brightness[0].mean() << ", " << runs[k].name << " "
                << brightness[k].mean();
        }
    }
}

// BSDF candidates at glossy pixels beside light points drawn from the pixel (MIS in the
// measure the light strategy sampled, restir::LightPoints::from_receiver) estimate the same
// image as beside area points: the glossy Cornell box's mean brightness over 8 seeds agrees
// within 4 standard errors, for RIS and ReSTIR.
TEST(Renderer, BsdfCandidatesBesideSolidAngleLightPointsEstimateTheSameImage) {
    const pt::Scene scene = pt::make_glossy_cornell_box();
    struct Setup {
        Method method;
        pt::LightPoints points;
        std::string name;
    };
    for (const Method method : {Method::ris, Method::restir}) {
        const std::string name = method == Method::ris ? "ris" : "restir";
        const std::vector<Setup> setups = {
            {method, pt::LightPoints::area, name + " area"},
            {method, pt::LightPoints::solid_angle, name + " solid angle, BSDF candidates"}};
        pt::test::expect_agreement(scene, setups, 8, [&](const Setup& setup, std::uint64_t seed) {
            pt::RenderSettings s = tiny(scene, 32);
            s.gi = GlobalIllumination::none;
            s.candidates = 4;
            s.bsdf_candidates = 1;
            s.bsdf_max_roughness = 1.0f; // every glossy pixel
            s.method = setup.method;
            s.light_points = setup.points;
            s.seed = seed;
            return s;
        });
    }
}

// With an orbiting camera, temporal reuse reprojects every frame into the previous camera. RIS
// (no reuse) and ReSTIR are both unbiased estimates of the same frames, so the average
// brightness of their images must agree within the spread measured over independent seeds.
TEST(Renderer, RestirStaysUnbiasedUnderCameraMotion) {
    const pt::Scene scene = pt::make_cornell_box();
    pt::RenderSettings s = tiny(scene, 32);
    s.motion = pt::CameraMotion::orbit;
    s.gi = GlobalIllumination::none;
    restir::test::RunningStats brightness[2];
    const Method methods[2] = {Method::ris, Method::restir};
    for (std::uint64_t seed = 1; seed <= 8; ++seed)
        for (int m = 0; m < 2; ++m) {
            s.method = methods[m];
            s.seed = seed;
            double sum = 0.0;
            for (const glm::vec3& p : render(scene, s, 8).pixels)
                sum += static_cast<double>(p.x + p.y + p.z);
            brightness[m].add(sum);
        }
    const double difference = std::abs(brightness[1].mean() - brightness[0].mean());
    const double error = std::sqrt(brightness[0].variance() / 8.0 + brightness[1].variance() / 8.0);
    EXPECT_LT(difference, 4.0 * error)
        << "RIS " << brightness[0].mean() << ", ReSTIR " << brightness[1].mean();
}

// VPL reshooting: every `vpl_reshoot_interval` frames a new set, the same for the same VPL
// seed and independent of the last. Each frame must estimate the light of its own set: with
// the VPL seed fixed and the pixel seed varied, ReSTIR's frame 2 (a new set: no temporal reuse)
// and frame 3 (temporal reuse within that set) match the reference path tracer's same frames
// in mean brightness. Few VPLs make the sets differ clearly, so a frame that mixed in the last
// set's samples would miss.
TEST(Renderer, ReshotVplSetsAreNewAndEachFrameEstimatesItsOwnSet) {
    const pt::Scene scene = pt::make_cornell_box();
    pt::RenderSettings s = tiny(scene, 24);
    s.vpls = 40;
    s.vpl_reshoot_interval = 2;
    s.photons.seed = 5;
    const auto first_position = [](const pt::Renderer& r) { return r.vpls().front().position; };
    pt::Renderer a(scene, s), b(scene, s);
    std::vector<glm::vec3> firsts;
    for (std::uint32_t f = 0; f < 5; ++f) {
        a.render_frame();
        b.render_frame();
        ASSERT_FALSE(a.vpls().empty());
        EXPECT_EQ(first_position(a), first_position(b)) << "frame " << f;
        firsts.push_back(first_position(a));
    }
    EXPECT_EQ(firsts[0], firsts[1]); // frames 0, 1: set 0
    EXPECT_NE(firsts[1], firsts[2]); // frame 2: set 1
    EXPECT_EQ(firsts[2], firsts[3]);
    EXPECT_NE(firsts[3], firsts[4]); // frame 4: set 2

    constexpr int seeds = 16;
    restir::test::RunningStats brightness[2][2]; // [method][frame 2, frame 3]
    const Method methods[2] = {Method::reference, Method::restir};
    for (int m = 0; m < 2; ++m)
        for (std::uint64_t seed = 1; seed <= seeds; ++seed) {
            s.method = methods[m];
            s.seed = seed;
            pt::Renderer renderer(scene, s);
            for (std::uint32_t f = 0; f < 4; ++f) {
                renderer.render_frame();
                if (f < 2)
                    continue;
                double sum = 0.0;
                for (const glm::vec3& p : renderer.last_frame().pixels)
                    sum += static_cast<double>(p.x + p.y + p.z);
                brightness[m][f - 2].add(sum);
            }
        }
    for (int f = 0; f < 2; ++f) {
        const double difference = brightness[1][f].mean() - brightness[0][f].mean();
        const double error =
            std::hypot(brightness[0][f].standard_error(), brightness[1][f].standard_error());
        EXPECT_LT(std::abs(difference), 4.0 * error)
            << "frame " << f + 2 << ": reference " << brightness[0][f].mean() << ", ReSTIR "
            << brightness[1][f].mean();
    }
}

// The boiling filter runs after the spatial passes and only empties reservoirs: on the first
// frame (same random numbers up to the filter) every pixel is at most as bright as without it,
// and a low threshold empties some.
TEST(Renderer, BoilingFilterOnlyEmptiesReservoirs) {
    const pt::Scene scene = pt::make_cornell_box();
    pt::RenderSettings s = tiny(scene, 24);
    const pt::Image plain = render(scene, s, 1);
    s.di_frame.boiling_filter = true;
    s.di_frame.boiling.threshold = 1.5f;
    const pt::Image filtered = render(scene, s, 1);
    std::size_t darker = 0;
    for (std::size_t i = 0; i < plain.pixels.size(); ++i)
        for (int c = 0; c < 3; ++c) {
            ASSERT_LE(filtered.pixels[i][c], plain.pixels[i][c]) << "pixel " << i;
            darker += filtered.pixels[i][c] < plain.pixels[i][c] ? 1u : 0u;
        }
    EXPECT_GT(darker, 0u);
}

// The photon budget is bounded: a scene whose surfaces reflect nothing leaves no VPL in the
// pilot pass and gets no more photons (it used to get a hundred million: seconds to minutes of
// work for nothing), and otherwise at most 64 photons are shot per VPL asked for.
TEST(Renderer, PhotonBudgetIsBounded) {
    const pt::Scene black = furnace(0.0f);
    pt::RenderSettings s = tiny(black, 8);
    s.vpls = 100'000;
    pt::Renderer dark(black, s);
    EXPECT_EQ(dark.vpl_count(), 0u);
    EXPECT_EQ(dark.photons_per_set(), 0u);
    dark.render_frame();
    for (const glm::vec3& p : dark.accumulated().pixels)
        EXPECT_TRUE(std::isfinite(p.x) && std::isfinite(p.y) && std::isfinite(p.z));

    const pt::Scene box = pt::make_cornell_box();
    s = tiny(box, 8);
    const pt::Renderer lit(box, s);
    EXPECT_GT(lit.vpl_count(), 0u);
    EXPECT_GT(lit.photons_per_set(), 0u);
    EXPECT_LE(lit.photons_per_set(), 64u * s.vpls);
}

// The default source is the BVH from bvh_source_emitters emitter triangles on (4 candidates),
// power tiles below (32); what the command line names is kept.
TEST(Renderer, AutomaticCandidatesFollowTheEmitterCount) {
    const pt::Scene box = pt::make_cornell_box();
    const pt::Scene many = pt::make_many_lights(pt::bvh_source_emitters / 2u, 1u); // 2 a quad
    const pt::Scene fewer = pt::make_many_lights(pt::bvh_source_emitters / 2u - 1u, 1u);
    const pt::Renderer in_box(box, tiny(box, 8));
    const pt::Renderer among_many(many, tiny(many, 8));
    const pt::Renderer among_fewer(fewer, tiny(fewer, 8));
    ASSERT_EQ(among_many.emitter_count(), pt::bvh_source_emitters);
    EXPECT_EQ(in_box.settings().source, pt::CandidateSource::power);
    EXPECT_EQ(in_box.settings().candidates, pt::default_tile_candidates);
    EXPECT_EQ(among_fewer.settings().source, pt::CandidateSource::power);
    EXPECT_EQ(among_many.settings().source, pt::CandidateSource::bvh);
    EXPECT_EQ(among_many.settings().candidates, pt::default_bvh_candidates);

    pt::RenderSettings chosen = tiny(many, 8);
    chosen.source = pt::CandidateSource::grid;
    chosen.candidates = 7u;
    const pt::RenderSettings kept = pt::resolved_candidates(chosen, 1000u);
    EXPECT_EQ(kept.source, pt::CandidateSource::grid);
    EXPECT_EQ(kept.candidates, 7u);
    chosen.candidates = 0u;
    EXPECT_EQ(pt::resolved_candidates(chosen, 1000u).candidates, pt::default_tile_candidates);
}

TEST(Renderer, SceneWithoutEmittersIsAnError) {
    pt::Scene scene = furnace(0.5f);
    scene.materials[0].emission = glm::vec3(0.0f);
    EXPECT_THROW(pt::Renderer(scene, tiny(scene, 8)), pt::SceneError);
}

} // namespace

namespace {

// A large floor (so that the ray offset, 1e-4 of the scene's size, is 0.14) under one square
// light of side 2 at height 1, the camera looking at the floor beneath it.
pt::Scene light_close_to_a_large_floor() {
    pt::Scene scene;
    scene.name = "light over a large floor";
    const auto quad = [&scene](std::array<glm::vec3, 4> corners, std::uint32_t material) {
        const auto first = static_cast<std::uint32_t>(scene.positions.size());
        for (const glm::vec3& p : corners)
            scene.positions.push_back(p);
        for (std::uint32_t v : {0u, 1u, 2u, 0u, 2u, 3u})
            scene.indices.push_back(first + v);
        scene.triangle_materials.push_back(material);
        scene.triangle_materials.push_back(material);
    };
    const float f = 500.0f;
    quad({{{-f, 0.0f, -f}, {-f, 0.0f, f}, {f, 0.0f, f}, {f, 0.0f, -f}}}, 0u); // normal +y
    quad({{{-1.0f, 1.0f, -1.0f}, {1.0f, 1.0f, -1.0f}, {1.0f, 1.0f, 1.0f}, {-1.0f, 1.0f, 1.0f}}},
         1u); // normal -y: emits towards the floor
    scene.materials.push_back({"floor", glm::vec3(0.5f), glm::vec3(0.0f)});
    scene.materials.push_back({"light", glm::vec3(0.5f), glm::vec3(1.0f)});
    scene.camera = pt::CameraSetup{{0.0f, 0.5f, 4.0f}, {0.0f, 0.0f, 0.0f}, {0, 1, 0}, 30.0f};
    return scene;
}

} // namespace

// The reference path tracer's cosine-sampled rays must leave from the surface point itself: a
// ray pushed off along the normal sees a light close above from nearer than the point does, and
// the MIS weight of those rays (large for a large, close light) carried that brighter view into
// the image. The mean brightness of the reference must agree with RIS's within 4 standard
// errors measured over seeds.
TEST(Renderer, ReferenceAgreesWithRisUnderALightCloseToTheFloor) {
    const pt::Scene scene = light_close_to_a_large_floor();
    pt::RenderSettings s = tiny(scene, 24);
    s.gi = GlobalIllumination::none;
    restir::test::RunningStats brightness[2];
    const Method methods[2] = {Method::reference, Method::ris};
    for (std::uint64_t seed = 1; seed <= 8; ++seed)
        for (int k = 0; k < 2; ++k) {
            s.method = methods[k];
            s.seed = seed;
            double sum = 0.0;
            for (const glm::vec3& p : render(scene, s, 8).pixels)
                sum += static_cast<double>(p.x + p.y + p.z);
            brightness[k].add(sum);
        }
    const double difference = std::abs(brightness[0].mean() - brightness[1].mean());
    const double error = std::sqrt(brightness[0].variance() / 8.0 + brightness[1].variance() / 8.0);
    std::printf("light close to the floor: reference %.3f, RIS %.3f, difference %.3f, SE %.3f\n",
                brightness[0].mean(), brightness[1].mean(), difference, error);
    EXPECT_LT(difference, 4.0 * error);
}

namespace {

// The glossy pixels' mean brightness (channel sums) of `frames` frames.
double glossy_brightness(const pt::Scene& scene, const pt::RenderSettings& settings,
                         std::uint32_t frames) {
    pt::Renderer renderer(scene, settings);
    for (std::uint32_t f = 0; f < frames; ++f)
        renderer.render_frame();
    const std::vector<std::uint8_t> glossy = renderer.glossy_pixels();
    double sum = 0.0;
    for (std::size_t i = 0; i < glossy.size(); ++i)
        if (glossy[i] != 0u) {
            const glm::vec3 p = renderer.accumulated().pixels[i];
            sum += static_cast<double>(p.x + p.y + p.z);
        }
    return sum;
}

} // namespace

// On the glossy Cornell box, ReSTIR (tile candidates, and with BSDF candidates) and RIS with
// BSDF candidates estimate the glossy pixels' direct light as the reference path tracer does:
// mean brightness within 4 standard errors measured over seeds.
// The same with VPLs (one VPL set for all, their light on glossy surfaces widened alike in every
// method): the reference's VPL next-event estimation against ReSTIR with BSDF candidates.
TEST(Renderer, GlossyCornellBoxWithVplsAgreesWithTheReference) {
    const pt::Scene scene = pt::make_glossy_cornell_box();
    pt::RenderSettings s = tiny(scene, 32);
    s.gi = GlobalIllumination::vpl;
    restir::test::RunningStats brightness[2];
    for (std::uint64_t seed = 1; seed <= 16; ++seed)
        for (int k = 0; k < 2; ++k) {
            s.method = k == 0 ? Method::reference : Method::restir;
            s.bsdf_candidates = k == 0 ? 0u : 1u;
            s.bsdf_max_roughness = 1.0f; // every glossy pixel
            s.spp = k == 0 ? 32u : 1u;
            s.seed = seed;
            brightness[k].add(glossy_brightness(scene, s, k == 0 ? 4u : 16u));
        }
    const double error =
        std::sqrt(brightness[0].variance() / 16.0 + brightness[1].variance() / 16.0);
    std::printf(
        "glossy Cornell box with VPLs: ReSTIR %.3f against the reference's %.3f (SE %.3f)\n",
        brightness[1].mean(), brightness[0].mean(), error);
    EXPECT_LT(std::abs(brightness[1].mean() - brightness[0].mean()), 4.0 * error);
}

TEST(Renderer, GlossyCornellBoxAgreesWithTheReference) {
    const pt::Scene scene = pt::make_glossy_cornell_box();
    pt::RenderSettings s = tiny(scene, 32);
    s.gi = GlobalIllumination::none;
    struct Setup {
        Method method;
        std::uint32_t bsdf_candidates;
        std::uint32_t frames;
        pt::CandidateSource source = pt::CandidateSource::automatic;
        float narrow = 0.0f; // the narrow-lobe rules of reuse below this roughness
    };
    // BSDF candidates beside the tiles' candidates and beside the light BVH's; the floor (0.12)
    // and the metal block (0.25) as narrow lobes, apart in reuse.
    const Setup setups[] = {{Method::reference, 0u, 4u},
                            {Method::restir, 0u, 8u},
                            {Method::restir, 1u, 8u},
                            {Method::ris, 2u, 8u},
                            {Method::ris, 1u, 8u, pt::CandidateSource::bvh},
                            {Method::restir, 1u, 8u, pt::CandidateSource::automatic, 0.3f}};
    constexpr int setup_count = static_cast<int>(std::size(setups));
    restir::test::RunningStats brightness[setup_count];
    for (std::uint64_t seed = 1; seed <= 8; ++seed)
        for (int k = 0; k < setup_count; ++k) {
            s.method = setups[k].method;
            s.bsdf_candidates = setups[k].bsdf_candidates;
            s.bsdf_max_roughness = 1.0f; // every glossy pixel
            s.source = setups[k].source;
            s.candidates = setups[k].source == pt::CandidateSource::bvh ? 4u : 0u;
            s.di_frame.spatial.min_roughness = setups[k].narrow;
            s.di_frame.temporal.permutation_min_roughness = setups[k].narrow;
            s.spp = setups[k].method == Method::reference ? 16u : 1u;
            s.seed = seed;
            brightness[k].add(glossy_brightness(scene, s, setups[k].frames));
        }
    EXPECT_GT(brightness[0].mean(), 0.0);
    for (int k = 1; k < setup_count; ++k) {
        const double difference = brightness[k].mean() - brightness[0].mean();
        const double error =
            std::sqrt(brightness[0].variance() / 8.0 + brightness[k].variance() / 8.0);
        std::printf("glossy Cornell box, setup %d: %.3f against the reference's %.3f (SE %.3f)\n",
                    k, brightness[k].mean(), brightness[0].mean(), error);
        EXPECT_LT(std::abs(difference), 4.0 * error) << "setup " << k;
    }
}

// The G-buffer texel keeps its view direction and material packed: they come back to within
// the packing's steps (2^-15 of the octahedral square, 1/65535 of F0 and roughness).
TEST(GBuffer, PackedViewAndMaterialComeBack) {
    pt::Material m;
    m.albedo = {0.9f, 0.6f, 0.3f};
    m.specular = 0.04f;
    m.roughness = 0.12f;
    m.metallic = 1.0f;
    m.emission = {2.0f, 1.0f, 0.5f};
    pt::Scene scene;
    scene.materials = {pt::Material{}, m};
    restir::Pcg32 rng = restir::make_pixel_rng(0u, 0u, 0u, 5u);
    for (int i = 0; i < 1000; ++i) {
        const float z = 1.0f - 2.0f * next_float(rng);
        const float phi = 6.2831853f * next_float(rng);
        const float r = std::sqrt(std::max(0.0f, 1.0f - z * z));
        const glm::vec3 wo{r * std::cos(phi), r * std::sin(phi), z};
        pt::GSurface s;
        pt::set_view_and_material(s, wo, m, 1u);
        EXPECT_LT(glm::length(pt::view_direction(s) - wo), 2e-4f) << i; // 2^-15 steps
        const restir::GlossyBsdf packed = pt::surface_bsdf(s);
        const restir::GlossyBsdf exact = m.bsdf();
        EXPECT_NEAR(packed.roughness, exact.roughness, 1e-5f);
        for (int c = 0; c < 3; ++c) {
            EXPECT_NEAR(packed.specular_f0[c], exact.specular_f0[c], 1e-5f);
            EXPECT_NEAR(packed.diffuse_albedo[c], exact.diffuse_albedo[c], 1e-5f);
        }
        EXPECT_FALSE(pt::is_lambertian(s));
        EXPECT_EQ(pt::emitted(scene, s), m.emission);
        s.front = false;
        EXPECT_EQ(pt::emitted(scene, s), glm::vec3(0.0f));
    }
    pt::GSurface diffuse;
    pt::set_view_and_material(diffuse, {0.0f, 0.0f, 1.0f}, pt::Material{}, 0u);
    EXPECT_TRUE(pt::is_lambertian(diffuse));
    EXPECT_EQ(pt::surface_bsdf(diffuse).specular_f0, glm::vec3(0.0f));
}
