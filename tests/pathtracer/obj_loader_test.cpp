// OBJ and MTL files are untrusted input: numbers tinyobjloader would read as 0, indices that
// would overflow, unreadable material libraries: one-line SceneErrors, never a silent misreading.
#include "scene.hpp"

#include "scratch_dir.hpp"

#include <gtest/gtest.h>

#include <algorithm>
#include <filesystem>
#include <fstream>
#include <string>

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

} // namespace
