// OBJ and MTL files are untrusted input: numbers tinyobjloader would read as 0, indices that
// would overflow, unreadable material libraries: one-line SceneErrors, never a silent misreading.
#include "render_options.hpp"
#include "scene.hpp"

#include "scratch_dir.hpp"

#include <gtest/gtest.h>

#include <algorithm>
#include <cmath>
#include <filesystem>
#include <fstream>
#include <optional>
#include <string>
#include <vector>

namespace {

namespace fs = std::filesystem;

using pt_test::scratch_dir;

const std::string triangle = "v 0 0 0\nv 1 0 0\nv 0 1 0\nf 1 2 3\n";

void expect_refused(const std::string& obj, const std::string& mtl, const std::string& needle) {
    try {
        pt::parse_obj(obj, mtl, "hostile.obj");
        ADD_FAILURE() << "accepted:\n" << obj;
    } catch (const pt::SceneError& e) {
        const std::string what = e.what();
        EXPECT_EQ(what.find('\n'), std::string::npos) << what;
        EXPECT_NE(what.find(needle), std::string::npos) << what;
        EXPECT_NE(what.find("hostile.obj"), std::string::npos) << what;
    }
}

TEST(ObjLoader, ReadsPositionsFacesAndMaterials) {
    const pt::Scene scene =
        pt::parse_obj("mtllib any.mtl\nv 0 0 0\nv +1.5 0 0 # a comment\nv 0 1e2 0\nv 1 1 0\n"
                      "usemtl lamp\nf 1 2 3 4\nf -4 -3 -2\n",
                      "newmtl lamp\nKd 0.5 0.25 1\nKe 3 4 5\n", "good.obj");
    ASSERT_EQ(scene.positions.size(), 4u);
    const auto has = [&](glm::vec3 p) {
        return std::find(scene.positions.begin(), scene.positions.end(), p) !=
               scene.positions.end();
    };
    EXPECT_TRUE(has(glm::vec3(1.5f, 0.0f, 0.0f)));
    EXPECT_TRUE(has(glm::vec3(0.0f, 100.0f, 0.0f)));
    EXPECT_EQ(scene.triangle_materials.size(), 3u); // a quad and a triangle
    ASSERT_GE(scene.materials.size(), 1u);
    EXPECT_EQ(scene.materials[0].albedo, glm::vec3(0.5f, 0.25f, 1.0f));
    EXPECT_EQ(scene.materials[0].emission, glm::vec3(3.0f, 4.0f, 5.0f));
}

// tinyobjloader reads what it cannot parse as 0: "v nan 0 0" became the origin.
TEST(ObjLoader, NumbersThatAreNotFiniteAreRefused) {
    for (const std::string bad : {"nan", "inf", "-inf", "1e400", "x", "1.0.0", "0x10"})
        expect_refused("v " + bad + " 0 0\n" + triangle, "", std::string(1, '\'').append(bad));
    expect_refused("v 0 0\n" + triangle, "", "three coordinates");
    expect_refused("vn 0 nan 1\n" + triangle, "", "line 1");
    expect_refused(triangle + "vt 0 inf\n", "", "line 5");
    // Material colours too: "Ke nan" would have been a black emitter.
    expect_refused("mtllib m.mtl\nusemtl a\n" + triangle, "newmtl a\nKe nan 1 1\n", "'nan'");
    expect_refused("mtllib m.mtl\nusemtl a\n" + triangle, "newmtl a\nKd 1 1 1e99999\n", "1e99999");
}

// The index message used to show a wrapped number ("vertex 1215752191" for 99999999999).
TEST(ObjLoader, IndicesBeyondAnIntAreRefusedAsWritten) {
    expect_refused(triangle + "f 1 2 99999999999\n", "", "'99999999999'");
    expect_refused(triangle + "f 1 2 -99999999999\n", "", "'-99999999999'");
    expect_refused(triangle + "f 1 2 0\n", "", "'0'");
    expect_refused(triangle + "f 1 2 3/x\n", "", "'3/x'");
    expect_refused(triangle + "f 1 2 /3\n", "", "'/3'");
    expect_refused(triangle + "f 1 2 4\n", "", "vertex 4"); // in range, but not defined
    EXPECT_NO_THROW(pt::parse_obj(triangle + "vt 0 0\nvn 0 0 1\nf 1/1/1 2//1 3/1\n", "", "ok"));
}

TEST(ObjLoader, UnreadableAndMissingMaterialLibrariesAreNamed) {
    const fs::path dir = scratch_dir();
    std::ofstream(dir / "folder.obj") << "mtllib lib.mtl\n" << triangle;
    fs::create_directories(dir / "lib.mtl"); // a directory where the library should be
    try {
        pt::load_obj(dir / "folder.obj");
        ADD_FAILURE() << "accepted a directory as material library";
    } catch (const pt::SceneError& e) {
        EXPECT_NE(std::string(e.what()).find("material library lib.mtl: it is a directory"),
                  std::string::npos)
            << e.what();
    }
    std::ofstream(dir / "missing.obj") << "mtllib nowhere.mtl\n" << triangle;
    try {
        pt::load_obj(dir / "missing.obj");
        ADD_FAILURE() << "accepted a missing material library";
    } catch (const pt::SceneError& e) {
        EXPECT_NE(std::string(e.what()).find("nowhere.mtl not found"), std::string::npos)
            << e.what();
    }
    std::ofstream(dir / "hot.mtl") << "newmtl hot\nKe 1 1 nan\n";
    std::ofstream(dir / "hot.obj") << "mtllib hot.mtl\nusemtl hot\n" << triangle;
    try {
        pt::load_obj(dir / "hot.obj");
        ADD_FAILURE() << "accepted Ke nan";
    } catch (const pt::SceneError& e) {
        EXPECT_NE(std::string(e.what()).find("'nan' is not a finite number"), std::string::npos)
            << e.what();
    }
}

// The material called `name`, or a failure.
const pt::Material& material_named(const pt::Scene& scene, const std::string& name) {
    const auto found = std::find_if(scene.materials.begin(), scene.materials.end(),
                                    [&](const pt::Material& m) { return m.name == name; });
    if (found == scene.materials.end()) {
        ADD_FAILURE() << "no material " << name;
        return scene.materials.front();
    }
    return *found;
}

// As Blender writes its Principled BSDF: Ks = "specular" (F0 = 0.08 Ks), Ns = ((1 - roughness)
// 30)^2, and with the PBR extension Pr and Pm, which take precedence.
const std::string blender_mtl = "newmtl plastic\nKd 0.8 0.6 0.4\nKs 0.5 0.5 0.5\nNs 96.078431\n"
                                "newmtl metal\nKd 1 0.78 0.34\nKs 0.5 0.5 0.5\nNs 900\n"
                                "Pr 0.25\nPm 1\n"
                                "newmtl mirror\nKs 1 1 1\nNs 900\nPr 0\n"
                                "newmtl bright\nKs 3 3 3\nNs 225\n"
                                "newmtl tinted\nKs 0.2 0.4 0.6\nNs 0\nPm 7\n"
                                "newmtl plain\nKd 0.5 0.5 0.5\n";

TEST(ObjLoader, MtlSpecularIsReadAsBlendersPrincipledBsdf) {
    const pt::Scene scene =
        pt::parse_obj("mtllib m.mtl\nusemtl plastic\n" + triangle, blender_mtl, "blender.obj");
    const pt::Material& plastic = material_named(scene, "plastic");
    EXPECT_EQ(plastic.albedo, glm::vec3(0.8f, 0.6f, 0.4f));
    EXPECT_FLOAT_EQ(plastic.specular, 0.04f); // not a 50 % mirror
    EXPECT_NEAR(plastic.roughness, 1.0 - std::sqrt(96.078431) / 30.0, 1e-6);
    EXPECT_NEAR(plastic.roughness, 0.673, 1e-3);
    EXPECT_EQ(plastic.metallic, 0.0f);
    EXPECT_FALSE(plastic.is_lambertian());

    const pt::Material& metal = material_named(scene, "metal");
    EXPECT_FLOAT_EQ(metal.roughness, 0.25f); // Pr, not Ns 900 (roughness 0)
    EXPECT_EQ(metal.metallic, 1.0f);
    EXPECT_EQ(material_named(scene, "mirror").roughness, 0.0f); // Pr 0 is a value, not "absent"
    EXPECT_FLOAT_EQ(material_named(scene, "mirror").specular, 0.08f);
    EXPECT_FLOAT_EQ(material_named(scene, "bright").specular, 0.08f); // Ks clamped to 1
    EXPECT_FLOAT_EQ(material_named(scene, "bright").roughness, 0.5f); // 1 - 15 / 30

    const pt::Material& tinted = material_named(scene, "tinted");
    EXPECT_FLOAT_EQ(tinted.specular, 0.08f * 0.4f); // the channels' mean
    EXPECT_EQ(tinted.roughness, 1.0f);              // Ns 0
    EXPECT_EQ(tinted.metallic, 1.0f);               // Pm clamped to 1

    const pt::Material& plain = material_named(scene, "plain"); // no Ks, Ns, Pr or Pm
    EXPECT_TRUE(plain.is_lambertian());
    EXPECT_EQ(plain.roughness, 1.0f);
    EXPECT_EQ(plain.specular, 0.0f);
}

TEST(ObjLoader, NegativeOrNonFiniteSpecularValuesAreRefused) {
    const std::string obj = "mtllib m.mtl\nusemtl a\n" + triangle;
    expect_refused(obj, "newmtl a\nKs 0.5 -0.5 0.5\n", "Ks '-0.5' is negative");
    expect_refused(obj, "newmtl a\nNs -1\n", "Ns '-1' is negative");
    expect_refused(obj, "newmtl a\nPr -0.25\n", "line 2: Pr '-0.25' is negative");
    expect_refused(obj, "newmtl a\nPm -1e-9\n", "Pm '-1e-9' is negative");
    expect_refused(obj, "newmtl a\nPr nan\n", "'nan' is not a finite number");
    expect_refused(obj, "newmtl a\nNs 1e99999\n", "'1e99999' is not a finite number");
    expect_refused(obj, "newmtl a\nPm inf\n", "'inf'");
    expect_refused(obj, "newmtl a\nPr\n", "Pr needs a number"); // would read as 0: a mirror
    EXPECT_NO_THROW(pt::parse_obj(obj, "newmtl a\nPr -0\nKs 0 0 0\n", "ok.obj"));
}

// The scene as restir-render loads it from `arguments` (after the program's name).
pt::Scene scene_from_command_line(const std::vector<std::string>& arguments) {
    std::vector<const char*> argv{"restir-render"};
    for (const std::string& argument : arguments)
        argv.push_back(argument.c_str());
    std::string help;
    const std::optional<pt::RenderOptions> options =
        pt::parse_render_options(static_cast<int>(argv.size()), argv.data(), help);
    EXPECT_TRUE(options.has_value());
    return pt::load_scene(*options);
}

TEST(ObjLoader, MaterialsDiffuseMakesEveryMaterialLambertianInItsBaseColour) {
    const fs::path dir = scratch_dir();
    std::ofstream(dir / "glossy.mtl") << blender_mtl;
    std::ofstream(dir / "glossy.obj") << "mtllib glossy.mtl\nusemtl metal\n" << triangle;
    const std::string path = (dir / "glossy.obj").string();
    const pt::Scene as_written = scene_from_command_line({"--scene", path});
    const pt::Scene diffuse = scene_from_command_line({"--scene", path, "--materials", "diffuse"});
    ASSERT_EQ(as_written.materials.size(), diffuse.materials.size());
    EXPECT_FALSE(material_named(as_written, "metal").is_lambertian()); // mtl is the default
    for (std::size_t m = 0; m < diffuse.materials.size(); ++m) {
        EXPECT_TRUE(diffuse.materials[m].is_lambertian()) << diffuse.materials[m].name;
        EXPECT_EQ(diffuse.materials[m].albedo, as_written.materials[m].albedo);
        EXPECT_EQ(diffuse.materials[m].emission, as_written.materials[m].emission);
    }
    const pt::Scene glossy_box =
        scene_from_command_line({"--scene", "cornell-glossy", "--materials", "DIFFUSE"});
    for (const pt::Material& m : glossy_box.materials)
        EXPECT_TRUE(m.is_lambertian()) << m.name;
}

TEST(Materials, BuiltInScenesAreLambertianExceptCornellGlossy) {
    for (const pt::Scene& scene : {pt::make_cornell_box(), pt::make_many_lights(50, 1u)})
        for (const pt::Material& m : scene.materials)
            EXPECT_TRUE(m.is_lambertian()) << scene.name << " " << m.name;
    const pt::Scene glossy = pt::make_glossy_cornell_box();
    const pt::Scene diffuse = pt::make_cornell_box();
    EXPECT_EQ(glossy.positions, diffuse.positions); // the same box
    EXPECT_EQ(glossy.indices, diffuse.indices);
    const auto of_triangle = [&](std::uint32_t t) -> const pt::Material& {
        return glossy.materials[glossy.triangle_materials[t]];
    };
    EXPECT_NEAR(of_triangle(0).roughness, 0.12f, 0.03f); // the floor, first in the box
    EXPECT_GT(of_triangle(0).specular, 0.0f);
    EXPECT_EQ(of_triangle(glossy.triangle_count() - 1).metallic, 1.0f); // the tall block, last
    // The walls, the ceiling and the light keep the diffuse box's materials.
    for (std::uint32_t t = 0; t < glossy.triangle_count(); ++t) {
        if (glossy.triangle_materials[t] == diffuse.triangle_materials[t]) {
            EXPECT_TRUE(of_triangle(t).is_lambertian()) << t;
        }
    }
    EXPECT_EQ(glossy.triangle_materials[2], diffuse.triangle_materials[2]); // the light
}

// ../shared/scenes/cornell-box.mtl: Ks 0.5, Ns 96.078431 on every diffuse material.
TEST(ObjLoader, SharedCornellBoxHasFourPercentSpecularAtRoughnessTwoThirds) {
    const fs::path obj = fs::path(RESTIR_SHARED_SCENES) / "cornell-box.obj";
    if (!fs::exists(obj))
        GTEST_SKIP() << obj << " is not there";
    const pt::Scene scene = pt::load_obj(obj);
    const pt::Material& khaki = material_named(scene, "Khaki");
    EXPECT_FLOAT_EQ(khaki.specular, 0.04f);
    EXPECT_NEAR(khaki.roughness, 0.673f, 1e-3f);
    EXPECT_TRUE(material_named(scene, "Light").is_lambertian()); // Ks 0
}

} // namespace
