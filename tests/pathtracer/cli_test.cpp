// restir-render's command line: bad input gives one line on stderr and exit status 2, never a
// crash; good input writes the image and the CSV.
#include "image_io.hpp"
#include "render_options.hpp"
#include "renderer.hpp"

#include "scratch_dir.hpp"

#include <gtest/gtest.h>

#include <sys/wait.h>

#include <algorithm>
#include <cstdlib>
#include <filesystem>
#include <fstream>
#include <limits>
#include <optional>
#include <sstream>
#include <string>
#include <vector>

namespace {

namespace fs = std::filesystem;

struct Outcome {
    int status = -1;
    std::string err;
    std::string out;
};

using pt_test::scratch_dir;

std::string slurp(const fs::path& path) {
    std::ifstream in(path);
    std::stringstream text;
    text << in.rdbuf();
    return text.str();
}

Outcome run(const std::string& arguments) {
    const fs::path dir = scratch_dir();
    const std::string command = std::string(RESTIR_RENDER_EXECUTABLE) + " " + arguments + " > " +
                                (dir / "stdout").string() + " 2> " + (dir / "stderr").string();
    const int raw = std::system(command.c_str());
    Outcome r;
    r.status = WIFEXITED(raw) ? WEXITSTATUS(raw) : -1;
    r.err = slurp(dir / "stderr");
    r.out = slurp(dir / "stdout");
    return r;
}

// A fast render of the built-in box, plus `extra`.
std::string small(const std::string& extra) {
    return "--width 8 --height 8 --frames 1 --vpls 200 --out " +
           (scratch_dir() / "small.png").string() + " " + extra;
}

void expect_one_line_error(const std::string& arguments, const std::string& needle) {
    const Outcome r = run(arguments);
    EXPECT_EQ(r.status, 2) << arguments << "\n" << r.err;
    EXPECT_EQ(r.err.rfind("restir-render: error: ", 0), 0u) << arguments << "\n" << r.err;
    EXPECT_EQ(std::count(r.err.begin(), r.err.end(), '\n'), 1) << arguments << "\n" << r.err;
    EXPECT_NE(r.err.find(needle), std::string::npos) << arguments << "\n" << r.err;
}

TEST(Cli, HelpDocumentsEveryFlagWithItsDefault) {
    const Outcome r = run("--help");
    EXPECT_EQ(r.status, 0);
    for (const char* flag : {"--scene",
                             "--lights",
                             "--method",
                             "--gi",
                             "--spp",
                             "--frames",
                             "--width",
                             "--height",
                             "--look-from",
                             "--look-at",
                             "--fov",
                             "--seed",
                             "--threads",
                             "--out",
                             "--reference",
                             "--csv",
                             "--candidates",
                             "--source",
                             "--grid-cells",
                             "--neighbours",
                             "--radius",
                             "--spatial-passes",
                             "--history-cap",
                             "--bias-correction",
                             "--vpls",
                             "--attenuation-radius",
                             "--vpl-reshoot",
                             "--vpl-seed",
                             "--permutation-sampling",
                             "--boiling-filter",
                             "--scene-seed",
                             "--materials",
                             "--max-memory",
                             "--env",
                             "--env-scale",
                             "--env-rotate",
                             "--indirect-only",
                             "--out-frame",
                             "--gi-min-roughness",
                             "--pt-min-roughness",
                             "--pt-min-distance",
                             "--partition-radius",
                             "--vpl-path-part",
                             "vpl-unbiased"})
        EXPECT_NE(r.out.find(flag), std::string::npos) << flag;
    EXPECT_NE(r.out.find("restir"), std::string::npos);
    EXPECT_NE(r.out.find("cornell-glossy"), std::string::npos);
    EXPECT_NE(r.out.find("sun-sky"), std::string::npos);
}

TEST(Cli, BadInputIsOneLineAndStatusTwo) {
    const fs::path dir = scratch_dir();
    expect_one_line_error(small("--no-such-flag"), "--no-such-flag");
    expect_one_line_error(small("--method fastest"), "fastest");
    expect_one_line_error(small("--gi sometimes"), "sometimes");
    expect_one_line_error("--width 0 --out x.png", "width");
    expect_one_line_error(small("--frames -3"), "frames");
    expect_one_line_error(small("--source grid --grid-cells 0"), "grid-cells");
    expect_one_line_error(small("--source grid --grid-cells 257"), "grid-cells");
    expect_one_line_error(small("--bsdf-max-roughness 1.5"), "bsdf-max-roughness");
    expect_one_line_error(small("--bsdf-light-candidates -1"), "bsdf-light-candidates");
    expect_one_line_error(small("--spatial-min-roughness -0.1"), "spatial-min-roughness");
    expect_one_line_error(small("--permutation-min-roughness nan"), "permutation-min-roughness");
    expect_one_line_error(small("--look-from 1,2"), "look-from");
    expect_one_line_error(small("--method restir --spp 4"), "--frames");
    expect_one_line_error(small("--method ris --gi restir-gi"), "--method restir");
    expect_one_line_error(small("--gi vpl --indirect-only"), "--indirect-only");
    expect_one_line_error(small("--gi restir-gi --gi-min-roughness 2"), "gi-min-roughness");
    expect_one_line_error(small("--method uniform --gi restir-pt"), "--method restir");
    expect_one_line_error(small("--gi restir-pt --pt-min-roughness 2"), "pt-min-roughness");
    expect_one_line_error(small("--gi restir-pt --pt-min-distance -1"), "pt-min-distance");
    expect_one_line_error(small("--method ris --gi vpl-unbiased"), "--method restir");
    expect_one_line_error(small("--gi vpl-unbiased --indirect-only"), "--indirect-only");
    expect_one_line_error(small("--gi vpl-unbiased --partition-radius 0"), "partition-radius");
    expect_one_line_error(small("--gi vpl-unbiased --partition-radius inf"), "partition-radius");
    expect_one_line_error(small("--gi vpl-unbiased --vpl-path-part some"), "some");
    expect_one_line_error(small("--scene " + (dir / "missing.obj").string()), "missing.obj");

    std::ofstream(dir / "broken.obj") << "v 0 0 0\nf 1 2 3\n";
    expect_one_line_error(small("--scene " + (dir / "broken.obj").string()), "broken.obj");
    std::ofstream(dir / "dark.obj") << "v 0 0 0\nv 1 0 0\nv 0 1 0\nf 1 2 3\n";
    expect_one_line_error(small("--scene " + (dir / "dark.obj").string()), "no emitters");

    expect_one_line_error(small("--reference " + (dir / "missing.exr").string()), "missing.exr");
    expect_one_line_error(
        "--width 8 --height 8 --frames 1 --vpls 200 --out " + (dir / "image.bmp").string(), ".bmp");
}

// Inputs that used to crash the renderer inside Embree (rays from a degenerate camera) or that
// were silently replaced or accepted (NaN in float flags): now one-line errors, status 2.
TEST(Cli, DegenerateCamerasAndNonFiniteNumbersAreOneLineErrors) {
    expect_one_line_error(small("--look-from 1,1,1 --look-at 1,1,1"), "same point");
    expect_one_line_error(small("--look-from 1e19,0,0"), "1e15");
    for (const char* flag :
         {"--fov", "--radius", "--attenuation-radius", "--exposure", "--boiling-filter"})
        for (const char* value : {"nan", "inf", "-inf"})
            expect_one_line_error(small(std::string(flag) + " " + value), flag);
    expect_one_line_error(small("--look-from nan,0,0"), "--look-from");
    expect_one_line_error(small("--look-at 0,inf,0"), "--look-at");
    // An OBJ with a vertex beyond the range Embree accepts (its automatic framing used to put
    // the camera out there and crash).
    const fs::path obj = scratch_dir() / "huge.obj";
    std::ofstream(obj) << "v 0 0 0\nv 1 0 0\nv 0 1 0\nv 1e19 0 0\nf 1 4 3\nf 1 2 3\n";
    expect_one_line_error(small("--scene " + obj.string()), "1e15");
}

// A render that would not fit the memory limit is refused before any work, naming its
// estimate (16384 x 16384 used to be accepted and killed by the kernel at about 70 GB).
TEST(Cli, RendersBeyondTheMemoryLimitAreRefused) {
    expect_one_line_error("--width 4096 --height 4096 --max-memory 1000 --out x.png",
                          "needs about");
    expect_one_line_error(small("--vpls 100000000 --max-memory 1000"), "VPLs");
    EXPECT_EQ(run(small("--max-memory 1000")).status, 0);
    pt::RenderSettings huge;
    huge.width = 16384;
    huge.height = 16384;
    EXPECT_GT(pt::estimated_memory_bytes(huge, false), std::uint64_t{64} << 30u);
    // vpl-unbiased keeps ReSTIR GI's three 72-byte reservoir buffers only when it reuses paths.
    pt::RenderSettings unbiased;
    unbiased.gi = pt::GlobalIllumination::vpl_unbiased;
    pt::RenderSettings reused = unbiased;
    reused.vpl_path_part = pt::VplPathPart::reuse;
    const std::uint64_t pixels = std::uint64_t{unbiased.width} * unbiased.height;
    EXPECT_EQ(pt::estimated_memory_bytes(reused, false) -
                  pt::estimated_memory_bytes(unbiased, false),
              216u * pixels);
}

// An emitter whose power overflows a float used to be reported as "all weights are zero".
TEST(Cli, TooBrightEmitterIsNamed) {
    const fs::path dir = scratch_dir();
    std::ofstream(dir / "hot.mtl") << "newmtl hot\nKd 0.5 0.5 0.5\nKe 3e38 3e38 3e38\n";
    std::ofstream(dir / "hot.obj") << "mtllib hot.mtl\nv 0 0 0\nv 1 0 0\nv 0 1 0\nv 0 0 1\n"
                                      "usemtl hot\nf 1 2 3\nf 1 3 4\n";
    expect_one_line_error(small("--scene " + (dir / "hot.obj").string()), "too bright");
    // (it names the emitter and the cause)
}

// A reference with NaN or infinite pixels used to give an RMSE of nan every frame.
TEST(Cli, NonFiniteReferenceIsAnError) {
    const fs::path reference = scratch_dir() / "nan.pfm";
    pt::Image image(8, 8);
    image.at(3, 4) = glm::vec3(std::numeric_limits<float>::quiet_NaN(), 0.0f, 0.0f);
    image.at(5, 1) = glm::vec3(std::numeric_limits<float>::infinity());
    pt::write_image(reference, image);
    expect_one_line_error(small("--reference " + reference.string()), "2 pixel(s)");
}

// Hostile references (tinyexr asserted on the first; a larger image is not even allocated).
TEST(Cli, HostileReferencesAreOneLineErrors) {
    const fs::path dir = scratch_dir();
    {
        std::ofstream out(dir / "type.exr", std::ios::binary);
        const char bytes[] = "\x76\x2f\x31\x01\x02\x00\x00\x00type\0string\0\x01\0\0\0x";
        out.write(bytes, sizeof bytes); // 26 bytes with the final NUL
    }
    expect_one_line_error(small("--reference " + (dir / "type.exr").string()), "type.exr");
    pt::write_image(dir / "large.pfm", pt::Image(64, 64));
    expect_one_line_error(small("--reference " + (dir / "large.pfm").string()), "pixels allowed");
    expect_one_line_error(small("--threads 5000"), "--threads");
}

// Looking straight down the up axis used to give the camera no right vector (NaN rays).
TEST(Cli, LookingAlongTheUpAxisRenders) {
    const Outcome r = run(small("--look-from 278,900,-279 --look-at 278,0,-279"));
    EXPECT_EQ(r.status, 0) << r.err;
    EXPECT_NE(r.out.find("wrote"), std::string::npos) << r.out;
}

// An output the renderer cannot write is reported before the render, and no other output is
// written.
TEST(Cli, UnknownOutputFormatFailsBeforeTheRender) {
    const fs::path dir = scratch_dir();
    fs::remove(dir / "first.png");
    expect_one_line_error("--width 8 --height 8 --frames 1 --vpls 200 --out " +
                              (dir / "first.png").string() + " --out " +
                              (dir / "second.bmp").string(),
                          ".bmp");
    EXPECT_FALSE(fs::exists(dir / "first.png"));
}

TEST(Cli, WritesTheImageTheCsvAndMeasuresAgainstAReference) {
    const fs::path dir = scratch_dir();
    const fs::path reference = dir / "reference.exr";
    fs::remove(reference);
    Outcome r =
        run("--width 12 --height 12 --frames 1 --spp 16 --method reference --vpls 200 --out " +
            reference.string());
    ASSERT_EQ(r.status, 0) << r.err;
    ASSERT_TRUE(fs::exists(reference));

    const fs::path csv = dir / "frames.csv";
    r = run("--width 12 --height 12 --frames 3 --vpls 200 --out " + (dir / "restir.png").string() +
            " --reference " + reference.string() + " --csv " + csv.string());
    ASSERT_EQ(r.status, 0) << r.err;
    EXPECT_TRUE(fs::exists(dir / "restir.png"));
    std::istringstream lines(slurp(csv));
    std::string header, row;
    std::getline(lines, header);
    EXPECT_EQ(header.rfind("frame,rmse,", 0), 0u) << header;
    EXPECT_NE(header.find("frame_ms"), std::string::npos);
    int rows = 0;
    while (std::getline(lines, row)) {
        ++rows;
        EXPECT_EQ(row.rfind(std::to_string(rows) + ",", 0), 0u) << row;
        EXPECT_NE(row.find(",0."), std::string::npos) << "an RMSE in " << row;
    }
    EXPECT_EQ(rows, 3);

    // A reference of another size is refused.
    r = run("--width 10 --height 12 --frames 1 --vpls 200 --out " + (dir / "x.png").string() +
            " --reference " + reference.string());
    EXPECT_EQ(r.status, 2);
    EXPECT_NE(r.err.find("12x12"), std::string::npos) << r.err;
}

std::vector<std::string> split(const std::string& line) {
    std::vector<std::string> fields;
    std::istringstream text(line);
    std::string field;
    while (std::getline(text, field, ','))
        fields.push_back(field);
    if (!line.empty() && line.back() == ',')
        fields.emplace_back();
    return fields;
}

TEST(Cli, CsvHasTheErrorMeasuresAndItsDirectoryIsMade) {
    const fs::path dir = scratch_dir();
    const fs::path reference = dir / "reference-12.exr";
    Outcome r = run("--width 12 --height 12 --frames 1 --spp 16 --method reference --vpls 200 "
                    "--out " +
                    reference.string());
    ASSERT_EQ(r.status, 0) << r.err;
    const fs::path csv_dir = dir / "new-directory";
    fs::remove_all(csv_dir);
    const fs::path csv = csv_dir / "deeper" / "frames.csv";
    r = run("--width 12 --height 12 --frames 2 --vpls 200 --out " + (dir / "x.png").string() +
            " --reference " + reference.string() + " --csv " + csv.string());
    ASSERT_EQ(r.status, 0) << r.err;
    std::istringstream lines(slurp(csv));
    std::string line;
    std::getline(lines, line);
    const std::vector<std::string> header = split(line);
    std::string expected =
        "frame,rmse,frame_rmse,frame_ms,elapsed_ms,primary_ms,photons_ms,"
        "candidates_ms,temporal_ms,spatial_ms,shading_ms,tiles_ms,indirect_ms,bias,"
        "frame_bias,rel_mse,fireflies,p999,row_ratio,column_ratio";
    for (const char* axis : {"acf_x", "acf_y"})
        for (int lag = 1; lag <= 8; ++lag)
            expected.append(",").append(axis).append(std::to_string(lag));
    expected += ",mse_glossy,frame_mse_glossy,flicker,flicker_glossy";
    EXPECT_EQ(line, expected);
    int rows = 0;
    while (std::getline(lines, line)) {
        ++rows;
        const std::vector<std::string> fields = split(line);
        ASSERT_EQ(fields.size(), header.size()) << line;
        for (std::size_t i = 0; i < fields.size(); ++i) {
            // The flicker compares a frame with the one before: none in the first frame.
            const bool first_flicker = rows == 1 && header[i].starts_with("flicker");
            char* end = nullptr;
            std::strtod(fields[i].c_str(), &end);
            EXPECT_TRUE(first_flicker ? fields[i].empty() : !fields[i].empty() && *end == '\0')
                << header[i] << " = " << fields[i];
        }
    }
    EXPECT_EQ(rows, 2);

    // Without a reference the measures are empty, the columns still there.
    r = run(small("--csv " + csv.string()));
    ASSERT_EQ(r.status, 0) << r.err;
    std::istringstream again(slurp(csv));
    std::getline(again, line);
    std::getline(again, line);
    const std::vector<std::string> fields = split(line);
    ASSERT_EQ(fields.size(), header.size()) << line;
    EXPECT_EQ(fields.back(), "");
    EXPECT_EQ(fields[1], "");
}

// The glossy box renders with every method, its reference on all three indirect modes.
TEST(Cli, RendersTheGlossyCornellBox) {
    for (const char* method : {"reference", "restir"})
        for (const char* gi : {"none", "vpl", "path"}) {
            const Outcome r = run(
                small(std::string("--scene cornell-glossy --method ") + method + " --gi " + gi));
            EXPECT_EQ(r.status, 0) << method << " " << gi << "\n" << r.err;
            EXPECT_NE(r.out.find("scene cornell-glossy: 32 triangles, 2 emitters"),
                      std::string::npos)
                << r.out;
        }
    expect_one_line_error(small("--scene cornell-glossy --materials shiny"), "--materials");
    expect_one_line_error(small("--packed-history true --light-points solid-angle"),
                          "--packed-history");
}

TEST(Cli, RendersTheSharedCornellBoxObj) {
    const fs::path obj = fs::path(RESTIR_SHARED_SCENES) / "cornell-box.obj";
    if (!fs::exists(obj))
        GTEST_SKIP() << obj << " is not there";
    for (const char* materials : {"mtl", "diffuse"}) {
        const Outcome r = run("--scene " + obj.string() + " --materials " + materials +
                              " --width 16 --height 16 --frames 1 --vpls 500 "
                              "--out " +
                              (scratch_dir() / "obj.png").string());
        EXPECT_EQ(r.status, 0) << r.err;
        EXPECT_NE(r.out.find("2 emitters"), std::string::npos) << r.out;
    }
}

// A PFM file as given: its header text, then `floats` (little-endian, as the header's negative
// scale says), possibly fewer than the header promises.
void write_raw_pfm(const fs::path& path, const std::string& header,
                   const std::vector<float>& floats) {
    std::ofstream out(path, std::ios::binary);
    out << header;
    out.write(reinterpret_cast<const char*>(floats.data()),
              static_cast<std::streamsize>(floats.size() * sizeof(float)));
}

// Every environment map the renderer cannot use is one line on stderr and status 2, before
// the render: bad texels, a black map, sizes the reader refuses from the header (16384 x 8192
// is more than its 2^25 pixels), a file cut short, an empty one; and the flags' values.
TEST(Cli, BadEnvironmentMapsAreOneLineErrors) {
    const fs::path dir = scratch_dir();
    const float nan = std::numeric_limits<float>::quiet_NaN();
    const auto env = [&dir](const char* file) {
        return small("--method reference --gi path --env " + (dir / file).string());
    };
    write_raw_pfm(dir / "nan.pfm", "PF\n2 1\n-1.0\n", {1, 1, 1, 1, nan, 1});
    expect_one_line_error(env("nan.pfm"), "texel (1, 0) has a negative, NaN or infinite channel");
    write_raw_pfm(dir / "negative.pfm", "PF\n2 1\n-1.0\n", {1, -1, 1, 1, 1, 1});
    expect_one_line_error(env("negative.pfm"), "texel (0, 0)");
    write_raw_pfm(dir / "zeros.pfm", "PF\n4 2\n-1.0\n", std::vector<float>(24, 0.0f));
    expect_one_line_error(env("zeros.pfm"), "zero everywhere");
    write_raw_pfm(dir / "huge.pfm", "PF\n16384 8192\n-1.0\n", {1, 1, 1});
    expect_one_line_error(env("huge.pfm"), "16384x8192");
    write_raw_pfm(dir / "truncated.pfm", "PF\n4 2\n-1.0\n", std::vector<float>(23, 1.0f));
    expect_one_line_error(env("truncated.pfm"), "cut short");
    write_raw_pfm(dir / "zero-size.pfm", "PF\n0 0\n-1.0\n", {});
    expect_one_line_error(env("zero-size.pfm"), "bad width '0'");
    write_raw_pfm(dir / "empty.pfm", "", {});
    expect_one_line_error(env("empty.pfm"), "empty.pfm");
    expect_one_line_error(env("missing.exr"), "no such file");
    expect_one_line_error(env("sky.hdr"), "'.hdr'");
    for (const char* value : {"0", "-1", "nan", "inf"})
        expect_one_line_error(small(std::string("--scene sun-sky --env-scale ") + value),
                              "--env-scale");
    expect_one_line_error(small("--scene sun-sky --env-rotate nan"), "--env-rotate");
    expect_one_line_error(small("--scene sun-sky --env-scale 1e30"), "1e30");
    for (const char* value : {"-0.1", "1", "nan"})
        expect_one_line_error(small(std::string("--scene sun-sky --env-share ") + value),
                              "--env-share");
    expect_one_line_error(small("--scene sun-sky --env-sampling cosine"), "--env-sampling");
    expect_one_line_error(small("--scene sun-sky --env-sampling bsdf --bsdf-candidates 0"),
                          "--bsdf-candidates");
}

// A 1 x 1 map is a constant sky: the box renders under it, and the pixels that see out of the
// box's open front show it times --env-scale, in the reference and in ReSTIR.
TEST(Cli, OneTexelEnvironmentIsAConstantSky) {
    const fs::path dir = scratch_dir();
    write_raw_pfm(dir / "one.pfm", "PF\n1 1\n-1.0\n", {0.25f, 0.5f, 0.75f});
    for (const char* method : {"reference", "restir"}) {
        const fs::path out = dir / (std::string(method) + ".pfm");
        const Outcome r = run("--width 24 --height 24 --frames 1 --vpls 200 --gi path --method " +
                              std::string(method) + " --env " + (dir / "one.pfm").string() +
                              " --env-scale 2 --env-rotate 720 --out " + out.string());
        ASSERT_EQ(r.status, 0) << r.err;
        const pt::Image image = pt::read_image(out);
        const auto sky =
            std::count(image.pixels.begin(), image.pixels.end(), glm::vec3(0.5f, 1.0f, 1.5f));
        EXPECT_GT(sky, 0) << method;
        EXPECT_LT(sky, 24 * 24 / 4) << method;
    }
}

// The sun-sky scene renders with every method; its summary names the environment.
TEST(Cli, RendersTheSunSkyScene) {
    for (const char* method : {"reference", "restir", "ris", "uniform"}) {
        const Outcome r = run(small(std::string("--scene sun-sky --gi path --method ") + method));
        EXPECT_EQ(r.status, 0) << method << "\n" << r.err;
        EXPECT_NE(r.out.find("scene sun-sky:"), std::string::npos) << r.out;
        EXPECT_NE(r.out.find("environment sun-sky 2048x1024"), std::string::npos) << r.out;
    }
}

// ReSTIR GI and PT, and unbiased VPL GI, render in every scene, under a turning camera too,
// report their phase and write their last frame alone.
TEST(Cli, RendersRestirGiAndPt) {
    const fs::path frame = scratch_dir() / "gi-frame.pfm";
    for (const std::string gi :
         {"restir-gi", "restir-pt", "vpl-unbiased --vpl-path-part reuse", "vpl-unbiased"})
        for (const char* scene : {"cornell", "cornell-glossy", "sun-sky"}) {
            fs::remove(frame);
            const Outcome r =
                run("--width 12 --height 8 --frames 3 --gi " + gi +
                    " --camera-motion orbit --scene " + scene + " --out " +
                    (scratch_dir() / "gi.png").string() + " --out-frame " + frame.string());
            EXPECT_EQ(r.status, 0) << gi << " " << scene << "\n" << r.err;
            if (gi != "vpl-unbiased") { // its independent path samples are in its shading
                EXPECT_NE(r.out.find(", indirect "), std::string::npos) << r.out;
            }
            EXPECT_TRUE(fs::exists(frame)) << gi << " " << scene;
        }
}

// --max-depth 1 has no indirect light: vpl-unbiased shoots no VPL bounce then, and says nothing
// of photons that left no VPL.
TEST(Cli, UnbiasedVplsFollowTheDepthLimit) {
    const Outcome r = run(small("--gi vpl-unbiased --max-depth 1"));
    EXPECT_EQ(r.status, 0) << r.err;
    EXPECT_NE(r.out.find(", 0 VPLs"), std::string::npos) << r.out;
    EXPECT_EQ(r.err.find("warning"), std::string::npos) << r.err;
    const Outcome deeper = run(small("--gi vpl-unbiased --max-depth 3"));
    EXPECT_EQ(deeper.status, 0) << deeper.err;
    EXPECT_EQ(deeper.out.find(", 0 VPLs"), std::string::npos) << deeper.out;
}

// A scene without Lambertian surfaces (a glossy floor under a glossy lamp) holds no VPL under
// vpl-unbiased: path samples carry its indirect light, as it says.
TEST(Cli, UnbiasedVplsNeedLambertianSurfaces) {
    const fs::path dir = scratch_dir();
    std::ofstream(dir / "glossy.mtl") << "newmtl floor\nKd 0.8 0.8 0.8\nKs 0.5 0.5 0.5\nNs 100\n"
                                      << "newmtl lamp\nKd 0.8 0.8 0.8\nKs 0.5 0.5 0.5\nNs 100\n"
                                      << "Ke 5 5 5\n";
    std::ofstream(dir / "glossy.obj")
        << "mtllib glossy.mtl\nv -1 0 -1\nv 1 0 -1\nv 1 0 1\nv -1 0 1\n"
        << "v -0.2 1 -0.2\nv 0.2 1 -0.2\nv 0.2 1 0.2\nv -0.2 1 0.2\n"
        << "usemtl floor\nf 1 4 3\nf 1 3 2\nusemtl lamp\nf 5 6 7\nf 5 7 8\n";
    const Outcome r =
        run("--width 12 --height 8 --frames 1 --gi vpl-unbiased --vpls 1000 --scene " +
            (dir / "glossy.obj").string() + " --out " + (dir / "glossy.png").string());
    EXPECT_EQ(r.status, 0) << r.err;
    EXPECT_NE(r.out.find(", 0 VPLs"), std::string::npos) << r.out;
    EXPECT_NE(r.err.find("path samples carry all the indirect light"), std::string::npos) << r.err;
}

// The settings restir-render parses from `arguments` (after the program's name).
pt::RenderSettings settings_from_command_line(const std::vector<const char*>& arguments) {
    std::vector<const char*> argv{"restir-render"};
    argv.insert(argv.end(), arguments.begin(), arguments.end());
    std::string help;
    const std::optional<pt::RenderOptions> options =
        pt::parse_render_options(static_cast<int>(argv.size()), argv.data(), help);
    EXPECT_TRUE(options.has_value()) << help;
    return options ? options->settings : pt::RenderSettings{};
}

// The reuse settings restir-render parses from `arguments`.
restir::DiFrameParams frame_from_command_line(const std::vector<const char*>& arguments) {
    return settings_from_command_line(arguments).di_frame;
}

// --preset sets the library's preset (the default: unbiased), and a reuse flag beside it, before
// or after it on the line, changes that one setting.
TEST(Cli, PresetsAreTheLibrarysAndFlagsChangeThem) {
    const restir::DiFrameParams defaults = frame_from_command_line({});
    const restir::DiFrameParams unbiased = frame_from_command_line({"--preset", "unbiased"});
    for (const restir::DiFrameParams& p : {defaults, unbiased}) {
        EXPECT_EQ(p.spatial.neighbour_count, 5u);
        EXPECT_EQ(p.temporal.history_cap_multiplier, 4u);
        EXPECT_TRUE(p.temporal.permutation_sampling);
        EXPECT_EQ(p.visibility, restir::ReuseVisibility::traced);
        EXPECT_EQ(p.spatial_bias_correction, restir::BiasCorrection::pairwise);
        EXPECT_EQ(p.spatial.radius, 0.0f); // by the image height
    }
    const restir::DiFrameParams balanced = frame_from_command_line({"--preset", "balanced"});
    EXPECT_EQ(balanced.spatial.neighbour_count, 3u);
    EXPECT_EQ(balanced.temporal.history_cap_multiplier, 20u);
    EXPECT_FALSE(balanced.temporal.permutation_sampling);
    EXPECT_EQ(balanced.visibility, restir::ReuseVisibility::traced);
    EXPECT_EQ(balanced.spatial_bias_correction, restir::BiasCorrection::defensive_pairwise);
    EXPECT_EQ(balanced.temporal_bias_correction, restir::BiasCorrection::defensive_pairwise);
    const restir::DiFrameParams fast = frame_from_command_line({"--preset", "fast"});
    EXPECT_EQ(fast.visibility, restir::ReuseVisibility::assumed);
    EXPECT_EQ(fast.spatial.neighbour_count, 3u);
    for (const auto& arguments : std::vector<std::vector<const char*>>{
             {"--preset", "fast", "--neighbours", "4", "--mis-rays", "true"},
             {"--neighbours", "4", "--mis-rays", "true", "--preset", "fast"},
             {"--preset", "fast", "--neighbours", "4", "--mis-rays", "true", "--bias-correction",
              "defensive-pairwise"}}) {
        const restir::DiFrameParams changed = frame_from_command_line(arguments);
        EXPECT_EQ(changed.spatial.neighbour_count, 4u);
        EXPECT_EQ(changed.visibility, restir::ReuseVisibility::traced);
        EXPECT_EQ(changed.temporal.history_cap_multiplier, 20u);
    }
    expect_one_line_error(small("--preset fastest"), "--preset");
}

// The spatial radius a frame runs with: --radius where given, else two thirds of the preset's
// per 1080 rows (at least 3 px), whichever order --preset and --radius come in.
TEST(Cli, TheRadiusIsThePresetsScaledToTheImageUnlessGiven) {
    const auto radius = [](const std::vector<const char*>& arguments) {
        return pt::frame_params(settings_from_command_line(arguments)).spatial.radius;
    };
    EXPECT_FLOAT_EQ(radius({"--height", "1080"}), 20.0f);
    EXPECT_FLOAT_EQ(radius({"--height", "540", "--preset", "unbiased"}), 10.0f);
    EXPECT_FLOAT_EQ(radius({"--height", "1080", "--preset", "balanced"}), 10.0f);
    EXPECT_FLOAT_EQ(radius({"--height", "720", "--preset", "fast"}), 10.0f * 720.0f / 1080.0f);
    EXPECT_FLOAT_EQ(radius({"--height", "180", "--preset", "balanced"}), 3.0f);
    EXPECT_FLOAT_EQ(radius({"--preset", "balanced", "--radius", "7"}), 7.0f);
    EXPECT_FLOAT_EQ(radius({"--radius", "7", "--preset", "balanced"}), 7.0f);
}

} // namespace
