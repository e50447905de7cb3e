#include "error_metrics.hpp"

#include <algorithm>
#include <cmath>
#include <cstddef>
#include <functional>
#include <limits>
#include <string>

namespace pt {
namespace {

std::string size_text(std::uint32_t width, std::uint32_t height) {
    return std::to_string(width) + "x" + std::to_string(height);
}

void check_consistent(const Image& image) {
    if (image.pixels.size() != std::size_t{image.width} * image.height) {
        throw ImageError("image is " + size_text(image.width, image.height) + " but holds " +
                         std::to_string(image.pixels.size()) + " pixels");
    }
}

void check_same_size(const Image& image, const Image& reference) {
    if (image.width != reference.width || image.height != reference.height) {
        throw ImageError("image is " + size_text(image.width, image.height) +
                         " but the reference is " + size_text(reference.width, reference.height));
    }
    check_consistent(image);
    check_consistent(reference);
}

void check_region(const Image& image, const Region& region) {
    check_consistent(image);
    if (region.x0 >= region.x1 || region.y0 >= region.y1 || region.x1 > image.width ||
        region.y1 > image.height) {
        throw ImageError("region x " + std::to_string(region.x0) + ".." +
                         std::to_string(region.x1) + ", y " + std::to_string(region.y0) + ".." +
                         std::to_string(region.y1) + " is empty or not inside the " +
                         size_text(image.width, image.height) + " image");
    }
}

double channel_sum(const glm::vec3& p) {
    return static_cast<double>(p.r) + static_cast<double>(p.g) + static_cast<double>(p.b);
}

constexpr std::uint32_t high_pass_radius = 4;
constexpr std::uint32_t firefly_radius = 3;
constexpr double firefly_factor = 10.0;

// Writes the sums over the (2 radius + 1)-wide windows of `values`, clipped at the ends. The
// interior sums each add their window anew: no running sum, so no chain of dependent
// additions and no rounding drift.
template <std::uint32_t radius>
void window_sums(const double* values, std::uint32_t width, double* sums) {
    const auto clipped = [&](std::uint32_t x) {
        double sum = 0.0;
        for (std::uint32_t k = x > radius ? x - radius : 0; k < std::min(x + radius + 1, width);
             ++k) {
            sum += values[k];
        }
        sums[x] = sum;
    };
    if (width <= 2 * radius) {
        for (std::uint32_t x = 0; x < width; ++x) {
            clipped(x);
        }
        return;
    }
    for (std::uint32_t x = 0; x < radius; ++x) {
        clipped(x);
        clipped(width - 1 - x);
    }
    for (std::uint32_t x = radius; x < width - radius; ++x) {
        double sum = 0.0;
        for (std::uint32_t k = 0; k <= 2 * radius; ++k) {
            sum += values[x - radius + k];
        }
        sums[x] = sum;
    }
}

// Streams the rows [y_begin, y_end) of a width x height image whose rows `fill(y, row)` writes,
// each with the mean of every pixel's (2 radius + 1)^2 window, clipped at the image border:
// `use(y, values, means)`. Holds 2 radius + 1 rows and running column sums, so that every
// row is made once and a frame is read once.
template <std::uint32_t radius, class Fill, class Use>
void stream_window_means(std::uint32_t width, std::uint32_t height, std::uint32_t y_begin,
                         std::uint32_t y_end, Fill fill, Use use) {
    constexpr std::uint32_t span = 2 * radius + 1;
    std::vector<double> rows(std::size_t{span} * width);
    std::vector<double> column_sums(width, 0.0);
    std::vector<double> means(width);
    std::vector<double> inverse_widths(width);
    for (std::uint32_t x = 0; x < width; ++x) {
        const std::uint32_t x0 = x > radius ? x - radius : 0;
        inverse_widths[x] = 1.0 / (std::min(x + radius + 1, width) - x0);
    }
    const auto row = [&](std::uint32_t y) { return rows.data() + std::size_t{y % span} * width; };
    const auto add_row = [&](std::uint32_t y, double sign) {
        const double* values = row(y);
        for (std::uint32_t x = 0; x < width; ++x) {
            column_sums[x] += sign * values[x];
        }
    };
    for (std::uint32_t y = y_begin > radius ? y_begin - radius : 0;
         y < std::min(y_begin + radius, height); ++y) {
        fill(y, row(y));
        add_row(y, 1.0);
    }
    for (std::uint32_t y = y_begin; y < y_end; ++y) {
        if (y + radius < height) {
            fill(y + radius, row(y + radius)); // the window's new bottom row
            add_row(y + radius, 1.0);
        }
        const std::uint32_t y0 = y > radius ? y - radius : 0;
        const double inverse_rows = 1.0 / (std::min(y + radius + 1, height) - y0);
        window_sums<radius>(column_sums.data(), width, means.data());
        for (std::uint32_t x = 0; x < width; ++x) {
            means[x] *= inverse_widths[x] * inverse_rows;
        }
        use(y, static_cast<const double*>(row(y)), static_cast<const double*>(means.data()));
        if (y >= radius) {
            add_row(y - radius, -1.0); // leaves the window of the next row
        }
    }
}

// Row and column means, and the spread, of values added pixel by pixel over a region.
class RowColumnStatistics {
public:
    RowColumnStatistics(std::uint32_t columns, std::uint32_t rows)
        : row_sums_(rows, 0.0), column_sums_(columns, 0.0) {}

