// restir-compare's command line: one `name value` line per measure, the values those of
// error_metrics.hpp; bad input gives one line on stderr and exit status 2, never a crash.
#include "error_metrics.hpp"
#include "image_io.hpp"

#include "scratch_dir.hpp"

#include <gtest/gtest.h>

#include <sys/wait.h>

#include <algorithm>
#include <cstdlib>
#include <filesystem>
#include <fstream>
#include <limits>
#include <map>
#include <random>
#include <sstream>
#include <string>

namespace {

namespace fs = std::filesystem;

struct Outcome {
    int status = -1;
    std::string err;
    std::map<std::string, double> values;
    int lines = 0;
};

using pt_test::scratch_dir;

Outcome run(const std::string& arguments) {
    const fs::path dir = scratch_dir();
    const std::string command = std::string(RESTIR_COMPARE_EXECUTABLE) + " " + arguments + " > " +
                                (dir / "stdout").string() + " 2> " + (dir / "stderr").string();
    const int raw = std::system(command.c_str());
    Outcome r;
    r.status = WIFEXITED(raw) ? WEXITSTATUS(raw) : -1;
    std::ifstream err(dir / "stderr");
    std::stringstream text;
    text << err.rdbuf();
    r.err = text.str();
    std::ifstream out(dir / "stdout");
    std::string name;
    double value = 0.0;
    while (out >> name >> value) {
        r.values[name] = value;
        ++r.lines;
    }
    return r;
}

void expect_one_line_error(const std::string& arguments, const std::string& needle) {
    const Outcome r = run(arguments);
    EXPECT_EQ(r.status, 2) << arguments << "\n" << r.err;
    EXPECT_EQ(r.err.rfind("restir-compare: error: ", 0), 0u) << arguments << "\n" << r.err;
    EXPECT_EQ(std::count(r.err.begin(), r.err.end(), '\n'), 1) << arguments << "\n" << r.err;
    EXPECT_NE(r.err.find(needle), std::string::npos) << arguments << "\n" << r.err;
}

// A reference with a gradient and an image that adds noise to it, written as .exr.
struct Pair {
    pt::Image image{40, 30};
    pt::Image reference{40, 30};
    fs::path image_path = scratch_dir() / "image.exr";
    fs::path reference_path = scratch_dir() / "reference.exr";

