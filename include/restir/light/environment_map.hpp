/// @file light/environment_map.hpp
/// An environment light: an equirectangular map of radiance arriving from infinitely far away,
/// looked up piecewise constant and importance-sampled in O(1) in proportion to luminance times
/// solid angle (a marginal alias table over rows, a conditional one per row; the 2D
/// piecewise-constant construction of Pharr, Jakob and Humphreys, "Physically Based Rendering",
/// 3rd ed., section 13.6.7, with Walker's alias tables (Vose's construction,
/// core/alias_buckets.hpp) in place of CDF inversion). The tables have their own 8-byte entry: a
/// draw reads no pmf (the density is the texel's luminance over the map's integral).
#pragma once

#include "restir/config.hpp"
#include "restir/core/alias_buckets.hpp"
#include "restir/core/math.hpp"

#include <glm/vec2.hpp>
#include <glm/vec3.hpp>

#include <cmath>
#include <cstddef>
#include <cstdint>
#include <numbers>
#include <span>
#include <stdexcept>
#include <string>
#include <type_traits>
#include <vector>

namespace restir {

/// A direction drawn from an environment: unit direction towards the sky, the radiance arriving
/// from it (scale applied), and its density per steradian (0 where the map is black).
struct EnvironmentSample {
    glm::vec3 direction{0.0f, 1.0f, 0.0f};
    glm::vec3 radiance{0.0f};
    float pdf = 0.0f; ///< solid angle
};

/// Equirectangular mapping, +Y up: v = theta / pi with theta = acos(d.y) (row 0 at +Y), and
/// u = 0.5 + atan2(d.x, -d.z) / (2 pi) (the image centre looks down -Z, u = 0.75 is +X). This is
/// the map's own frame, before the rotation about +Y. `direction` should be unit length (its y
/// is clamped to [-1, 1]); the result lies in [0, 1]^2.
RESTIR_HOST_DEVICE inline glm::vec2 equirect_uv(glm::vec3 direction) {
    const float y = max_of(-1.0f, min_of(direction.y, 1.0f));
    const float u = 0.5f + std::atan2(direction.x, -direction.z) * (0.5f * inv_pi);
    const float v = std::acos(y) * inv_pi;
    return {max_of(0.0f, min_of(u, 1.0f)), max_of(0.0f, min_of(v, 1.0f))};
}

/// The unit direction at `uv` of the equirectangular mapping (inverse of `equirect_uv`):
/// theta = pi v, phi = 2 pi (u - 0.5), d = (sin theta sin phi, cos theta, -sin theta cos phi).
RESTIR_HOST_DEVICE inline glm::vec3 equirect_direction(glm::vec2 uv) {
    const float theta = pi * uv.y;
    const float phi = two_pi * (uv.x - 0.5f);
    const float sin_theta = std::sin(theta);
    return {sin_theta * std::sin(phi), std::cos(theta), -sin_theta * std::cos(phi)};
}

/// Rec. 709 luminance, the sampling weight of a texel's radiance.
RESTIR_HOST_DEVICE inline float environment_luminance(glm::vec3 radiance) {
    return 0.2126f * radiance.x + 0.7152f * radiance.y + 0.0722f * radiance.z;
}

/// One bucket of the environment map's alias tables (Walker's method): keep the bucket when the
/// bits left of the uniform number after choosing it are below `threshold`, otherwise take
/// `alias`. 8 bytes, so that 8 share a cache line; no pmf, which a draw does not read.
struct EnvironmentAliasEntry {
    float threshold = 1.0f;
    std::uint32_t alias = 0u;
};

static_assert(std::is_trivially_copyable_v<EnvironmentAliasEntry>);
static_assert(sizeof(EnvironmentAliasEntry) == 8);

namespace detail {

/// An alias-table choice made from one uniform number, with what is left of the number.
struct ReusedChoice {
    std::uint32_t index = 0u;
    float rest = 0.0f; ///< In [0, 1): uniform again, independent of the index given it.
};

/// A bucket of a table of `count` entries picked by the top bits of a uniform number u (its 24
/// bits times count, in fixed point), and the bits below them.
struct UniformBucket {
    std::uint32_t index = 0u;    ///< floor(u count), in [0, count).
    std::uint32_t fraction = 0u; ///< In [0, 2^24): the position inside the bucket.
};

RESTIR_HOST_DEVICE inline UniformBucket uniform_bucket(float u, std::uint32_t count) {
    const std::uint64_t scaled = std::uint64_t{unit_bits24(u)} * count;
    return {static_cast<std::uint32_t>(scaled >> 24),
            static_cast<std::uint32_t>(scaled & 0xffffffu)};
}

/// Tests the threshold of `entries[bucket.index]` with the bucket's fraction and remaps what is
/// left after the test to [0, 1) (as pbrt-v4's SampleDiscrete remaps its number): fraction / t
/// when the bucket is kept, (fraction - t) / (1 - t) when its alias is taken.
RESTIR_HOST_DEVICE inline ReusedChoice choose_reusing(const EnvironmentAliasEntry* entries,
                                                      UniformBucket bucket) {
    const EnvironmentAliasEntry entry = entries[bucket.index];
    // Both exact in float: the fraction is below 2^24, the threshold scaled by a power of two.
    const auto fraction = static_cast<float>(bucket.fraction);
    const float threshold = entry.threshold * 16777216.0f;
    const bool keep = fraction < threshold;
    // Kept: fraction < threshold, so the divisor is > 0; aliased: threshold <= fraction < 2^24.
    const float numerator = select_float(keep, fraction, fraction - threshold);
    const float denominator = select_float(keep, threshold, 16777216.0f - threshold);
    const float rest = min_of(numerator / denominator, 0.99999994f);
    return {select_bits(keep, bucket.index, entry.alias), rest};
}

/// sin and cos of `x` in [-pi, pi] (outside it, of x reduced by one quarter turn too few),
/// inline and branch-free: x = k pi / 2 + r with |r| <= pi / 4 (pi / 2 split in two floats so
/// that r keeps its bits), the Taylor polynomials of sin r to r^9 and cos r to r^10 (truncation
/// below 2e-9 on [-pi / 4, pi / 4], under the float rounding), then the quadrant k mod 4 swaps
/// and negates them. Within 1.5e-7 of sin and cos (2 float ulps at 1; tested), inline where the
/// C library's sincosf is a call with a general range reduction (a third of a draw's time).
struct SinCos {
    float sin = 0.0f;
    float cos = 1.0f;
};

RESTIR_HOST_DEVICE inline SinCos sin_cos_half_turn(float x) {
    const float k = std::nearbyint(x * 0.636619772f);           // 2 / pi
    const float r = (x - k * 1.57079637f) + k * 4.37113883e-8f; // pi / 2 = 1.57079637 - 4.37e-8
    const float r2 = r * r;
    const float s =
        r + r * r2 *
                (-1.0f / 6.0f +
                 r2 * (1.0f / 120.0f + r2 * (-1.0f / 5040.0f + r2 * (1.0f / 362880.0f))));
    const float c =
        1.0f + r2 * (-0.5f + r2 * (1.0f / 24.0f +
                                   r2 * (-1.0f / 720.0f +
                                         r2 * (1.0f / 40320.0f + r2 * (-1.0f / 3628800.0f)))));
    const auto quadrant = static_cast<std::uint32_t>(static_cast<std::int32_t>(k)) & 3u;
    const bool swap = (quadrant & 1u) != 0u;
    const float sin_value = select_float(swap, c, s);
    const float cos_value = select_float(swap, s, c);
    // Quadrants 2 and 3 negate sin; 1 and 2 negate cos.
    return {select_float(quadrant >= 2u, -sin_value, sin_value),
            select_float(quadrant == 1u || quadrant == 2u, -cos_value, cos_value)};
}

} // namespace detail

/// Device-callable view over memory the host builder `EnvironmentMap` owns (copy the arrays for
/// a kernel). Trivially copyable; a default-constructed view is empty (black everywhere).
struct EnvironmentMapView {
    /// width * height linear RGB radiance, row-major, row 0 at +Y.
    const glm::vec3* texels = nullptr;
    std::uint32_t width = 0u;
    std::uint32_t height = 0u;
    /// Marginal alias table over rows (`height` entries), weights sum_x luminance * solid angle.
    const EnvironmentAliasEntry* row_table = nullptr;
    /// One conditional alias table per row (`width` entries each, row after row), weights the
    /// texels' luminance; indices are within the row.
    const EnvironmentAliasEntry* column_tables = nullptr;
    /// cos theta at the `height + 1` row boundaries: cos(pi y / height), from 1 down to -1.
    const float* row_cos = nullptr;
    /// 1 / (integral of luminance over the sphere), scale not applied: the density per
    /// steradian is a texel's luminance times this.
    float inverse_luminance_integral = 0.0f;
    float scale = 1.0f; ///< radiance multiplier (--env-scale)
    /// Rotation of the map about +Y (--env-rotate): the map's direction d is seen at world
    /// direction R d, R = [[c, 0, s], [0, 1, 0], [-s, 0, c]] (right-handed, by the angle).
    float rotation_cos = 1.0f;
    float rotation_sin = 0.0f;