    // `value` at (column, row) of the region; `size` the magnitude of the measured quantity
    // there, which tells a flat region from rounding.
    void add(std::uint32_t column, std::uint32_t row, double value, double size) {
        row_sums_[row] += value;
        column_sums_[column] += value;
        sum_ += value;
        squares_ += value * value;
        size_ += std::abs(size);
    }

    RowStructure ratios() const {
        const double n = static_cast<double>(row_sums_.size() * column_sums_.size());
        const double mean = sum_ / n;
        const double spread = std::sqrt(std::max(squares_ / n - mean * mean, 0.0));
        if (spread <= 1e-9 * size_ / n) {
            return {}; // flat; NaN goes on, so that a broken image does not look flat
        }
        return {spread_of_means(row_sums_, column_sums_.size()) / spread,
                spread_of_means(column_sums_, row_sums_.size()) / spread};
    }

private:
    // Population standard deviation of sums[i] / count.
    static double spread_of_means(const std::vector<double>& sums, std::size_t count) {
        double mean = 0.0;
        for (double s : sums) {
            mean += s / static_cast<double>(count);
        }
        mean /= static_cast<double>(sums.size());
        double squares = 0.0;
        for (double s : sums) {
            const double d = s / static_cast<double>(count) - mean;
            squares += d * d;
        }
        return std::sqrt(squares / static_cast<double>(sums.size()));
    }

    std::vector<double> row_sums_;
    std::vector<double> column_sums_;
    double sum_ = 0.0;
    double squares_ = 0.0;
    double size_ = 0.0;
};

// RowStructure of the high-passed values that `fill(y, row)` makes, in `region`.
template <class Fill>
RowStructure high_passed_structure(std::uint32_t width, std::uint32_t height, const Region& region,
                                   Fill fill) {
    RowColumnStatistics statistics(region.x1 - region.x0, region.y1 - region.y0);
    stream_window_means<high_pass_radius>(
        width, height, region.y0, region.y1, fill,
        [&](std::uint32_t y, const double* values, const double* means) {
            for (std::uint32_t x = region.x0; x < region.x1; ++x) {
                statistics.add(x - region.x0, y - region.y0, values[x] - means[x], values[x]);
            }
        });
    return statistics.ratios();
}

// Writes row y of the channel-summed error image - reference.
auto error_rows(const Image& image, const Image& reference) {
    return [&image, &reference](std::uint32_t y, double* row) {
        const std::size_t begin = std::size_t{y} * image.width;
        for (std::uint32_t x = 0; x < image.width; ++x) {
            row[x] =
                channel_sum(image.pixels[begin + x]) - channel_sum(reference.pixels[begin + x]);
        }
    };
}

// Sum over k < n of a[k] b[k], in 16 interleaved partial sums: independent chains that the
// compiler keeps in vector registers.
double dot(const double* a, const double* b, std::uint32_t n) {
    constexpr std::uint32_t lanes = 16;
    double partial[lanes] = {};
    std::uint32_t k = 0;
    for (; k + lanes <= n; k += lanes) {
        for (std::uint32_t j = 0; j < lanes; ++j) {
            partial[j] += a[k + j] * b[k + j];
        }
    }
    for (; k < n; ++k) {
        partial[0] += a[k] * b[k];
    }
    double sum = 0.0;
    for (double p : partial) {
        sum += p;
    }
    return sum;
}

// The `k` largest of the values offered, smallest first out.
class LargestValues {
public:
    explicit LargestValues(std::size_t k) : k_(k) { heap_.reserve(k); }

