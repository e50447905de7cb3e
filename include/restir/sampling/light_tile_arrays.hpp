/// @file sampling/light_tile_arrays.hpp
/// Presampled light tiles (sampling/light_tiles.hpp) in a structure-of-arrays layout for
/// batch RIS (sampling/ris_batch.hpp): each tile keeps one contiguous array per quantity, so
/// that the target values of a block of consecutive entries are one plain loop over floats
/// that the compiler vectorises. Every entry folds its falloff into two numbers, which makes
/// area lights, VPLs and point lights one formula without branches.
#pragma once

#include "restir/config.hpp"
#include "restir/core/math.hpp"
#include "restir/light/attenuation.hpp"
#include "restir/light/irradiance.hpp"
#include "restir/light/light_sample.hpp"
#include "restir/sampling/light_tiles.hpp"
#include "restir/sampling/ris_batch.hpp"

#include <glm/vec3.hpp>

#include <cmath>
#include <cstdint>

namespace restir {

/// The arrays of one tile entry, in the order they are stored.
enum class TilePlane : std::uint32_t {
    position_x,
    position_y,
    position_z,
    normal_x,
    normal_y,
    normal_z,
    isotropic,  ///< 1 for a light that emits the same in every direction (zero normal), else 0.
    radiance_r, ///< Radiance / area_pdf for area lights, intensity for delta lights.
    radiance_g,
    radiance_b,
    yuksel_radius_squared,  ///< r^2 of Yuksel's falloff for delta lights, else 0.
    min_distance_squared,   ///< d_min^2 of the clamped falloff for delta lights, else 0.
    inverse_pdf,            ///< 1 / p of the entry's source density (0 if p = 0).
    count
};

inline constexpr std::uint32_t tile_plane_count = static_cast<std::uint32_t>(TilePlane::count);

/// `tile_count` tiles of `tile_size` presampled lights as planes of floats: tile t occupies
/// floats [t * tile_size * tile_plane_count, (t + 1) * tile_size * tile_plane_count) of
/// `planes`, plane k of it starting at k * tile_size there. `references` holds the entries'
/// light references in entry order. A view over the caller's memory (device memory for a
/// kernel); the caller refills it every frame.
struct LightTileArrays {
    float* planes = nullptr;
    LightSampleRef* references = nullptr;
    std::uint32_t tile_count = 0u;
    std::uint32_t tile_size = 0u;

    /// Number of floats `planes` must hold.
    RESTIR_HOST_DEVICE constexpr std::uint64_t plane_float_count() const noexcept {
        return std::uint64_t{tile_count} * tile_size * tile_plane_count;
    }

    /// Plane `plane` of tile `tile`.
    RESTIR_HOST_DEVICE constexpr float* plane(std::uint32_t tile, TilePlane plane) const noexcept {
        return planes + (std::uint64_t{tile} * tile_plane_count + static_cast<std::uint32_t>(plane)) *
                            tile_size;
    }

    /// The tile that a group of pixels uses in `frame` (the hash of `LightTilesView::tile_for`).
    RESTIR_HOST_DEVICE constexpr std::uint32_t tile_for(std::uint32_t group,
                                                        std::uint32_t frame) const noexcept {
        return LightTilesView{nullptr, tile_count, tile_size}.tile_for(group, frame);
    }

