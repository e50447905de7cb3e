// Midpoint-rule quadrature for the truth of unbiasedness tests: over the unit square (a light's
// uv) and over the sphere of directions.
#pragma once

#include <glm/vec2.hpp>
#include <glm/vec3.hpp>

#include <algorithm>
#include <cmath>

namespace restir::test {

/// The mean of f(uv) over [0, 1)^2 by the midpoint rule on n x n cells.
template <class T, class F>
T mean_over_unit_square(int n, const F& f) {
    T sum{};
    for (int i = 0; i < n; ++i)
        for (int j = 0; j < n; ++j)
            sum += f(glm::vec2((static_cast<float>(i) + 0.5f) / static_cast<float>(n),
                               (static_cast<float>(j) + 0.5f) / static_cast<float>(n)));
    return sum / (static_cast<double>(n) * n);
}

/// The integral of f(w) over the unit sphere of directions w, by the midpoint rule on n x n
/// cells in (phi, cos theta), where d omega = d phi d cos theta.
template <class T, class F>
T integrate_over_sphere(int n, const F& f) {
    constexpr double pi = 3.14159265358979323846;
    T sum{};
    for (int i = 0; i < n; ++i)
        for (int j = 0; j < n; ++j) {
            const double z = 1.0 - 2.0 * (i + 0.5) / n;
            const double phi = 2.0 * pi * (j + 0.5) / n;
            const double r = std::sqrt(std::max(0.0, 1.0 - z * z));
            sum += f(glm::vec3(static_cast<float>(r * std::cos(phi)), static_cast<float>(z),
                               static_cast<float>(r * std::sin(phi))));
        }
    return sum * (4.0 * pi / (static_cast<double>(n) * n));
}

} // namespace restir::test