    /// No texels: radiance and pdf are 0 everywhere and `sample` returns pdf 0.
    RESTIR_HOST_DEVICE bool empty() const {
        return texels == nullptr || width == 0u || height == 0u;
    }

    /// World direction to the map's own frame (the inverse rotation, R^T d).
    RESTIR_HOST_DEVICE glm::vec3 to_map(glm::vec3 world) const {
        return {rotation_cos * world.x - rotation_sin * world.z, world.y,
                rotation_sin * world.x + rotation_cos * world.z};
    }

    /// The map's own direction to the world (R d).
    RESTIR_HOST_DEVICE glm::vec3 to_world(glm::vec3 map) const {
        return {rotation_cos * map.x + rotation_sin * map.z, map.y,
                -rotation_sin * map.x + rotation_cos * map.z};
    }

    /// Row-major index of the texel that the unit world `direction` falls in (the nearest texel
    /// of the piecewise-constant lookup). Requires !empty().
    RESTIR_HOST_DEVICE std::uint32_t texel_index(glm::vec3 direction) const {
        const glm::vec2 uv = equirect_uv(to_map(direction));
        return uniform_index(uv.y, height) * width + uniform_index(uv.x, width);
    }

    /// Radiance arriving from the unit world `direction`: the texel it falls in, times scale.
    RESTIR_HOST_DEVICE glm::vec3 radiance(glm::vec3 direction) const {
        if (empty())
            return glm::vec3(0.0f);
        return texels[texel_index(direction)] * scale;
    }

