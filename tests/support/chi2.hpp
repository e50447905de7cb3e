// Pearson chi-square goodness-of-fit test for discrete sampling code: cells with an
// expected count below a threshold are pooled, the p-value comes from the chi-square
// survival function, and a failure prints the histogram.
#pragma once

#include <gtest/gtest.h>

#include <cmath>
#include <cstddef>
#include <sstream>
#include <string>
#include <vector>

namespace restir::test {

/// Regularized upper incomplete gamma function Q(a, x) = Gamma(a, x) / Gamma(a): the power
/// series for x < a + 1, Lentz's continued fraction otherwise.
inline double regularized_gamma_q(double a, double x) {
    if (x <= 0.0)
        return 1.0;
    const double log_prefactor = a * std::log(x) - x - std::lgamma(a);
    if (x < a + 1.0) {
        double term = 1.0 / a, sum = term;
        for (int n = 1; n < 10000 && std::abs(term) > std::abs(sum) * 1e-15; ++n) {
            term *= x / (a + n);
            sum += term;
        }
        return 1.0 - sum * std::exp(log_prefactor);
    }
    constexpr double tiny = 1e-300;
    double b = x + 1.0 - a, c = 1.0 / tiny, d = 1.0 / b, h = d;
    for (int n = 1; n < 10000; ++n) {
        const double an = -n * (n - a);
        b += 2.0;
        d = an * d + b;
        d = std::abs(d) < tiny ? tiny : d;
        c = b + an / c;
        c = std::abs(c) < tiny ? tiny : c;
        d = 1.0 / d;
        const double delta = d * c;
        h *= delta;
        if (std::abs(delta - 1.0) < 1e-15)
            break;
    }
    return std::exp(log_prefactor) * h;
}

/// P(X >= statistic) for X chi-square distributed with `dof` degrees of freedom.
inline double chi2_survival(double statistic, double dof) {
    return regularized_gamma_q(0.5 * dof, 0.5 * statistic);
}

/// Per-test significance that keeps the family-wise rate at `alpha` over `test_count`
/// independent tests (Sidak correction).
inline double sidak_significance(double alpha, int test_count) {
    return 1.0 - std::pow(1.0 - alpha, 1.0 / test_count);
}

/// Outcome of a Pearson test.
struct Chi2Result {
    double statistic = 0.0;
    int degrees_of_freedom = 0;
    double p_value = 1.0;
    std::string histogram; ///< Cell by cell: index, observed, expected.
};

/// Pearson's test of observed counts against expected counts (same total). Cells whose
/// expected count is below `min_expected` are pooled in order until the pool reaches it; a
/// last under-full pool joins the previous cell. A cell expected empty but observed
/// non-empty makes the p-value 0.
inline Chi2Result pearson_chi2(const std::vector<double>& observed,
                               const std::vector<double>& expected, double min_expected = 5.0) {
    Chi2Result result;
    std::ostringstream dump;
    std::vector<double> cell_observed, cell_expected;
    double pool_observed = 0.0, pool_expected = 0.0;
    bool impossible_hit = false;
    for (std::size_t i = 0; i < observed.size(); ++i) {
        dump << "  cell " << i << ": observed " << observed[i] << ", expected " << expected[i]
             << "\n";
        if (expected[i] == 0.0 && observed[i] > 0.0)
            impossible_hit = true;
        pool_observed += observed[i];
        pool_expected += expected[i];
        if (pool_expected >= min_expected) {
            cell_observed.push_back(pool_observed);
            cell_expected.push_back(pool_expected);
            pool_observed = pool_expected = 0.0;
        }
    }
    if (pool_expected > 0.0 || pool_observed > 0.0) {
        if (cell_expected.empty()) {
            cell_observed.push_back(pool_observed);
            cell_expected.push_back(pool_expected);
        } else {
            cell_observed.back() += pool_observed;
            cell_expected.back() += pool_expected;
        }
    }
    for (std::size_t i = 0; i < cell_observed.size(); ++i) {
        const double diff = cell_observed[i] - cell_expected[i];
        result.statistic += diff * diff / cell_expected[i];
    }
    result.degrees_of_freedom = static_cast<int>(cell_observed.size()) - 1;
    result.p_value = impossible_hit ? 0.0
                     : result.degrees_of_freedom > 0
                         ? chi2_survival(result.statistic, result.degrees_of_freedom)
                         : 1.0;
    result.histogram = dump.str();
    return result;
}

/// GoogleTest predicate: the histogram of `samples` (indices in [0, pmf.size())) fits `pmf`
/// at significance `alpha`. On failure the message carries the statistic and histogram.
inline ::testing::AssertionResult fits_distribution(const std::vector<double>& observed,
                                                    const std::vector<double>& pmf, double alpha) {
    double total = 0.0;
    for (double count : observed)
        total += count;
    std::vector<double> expected(pmf.size());
    for (std::size_t i = 0; i < pmf.size(); ++i)
        expected[i] = pmf[i] * total;
    const Chi2Result r = pearson_chi2(observed, expected);
    if (r.p_value >= alpha)
        return ::testing::AssertionSuccess();
    return ::testing::AssertionFailure()
           << "chi-square " << r.statistic << " with " << r.degrees_of_freedom
           << " degrees of freedom, p = " << r.p_value << " < " << alpha << "\n"
           << r.histogram;
}

} // namespace restir::test
