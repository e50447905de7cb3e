// ReSTIR GI in the renderer (--gi restir-gi): its indirect light estimates the path tracer's
// under every unbiased bias correction, in the diffuse Cornell box and in the glossy one (whose
// glossy sample points reconnect only where the rule allows); its reuse lowers the error of a
// frame; and the direct light's frame stays as it was.
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
using restir::BiasCorrection;

pt::RenderSettings small(const pt::Scene& scene) {
    pt::RenderSettings s;
    s.width = 40;
    s.height = 30;
    s.camera = *scene.camera;
    s.gi = GlobalIllumination::restir_gi;
    s.indirect_only = true;
    s.di_frame.spatial.radius = 4.0f;
    s.threads = 2;
    return s;
}

struct GiSetup {
    std::string name;
    Method method;
    BiasCorrection correction = BiasCorrection::pairwise;
    float min_roughness = 0.5f;
};

// Each setup after the first (the path-traced reference) estimates its indirect light over 24
// seeds.
void expect_agreement(const pt::Scene& scene, const std::vector<GiSetup>& setups) {
    pt::test::expect_agreement(scene, setups, 24, [&](const GiSetup& setup, std::uint64_t seed) {
        pt::RenderSettings s = small(scene);
        s.method = setup.method;
        s.spp = s.method == Method::reference ? 16u : 1u;
        s.di_frame.temporal_bias_correction = setup.correction;
        s.di_frame.spatial_bias_correction = setup.correction;
        s.reconnection.min_roughness = setup.min_roughness;
        s.seed = seed;
        return s;
    });
}

TEST(RestirGi, EveryUnbiasedModeEstimatesThePathTracersIndirectLight) {
    const pt::Scene scene = pt::make_cornell_box();
    expect_agreement(
        scene, {{"reference", Method::reference},
                {"restir-gi pairwise", Method::restir, BiasCorrection::pairwise},
                {"restir-gi balance heuristic", Method::restir, BiasCorrection::balance_heuristic},
                {"restir-gi 1/Z", Method::restir, BiasCorrection::one_over_z}});
}

// Glossy sample points (the polished floor, the metal block) reconnect only to the same visible
// point under min_roughness 1: the glossy box's indirect light stays unbiased.
TEST(RestirGi, GlossySamplePointsReconnectOnlyWhereTheRuleAllows) {
    const pt::Scene scene = pt::make_glossy_cornell_box();
    expect_agreement(scene, {{"reference", Method::reference},
                             {"restir-gi pairwise, Lambertian", Method::restir,
                              BiasCorrection::pairwise, 1.0f}});
}

// Mean squared difference of two images' pixels (all channels).
double mse(const pt::Image& a, const pt::Image& b) {
    double sum = 0.0;
    for (std::size_t i = 0; i < a.pixels.size(); ++i) {
        const glm::vec3 d = a.pixels[i] - b.pixels[i];
        sum += static_cast<double>(glm::dot(d, d));
    }
    return sum / static_cast<double>(a.pixels.size());
}

// Reuse is what ReSTIR GI adds to a path per pixel: its sixth frame alone is closer to the
// reference than the path tracer's sixth frame (each frame one path per pixel).
TEST(RestirGi, ReuseLowersTheErrorOfAFrame) {
    const pt::Scene scene = pt::make_cornell_box();
    pt::RenderSettings s = small(scene);
    s.method = Method::reference;
    s.spp = 512;
    pt::Renderer reference(scene, s);
    reference.render_frame();
    double frame_mse[2] = {};
    for (int k = 0; k < 2; ++k) {
        s.method = Method::restir;
        s.spp = 1;
        s.gi = k == 0 ? GlobalIllumination::path : GlobalIllumination::restir_gi;
        pt::Renderer renderer(scene, s);
        for (int f = 0; f < 6; ++f)
            renderer.render_frame();
        frame_mse[k] = mse(renderer.last_frame(), reference.accumulated());
    }
    std::printf("sixth frame's MSE: path %.4g, restir-gi %.4g\n", frame_mse[0], frame_mse[1]);
    EXPECT_LT(frame_mse[1], 0.5 * frame_mse[0]);
}

} // namespace