    /// Density per steradian with which `sample` returns the unit world `direction`:
    /// luminance(texel) / integral of luminance over the sphere, constant within a texel.
    RESTIR_HOST_DEVICE float pdf(glm::vec3 direction) const {
        if (empty())
            return 0.0f;
        return environment_luminance(texels[texel_index(direction)]) * inverse_luminance_integral;
    }

    /// Asks for the two reads of `sample(u)` that miss the cache in a large map (host
    /// prefetches): the conditional-table entry of u.y's bucket in u.x's row, and its texel.
    RESTIR_HOST_DEVICE RESTIR_FORCE_INLINE void prefetch_sample(glm::vec2 u) const {
        if (empty())
            return;
        const detail::ReusedChoice row =
            detail::choose_reusing(row_table, detail::uniform_bucket(u.x, height));
        const std::size_t bucket =
            std::size_t{row.index} * width + detail::uniform_bucket(u.y, width).index;
        RESTIR_PREFETCH(column_tables + bucket);
        RESTIR_PREFETCH(texels + bucket);
    }

    /// A direction with density `pdf` from exactly two uniform numbers in [0, 1), in O(1): u.x
    /// picks the row (marginal table), u.y the texel in it (its conditional table), and what
    /// each number has left after its choice places the direction uniformly in (phi, cos theta)
    /// inside the texel. Two table reads and one texel read.
    RESTIR_HOST_DEVICE EnvironmentSample sample(glm::vec2 u) const {
        if (empty())
            return {};
        const detail::ReusedChoice row =
            detail::choose_reusing(row_table, detail::uniform_bucket(u.x, height));
        const std::size_t row_start = std::size_t{row.index} * width;
        const detail::UniformBucket column_bucket = detail::uniform_bucket(u.y, width);
        // The texel of the column's own bucket, which it keeps with probability threshold
        // (mostly near 1 in a smooth sky): asked for now, its cache miss overlaps the table
        // entry's instead of following it (host only).
        RESTIR_PREFETCH(texels + row_start + column_bucket.index);
        const detail::ReusedChoice column =
            detail::choose_reusing(column_tables + row_start, column_bucket);
        const float cos_top = row_cos[row.index];
        const float cos_bottom = row_cos[row.index + 1u];
        const float cos_theta = cos_top + row.rest * (cos_bottom - cos_top);
        // (1 - c)(1 + c): no cancellation near the poles.
        const float sin_theta = std::sqrt(max_of(0.0f, (1.0f - cos_theta) * (1.0f + cos_theta)));
        const float phi = (static_cast<float>(column.index) + column.rest) *
                              (two_pi / static_cast<float>(width)) -
                          pi;
        const detail::SinCos turn = detail::sin_cos_half_turn(phi);
        const glm::vec3 map_direction{sin_theta * turn.sin, cos_theta, -sin_theta * turn.cos};
        const glm::vec3 texel = texels[row_start + column.index];
        return {to_world(map_direction), texel * scale,
                environment_luminance(texel) * inverse_luminance_integral};
    }
};

static_assert(std::is_trivially_copyable_v<EnvironmentMapView>);

/// The integral of `view`'s radiance over the sphere, RGB, scale applied (host, O(texels)): the
/// sum over texels of L * (texel solid angle (2 pi / width)(cos theta_top - cos theta_bottom))
/// * scale, in double. 0 for an empty view.
inline glm::vec3 environment_radiance_integral(const EnvironmentMapView& view) {
    if (view.empty())
        return glm::vec3(0.0f);
    glm::dvec3 sum(0.0);
    for (std::uint32_t y = 0; y < view.height; ++y) {
        const double top = std::cos(std::numbers::pi * y / view.height);
        const double bottom = std::cos(std::numbers::pi * (y + 1.0) / view.height);
        glm::dvec3 row(0.0);
        for (std::uint32_t x = 0; x < view.width; ++x)
            row += glm::dvec3(view.texels[std::size_t{y} * view.width + x]);
        sum += row * (2.0 * std::numbers::pi / view.width * (top - bottom));
    }
    return glm::vec3(sum * static_cast<double>(view.scale));
}

/// Host owner and builder of an environment map and its sampling tables. Throws
/// std::invalid_argument with a one-line message for: width or height 0, width * height
/// > 2^27, a texel span whose size is not width * height, a NaN, infinite or negative texel
/// channel (the message names the texel x, y), a map whose luminance is zero everywhere (or
/// whose luminance integral is outside float range), a scale that is not finite and > 0, and a
/// rotation that is not finite.
class EnvironmentMap {
public:
    /// Most texels a map may have (2^27: 1.5 GiB of texels and 2 GiB of tables).
    static constexpr std::uint64_t max_texels = std::uint64_t{1} << 27;

