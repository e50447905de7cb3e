// Chi-square test of a sampler of directions on the upper hemisphere (z up) against its
// density: samples binned on a (cos theta, phi) grid, each bin's expected mass integrated
// from the density by adaptive Gauss-Legendre quadrature, and one more cell for the draws
// that returned no direction (expected: the mass the density misses on the hemisphere).
#pragma once

#include "support/chi2.hpp"

#include <restir/core/math.hpp>
#include <restir/core/rng.hpp>

#include <glm/vec3.hpp>

#include <gtest/gtest.h>

#include <algorithm>
#include <array>
#include <cmath>
#include <cstddef>
#include <numbers>
#include <optional>
#include <vector>

namespace restir::test {

/// A cell of the (cos theta, phi) parameter plane.
struct HemisphereCell {
    double cos0 = 0.0, cos1 = 1.0, phi0 = 0.0, phi1 = 0.0;
};

/// The roughnesses and view angles (degrees from the normal) the BSDF tests sweep.
inline constexpr float roughnesses[] = {0.05f, 0.2f, 0.5f, 1.0f};
inline constexpr float view_degrees[] = {0.0f, 45.0f, 80.0f};

/// A unit view at `degrees` from the normal (z), turned 0.7 rad about it (off every axis).
inline glm::vec3 view_at(float degrees) {
    const float theta = degrees * (std::numbers::pi_v<float> / 180.0f);
    return {std::sin(theta) * std::cos(0.7f), std::sin(theta) * std::sin(0.7f), std::cos(theta)};
}

/// A direction uniform on the sphere.
inline glm::vec3 random_unit(restir::Pcg32& rng) {
    const float z = 1.0f - 2.0f * next_float(rng);
    const float r = std::sqrt(std::fmax(0.0f, 1.0f - z * z));
    const float phi = restir::two_pi * next_float(rng);
    return {r * std::cos(phi), r * std::sin(phi), z};
}

/// The unit direction at (cos theta, phi).
inline glm::vec3 hemisphere_direction(double cos_theta, double phi) {
    const double sin_theta = std::sqrt(std::max(0.0, 1.0 - cos_theta * cos_theta));
    return {static_cast<float>(sin_theta * std::cos(phi)),
            static_cast<float>(sin_theta * std::sin(phi)), static_cast<float>(cos_theta)};
}

/// Adaptive quadrature of a density over cells of the hemisphere, with dw = d(cos theta)
/// d(phi). A cell is split along its longer side (in angle) until a 4 x 4 Gauss-Legendre rule
/// on it agrees with the rule on its halves, and in any case while its radius is above a
/// quarter of its distance to `peak` or of `scale`, whichever is larger: cells shrink
/// geometrically towards the peak, so that a lobe narrower than the first rule's nodes cannot
/// be missed.
template <class Density>
class HemisphereQuadrature {
public:
    HemisphereQuadrature(const Density& density, glm::vec3 peak, float scale)
        : density_(density), peak_{static_cast<double>(peak.x), static_cast<double>(peak.y),
                                   static_cast<double>(peak.z)},
          scale_(static_cast<double>(scale)) {}

    double integrate(const HemisphereCell& cell) const { return refine(cell, rule(cell), 0); }

private:
    static constexpr int max_depth = 40;
    static constexpr double relative_tolerance = 1e-5;
    static constexpr double absolute_tolerance = 1e-10;

    double rule(const HemisphereCell& c) const {
        // 4-point Gauss-Legendre nodes and weights on [-1, 1].
        constexpr std::array<double, 4> x{-0.8611363115940526, -0.3399810435848563,
                                          0.3399810435848563, 0.8611363115940526};
        constexpr std::array<double, 4> w{0.3478548451374538, 0.6521451548625461,
                                          0.6521451548625461, 0.3478548451374538};
        const double hc = 0.5 * (c.cos1 - c.cos0), mc = 0.5 * (c.cos1 + c.cos0);
        const double hp = 0.5 * (c.phi1 - c.phi0), mp = 0.5 * (c.phi1 + c.phi0);
        double sum = 0.0;
        for (std::size_t i = 0; i < 4; ++i)
            for (std::size_t j = 0; j < 4; ++j)
                sum += w[i] * w[j] *
                       static_cast<double>(
                           density_(hemisphere_direction(mc + hc * x[i], mp + hp * x[j])));
        return sum * hc * hp;
    }

