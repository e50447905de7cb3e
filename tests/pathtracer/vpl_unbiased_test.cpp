// VPL GI without bias in the renderer (--gi vpl-unbiased): ReSTIR DI over the emitters and the
// VPLs of restir::VplPartition, beside ReSTIR GI's path samples for the rest, estimates the
// path tracer's image (direct and indirect light) in the diffuse Cornell box, the glossy one
// and ../shared/scenes/cornell-box.obj (its materials made Lambertian).
#include "renderer.hpp"
#include "scene.hpp"

#include "pathtracer/image_sums.hpp"

#include <gtest/gtest.h>

#include <cstdint>
#include <filesystem>
#include <string>
#include <vector>

namespace {

namespace fs = std::filesystem;
using pt::GlobalIllumination;
using pt::Method;

struct VplSetup {
    std::string name;
    Method method;
    GlobalIllumination gi;
    /// The partition's radius relative to the scene's size (0: the renderer's default).
    float radius = 0.0f;
    pt::VplPathPart path_part = pt::VplPathPart::independent;
};

pt::RenderSettings small(const pt::Scene& scene, const VplSetup& setup, std::uint64_t seed) {
    pt::RenderSettings s;
    s.width = 40;
    s.height = 30;
    s.camera = scene.camera ? *scene.camera : pt::frame_bounds(scene, 4.0f / 3.0f);
    s.method = setup.method;
    s.spp = s.method == Method::reference ? 16u : 1u;
    s.gi = setup.gi;
    s.vpls = 20'000;
    s.di_frame.spatial.radius = 4.0f;
    s.threads = 2;
    s.seed = seed; // the photons' seed too: each seed has its own VPL set
    s.photons.seed = seed;
    if (setup.radius > 0.0f)
        s.partition_radius = setup.radius;
    s.vpl_path_part = setup.path_part;
    return s;
}

// Each setup after the reference estimates its image over 24 seeds.
void expect_agreement(const pt::Scene& scene, const std::vector<VplSetup>& setups) {
    pt::test::expect_agreement(scene, setups, 24, [&](const VplSetup& setup, std::uint64_t seed) {
        return small(scene, setup, seed);
    });
}

const VplSetup reference{"reference", Method::reference, GlobalIllumination::path};
// The path part from independent path samples (the default), and reused by ReSTIR GI's frame.
const VplSetup unbiased{"vpl-unbiased", Method::restir, GlobalIllumination::vpl_unbiased};
const VplSetup reused{"vpl-unbiased, paths reused", Method::restir,
                      GlobalIllumination::vpl_unbiased, 0.0f, pt::VplPathPart::reuse};

// At any radius: with r 1 % of the scene's size VPLs carry nearly all the diffuse light, with
// r 100 % path samples carry most of it (and reused ones: ReSTIR GI's target is the path part).
TEST(VplUnbiased, DiffuseBoxImageIsThePathTracers) {
    constexpr auto reuse = pt::VplPathPart::reuse;
    constexpr auto vpl_unbiased = GlobalIllumination::vpl_unbiased;
    expect_agreement(
        pt::make_cornell_box(),
        {reference,
         unbiased,
         reused,
         {"vpl-unbiased, r 1 %", Method::restir, vpl_unbiased, 0.01f},
         {"vpl-unbiased, r 100 %", Method::restir, vpl_unbiased, 1.0f},
         {"vpl-unbiased, r 100 %, paths reused", Method::restir, vpl_unbiased, 1.0f, reuse}});
}

// The polished floor and the metal block take their VPL light through the diffuse lobe alone,
// and hold no VPL: their light reaches the walls through path samples.
TEST(VplUnbiased, GlossyBoxImageIsThePathTracers) {
    expect_agreement(pt::make_glossy_cornell_box(), {reference, unbiased, reused});
}

TEST(VplUnbiased, SharedCornellBoxImageIsThePathTracers) {
    const fs::path obj = fs::path(RESTIR_SHARED_SCENES) / "cornell-box.obj";
    if (!fs::exists(obj))
        GTEST_SKIP() << obj << " is not there";
    pt::Scene scene = pt::load_obj(obj);
    pt::make_materials_diffuse(scene); // VPLs lie on Lambertian surfaces alone
    expect_agreement(scene, {reference, unbiased, reused});
}

} // namespace