    EnvironmentMap() = default;

    /// Copies `texels` (width * height linear RGB, row-major, row 0 at +Y) and builds the tables
    /// in O(width * height). `rotation_radians` turns the map about +Y (see
    /// `EnvironmentMapView::rotation_cos`).
    EnvironmentMap(std::span<const glm::vec3> texels, std::uint32_t width, std::uint32_t height,
                   float scale = 1.0f, float rotation_radians = 0.0f) {
        validate(texels, width, height, scale, rotation_radians);
        width_ = width;
        height_ = height;
        scale_ = scale;
        rotation_cos_ = static_cast<float>(std::cos(static_cast<double>(rotation_radians)));
        rotation_sin_ = static_cast<float>(std::sin(static_cast<double>(rotation_radians)));
        texels_.assign(texels.begin(), texels.end());
        build_tables();
    }

    /// A view that stays valid while this map lives and is not assigned to.
    EnvironmentMapView view() const {
        if (texels_.empty())
            return {};
        return {texels_.data(),
                width_,
                height_,
                row_table_.data(),
                column_tables_.data(),
                row_cos_.data(),
                inverse_luminance_integral_,
                scale_,
                rotation_cos_,
                rotation_sin_};
    }

    std::uint32_t width() const { return width_; }
    std::uint32_t height() const { return height_; }

