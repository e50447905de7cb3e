// The brightness of a small render, and the check that renders of one scene by several methods
// estimate the same image: what the renderer's statistical tests compare across methods and
// seeds.
#pragma once

#include "renderer.hpp"
#include "scene.hpp"

#include "support/statistics.hpp"

#include <gtest/gtest.h>

#include <cmath>
#include <cstdint>
#include <cstdio>
#include <vector>

namespace pt::test {

/// Sum of the pixels' channels of the accumulated image after `frames` frames of `s`.
inline double brightness(const pt::Scene& scene, const pt::RenderSettings& s,
                         std::uint32_t frames) {
    pt::Renderer renderer(scene, s);
    for (std::uint32_t f = 0; f < frames; ++f)
        renderer.render_frame();
    double sum = 0.0;
    for (const glm::vec3& p : renderer.accumulated().pixels)
        sum += static_cast<double>(p.x + p.y + p.z);
    return sum;
}

/// Each setup after the first (the reference) estimates the first's image: the mean brightness
/// after 4 frames over seeds 1..`seeds` agrees within 4 standard errors of the difference.
/// `settings(setup, seed)` is the render of a setup (which has a `name`) with a seed.
template <class Setup, class Settings>
void expect_agreement(const pt::Scene& scene, const std::vector<Setup>& setups, std::uint64_t seeds,
                      const Settings& settings) {
    std::vector<restir::test::RunningStats> stats(setups.size());
    for (std::size_t k = 0; k < setups.size(); ++k)
        for (std::uint64_t seed = 1; seed <= seeds; ++seed)
            stats[k].add(brightness(scene, settings(setups[k], seed), 4));
    EXPECT_GT(stats[0].mean(), 0.0);
    for (std::size_t k = 1; k < setups.size(); ++k) {
        const double error = std::hypot(stats[0].standard_error(), stats[k].standard_error());
        std::printf("%s, %-34s %.2f against the reference's %.2f (SE %.2f)\n", scene.name.c_str(),
                    setups[k].name.c_str(), stats[k].mean(), stats[0].mean(), error);
        EXPECT_LT(std::abs(stats[k].mean() - stats[0].mean()), 4.0 * error) << setups[k].name;
    }
}

} // namespace pt::test
