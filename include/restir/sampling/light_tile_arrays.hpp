/// @file sampling/light_tile_arrays.hpp
/// Presampled light tiles (sampling/light_tiles.hpp) in a structure-of-arrays layout for
/// batch RIS (sampling/ris_batch.hpp): each tile keeps one contiguous array per quantity, so
/// that the target values of a block of consecutive entries are one plain loop over floats
/// that the compiler vectorises. Every entry is folded as `folded_irradiance_factor` wants it,
/// which makes area lights, VPLs and point lights one formula without branches.
#pragma once

#include "restir/config.hpp"
#include "restir/core/math.hpp"
#include "restir/light/attenuation.hpp"
#include "restir/light/irradiance.hpp"
#include "restir/light/light_point_sample.hpp"
#include "restir/light/light_sample.hpp"
#include "restir/sampling/light_tiles.hpp"
#include "restir/sampling/ris_batch.hpp"

#include <glm/vec3.hpp>

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
    delta,                  ///< 1 for a delta light (only `point_sample` reads it).
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

    /// Entry `entry` (a global index, as `evaluate_tile_block` hands out) as a light sample with
    /// its point, for reservoirs that reuse it without light lookups.
    RESTIR_HOST_DEVICE LightPointSample point_sample(std::uint32_t entry) const {
        const std::uint32_t tile = entry / tile_size;
        const std::uint32_t index = entry % tile_size;
        const auto get = [&](TilePlane k) { return plane(tile, k)[index]; };
        LightPointSample s;
        s.reference = references[entry];
        s.position = {get(TilePlane::position_x), get(TilePlane::position_y),
                      get(TilePlane::position_z)};
        s.normal = {get(TilePlane::normal_x), get(TilePlane::normal_y), get(TilePlane::normal_z)};
        s.intensity = {get(TilePlane::radiance_r), get(TilePlane::radiance_g),
                       get(TilePlane::radiance_b)};
        const float radius2 = get(TilePlane::yuksel_radius_squared);
        s.falloff = radius2 > 0.0f ? radius2 : -get(TilePlane::min_distance_squared);
        s.is_delta = get(TilePlane::delta) != 0.0f;
        return s;
    }

    /// Stores `entry` as entry `index` (in [0, tile_size)) of tile `tile`, with the falloff
    /// its delta lights use.
    RESTIR_HOST_DEVICE void store(std::uint32_t tile, std::uint32_t index,
                                  const PresampledLight& entry, const Falloff& falloff) const {
        const LightPointSample s = make_light_point_sample(entry.reference, entry.point, falloff);
        const bool usable = entry.pdf > 0.0f;
        const bool isotropic = s.normal.x == 0.0f && s.normal.y == 0.0f && s.normal.z == 0.0f;
        const auto put = [&](TilePlane k, float value) { plane(tile, k)[index] = value; };
        put(TilePlane::position_x, s.position.x);
        put(TilePlane::position_y, s.position.y);
        put(TilePlane::position_z, s.position.z);
        put(TilePlane::normal_x, s.normal.x);
        put(TilePlane::normal_y, s.normal.y);
        put(TilePlane::normal_z, s.normal.z);
        put(TilePlane::isotropic, isotropic ? 1.0f : 0.0f);
        put(TilePlane::radiance_r, usable ? s.intensity.x : 0.0f);
        put(TilePlane::radiance_g, usable ? s.intensity.y : 0.0f);
        put(TilePlane::radiance_b, usable ? s.intensity.z : 0.0f);
        put(TilePlane::yuksel_radius_squared, max_of(s.falloff, 0.0f));
        put(TilePlane::min_distance_squared, max_of(-s.falloff, 0.0f));
        put(TilePlane::inverse_pdf, usable ? 1.0f / entry.pdf : 0.0f);
        put(TilePlane::delta, s.is_delta ? 1.0f : 0.0f);
        references[std::uint64_t{tile} * tile_size + index] = entry.reference;
    }
};

/// Target values of the `Size` consecutive entries [first, first + Size) of tile `tile` at a
/// receiver (`position`, `normal`): p-hat_i = dot(channel_weights, E_i), E_i the unshadowed
/// irradiance (`folded_irradiance_factor` times the entry's intensity; channel_weights =
/// albedo / pi gives the channel sum of a diffuse receiver's reflected radiance). Fills
/// `block` and returns the global entry index of its lane 0, as `resample_ris_batch` expects.
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
        const float factor = folded_irradiance_factor(
            px[i] - position.x, py[i] - position.y, pz[i] - position.z, normal, nx[i], ny[i],
            nz[i], isotropic[i], radius2[i], min_distance2[i]);
        const float intensity =
            channel_weights.x * red[i] + channel_weights.y * green[i] + channel_weights.z * blue[i];
        const float target = intensity * factor;
        block.target[i] = is_valid_weight(target) ? target : 0.0f;
        block.inverse_pdf[i] = inverse_pdf[i];
    }
    return tile * tiles.tile_size + first;
}

} // namespace restir
