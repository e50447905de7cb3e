// A discrete light set for unbiasedness tests of RIS: 64 lights whose contributions span three
// decades (the sum is the truth), powers that follow the contributions only roughly (the
// candidate distribution), and a target that follows them less still (the square root).
#pragma once

#include <restir/core/rng.hpp>

#include <cmath>
#include <cstddef>
#include <cstdint>
#include <vector>

namespace restir::test {

struct DiscreteLights {
    std::vector<double> contribution;
    std::vector<float> power;
    double truth = 0.0;

    explicit DiscreteLights(std::uint64_t seed, std::size_t count = 64)
        : contribution(count), power(count) {
        Pcg32 setup = make_pixel_rng(0u, 0u, 0u, seed);
        for (std::size_t i = 0; i < count; ++i) {
            contribution[i] = std::pow(10.0, 3.0 * static_cast<double>(next_float(setup)));
            power[i] = static_cast<float>(contribution[i]) * (0.5f + next_float(setup));
            truth += contribution[i];
        }
    }

    float target(std::uint32_t light) const {
        return static_cast<float>(std::sqrt(contribution[light]));
    }
};

} // namespace restir::test
