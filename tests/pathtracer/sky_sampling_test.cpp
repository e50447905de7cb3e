// The environment as one light among the emitters in RIS and ReSTIR: on the sun-sky scene (its
// sun, sky and two lamps), every unbiased way of sampling it estimates the image the reference
// path tracer does; and the environment's light candidates, by importance, beat BSDF-sampled
// directions alone.
#include "environment.hpp"
#include "renderer.hpp"
#include "scene.hpp"

#include "pathtracer/image_sums.hpp"
#include "support/statistics.hpp"

#include <gtest/gtest.h>

#include <cmath>
#include <cstdint>
#include <cstdio>
#include <string>
#include <vector>

namespace {

using pt::GlobalIllumination;
using pt::Method;

// The sun-sky scene under a smaller map: a sun of 2 degrees, which spans a few of its texels,
// or no sun.
pt::Scene make_sun_sky(float sun_to_sky_ratio) {
    pt::SunSkyParams sky;
    sky.width = 512;
    sky.height = 256;
    sky.sun_diameter_degrees = 2.0f;
    sky.sun_to_sky_ratio = sun_to_sky_ratio;
    return pt::make_sun_sky_scene(pt::make_sun_sky_environment(sky));
}
const pt::Scene& sun_sky() {
    static const pt::Scene scene = make_sun_sky(4.0f);
    return scene;
}

pt::RenderSettings small(const pt::Scene& scene) {
    pt::RenderSettings s;
    s.width = 40;
    s.height = 24;
    s.camera = *scene.camera;
    s.gi = GlobalIllumination::none;
    s.di_frame.spatial.radius = 4.0f;
    s.threads = 2;
    return s;
}

struct SkySetup {
    std::string name;
    Method method;
    restir::BiasCorrection correction = restir::BiasCorrection::pairwise;
    std::uint32_t bsdf_candidates = 0u;
    pt::EnvironmentSampling sampling = pt::EnvironmentSampling::importance;
    pt::CandidateSource source = pt::CandidateSource::power;
    bool packed_history = false;
    float environment_share = 0.0f;
};

// Each setup after the first (the reference) estimates its image over 6 seeds.
void expect_agreement(const pt::Scene& scene, const std::vector<SkySetup>& setups) {
    pt::test::expect_agreement(scene, setups, 6, [&](const SkySetup& setup, std::uint64_t seed) {
        pt::RenderSettings s = small(scene);
        s.method = setup.method;
        s.spp = s.method == Method::reference ? 16u : 1u;
        s.di_frame.temporal_bias_correction = setup.correction;
        s.di_frame.spatial_bias_correction = setup.correction;
        s.bsdf_candidates = setup.bsdf_candidates;
        s.bsdf_max_roughness = 1.0f; // every glossy pixel
        s.environment_sampling = setup.sampling;
        s.source = setup.source;
        s.packed_history = setup.packed_history;
        s.environment_share = setup.environment_share;
        s.seed = seed;
        return s;
    });
}

TEST(SkySampling, EveryUnbiasedModeAgreesWithTheReference) {
    const pt::Scene& scene = sun_sky();
    const std::vector<SkySetup> setups = {
        {"reference", Method::reference},
        {"ris", Method::ris},
        {"ris, bsdf candidates", Method::ris, {}, 2u},
        {"restir 1/Z", Method::restir, restir::BiasCorrection::one_over_z},
        {"restir balance", Method::restir, restir::BiasCorrection::balance_heuristic},
        {"restir pairwise", Method::restir, restir::BiasCorrection::pairwise},
        {"restir pairwise, bsdf candidates", Method::restir, restir::BiasCorrection::pairwise, 1u},
        {"restir pairwise, packed history", Method::restir, restir::BiasCorrection::pairwise, 0u,
         pt::EnvironmentSampling::importance, pt::CandidateSource::power, true},
        {"restir pairwise, bvh", Method::restir, restir::BiasCorrection::pairwise, 0u,
         pt::EnvironmentSampling::importance, pt::CandidateSource::bvh},
        {"restir pairwise, grid", Method::restir, restir::BiasCorrection::pairwise, 0u,
         pt::EnvironmentSampling::importance, pt::CandidateSource::grid},
        {"ris, environment share 0.1", Method::ris, restir::BiasCorrection::pairwise, 0u,
         pt::EnvironmentSampling::importance, pt::CandidateSource::power, false, 0.1f},
    };
    expect_agreement(scene, setups);
}

// RIS that finds the sky through BSDF candidates alone (cosine-weighted at diffuse pixels, the
// sky out of the light candidates: --env-sampling bsdf) estimates the reference's image, under
// the sky without its sun (with it, the sun's rare hits leave a standard error of several per
// cent, which no test of this size resolves).
TEST(SkySampling, BsdfCandidatesAloneFindTheSky) {
    const pt::Scene scene = make_sun_sky(0.0f);
    expect_agreement(
        scene,
        {{"reference", Method::reference},
         {"ris, environment by bsdf only", Method::ris, {}, 2u, pt::EnvironmentSampling::bsdf}});
}

} // namespace

namespace {

// With the panels dark, the sky alone lights the courtyard: the renderer takes a scene with no
// emitter, and the photons of --gi vpl leave the sky, so its light bounces through VPLs.
TEST(SkySampling, TheSkyAloneLightsTheSceneAndShootsPhotons) {
    pt::Scene scene = sun_sky();
    for (pt::Material& m : scene.materials)
        m.emission = glm::vec3(0.0f);
    pt::RenderSettings s = small(scene);
    s.method = Method::restir;
    s.gi = GlobalIllumination::vpl;
    s.vpls = 2000;
    pt::Renderer renderer(scene, s);
    EXPECT_GT(renderer.vpl_count(), 500u);
    EXPECT_EQ(renderer.emitter_count(), 0u);
    renderer.render_frame();
    double sum = 0.0;
    for (const glm::vec3& p : renderer.accumulated().pixels)
        sum += static_cast<double>(p.x + p.y + p.z);
    EXPECT_GT(sum, 0.0);
}

} // namespace