    /// The integral of radiance over the sphere, RGB, scale applied: the sum over texels of
    /// L * (texel solid angle) * scale (`environment_radiance_integral`). A sphere of radius R
    /// receives pi R^2 times it from the sky (each direction's parallel beam crosses a disk of
    /// area pi R^2); used for power estimates.
    glm::vec3 radiance_integral() const { return radiance_integral_; }

    /// Bytes of the sampling tables (rows, per-row conditionals, row boundaries), not the
    /// texels: what a draw reads besides one texel.
    std::size_t table_bytes() const {
        return row_table_.size() * sizeof(EnvironmentAliasEntry) +
               column_tables_.size() * sizeof(EnvironmentAliasEntry) +
               row_cos_.size() * sizeof(float);
    }

    /// The texels, for copying to another memory space.
    std::span<const glm::vec3> texels() const { return texels_; }
    /// The marginal table over rows, for copying.
    std::span<const EnvironmentAliasEntry> row_table() const { return row_table_; }
    /// The conditional tables, row after row, for copying.
    std::span<const EnvironmentAliasEntry> column_tables() const { return column_tables_; }
    /// The cos theta of the row boundaries, for copying.
    std::span<const float> row_cos() const { return row_cos_; }

private:
    static void validate(std::span<const glm::vec3> texels, std::uint32_t width,
                         std::uint32_t height, float scale, float rotation_radians) {
        if (width == 0u || height == 0u)
            throw std::invalid_argument("environment map: width and height must be > 0, got " +
                                        std::to_string(width) + " x " + std::to_string(height));
        const std::uint64_t count = std::uint64_t{width} * height;
        if (count > max_texels)
            throw std::invalid_argument("environment map: " + std::to_string(width) + " x " +
                                        std::to_string(height) + " is more than 2^27 texels");
        if (texels.size() != count)
            throw std::invalid_argument("environment map: " + std::to_string(texels.size()) +
                                        " texels given for " + std::to_string(width) + " x " +
                                        std::to_string(height));
        if (!(is_finite(scale) && scale > 0.0f))
            throw std::invalid_argument("environment map: scale must be finite and > 0, got " +
                                        std::to_string(scale));
        if (!is_finite(rotation_radians))
            throw std::invalid_argument("environment map: rotation must be finite");
        for (std::size_t i = 0; i < texels.size(); ++i) {
            const glm::vec3 t = texels[i];
            // is_finite on the bits, and !(c >= 0) also catches NaN.
            if (!(t.x >= 0.0f && t.y >= 0.0f && t.z >= 0.0f && is_finite(t.x) && is_finite(t.y) &&
                  is_finite(t.z)))
                throw std::invalid_argument("environment map: texel (" + std::to_string(i % width) +
                                            ", " + std::to_string(i / width) +
                                            ") has a negative, NaN or infinite channel");
        }
    }

