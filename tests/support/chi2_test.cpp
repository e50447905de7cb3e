// The statistical helpers are code too: known quantiles, and a wrong distribution rejected.
#include "support/chi2.hpp"
#include "support/statistics.hpp"

#include <gtest/gtest.h>

#include <vector>

namespace {

TEST(Chi2Helper, SurvivalMatchesTabulatedQuantiles) {
    // Upper 5% and 1% points of the chi-square distribution.
    EXPECT_NEAR(restir::test::chi2_survival(3.841, 1), 0.05, 1e-4);
    EXPECT_NEAR(restir::test::chi2_survival(18.307, 10), 0.05, 1e-4);
    EXPECT_NEAR(restir::test::chi2_survival(6.635, 1), 0.01, 1e-4);
    EXPECT_NEAR(restir::test::chi2_survival(124.342, 100), 0.05, 1e-4);
}

TEST(Chi2Helper, SidakCorrection) {
    EXPECT_NEAR(restir::test::sidak_significance(0.01, 1), 0.01, 1e-12);
    EXPECT_NEAR(restir::test::sidak_significance(0.01, 3), 0.0033445, 1e-6);
}

TEST(Chi2Helper, RejectsAWrongDistributionAndPoolsSmallCells) {
    const std::vector<double> observed = {520, 480, 0, 1};
    EXPECT_TRUE(restir::test::fits_distribution(observed, {0.5, 0.5, 0.0005, 0.0005}, 0.01));
    EXPECT_FALSE(restir::test::fits_distribution(observed, {0.6, 0.4, 0.0, 0.0}, 0.01));
    // A count in a cell of probability zero can never fit.
    EXPECT_FALSE(restir::test::fits_distribution({500, 500, 1}, {0.5, 0.5, 0.0}, 0.01));
}

TEST(StatisticsHelper, AgreementIsMeasuredInStandardErrors) {
    restir::test::RunningStats stats;
    for (double x : {1.0, 2.0, 3.0, 4.0})
        stats.add(x);
    EXPECT_DOUBLE_EQ(stats.mean(), 2.5);
    EXPECT_DOUBLE_EQ(stats.variance(), 5.0 / 3.0);
    // Standard error sqrt(5/12) ~ 0.645: 2.5 is within 4 of 4.9 but not of 5.2.
    EXPECT_TRUE(restir::test::agrees_with(stats, 4.9));
    EXPECT_FALSE(restir::test::agrees_with(stats, 5.2));
}

} // namespace