    void offer(double value) {
        if (heap_.size() < k_) {
            heap_.push_back(value);
            std::push_heap(heap_.begin(), heap_.end(), std::greater<>());
        } else if (value > heap_.front()) {
            std::pop_heap(heap_.begin(), heap_.end(), std::greater<>());
            heap_.back() = value;
            std::push_heap(heap_.begin(), heap_.end(), std::greater<>());
        }
    }

    // The k-th largest value offered.
    double smallest() const { return heap_.front(); }

private:
    std::size_t k_;
    std::vector<double> heap_;
};

} // namespace

double rmse(const Image& image, const Image& reference) {
    check_same_size(image, reference);
    if (image.pixels.empty()) {
        return 0.0;
    }
    double sum = 0.0;
    for (std::size_t i = 0; i < image.pixels.size(); ++i) {
        for (int c = 0; c < 3; ++c) {
            const double d = static_cast<double>(image.pixels[i][c]) -
                             static_cast<double>(reference.pixels[i][c]);
            sum += d * d;
        }
    }
    return std::sqrt(sum / (3.0 * static_cast<double>(image.pixels.size())));
}

double worst_pixels_error_share(const Image& image, const Image& reference, std::size_t count) {
    check_same_size(image, reference);
    std::vector<double> squared(image.pixels.size(), 0.0);
    double total = 0.0;
    for (std::size_t i = 0; i < image.pixels.size(); ++i) {
        for (int c = 0; c < 3; ++c) {
            const double d = static_cast<double>(image.pixels[i][c]) -
                             static_cast<double>(reference.pixels[i][c]);
            squared[i] += d * d;
        }
        total += squared[i];
    }
    const std::size_t kept = std::min(count, squared.size());
    std::partial_sort(squared.begin(), squared.begin() + static_cast<std::ptrdiff_t>(kept),
                      squared.end(), std::greater<>());
    double worst = 0.0;
    for (std::size_t i = 0; i < kept; ++i)
        worst += squared[i];
    return total > 0.0 ? worst / total : 0.0;
}

double relative_mean_difference(const Image& image, const Image& reference) {
    check_same_size(image, reference);
    double difference = 0.0;
    double total = 0.0;
    for (std::size_t i = 0; i < image.pixels.size(); ++i) {
        for (int c = 0; c < 3; ++c) {
            difference += static_cast<double>(image.pixels[i][c]) -
                          static_cast<double>(reference.pixels[i][c]);
            total += static_cast<double>(reference.pixels[i][c]);
        }
    }
    return total > 0.0 ? difference / total : 0.0;
}

double masked_mse(const Image& image, const Image& other, const std::vector<std::uint8_t>& mask) {
    check_same_size(image, other);
    if (!mask.empty() && mask.size() != image.pixels.size())
        throw ImageError("the mask has " + std::to_string(mask.size()) + " pixels, the image " +
                         std::to_string(image.pixels.size()));
    double sum = 0.0;
    std::size_t counted = 0;
    for (std::size_t i = 0; i < image.pixels.size(); ++i) {
        if (!mask.empty() && mask[i] == 0u)
            continue;
        for (int c = 0; c < 3; ++c) {
            const double d =
                static_cast<double>(image.pixels[i][c]) - static_cast<double>(other.pixels[i][c]);
            sum += d * d;
        }
        ++counted;
    }
    return counted == 0 ? 0.0 : sum / (3.0 * static_cast<double>(counted));
}

double relative_mse(const Image& image, const Image& reference) {
    check_same_size(image, reference);
    if (image.pixels.empty()) {
        return 0.0;
    }
    constexpr double epsilon = 1e-2;
    double sum = 0.0;
    for (std::size_t i = 0; i < image.pixels.size(); ++i) {
        for (int c = 0; c < 3; ++c) {
            const double r = static_cast<double>(reference.pixels[i][c]);
            const double d = static_cast<double>(image.pixels[i][c]) - r;
            sum += d * d / (r * r + epsilon);
        }
    }
    return sum / (3.0 * static_cast<double>(image.pixels.size()));
}

ErrorAutocorrelation error_autocorrelation(const Image& image, const Image& reference,
                                           std::uint32_t max_lag) {
    check_same_size(image, reference);
    ErrorAutocorrelation result{std::vector<double>(std::size_t{max_lag} + 1, 0.0),
                                std::vector<double>(std::size_t{max_lag} + 1, 0.0)};
    if (image.pixels.empty()) {
        return result;
    }
    std::vector<double> e(image.pixels.size());
    double mean = 0.0;
    for (std::size_t i = 0; i < e.size(); ++i) {
        e[i] = channel_sum(image.pixels[i]) - channel_sum(reference.pixels[i]);
        mean += e[i];
    }
    mean /= static_cast<double>(e.size());
    for (double& v : e) {
        v -= mean;
    }
    // Row by row, so that the rows a row pairs with are still in cache.
    const std::uint32_t width = image.width;
    const std::uint32_t height = image.height;
    double variance = 0.0;
    std::vector<double> x_sums(std::size_t{max_lag} + 1, 0.0);
    std::vector<double> y_sums(std::size_t{max_lag} + 1, 0.0);
    for (std::uint32_t y = 0; y < height; ++y) {
        const double* row = e.data() + std::size_t{y} * width;
        variance += dot(row, row, width);
        for (std::uint32_t lag = 1; lag <= max_lag; ++lag) {
            if (lag < width) {
                x_sums[lag] += dot(row, row + lag, width - lag);
            }
            if (y + lag < height) {
                y_sums[lag] += dot(row, row + std::size_t{lag} * width, width);
            }
        }
    }
    variance /= static_cast<double>(e.size());
    if (variance == 0.0) {
        return result;
    }
    result.acf_x[0] = result.acf_y[0] = 1.0;
    for (std::uint32_t lag = 1; lag <= max_lag; ++lag) {
        if (lag < width) {
            result.acf_x[lag] =
                x_sums[lag] / (static_cast<double>(width - lag) * height) / variance;
        }
        if (lag < height) {
            result.acf_y[lag] =
                y_sums[lag] / (static_cast<double>(height - lag) * width) / variance;
        }
    }
    return result;
}

RowStructure row_structure(const Image& image, const Region& region) {
    check_region(image, region);
    return high_passed_structure(image.width, image.height, region,
                                 [&image](std::uint32_t y, double* row) {
                                     const std::size_t begin = std::size_t{y} * image.width;
                                     for (std::uint32_t x = 0; x < image.width; ++x) {
                                         row[x] = channel_sum(image.pixels[begin + x]);
                                     }
                                 });
}

RowStructure row_structure_of_error(const Image& image, const Image& reference) {
    check_same_size(image, reference);
    if (image.pixels.empty()) {
        return {};
    }
    return high_passed_structure(image.width, image.height, {0, 0, image.width, image.height},
                                 error_rows(image, reference));
}

FireflyMeasure firefly_measure(const Image& image, const Image& reference) {
    check_same_size(image, reference);
    if (image.pixels.empty()) {
        return {};
    }
    // The 99.9th percentile by nearest rank, the ceil(0.999 n)-th smallest value, is the k-th
    // largest for k = n - rank + 1.
    const std::size_t n = image.pixels.size();
    const std::size_t rank = (999 * n + 999) / 1000;
    LargestValues largest(n - rank + 1);
    FireflyMeasure result;
    const auto reference_rows = [&reference](std::uint32_t y, double* row) {
        const std::size_t begin = std::size_t{y} * reference.width;
        for (std::uint32_t x = 0; x < reference.width; ++x) {
            row[x] = channel_sum(reference.pixels[begin + x]);
        }
    };
    stream_window_means<firefly_radius>(
        image.width, image.height, 0, image.height, reference_rows,
        [&](std::uint32_t y, const double* values, const double* means) {
            const std::size_t begin = std::size_t{y} * image.width;
            for (std::uint32_t x = 0; x < image.width; ++x) {
                double e = std::abs(channel_sum(image.pixels[begin + x]) - values[x]);
                // A NaN error is an infinite one: it counts, and sorts last.
                e = std::isnan(e) ? std::numeric_limits<double>::infinity() : e;
                if (e > firefly_factor * means[x]) {
                    ++result.count;
                }
                largest.offer(e);
            }
        });
    result.p999 = largest.smallest();
    return result;
}

Region cornell_back_wall_region(std::uint32_t width, std::uint32_t height) {
    const auto at = [](double fraction, std::uint32_t size) {
        return static_cast<std::uint32_t>(std::lround(fraction * static_cast<double>(size)));
    };
    const Region region{at(0.25, width), at(0.25, height), at(0.75, width), at(0.39, height)};
    if (region.x0 >= region.x1 || region.y0 >= region.y1) {
        throw ImageError("a " + size_text(width, height) +
                         " image is too small for the Cornell box's back wall region");
    }
    return region;
}

} // namespace pt
