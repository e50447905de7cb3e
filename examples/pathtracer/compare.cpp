// restir-compare: the example renderer's error measures of an image against a reference, and
// the row structure of an image on its own (how streaks in a reference image are measured).
// Prints one `name value` line per measure; `restir-compare --help` lists the flags.
#include "command_line.hpp"
#include "error_metrics.hpp"
#include "image_io.hpp"

#include <CLI/CLI.hpp>

#include <algorithm>
#include <cstdint>
#include <cstdio>
#include <cstdlib>
#include <exception>
#include <iostream>
#include <string>
#include <vector>

namespace {

[[noreturn]] void fail(const std::string& message) { pt::fail("restir-compare", message); }

void print(const std::string& name, double value) { std::printf("%s %.6g\n", name.c_str(), value); }

void print_errors(const pt::Image& image, const pt::Image& reference) {
    print("rmse", pt::rmse(image, reference));
    print("bias", pt::relative_mean_difference(image, reference));
    print("rel_mse", pt::relative_mse(image, reference));
    const pt::FireflyMeasure fireflies = pt::firefly_measure(image, reference);
    std::printf("fireflies %llu\n", static_cast<unsigned long long>(fireflies.count));
    print("p999", fireflies.p999);
    print("worst20_share", pt::worst_pixels_error_share(image, reference, 20));
    const pt::RowStructure rows = pt::row_structure_of_error(image, reference);
    print("row_ratio", rows.row_ratio);
    print("column_ratio", rows.column_ratio);
    const pt::ErrorAutocorrelation acf = pt::error_autocorrelation(image, reference);
    for (std::size_t lag = 1; lag < acf.acf_x.size(); ++lag)
        print("acf_x" + std::to_string(lag), acf.acf_x[lag]);
    for (std::size_t lag = 1; lag < acf.acf_y.size(); ++lag)
        print("acf_y" + std::to_string(lag), acf.acf_y[lag]);
}

// The pixels of `image` in `area` (clipped to the image) as an image of their own.
pt::Image crop(const pt::Image& image, const pt::Region& area) {
    const std::uint32_t x1 = std::min(area.x1, image.width), y1 = std::min(area.y1, image.height);
    const std::uint32_t x0 = std::min(area.x0, x1), y0 = std::min(area.y0, y1);
    pt::Image out(x1 - x0, y1 - y0);
    for (std::uint32_t y = y0; y < y1; ++y)
        for (std::uint32_t x = x0; x < x1; ++x)
            out.at(x - x0, y - y0) = image.at(x, y);
    return out;
}

} // namespace

int main(int argc, char** argv) {
    std::string image_path;
    std::string reference_path;
    std::vector<std::uint32_t> region_values;
    bool back_wall = false;

    CLI::App app{"restir-compare: error measures of IMAGE against a reference (rmse, bias, "
                 "rel_mse, fireflies, p999, worst20_share (the 20 worst pixels' share of the "
                 "squared error), row/column_ratio and acf_x/acf_y 1-8 of the error), "
                 "and image_row_ratio/image_column_ratio, the row structure of IMAGE itself in "
                 "a region, and with a region and a reference region_bias, the relative mean "
                 "difference there; one `name value` line each"};
    app.add_option("image", image_path, "The image to measure (.exr or .pfm)")->required();
    app.add_option("--reference", reference_path,
                   "Reference image (.exr or .pfm) of the same size; without it only the "
                   "image's own row structure is printed");
    CLI::Option* region =
        app.add_option("--region", region_values,
                       "Pixels x0,y0,x1,y1 (half-open, y = 0 the top row) of the image's own row "
                       "structure and of region_bias (default: the whole image)")
            ->delimiter(',')
            ->expected(4);
    CLI::Option* wall = app.add_flag("--cornell-back-wall", back_wall,
                                     "Use the back wall of the built-in Cornell box as region");
    region->excludes(wall);

    pt::parse_command_line(app, argc, argv, "restir-compare");
    if (!region_values.empty() && region_values.size() != 4)
        fail("--region needs four numbers x0,y0,x1,y1, got " +
             std::to_string(region_values.size()));

    try {
        // Every measure of an image with NaN or infinite pixels would be NaN.
        const auto read_finite = [](const std::string& path) {
            pt::Image read = pt::read_image(path);
            if (const std::size_t bad = pt::non_finite_pixels(read); bad > 0)
                fail(path + " has " + std::to_string(bad) + " pixel(s) that are not finite");
            return read;
        };
        const pt::Image image = read_finite(image_path);
        pt::Region area{0, 0, image.width, image.height};
        if (back_wall)
            area = pt::cornell_back_wall_region(image.width, image.height);
        else if (!region_values.empty())
            area = {region_values[0], region_values[1], region_values[2], region_values[3]};
        const pt::RowStructure own = pt::row_structure(image, area);
        if (!reference_path.empty()) {
            const pt::Image reference = read_finite(reference_path);
            print_errors(image, reference);
            if (back_wall || !region_values.empty())
                print("region_bias",
                      pt::relative_mean_difference(crop(image, area), crop(reference, area)));
        }
        print("image_row_ratio", own.row_ratio);
        print("image_column_ratio", own.column_ratio);
    } catch (const std::exception& e) {
        fail(e.what());
    }
    return 0;
}