    double refine(const HemisphereCell& c, double whole, int depth) const {
        const double theta_extent = std::acos(c.cos0) - std::acos(c.cos1);
        const double sin_max = std::sqrt(std::max(0.0, 1.0 - c.cos0 * c.cos0));
        const double phi_extent = sin_max * (c.phi1 - c.phi0);
        const bool split_cos = theta_extent >= 0.5 * phi_extent;
        const bool split_phi = phi_extent >= 0.5 * theta_extent;
        // Up to four parts: halves in cos theta, then each halved in phi.
        std::array<HemisphereCell, 4> parts{c};
        std::size_t count = 1;
        if (split_cos) {
            const double mid = 0.5 * (c.cos0 + c.cos1);
            parts[0] = {c.cos0, mid, c.phi0, c.phi1};
            parts[1] = {mid, c.cos1, c.phi0, c.phi1};
            count = 2;
        }
        if (split_phi) {
            for (std::size_t i = count; i-- > 0;) {
                const HemisphereCell p = parts[i];
                const double mid = 0.5 * (p.phi0 + p.phi1);
                parts[2 * i] = {p.cos0, p.cos1, p.phi0, mid};
                parts[2 * i + 1] = {p.cos0, p.cos1, mid, p.phi1};
            }
            count *= 2;
        }
        std::array<double, 4> values{};
        double fine = 0.0;
        for (std::size_t i = 0; i < count; ++i) {
            values[i] = rule(parts[i]);
            fine += values[i];
        }
        const double radius = 0.5 * std::hypot(theta_extent, phi_extent);
        const double gap = std::max(angle_to_peak(c) - radius, 0.0);
        const bool near_peak = radius > 0.25 * std::max(gap, scale_);
        const bool converged = std::abs(fine - whole) <=
                               std::max(absolute_tolerance, relative_tolerance * std::abs(fine));
        if (depth >= max_depth || (converged && !near_peak))
            return fine;
        double sum = 0.0;
        for (std::size_t i = 0; i < count; ++i)
            sum += refine(parts[i], values[i], depth + 1);
        return sum;
    }

    double angle_to_peak(const HemisphereCell& c) const {
        const double cos_theta = 0.5 * (c.cos0 + c.cos1), phi = 0.5 * (c.phi0 + c.phi1);
        const double sin_theta = std::sqrt(std::max(0.0, 1.0 - cos_theta * cos_theta));
        const double dot = sin_theta * std::cos(phi) * peak_[0] +
                           sin_theta * std::sin(phi) * peak_[1] + cos_theta * peak_[2];
        return std::acos(std::clamp(dot, -1.0, 1.0));
    }

    const Density& density_;
    std::array<double, 3> peak_;
    double scale_;
};

/// A (cos theta, phi) grid over the upper hemisphere.
struct HemisphereGrid {
    int cos_bins = 16;
    int phi_bins = 32;

    int cell_count() const { return cos_bins * phi_bins; }

    HemisphereCell cell(int index) const {
        const int i = index / phi_bins, j = index % phi_bins;
        const double dphi = 2.0 * std::numbers::pi / phi_bins;
        return {static_cast<double>(i) / cos_bins, static_cast<double>(i + 1) / cos_bins, j * dphi,
                (j + 1) * dphi};
    }

    /// The cell of a direction with z >= 0.
    int index_of(glm::vec3 d) const {
        const double phi = std::atan2(static_cast<double>(d.y), static_cast<double>(d.x));
        const double unit_phi =
            (phi < 0.0 ? phi + 2.0 * std::numbers::pi : phi) / (2.0 * std::numbers::pi);
        const int i =
            std::clamp(static_cast<int>(static_cast<double>(d.z) * cos_bins), 0, cos_bins - 1);
        const int j = std::clamp(static_cast<int>(unit_phi * phi_bins), 0, phi_bins - 1);
        return i * phi_bins + j;
    }
};

/// Draws `count` directions from `draw()` (a std::optional<glm::vec3>, z up; nullopt when the
/// sampler returns no direction) and tests their histogram against `density` at significance
/// `alpha`. `peak` and `scale`: where the density may be narrow, and its angular width.
template <class Draw, class Density>
::testing::AssertionResult samples_fit_density(Draw&& draw, const Density& density, glm::vec3 peak,
                                               float scale, int count, double alpha,
                                               HemisphereGrid grid = {}) {
    const int cells = grid.cell_count();
    std::vector<double> observed(static_cast<std::size_t>(cells) + 1, 0.0);
    for (int k = 0; k < count; ++k) {
        const std::optional<glm::vec3> d = draw();
        if (!d || d->z < 0.0f)
            observed.back() += 1.0;
        else
            observed[static_cast<std::size_t>(grid.index_of(*d))] += 1.0;
    }
    const HemisphereQuadrature<Density> quadrature(density, peak, scale);
    std::vector<double> expected(observed.size(), 0.0);
    double mass = 0.0;
    for (int c = 0; c < cells; ++c) {
        const double m = quadrature.integrate(grid.cell(c));
        expected[static_cast<std::size_t>(c)] = m * count;
        mass += m;
    }
    // The draws without a direction: what the density leaves of 1 (a tiny floor, so that a
    // quadrature total a rounding above 1 does not make such a draw impossible).
    expected.back() = std::max(1.0 - mass, 1e-9) * count;
    const Chi2Result r = pearson_chi2(observed, expected);
    if (r.p_value >= alpha && mass < 1.0 + 1e-4)
        return ::testing::AssertionSuccess();
    return ::testing::AssertionFailure()
           << "density mass " << mass << ", chi-square " << r.statistic << " with "
           << r.degrees_of_freedom << " degrees of freedom, p = " << r.p_value << " < " << alpha
           << "\n"
           << r.histogram;
}

} // namespace restir::test
