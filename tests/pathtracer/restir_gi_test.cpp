// ReSTIR GI and PT in the renderer (--gi restir-gi, restir-pt): their indirect light estimates
// the path tracer's under every unbiased bias correction, in the diffuse Cornell box and in the
// glossy one (whose glossy sample points ReSTIR GI reconnects only where its rule allows, and
// whose glossy paths ReSTIR PT replays); their reuse lowers the error of a frame.
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
    GlobalIllumination gi = GlobalIllumination::restir_gi;
    /// restir-pt's reconnection criterion (the renderer's default unless given).
    restir::ReconnectionCriterion pt_rule = pt::RenderSettings{}.pt_reconnection;
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
        s.gi = setup.gi;
        s.pt_reconnection = setup.pt_rule;
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

// ReSTIR PT in the glossy box: the polished floor (roughness 0.12) and the metal block (0.25)
// are below the criterion's 0.3, so their paths are replayed to a later vertex before they
// reconnect. Under every unbiased bias correction, with the hybrid shift as the renderer
// sets it, with reconnection wherever the segment allows (roughness 0), and with random replay
// alone (no segment long enough), the indirect light is the path tracer's.
TEST(RestirPt, EveryUnbiasedModeAndShiftEstimatesThePathTracersIndirectLight) {
    const pt::Scene scene = pt::make_glossy_cornell_box();
    constexpr auto pt_gi = GlobalIllumination::restir_pt;
    expect_agreement(scene,
                     {{"reference", Method::reference},
                      {"restir-pt pairwise", Method::restir, BiasCorrection::pairwise, 0.5f, pt_gi},
                      {"restir-pt balance heuristic", Method::restir,
                       BiasCorrection::balance_heuristic, 0.5f, pt_gi},
                      {"restir-pt 1/Z", Method::restir, BiasCorrection::one_over_z, 0.5f, pt_gi},
                      {"restir-pt, reconnection anywhere",
                       Method::restir,
                       BiasCorrection::pairwise,
                       0.5f,
                       pt_gi,
                       {0.0f, 0.0f}},
                      {"restir-pt, random replay alone",
                       Method::restir,
                       BiasCorrection::pairwise,
                       0.5f,
                       pt_gi,
                       {0.0f, 1.0f}}});
}

TEST(RestirPt, DiffuseBoxIndirectLightIsThePathTracers) {
    const pt::Scene scene = pt::make_cornell_box();
    expect_agreement(scene, {{"reference", Method::reference},
                             {"restir-pt pairwise", Method::restir, BiasCorrection::pairwise, 0.5f,
                              GlobalIllumination::restir_pt}});
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

// In the glossy box, where ReSTIR GI cannot reuse the glossy pixels' samples, ReSTIR PT's
// frames alone are closer to the reference than ReSTIR GI's and the path tracer's: the mean of
// the MSE of frames 2 to 6 at 80 x 60 (at 40 x 30 the spatial radius of 3 pixels spans a tenth
// of the image, and the polished floor is a few rows).
TEST(RestirPt, ReuseLowersTheErrorOfAFrameInTheGlossyBox) {
    const pt::Scene scene = pt::make_glossy_cornell_box();
    pt::RenderSettings s = small(scene);
    s.width = 80;
    s.height = 60;
    s.method = Method::reference;
    s.spp = 512;
    pt::Renderer reference(scene, s);
    reference.render_frame();
    const GlobalIllumination modes[] = {GlobalIllumination::path, GlobalIllumination::restir_gi,
                                        GlobalIllumination::restir_pt};
    double frame_mse[3] = {};
    for (int k = 0; k < 3; ++k) {
        s.method = Method::restir;
        s.spp = 1;
        s.gi = modes[k];
        pt::Renderer renderer(scene, s);
        for (int f = 0; f < 6; ++f) {
            renderer.render_frame();
            if (f > 0)
                frame_mse[k] += mse(renderer.last_frame(), reference.accumulated()) / 5.0;
        }
    }
    std::printf("frames 2-6, mean MSE: path %.4g, restir-gi %.4g, restir-pt %.4g\n", frame_mse[0],
                frame_mse[1], frame_mse[2]);
    EXPECT_LT(frame_mse[2], 0.5 * frame_mse[0]);
    EXPECT_LT(frame_mse[2], frame_mse[1]);
}

} // namespace
