#include <restir/core/channels.hpp>

#include <gtest/gtest.h>

#include <array>
#include <cmath>
#include <random>

namespace {

using restir::ChannelNorm;
using restir::fold_channels;

TEST(Channels, FoldsAsDocumented) {
    const glm::vec3 f(3.0f, 4.0f, 12.0f);
    EXPECT_FLOAT_EQ(fold_channels<ChannelNorm::sum>(f), 19.0f);
    EXPECT_FLOAT_EQ(fold_channels<ChannelNorm::euclidean>(f), 13.0f);
    EXPECT_EQ(fold_channels<ChannelNorm::euclidean>(glm::vec3(0.0f)), 0.0f);
}

// Summed variance of the three channel estimates f_c(i) / p(i) of one sample drawn from p
// proportional to `norm` over a discrete set: sum_c (sum_i f_c(i)^2 / p(i) - I_c^2), exactly.
template <ChannelNorm Norm, std::size_t N>
double summed_channel_variance(const std::array<glm::vec3, N>& f) {
    double total = 0.0;
    for (const glm::vec3& x : f)
        total += static_cast<double>(fold_channels<Norm>(x));
    double variance = 0.0;
    for (int c = 0; c < 3; ++c) {
        double second_moment = 0.0, integral = 0.0;
        for (const glm::vec3& x : f) {
            const double p = static_cast<double>(fold_channels<Norm>(x)) / total;
            second_moment += static_cast<double>(x[c]) * static_cast<double>(x[c]) / p;
            integral += static_cast<double>(x[c]);
        }
        variance += second_moment - integral * integral;
    }
    return variance;
}

// The Euclidean fold is the optimum for the summed channel variance (Cauchy-Schwarz), so on
// random sets of coloured contributions it is never worse than the channel sum, and better on
// sets that mix saturated and grey contributions.
TEST(Channels, EuclideanFoldMinimisesTheSummedChannelVariance) {
    std::mt19937 engine(7u);
    std::uniform_real_distribution<float> uniform(0.0f, 1.0f);
    for (int trial = 0; trial < 200; ++trial) {
        std::array<glm::vec3, 16> f;
        for (glm::vec3& x : f)
            x = {uniform(engine), uniform(engine) * uniform(engine), uniform(engine) * 0.1f};
        const double euclidean = summed_channel_variance<ChannelNorm::euclidean>(f);
        const double sum = summed_channel_variance<ChannelNorm::sum>(f);
        EXPECT_LE(euclidean, sum * (1.0 + 1e-9)) << "trial " << trial;
    }
    // One white and one red contribution of equal channel sums: the sum draws the white one as
    // often as the red one and lets a red draw tint the pixel; the Euclidean fold does better.
    const std::array<glm::vec3, 2> mixed{glm::vec3(1.0f), glm::vec3(3.0f, 0.0f, 0.0f)};
    EXPECT_LT(summed_channel_variance<ChannelNorm::euclidean>(mixed),
              0.95 * summed_channel_variance<ChannelNorm::sum>(mixed));
}

} // namespace
