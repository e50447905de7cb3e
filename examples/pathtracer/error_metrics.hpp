// Error measures of the example renderer's images: against a reference (RMSE, relMSE, bias,
// fireflies, the error's spatial autocorrelation) and of an image's own structure (rows or
// columns standing out from their surroundings, the mark of horizontal or vertical streaks).
// Every measure is O(pixels): the renderer computes them after every frame.
#pragma once

#include "image_io.hpp"

#include <cstddef>
#include <cstdint>
#include <vector>

namespace pt {

/// A rectangle of pixels, half-open: x in [x0, x1), y in [y0, y1), y = 0 the top row.
struct Region {
    std::uint32_t x0 = 0;
    std::uint32_t y0 = 0;
    std::uint32_t x1 = 0;
    std::uint32_t y1 = 0;
};

/// Root-mean-square error over all pixels and channels; both images must be the same size
/// (ImageError otherwise).
double rmse(const Image& image, const Image& reference);

/// (mean(image) - mean(reference)) / mean(reference) over all pixels and channels: an
/// estimator's bias relative to the image mean, once the noise has averaged out over the
/// pixels; 0 for a black reference. Same size required (ImageError otherwise).
double relative_mean_difference(const Image& image, const Image& reference);

/// Mean squared difference over the pixels where `mask` is non-zero and their channels (every
/// pixel with an empty mask); 0 when no pixel counts. Same size required, and a mask of the
/// images' pixel count or empty (ImageError otherwise). Against a reference it is a masked MSE;
/// between two consecutive frames of a static camera, twice the per-pixel frame-to-frame
/// variance: the flicker of the image.
double masked_mse(const Image& image, const Image& other, const std::vector<std::uint8_t>& mask);

/// Relative mean squared error: the mean over pixels and channels of e^2 / (r^2 + 0.01), e the
/// error and r the reference's value. The 0.01 keeps black reference pixels from dominating.
/// Same size required (ImageError otherwise).
double relative_mse(const Image& image, const Image& reference);

/// Normalised autocorrelation of the error e = image - reference, summed over the channels,
/// its mean over the image removed: for lag l, the mean of e(x, y) e(x + l, y) over the pairs
/// inside the image, divided by the mean of e^2 (the variance). acf_x[l] is horizontal,
/// acf_y[l] vertical, for l = 0 .. max_lag (acf[0] = 1). Independent noise gives about 0 at
/// every lag l > 0, with a standard error of 1 / sqrt(pairs); noise correlated along rows
/// (streaks) gives acf_x > acf_y. Lags with no pair, and every lag of an error without
/// variance, are 0.
struct ErrorAutocorrelation {
    std::vector<double> acf_x;
    std::vector<double> acf_y;
};

/// See ErrorAutocorrelation. Same size required (ImageError otherwise).
ErrorAutocorrelation error_autocorrelation(const Image& image, const Image& reference,
                                           std::uint32_t max_lag = 8);

/// How much whole rows (columns) of a region stand out from their surroundings, as streaks
/// do. The values are high-passed first: each pixel's channel sum minus the mean channel sum
/// of its 9 x 9 window (radius 4, clipped at the image border), which removes smooth shading.
/// `row_ratio` is the standard deviation of the region's row means of the high-passed values
/// divided by the standard deviation of the region's high-passed pixels; `column_ratio` the
/// same with column means. For independent noise the row ratio is about sqrt(0.9 / width)
/// (0.06 for a region 256 pixels wide) and the column ratio sqrt(0.9 / height); rows that are
/// brighter or darker all along raise the row ratio towards 1. Both are 0 when the region is
/// flat after the high-pass (to rounding), NaN when the image holds NaNs.
struct RowStructure {
    double row_ratio = 0.0;
    double column_ratio = 0.0;
};

/// RowStructure of `region` in `image`. Throws ImageError for an empty region or one that
/// does not lie inside the image.
RowStructure row_structure(const Image& image, const Region& region);

/// RowStructure of the error image - reference (channel sums) over the whole image, with the
/// same high-pass as `row_structure`, so that a smooth bias does not count as structure and
/// independent noise gives about sqrt(0.9 / width). Same size required (ImageError otherwise).
RowStructure row_structure_of_error(const Image& image, const Image& reference);

/// Fireflies: isolated pixels far brighter or darker than they should be. The absolute error
/// of a pixel is |sum over the channels of image - reference|; its local level is the mean
/// reference channel sum over its 7 x 7 window (clipped at the image border). `count` is the
/// number of pixels whose absolute error exceeds 10 times their local level (where the
/// reference is black all around, any error counts); `p999` is the 99.9th percentile of the
/// absolute error over all pixels (nearest rank: the smallest value that at least 99.9 % of
/// the pixels do not exceed). A NaN error counts as an infinite one.
struct FireflyMeasure {
    std::uint64_t count = 0;
    double p999 = 0.0;
};

/// See FireflyMeasure. Same size required (ImageError otherwise).
FireflyMeasure firefly_measure(const Image& image, const Image& reference);

/// The share of the total squared error (summed over the channels) that the `count` pixels
/// with the largest squared error hold, in [0, 1]: near count / pixels for even noise, near 1
/// when a few fireflies carry it. 0 for an image equal to the reference. Same size required
/// (ImageError otherwise).
double worst_pixels_error_share(const Image& image, const Image& reference, std::size_t count);

/// The back wall of the built-in Cornell box (`--scene cornell`) at its own camera, between
/// the ceiling and the tall box: x in [0.25, 0.75) of the width, y in [0.25, 0.39) of the
/// height, rounded to pixels. The wall spans x in [0.21, 0.79) and y in [0.21, 0.42): from 128
/// pixels up, the region's high-pass windows (4 pixels around it) stay on the wall too.
/// Throws ImageError when the region is empty (tiny images).
Region cornell_back_wall_region(std::uint32_t width, std::uint32_t height);

} // namespace pt
