// Running mean and standard error of independent trials, and the unbiasedness check the
// project uses everywhere: |mean - truth| < 4 standard errors, the error measured from
// the trials themselves.
#pragma once

#include <gtest/gtest.h>

#include <cmath>
#include <cstddef>
#include <cstdint>
#include <string_view>

namespace restir::test {

/// A test setup's own random seed, from its name (FNV-1a): no two setups share a draw, so a
/// chance fluctuation of one stream cannot fail several setups at once.
inline std::uint64_t seed_of_name(std::string_view name) {
    std::uint64_t h = 14695981039346656037ull;
    for (const char c : name)
        h = (h ^ static_cast<unsigned char>(c)) * 1099511628211ull;
    return h;
}

/// Welford's online mean and variance.
class RunningStats {
public:
    void add(double x) {
        ++count_;
        const double delta = x - mean_;
        mean_ += delta / static_cast<double>(count_);
        m2_ += delta * (x - mean_);
    }
    std::size_t count() const { return count_; }
    double mean() const { return mean_; }
    double variance() const { return count_ > 1 ? m2_ / static_cast<double>(count_ - 1) : 0.0; }
    double standard_error() const { return std::sqrt(variance() / static_cast<double>(count_)); }

private:
    std::size_t count_ = 0;
    double mean_ = 0.0;
    double m2_ = 0.0;
};

/// The estimator's mean lies within `sigmas` measured standard errors of `truth`.
inline ::testing::AssertionResult agrees_with(const RunningStats& stats, double truth,
                                              double sigmas = 4.0) {
    const double error = std::abs(stats.mean() - truth);
    const double bound = sigmas * stats.standard_error();
    // A zero-variance estimator must hit the truth up to rounding.
    const bool exact = error <= 1e-9 * std::fmax(1.0, std::abs(truth));
    if (stats.count() > 1 && (error < bound || exact))
        return ::testing::AssertionSuccess();
    return ::testing::AssertionFailure()
           << "mean " << stats.mean() << " vs truth " << truth << ": |error| " << error
           << " is not below " << sigmas << " standard errors (" << bound << ", " << stats.count()
           << " trials)";
}

/// The estimator's mean lies more than `sigmas` measured standard errors from `value`:
/// used to show that a biased estimator is told apart from the truth.
inline ::testing::AssertionResult differs_from(const RunningStats& stats, double value,
                                               double sigmas = 6.0) {
    const double error = std::abs(stats.mean() - value);
    const double bound = sigmas * stats.standard_error();
    if (error > bound)
        return ::testing::AssertionSuccess();
    return ::testing::AssertionFailure()
           << "mean " << stats.mean() << " is within " << sigmas << " standard errors of " << value;
}

} // namespace restir::test