    Pair() {
        std::mt19937 rng(1);
        std::normal_distribution<float> noise(0.0f, 0.1f);
        for (std::uint32_t y = 0; y < 30; ++y)
            for (std::uint32_t x = 0; x < 40; ++x) {
                reference.at(x, y) = glm::vec3(0.02f * static_cast<float>(x), 0.5f, 1.0f);
                image.at(x, y) = reference.at(x, y) + glm::vec3(noise(rng), noise(rng), 0.0f);
            }
        image.at(5, 5) += glm::vec3(40.0f);
        pt::write_image(image_path, image);
        pt::write_image(reference_path, reference);
    }
};

void expect_close(const Outcome& r, const std::string& name, double expected) {
    const auto found = r.values.find(name);
    ASSERT_NE(found, r.values.end()) << name;
    // Six significant digits printed.
    EXPECT_NEAR(found->second, expected, 1e-5 * std::abs(expected) + 1e-12) << name;
}

TEST(CompareCli, PrintsEveryMeasureAgainstAReference) {
    const Pair pair;
    const Outcome r =
        run(pair.image_path.string() + " --reference " + pair.reference_path.string());
    ASSERT_EQ(r.status, 0) << r.err;
    EXPECT_EQ(r.lines, 26);
    expect_close(r, "rmse", pt::rmse(pair.image, pair.reference));
    expect_close(r, "bias", pt::relative_mean_difference(pair.image, pair.reference));
    expect_close(r, "rel_mse", pt::relative_mse(pair.image, pair.reference));
    const pt::FireflyMeasure fireflies = pt::firefly_measure(pair.image, pair.reference);
    EXPECT_EQ(fireflies.count, 1u);
    expect_close(r, "fireflies", static_cast<double>(fireflies.count));
    expect_close(r, "p999", fireflies.p999);
    expect_close(r, "worst20_share", pt::worst_pixels_error_share(pair.image, pair.reference, 20));
    const pt::RowStructure rows = pt::row_structure_of_error(pair.image, pair.reference);
    expect_close(r, "row_ratio", rows.row_ratio);
    expect_close(r, "column_ratio", rows.column_ratio);
    const pt::ErrorAutocorrelation acf = pt::error_autocorrelation(pair.image, pair.reference);
    for (std::size_t lag = 1; lag <= 8; ++lag) {
        expect_close(r, "acf_x" + std::to_string(lag), acf.acf_x[lag]);
        expect_close(r, "acf_y" + std::to_string(lag), acf.acf_y[lag]);
    }
    const pt::RowStructure own = pt::row_structure(pair.image, {0, 0, 40, 30});
    expect_close(r, "image_row_ratio", own.row_ratio);
    expect_close(r, "image_column_ratio", own.column_ratio);
}

// With a region and a reference, region_bias is the relative mean difference of the region's
// pixels alone: (sum of the image's channels there) / (the reference's) - 1.
TEST(CompareCli, RegionBiasIsTheRegionsRelativeMeanDifference) {
    const Pair pair;
    const Outcome r = run(pair.image_path.string() + " --reference " +
                          pair.reference_path.string() + " --region 3,4,17,25");
    ASSERT_EQ(r.status, 0) << r.err;
    EXPECT_EQ(r.lines, 27);
    double image_sum = 0.0, reference_sum = 0.0;
    for (std::uint32_t y = 4; y < 25; ++y)
        for (std::uint32_t x = 3; x < 17; ++x) {
            const glm::vec3 a = pair.image.at(x, y), b = pair.reference.at(x, y);
            for (int c = 0; c < 3; ++c) {
                image_sum += static_cast<double>(a[c]);
                reference_sum += static_cast<double>(b[c]);
            }
        }
    expect_close(r, "region_bias", image_sum / reference_sum - 1.0);
    expect_close(r, "bias", pt::relative_mean_difference(pair.image, pair.reference));
}

TEST(CompareCli, WithoutAReferenceMeasuresTheImagesOwnRows) {
    const Pair pair;
    Outcome r = run(pair.reference_path.string() + " --region 2,3,30,20");
    ASSERT_EQ(r.status, 0) << r.err;
    EXPECT_EQ(r.lines, 2);
    const pt::RowStructure own = pt::row_structure(pair.reference, {2, 3, 30, 20});
    expect_close(r, "image_row_ratio", own.row_ratio);
    expect_close(r, "image_column_ratio", own.column_ratio);

    r = run(pair.image_path.string() + " --cornell-back-wall");
    ASSERT_EQ(r.status, 0) << r.err;
    const pt::RowStructure wall =
        pt::row_structure(pair.image, pt::cornell_back_wall_region(40, 30));
    expect_close(r, "image_row_ratio", wall.row_ratio);
}

TEST(CompareCli, BadInputIsOneLineAndStatusTwo) {
    const Pair pair;
    const fs::path dir = scratch_dir();
    const std::string image = pair.image_path.string();
    expect_one_line_error("", "image");
    expect_one_line_error((dir / "missing.exr").string(), "missing.exr");
    expect_one_line_error(image + " --reference " + (dir / "missing.exr").string(), "missing.exr");
    expect_one_line_error(image + " --no-such-flag", "--no-such-flag");
    expect_one_line_error(image + " --region 1,2,3", "region");
    expect_one_line_error(image + " --region 1,2,3,x", "region");
    expect_one_line_error(image + " --region 0,0,41,30", "region");
    expect_one_line_error(image + " --region 5,5,5,9", "region");
    expect_one_line_error(image + " --region 0,0,4,4 --cornell-back-wall", "excludes");

    pt::Image small(8, 6);
    pt::write_image(dir / "small.exr", small);
    expect_one_line_error(image + " --reference " + (dir / "small.exr").string(), "8x6");
    expect_one_line_error((dir / "small.exr").string() + " --cornell-back-wall", "too small");
    // Non-finite pixels, in the image or the reference (every measure would print nan).
    pt::Image poisoned(40, 30);
    poisoned.at(3, 4) = glm::vec3(std::numeric_limits<float>::quiet_NaN());
    pt::write_image(dir / "nan.pfm", poisoned);
    expect_one_line_error((dir / "nan.pfm").string(), "1 pixel(s) that are not finite");
    expect_one_line_error(image + " --reference " + (dir / "nan.pfm").string(), "not finite");
    std::ofstream(dir / "garbage.exr") << "not an image\n";
    expect_one_line_error((dir / "garbage.exr").string(), "garbage.exr");
    expect_one_line_error((dir / "image.png").string(), ".png");
}

} // namespace