    static double luminance_of(glm::vec3 c) {
        return 0.2126 * static_cast<double>(c.x) + 0.7152 * static_cast<double>(c.y) +
               0.0722 * static_cast<double>(c.z);
    }

    // The alias buckets of `weights` (total > 0) into `out` (`build_alias_buckets`).
    static void build_alias(std::span<const double> weights, EnvironmentAliasEntry* out,
                            AliasScratch& scratch) {
        double total = 0.0;
        for (const double w : weights)
            total += w;
        build_alias_buckets(weights, total, scratch,
                            [out](std::uint32_t i, float threshold, std::uint32_t alias) {
                                out[i] = {threshold, alias};
                            });
    }

    // Per row: the conditional table over its texels' luminance, and the row's weight
    // (sum of luminance) times its texels' solid angle (2 pi / width)(cos top - cos bottom);
    // then the marginal table over the rows' weights.
    void build_tables() {
        const std::size_t w = width_;
        row_cos_.resize(std::size_t{height_} + 1u);
        for (std::uint32_t y = 0; y <= height_; ++y)
            row_cos_[y] =
                static_cast<float>(std::cos(std::numbers::pi * static_cast<double>(y) / height_));
        row_cos_.front() = 1.0f;
        row_cos_.back() = -1.0f;
        column_tables_.assign(w * height_, EnvironmentAliasEntry{});
        std::vector<double> row_weight(height_, 0.0), luminance(w);
        AliasScratch scratch;
        double luminance_integral = 0.0;
        for (std::uint32_t y = 0; y < height_; ++y) {
            const double top = std::cos(std::numbers::pi * y / height_);
            const double bottom = std::cos(std::numbers::pi * (y + 1.0) / height_);
            const double solid_angle =
                2.0 * std::numbers::pi / static_cast<double>(w) * (top - bottom);
            const glm::vec3* row = texels_.data() + y * w;
            double luminance_sum = 0.0;
            for (std::size_t x = 0; x < w; ++x) {
                luminance[x] = luminance_of(row[x]);
                luminance_sum += luminance[x];
            }
            row_weight[y] = luminance_sum * solid_angle;
            luminance_integral += row_weight[y];
            // A black row keeps its default entries: the marginal never picks it.
            if (luminance_sum > 0.0)
                build_alias(luminance, column_tables_.data() + y * w, scratch);
        }
        if (!(luminance_integral > 0.0))
            throw std::invalid_argument("environment map: the luminance is zero everywhere");
        const auto inverse = static_cast<float>(1.0 / luminance_integral);
        if (!(is_finite(inverse) && inverse > 0.0f &&
              is_finite(static_cast<float>(luminance_integral))))
            throw std::invalid_argument(
                "environment map: the luminance integral is outside float range");
        inverse_luminance_integral_ = inverse;
        row_table_.assign(height_, EnvironmentAliasEntry{});
        build_alias(row_weight, row_table_.data(), scratch);
        radiance_integral_ = environment_radiance_integral(view());
    }

    std::vector<glm::vec3> texels_;
    std::vector<EnvironmentAliasEntry> row_table_;
    std::vector<EnvironmentAliasEntry> column_tables_;
    std::vector<float> row_cos_;
    std::uint32_t width_ = 0u;
    std::uint32_t height_ = 0u;
    float scale_ = 1.0f;
    float rotation_cos_ = 1.0f;
    float rotation_sin_ = 0.0f;
    float inverse_luminance_integral_ = 0.0f;
    glm::vec3 radiance_integral_{0.0f};
};

} // namespace restir
