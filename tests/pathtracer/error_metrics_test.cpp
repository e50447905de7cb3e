// The example renderer's error measures: exact values on images small enough to work out by
// hand, and statistical checks on noise images whose measures theory predicts (fixed seeds;
// tolerances of four standard errors, the standard errors from theory).
#include "error_metrics.hpp"
#include "image_io.hpp"

#include <gtest/gtest.h>

#include <algorithm>
#include <cmath>
#include <cstdint>
#include <iterator>
#include <random>
#include <string>
#include <vector>

namespace {

using pt::Image;

Image filled(std::uint32_t width, std::uint32_t height, glm::vec3 value) {
    Image image(width, height);
    std::fill(image.pixels.begin(), image.pixels.end(), value);
    return image;
}

// A smooth, non-constant reference: the error measures must not depend on it.
Image gradient(std::uint32_t width, std::uint32_t height) {
    Image image(width, height);
    for (std::uint32_t y = 0; y < height; ++y)
        for (std::uint32_t x = 0; x < width; ++x)
            image.at(x, y) = glm::vec3(1.0f + 0.002f * static_cast<float>(x),
                                       0.5f + 0.001f * static_cast<float>(y), 0.25f);
    return image;
}

// `reference` plus independent standard normal noise in every channel.
Image noisy(const Image& reference, std::uint64_t seed) {
    std::mt19937_64 rng(seed);
    std::normal_distribution<float> normal;
    Image image = reference;
    for (glm::vec3& p : image.pixels)
        p += glm::vec3(normal(rng), normal(rng), normal(rng));
    return image;
}

// The expected row ratio of independent noise in an interior region `width` pixels wide (its
// 9 x 9 windows not clipped by the image border), from the high-pass's coefficients: the
// high-passed row mean is sum over pixels q of k(q) s(q) with k(q) = (1[q in row] - c(x) / 81)
// / width, c(x) the number of the row's pixels whose window holds column x; its variance
// over that of a high-passed pixel, (80 / 81) sigma^2, is the squared ratio. About
// sqrt(0.9 / width).
double white_noise_ratio(std::uint32_t width) {
    const auto w = static_cast<int>(width);
    double same_row = 0.0;
    double other_rows = 0.0;
    for (int x = -4; x < w + 4; ++x) {
        const double c = std::min(x + 4, w - 1) - std::max(x - 4, 0) + 1;
        const double inside = x >= 0 && x < w ? 1.0 : 0.0;
        same_row += (inside - c / 81.0) * (inside - c / 81.0);
        other_rows += (c / 81.0) * (c / 81.0);
    }
    const double variance = (same_row + 8.0 * other_rows) / (static_cast<double>(w) * w);
    return std::sqrt(variance / (80.0 / 81.0));
}

// Relative standard error of a standard deviation measured over `n` row means of independent
// noise: sqrt(sum_k rho(k)^2 / (2 n)) for a Gaussian series whose autocorrelation rho comes
// from the high-pass along y (weights 8/9 at the row, -1/9 at the 8 rows around it).
double ratio_relative_error(std::uint32_t n) {
    double a[9];
    for (double& v : a)
        v = -1.0 / 9.0;
    a[4] = 8.0 / 9.0;
    double rho_squares = 0.0;
    double variance = 0.0;
    for (int k = -8; k <= 8; ++k) {
        double c = 0.0;
        for (int j = 0; j < 9; ++j)
            if (j + k >= 0 && j + k < 9)
                c += a[j] * a[j + k];
        if (k == 0)
            variance = c;
        rho_squares += c * c;
    }
    rho_squares /= variance * variance;
    return std::sqrt(rho_squares / (2.0 * n));
}

TEST(Metrics, RmseRelMseAndBiasOfHandComputedImages) {
    const Image black = filled(2, 1, glm::vec3(0.0f));
    Image image = black;
    image.pixels[0] = glm::vec3(1.0f);
    EXPECT_DOUBLE_EQ(pt::rmse(image, black), std::sqrt(3.0 / 6.0));
    EXPECT_DOUBLE_EQ(pt::relative_mse(image, black), 3.0 * (1.0 / 0.01) / 6.0);
    EXPECT_EQ(pt::relative_mean_difference(image, black), 0.0); // black reference

    const Image ones = filled(2, 1, glm::vec3(1.0f));
    image = ones;
    image.pixels[0] = glm::vec3(2.0f, 0.0f, 1.0f);
    // Errors +1, -1, 0, 0, 0, 0 against a reference of 1 everywhere.
    EXPECT_DOUBLE_EQ(pt::rmse(image, ones), std::sqrt(2.0 / 6.0));
    EXPECT_DOUBLE_EQ(pt::relative_mse(image, ones), 2.0 / 1.01 / 6.0);
    EXPECT_DOUBLE_EQ(pt::relative_mean_difference(image, ones), 0.0);
    image.pixels[1] = glm::vec3(1.5f);
    EXPECT_DOUBLE_EQ(pt::relative_mean_difference(image, ones), 1.5 / 6.0);
    EXPECT_EQ(pt::rmse(ones, ones), 0.0);
    EXPECT_EQ(pt::relative_mse(ones, ones), 0.0);
}

TEST(Metrics, MaskedMseCountsTheMaskedPixelsOnly) {
    Image a = filled(2, 2, glm::vec3(1.0f));
    const Image b = filled(2, 2, glm::vec3(0.0f));
    a.pixels[3] = glm::vec3(3.0f, 0.0f, 0.0f); // squared differences 9, 0, 0; the others 1, 1, 1
    EXPECT_DOUBLE_EQ(pt::masked_mse(a, b, {}), (9.0 + 9.0) / 12.0);
    EXPECT_DOUBLE_EQ(pt::masked_mse(a, b, {0u, 0u, 0u, 1u}), 3.0);
    EXPECT_DOUBLE_EQ(pt::masked_mse(a, b, {1u, 0u, 0u, 0u}), 1.0);
    EXPECT_DOUBLE_EQ(pt::masked_mse(a, b, {0u, 0u, 0u, 0u}), 0.0);
    EXPECT_THROW(pt::masked_mse(a, b, {1u, 1u}), pt::ImageError);
}

TEST(Metrics, WorstPixelsShareOfTheSquaredErrorOfHandComputedImages) {
    const Image reference = filled(4, 1, glm::vec3(1.0f));
    Image image = reference;
    EXPECT_EQ(pt::worst_pixels_error_share(image, reference, 1), 0.0); // no error
    // Squared errors per pixel (channel sums): 3 * 9 = 27, 3 * 1 = 3, 0, 0.
    image.pixels[2] = glm::vec3(4.0f);
    image.pixels[0] = glm::vec3(0.0f);
    EXPECT_DOUBLE_EQ(pt::worst_pixels_error_share(image, reference, 1), 27.0 / 30.0);
    EXPECT_DOUBLE_EQ(pt::worst_pixels_error_share(image, reference, 2), 1.0);
    EXPECT_DOUBLE_EQ(pt::worst_pixels_error_share(image, reference, 20),
                     1.0); // more than pixels
    EXPECT_EQ(pt::worst_pixels_error_share(image, reference, 0), 0.0);
}

TEST(Metrics, ImagesOfDifferentSizesThrowAOneLineError) {
    const Image a(4, 3);
    const Image b(3, 4);
    const auto expect_throw = [](auto measure) {
        try {
            measure();
            ADD_FAILURE() << "no exception";
        } catch (const pt::ImageError& e) {
            const std::string message = e.what();
            EXPECT_NE(message.find("4x3"), std::string::npos) << message;
            EXPECT_EQ(message.find('\n'), std::string::npos) << message;
        }
    };
    expect_throw([&] { pt::rmse(a, b); });
    expect_throw([&] { pt::relative_mean_difference(a, b); });
    expect_throw([&] { pt::relative_mse(a, b); });
    expect_throw([&] { pt::error_autocorrelation(a, b); });
    expect_throw([&] { pt::row_structure_of_error(a, b); });
    expect_throw([&] { pt::worst_pixels_error_share(a, b, 20); });
    expect_throw([&] { pt::firefly_measure(a, b); });

    Image broken(4, 3);
    broken.pixels.pop_back();
    expect_throw([&] { pt::rmse(broken, a); });
    expect_throw([&] { pt::row_structure(broken, {0, 0, 1, 1}); });
}

TEST(Metrics, RegionsMustLieInsideTheImage) {
    const Image image(8, 6);
    EXPECT_NO_THROW(pt::row_structure(image, {0, 0, 8, 6}));
    EXPECT_THROW(pt::row_structure(image, {0, 0, 9, 6}), pt::ImageError);
    EXPECT_THROW(pt::row_structure(image, {0, 0, 8, 7}), pt::ImageError);
    EXPECT_THROW(pt::row_structure(image, {3, 0, 3, 6}), pt::ImageError);
    EXPECT_THROW(pt::row_structure(image, {5, 2, 4, 6}), pt::ImageError);
    EXPECT_THROW(pt::cornell_back_wall_region(2, 2), pt::ImageError);
    const pt::Region wall = pt::cornell_back_wall_region(512, 512);
    EXPECT_EQ(wall.x0, 128u);
    EXPECT_EQ(wall.x1, 384u);
    EXPECT_EQ(wall.y0, 128u);
    EXPECT_EQ(wall.y1, 200u);
}

TEST(Metrics, FlatImagesHaveNoStructureAndNoCorrelation) {
    const Image reference = filled(32, 24, glm::vec3(1.0f));
    const Image image = filled(32, 24, glm::vec3(1.5f)); // a constant error: no variance
    const pt::ErrorAutocorrelation acf = pt::error_autocorrelation(image, reference);
    ASSERT_EQ(acf.acf_x.size(), 9u);
    ASSERT_EQ(acf.acf_y.size(), 9u);
    for (double v : acf.acf_x)
        EXPECT_EQ(v, 0.0);
    const pt::RowStructure rows =
        pt::row_structure(filled(32, 24, glm::vec3(2.0f)), {0, 0, 32, 24});
    EXPECT_EQ(rows.row_ratio, 0.0);
    EXPECT_EQ(rows.column_ratio, 0.0);
}

TEST(Metrics, WhiteNoiseErrorIsUncorrelated) {
    const Image reference = gradient(256, 192);
    const Image image = noisy(reference, 1);
    const pt::ErrorAutocorrelation acf = pt::error_autocorrelation(image, reference);
    EXPECT_EQ(acf.acf_x[0], 1.0);
    EXPECT_EQ(acf.acf_y[0], 1.0);
    for (std::uint32_t lag = 1; lag <= 8; ++lag) {
        // Standard error 1 / sqrt(pairs).
        const double x_pairs = (256.0 - lag) * 192.0;
        const double y_pairs = 256.0 * (192.0 - lag);
        EXPECT_LT(std::abs(acf.acf_x[lag]), 4.0 / std::sqrt(x_pairs)) << lag;
        EXPECT_LT(std::abs(acf.acf_y[lag]), 4.0 / std::sqrt(y_pairs)) << lag;
    }
}

TEST(Metrics, ErrorCorrelatedAlongRowsShowsInTheHorizontalAutocorrelation) {
    // e(x, y) = n(x, y) + n(x + 1, y): autocorrelation 1/2 at horizontal lag 1, 0 elsewhere.
    // Bartlett's standard errors: sqrt(0.5 / pairs) at lag 1, sqrt(1.5 / pairs) beyond.
    const std::uint32_t width = 256;
    const std::uint32_t height = 192;
    const Image reference = gradient(width, height);
    const Image noise = noisy(Image(width + 1, height), 2);
    Image image = reference;
    for (std::uint32_t y = 0; y < height; ++y)
        for (std::uint32_t x = 0; x < width; ++x)
            image.at(x, y) += noise.at(x, y) + noise.at(x + 1, y);
    const pt::ErrorAutocorrelation acf = pt::error_autocorrelation(image, reference, 4);
    ASSERT_EQ(acf.acf_x.size(), 5u);
    const double pairs = static_cast<double>(width) * height;
    EXPECT_NEAR(acf.acf_x[1], 0.5, 4.0 * std::sqrt(0.5 / pairs));
    for (std::uint32_t lag = 2; lag <= 4; ++lag)
        EXPECT_NEAR(acf.acf_x[lag], 0.0, 4.0 * std::sqrt(1.5 / pairs)) << lag;
    for (std::uint32_t lag = 1; lag <= 4; ++lag)
        EXPECT_NEAR(acf.acf_y[lag], 0.0, 4.0 * std::sqrt(1.0 / pairs)) << lag;
}

TEST(Metrics, LagsBeyondTheImageAreZero) {
    const Image reference(4, 3);
    const Image image = noisy(reference, 3);
    const pt::ErrorAutocorrelation acf = pt::error_autocorrelation(image, reference);
    for (std::uint32_t lag = 4; lag <= 8; ++lag)
        EXPECT_EQ(acf.acf_x[lag], 0.0) << lag;
    for (std::uint32_t lag = 3; lag <= 8; ++lag)
        EXPECT_EQ(acf.acf_y[lag], 0.0) << lag;
}

TEST(Metrics, RowRatioOfWhiteNoiseIsAsTheoryPredicts) {
    const std::uint32_t size = 512;
    const Image image = noisy(gradient(size, size), 4);
    // Inset by the window radius, so that no window is clipped.
    const pt::Region region{4, 4, size - 4, size - 4};
    const pt::RowStructure rows = pt::row_structure(image, region);
    const double expected = white_noise_ratio(size - 8);
    const double tolerance = 4.0 * ratio_relative_error(size - 8) * expected;
    EXPECT_NEAR(expected, std::sqrt(0.9 / (size - 8)), 0.02 * expected);
    EXPECT_NEAR(rows.row_ratio, expected, tolerance);
    EXPECT_NEAR(rows.column_ratio, expected, tolerance);
}

TEST(Metrics, HorizontalStripesRaiseTheRowRatioOnly) {
    // Rows offset by N(0, tau^2) in every channel, tau = sigma / 2: the high-passed row means
    // carry (8/9) 3 tau^2 of variance, the pixels (80/81) 3 sigma^2 + (8/9) 3 tau^2, so the row
    // ratio is about sqrt(0.222 / 1.21) = 0.43; the column means average the stripes out.
    const std::uint32_t width = 320;
    const std::uint32_t height = 240;
    Image image = noisy(gradient(width, height), 5);
    std::mt19937_64 rng(6);
    std::normal_distribution<float> stripe(0.0f, 0.5f);
    for (std::uint32_t y = 0; y < height; ++y) {
        const float offset = stripe(rng);
        for (std::uint32_t x = 0; x < width; ++x)
            image.at(x, y) += glm::vec3(offset);
    }
    const pt::Region region{4, 4, width - 4, height - 4};
    const pt::RowStructure rows = pt::row_structure(image, region);
    EXPECT_GT(rows.row_ratio, 0.3);
    // The white noise value is an upper bound: the stripes only add to the denominator.
    const std::uint32_t columns = height - 8;
    EXPECT_LT(rows.column_ratio,
              white_noise_ratio(columns) * (1.0 + 4.0 * ratio_relative_error(columns)));
    EXPECT_GT(rows.column_ratio, 0.5 / std::sqrt(static_cast<double>(columns)));

    // The same stripes in an error image, measured over the whole frame.
    const Image reference = gradient(width, height);
    const pt::RowStructure error_rows = pt::row_structure_of_error(image, reference);
    EXPECT_GT(error_rows.row_ratio, 0.3);
    EXPECT_LT(error_rows.column_ratio, 1.5 / std::sqrt(static_cast<double>(height)));
}

TEST(Metrics, FirefliesAreExactlyTheInjectedSpikes) {
    const std::uint32_t width = 64;
    const std::uint32_t height = 48;
    Image reference = gradient(width, height); // channel sums 1.75 to 2.0
    for (std::uint32_t y = 0; y < 10; ++y)
        for (std::uint32_t x = 0; x < 10; ++x)
            reference.at(x, y) = glm::vec3(0.0f); // a black corner
    Image image = reference;
    std::mt19937_64 rng(7);
    std::uniform_real_distribution<float> small(-0.05f, 0.05f);
    for (std::uint32_t y = 0; y < height; ++y)
        for (std::uint32_t x = 0; x < width; ++x)
            if (x >= 10 || y >= 10)
                image.at(x, y) += glm::vec3(small(rng), small(rng), small(rng));
    // Spikes: 10 times the local level is at most 20 (channel sums); these add 30 or more.
    const std::uint32_t spikes[][2] = {{20, 20}, {21, 20}, {63, 47}, {40, 5}, {12, 30}, {2, 2}};
    for (const auto& s : spikes)
        image.at(s[0], s[1]) += glm::vec3(10.0f, 12.0f, 8.0f);
    // Where the reference is black all around (7 x 7), any error counts, however small.
    image.at(3, 6) = glm::vec3(0.001f, 0.0f, 0.0f);
    const pt::FireflyMeasure fireflies = pt::firefly_measure(image, reference);
    EXPECT_EQ(fireflies.count, std::size(spikes) + 1);
}

TEST(Metrics, P999IsTheNearestRankPercentile) {
    // Absolute errors 1 .. 10000, shuffled: the 9990th smallest is 9990.
    const std::uint32_t width = 100;
    const std::uint32_t height = 100;
    std::vector<float> errors(width * height);
    for (std::size_t i = 0; i < errors.size(); ++i)
        errors[i] = static_cast<float>(i + 1) * (i % 2 == 0 ? 1.0f : -1.0f);
    std::mt19937_64 rng(8);
    std::shuffle(errors.begin(), errors.end(), rng);
    const Image reference = filled(width, height, glm::vec3(20000.0f));
    Image image = reference;
    for (std::size_t i = 0; i < errors.size(); ++i)
        image.pixels[i].g += errors[i];
    EXPECT_EQ(pt::firefly_measure(image, reference).p999, 9990.0);
}

TEST(Metrics, P999OfExponentialErrors) {
    // |e| exponential with mean 1: the 99.9th percentile is ln 1000; the sample quantile's
    // standard error is sqrt(p (1 - p) / n) / f(q) with density f(q) = 0.001 there.
    const std::uint32_t size = 1024;
    const Image reference = gradient(size, size);
    Image image = reference;
    std::mt19937_64 rng(9);
    std::exponential_distribution<double> exponential(1.0);
    for (glm::vec3& p : image.pixels)
        p.b += static_cast<float>(exponential(rng)) * (rng() % 2 == 0 ? 1.0f : -1.0f);
    const double n = static_cast<double>(size) * size;
    const double standard_error = std::sqrt(0.999 * 0.001 / n) / 0.001;
    EXPECT_NEAR(pt::firefly_measure(image, reference).p999, std::log(1000.0), 4.0 * standard_error);
}

} // namespace