    /// Stores `entry` as entry `index` (in [0, tile_size)) of tile `tile`, with the falloff
    /// its delta lights use.
    RESTIR_HOST_DEVICE void store(std::uint32_t tile, std::uint32_t index,
                                  const PresampledLight& entry, const Falloff& falloff) const {
        const LightSample& p = entry.point;
        const bool usable = entry.pdf > 0.0f && (p.is_delta || p.area_pdf > 0.0f);
        const float scale = !usable ? 0.0f : p.is_delta ? 1.0f : 1.0f / p.area_pdf;
        const float parameter_squared = falloff.parameter * falloff.parameter;
        const bool isotropic = p.normal.x == 0.0f && p.normal.y == 0.0f && p.normal.z == 0.0f;
        const auto put = [&](TilePlane k, float value) { plane(tile, k)[index] = value; };
        put(TilePlane::position_x, p.position.x);
        put(TilePlane::position_y, p.position.y);
        put(TilePlane::position_z, p.position.z);
        put(TilePlane::normal_x, p.normal.x);
        put(TilePlane::normal_y, p.normal.y);
        put(TilePlane::normal_z, p.normal.z);
        put(TilePlane::isotropic, isotropic ? 1.0f : 0.0f);
        put(TilePlane::radiance_r, p.radiance.x * scale);
        put(TilePlane::radiance_g, p.radiance.y * scale);
        put(TilePlane::radiance_b, p.radiance.z * scale);
        put(TilePlane::yuksel_radius_squared,
            p.is_delta && falloff.kind == Attenuation::yuksel ? parameter_squared : 0.0f);
        put(TilePlane::min_distance_squared,
            p.is_delta && falloff.kind == Attenuation::clamped_inverse_square ? parameter_squared
                                                                              : 0.0f);
        put(TilePlane::inverse_pdf, usable ? 1.0f / entry.pdf : 0.0f);
        references[std::uint64_t{tile} * tile_size + index] = entry.reference;
    }
};

/// Target values of the `Size` consecutive entries [first, first + Size) of tile `tile` at a
/// receiver (`position`, `normal`): p-hat_i = dot(channel_weights, E_i), where E_i is the
/// unshadowed irradiance of `unshadowed_irradiance` (channel_weights = albedo / pi gives the
/// channel sum of a diffuse receiver's reflected radiance). Fills `block` and returns the
/// global entry index of its lane 0, as `resample_ris_batch` expects. Per lane, with
/// x = p - position, d^2 = x.x and e = max(d^2, d_min^2):
///   E = I max(0, n.x) C / (d^2 D),   C = max(0, -n_l.x) (oriented) or d (isotropic),
///   D = (e + r^2 + sqrt(e (e + r^2))) / 2,
/// which is Yuksel's 2 / (d^2 + r^2 + d sqrt(d^2 + r^2)) for r > 0 (d sqrt(d^2 + r^2) written
/// as one square root), the clamped inverse square for d_min > 0, and 1/d^2 otherwise (area
/// lights, whose 1 / area_pdf is folded into I).
template <std::uint32_t Size>
RESTIR_HOST_DEVICE std::uint32_t evaluate_tile_block(const LightTileArrays& tiles,
                                                     std::uint32_t tile, std::uint32_t first,
                                                     glm::vec3 position, glm::vec3 normal,
                                                     glm::vec3 channel_weights,
                                                     CandidateBlock<Size>& block) {
    RESTIR_ASSERT(tile < tiles.tile_count && first + Size <= tiles.tile_size);
    const auto at = [&](TilePlane k) { return tiles.plane(tile, k) + first; };
    const float* px = at(TilePlane::position_x);
    const float* py = at(TilePlane::position_y);
    const float* pz = at(TilePlane::position_z);
    const float* nx = at(TilePlane::normal_x);
    const float* ny = at(TilePlane::normal_y);
    const float* nz = at(TilePlane::normal_z);
    const float* isotropic = at(TilePlane::isotropic);
    const float* red = at(TilePlane::radiance_r);
    const float* green = at(TilePlane::radiance_g);
    const float* blue = at(TilePlane::radiance_b);
    const float* radius2 = at(TilePlane::yuksel_radius_squared);
    const float* min_distance2 = at(TilePlane::min_distance_squared);
    const float* inverse_pdf = at(TilePlane::inverse_pdf);
    for (std::uint32_t i = 0; i < Size; ++i) {
        const float x = px[i] - position.x;
        const float y = py[i] - position.y;
        const float z = pz[i] - position.z;
        const float d2 = x * x + y * y + z * z;
        const float receiver = max_of(0.0f, normal.x * x + normal.y * y + normal.z * z);
        const float emitter = max_of(0.0f, -(nx[i] * x + ny[i] * y + nz[i] * z)) +
                              isotropic[i] * std::sqrt(d2);
        const float e = max_of(d2, min_distance2[i]);
        const float denominator = d2 * (e + radius2[i] + std::sqrt(e * (e + radius2[i])));
        const float intensity =
            channel_weights.x * red[i] + channel_weights.y * green[i] + channel_weights.z * blue[i];
        const float target = 2.0f * intensity * receiver * emitter / denominator;
        block.target[i] = is_valid_weight(target) ? target : 0.0f;
        block.inverse_pdf[i] = inverse_pdf[i];
    }
    return tile * tiles.tile_size + first;
}

} // namespace restir
