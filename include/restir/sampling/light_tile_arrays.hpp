/// @file sampling/light_tile_arrays.hpp
/// Presampled light tiles (sampling/light_tiles.hpp) in a structure-of-arrays layout for
/// batch RIS (sampling/ris_batch.hpp): entries keep one array per quantity in groups of 8, so
/// that the target values of a block of consecutive entries are one plain loop over floats
/// that the compiler vectorises. Every entry is folded as `folded_irradiance_factor` wants it,
/// which makes area lights, VPLs and point lights one formula without branches.
#pragma once

#include "restir/config.hpp"
#include "restir/core/channels.hpp"
#include "restir/core/math.hpp"
#include "restir/light/falloff.hpp"
#include "restir/light/irradiance.hpp"
#include "restir/light/light_point_sample.hpp"
#include "restir/light/light_sample.hpp"
#include "restir/light/receiver.hpp"
#include "restir/sampling/light_tiles.hpp"
#include "restir/sampling/ris_batch.hpp"

#include <glm/vec3.hpp>

#include <cmath>
#include <concepts>
#include <cstdint>
#include <type_traits>

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
    yuksel_radius_squared, ///< r^2 of Yuksel's falloff for delta lights, else 0.
    /// d_min^2 of the clamped falloff for delta lights, 0 for area lights, and -1 for a distant
    /// light's direction (`LightPointSample::positional` 0: the receiver's position is not
    /// subtracted from it), which needs no plane of its own.
    min_distance_squared,
    inverse_pdf, ///< 1 / p of the entry's source density (0 if p = 0).
    /// 1 / area_pdf of the entry's point on its light (per steradian for a distant light's
    /// direction); 0 for a delta light. What turns another strategy's density (a BSDF's, in
    /// the area measure) into the entry's measure, for MIS (sampling/tile_bsdf_candidates.hpp).
    inverse_point_pdf,
    count
};

inline constexpr std::uint32_t tile_plane_count = static_cast<std::uint32_t>(TilePlane::count);

namespace detail {
/// `LightPointSample::positional` of a tile entry from its min_distance_squared plane: 0 for a
/// distant light's direction (stored as -1), 1 for a point.
RESTIR_HOST_DEVICE constexpr float tile_positional(float min_distance_squared) noexcept {
    return min_distance_squared < 0.0f ? 0.0f : 1.0f;
}

} // namespace detail

/// Entries are stored in groups of this many consecutive ones; a batch-RIS block covers whole
/// groups.
inline constexpr std::uint32_t tile_group_size = 8u;

/// `tile_count` tiles of `tile_size` presampled lights (a multiple of `tile_group_size`), as
/// planes of floats in groups ("array of structures of arrays"): the entries are cut into
/// groups of `tile_group_size` consecutive ones, and group g keeps its planes one after the
/// other, plane k of it at floats [(g * tile_plane_count + k) * tile_group_size, ... +
/// tile_group_size) of `planes`. A group is 448 contiguous bytes (7 cache lines), so a block of
/// candidates reads neighbouring lines rather than one line in each of 14 distant arrays.
/// `references` holds the entries' light references in entry order. A view over the caller's memory
/// (device memory for a kernel, `planes` 16-byte aligned: device code reads it in 16-byte
/// loads); the caller refills it every frame.
struct LightTileArrays {
    float* planes = nullptr;
    LightSampleRef* references = nullptr;
    std::uint32_t tile_count = 0u;
    std::uint32_t tile_size = 0u;

    /// Number of floats `planes` must hold.
    RESTIR_HOST_DEVICE constexpr std::uint64_t plane_float_count() const noexcept {
        return std::uint64_t{tile_count} * tile_size * tile_plane_count;
    }

    /// Plane `plane` of the group that starts at global entry `entry` (a multiple of
    /// `tile_group_size`): `tile_group_size` floats.
    RESTIR_HOST_DEVICE constexpr float* group_plane(std::uint64_t entry,
                                                    TilePlane plane) const noexcept {
        return planes +
               (entry / tile_group_size * tile_plane_count + static_cast<std::uint32_t>(plane)) *
                   tile_group_size;
    }

    /// Value of plane `plane` for global entry `entry` (tile t's entries are [t * tile_size,
    /// (t + 1) * tile_size)).
    RESTIR_HOST_DEVICE constexpr float& value(std::uint64_t entry, TilePlane plane) const noexcept {
        return group_plane(entry - entry % tile_group_size, plane)[entry % tile_group_size];
    }

    /// The tile that a group of pixels uses in `frame` (the hash of `LightTilesView::tile_for`).
    RESTIR_HOST_DEVICE constexpr std::uint32_t tile_for(std::uint32_t group,
                                                        std::uint32_t frame) const noexcept {
        return LightTilesView{nullptr, tile_count, tile_size}.tile_for(group, frame);
    }

    /// Entry `entry` (a global index, as `evaluate_tile_block` hands out) as a light sample with
    /// its point, for reservoirs that reuse it without light lookups.
    RESTIR_HOST_DEVICE LightPointSample point_sample(std::uint32_t entry) const {
        const auto get = [&](TilePlane k) { return value(entry, k); };
        LightPointSample s;
        s.light_id = references[entry].light_id;
        s.position = {get(TilePlane::position_x), get(TilePlane::position_y),
                      get(TilePlane::position_z)};
        s.normal = {get(TilePlane::normal_x), get(TilePlane::normal_y), get(TilePlane::normal_z)};
        s.intensity = {get(TilePlane::radiance_r), get(TilePlane::radiance_g),
                       get(TilePlane::radiance_b)};
        const float radius2 = get(TilePlane::yuksel_radius_squared);
        const float min_distance2 = get(TilePlane::min_distance_squared);
        s.falloff = radius2 > 0.0f ? radius2 : -max_of(min_distance2, 0.0f);
        s.positional = detail::tile_positional(min_distance2);
        return s;
    }

    /// Stores `entry` as entry `index` (in [0, tile_size)) of tile `tile`, with the falloff
    /// its delta lights use.
    RESTIR_HOST_DEVICE void store(std::uint32_t tile, std::uint32_t index,
                                  const PresampledLight& entry, const Falloff& falloff) const {
        const LightPointSample s =
            make_light_point_sample(entry.reference.light_id, entry.point, falloff);
        const bool usable = entry.pdf > 0.0f;
        const bool isotropic = s.normal.x == 0.0f && s.normal.y == 0.0f && s.normal.z == 0.0f;
        const std::uint64_t global = std::uint64_t{tile} * tile_size + index;
        const auto put = [&](TilePlane k, float v) { value(global, k) = v; };
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
        put(TilePlane::min_distance_squared, s.is_distant() ? -1.0f : max_of(-s.falloff, 0.0f));
        put(TilePlane::inverse_pdf, usable ? 1.0f / entry.pdf : 0.0f);
        const bool has_measure = usable && !entry.point.is_delta && entry.point.area_pdf > 0.0f;
        put(TilePlane::inverse_point_pdf, has_measure ? 1.0f / entry.point.area_pdf : 0.0f);
        references[global] = entry.reference;
    }
};

namespace detail {
/// p-hat of one tile entry at a receiver, from its plane values `value(TilePlane)`.
template <ChannelNorm Norm, class Value>
RESTIR_HOST_DEVICE float tile_entry_target(const Value& value, glm::vec3 position, glm::vec3 normal,
                                           glm::vec3 channel_weights) {
    // x = position - positional * receiver: a distant light's direction is the same from
    // every receiver. A negative min_distance_squared (a distant light's) clamps nothing.
    const float positional = tile_positional(value(TilePlane::min_distance_squared));
    const float factor = folded_irradiance_factor(
        value(TilePlane::position_x) - positional * position.x,
        value(TilePlane::position_y) - positional * position.y,
        value(TilePlane::position_z) - positional * position.z, normal, value(TilePlane::normal_x),
        value(TilePlane::normal_y), value(TilePlane::normal_z), value(TilePlane::isotropic),
        value(TilePlane::yuksel_radius_squared), value(TilePlane::min_distance_squared));
    const float intensity = fold_channels<Norm>({channel_weights.x * value(TilePlane::radiance_r),
                                                 channel_weights.y * value(TilePlane::radiance_g),
                                                 channel_weights.z * value(TilePlane::radiance_b)});
    const float v = intensity * factor;
    return is_valid_weight(v) ? v : 0.0f;
}

/// The offset x = position - positional * receiver from a receiver at `position` to a tile
/// entry, its squared length and one over its length (0 at 0).
struct TileOffset {
    float x, y, z, d2, inverse_distance;
};

template <class Value>
RESTIR_HOST_DEVICE RESTIR_FORCE_INLINE TileOffset tile_entry_offset(const Value& value,
                                                                    glm::vec3 position) {
    const float positional = tile_positional(value(TilePlane::min_distance_squared));
    const float x = value(TilePlane::position_x) - positional * position.x;
    const float y = value(TilePlane::position_y) - positional * position.y;
    const float z = value(TilePlane::position_z) - positional * position.z;
    const float d2 = x * x + y * y + z * z;
    return {x, y, z, d2, d2 > 0.0f ? 1.0f / std::sqrt(d2) : 0.0f};
}

/// p-hat of one tile entry at any receiver: its unshadowed radiance, folded.
template <ChannelNorm Norm, class Value, class R>
RESTIR_HOST_DEVICE RESTIR_FORCE_INLINE float
tile_entry_radiance_target(const Value& value, glm::vec3 position, const R& receiver) {
    const auto [x, y, z, d2, inverse_distance] = tile_entry_offset(value, position);
    const float factor = folded_arrival_factor(
        x, y, z, value(TilePlane::normal_x), value(TilePlane::normal_y), value(TilePlane::normal_z),
        value(TilePlane::isotropic), value(TilePlane::yuksel_radius_squared),
        value(TilePlane::min_distance_squared), inverse_distance);
    const glm::vec3 wi{x * inverse_distance, y * inverse_distance, z * inverse_distance};
    const float sphere_radius =
        std::sqrt(value(TilePlane::yuksel_radius_squared)) * inverse_distance;
    const glm::vec3 f =
        reflected_from(receiver, wi, sphere_radius, value(TilePlane::min_distance_squared) > 0.0f);
    const float v =
        fold_channels<Norm>({f.x * value(TilePlane::radiance_r), f.y * value(TilePlane::radiance_g),
                             f.z * value(TilePlane::radiance_b)}) *
        factor;
    return is_valid_weight(v) ? v : 0.0f;
}

/// One lane of a `CandidateBlock`: p-hat and the inverse source density.
struct TileLane {
    float target;
    float inverse_pdf;
};

/// The lane of the entry whose plane values `value(TilePlane)` reads, with target `target`
/// and the entry's own inverse pdf.
template <class Value>
RESTIR_HOST_DEVICE TileLane tile_lane(const Value& value, float target) {
    return {target, value(TilePlane::inverse_pdf)};
}

#if defined(__CUDA_ARCH__)
/// Device code's part of `evaluate_tile_block_with`: the `lanes` lanes of one group whose planes
/// start at `planes` (each `tile_group_size` floats), into lanes [offset, offset + lanes) of
/// `block`. Up to four lanes at a time, each plane's values in one load (16 bytes for four)
/// through the read-only cache: a thread reads its block's bytes once. (With 4-byte loads of
/// eight lanes a 32-byte sector may be fetched from L2 once per lane, since L1 cannot hold every
/// thread's block; docs/performance.md, "GPU".)
template <std::uint32_t lanes, std::uint32_t Size, class LaneOf>
RESTIR_HOST_DEVICE RESTIR_FORCE_INLINE void
evaluate_tile_lanes_on_device(const float* planes, std::uint32_t offset,
                              CandidateBlock<Size>& block, const LaneOf& lane_of) {
    constexpr std::uint32_t width = lanes < 4u ? lanes : 4u;
    using Vector =
        std::conditional_t<width == 4u, float4, std::conditional_t<width == 2u, float2, float>>;
    RESTIR_ASSERT(reinterpret_cast<std::uintptr_t>(planes) % sizeof(Vector) == 0u);
    for (std::uint32_t quad = 0; quad < lanes; quad += width) {
        Vector values[tile_plane_count];
        for (std::uint32_t k = 0; k < tile_plane_count; ++k)
            values[k] = __ldg(reinterpret_cast<const Vector*>(planes + k * tile_group_size + quad));
        for (std::uint32_t j = 0; j < width; ++j) {
            const auto value = [&](TilePlane k) {
                const Vector& v = values[static_cast<std::uint32_t>(k)];
                if constexpr (width == 4u)
                    return j == 0u ? v.x : j == 1u ? v.y : j == 2u ? v.z : v.w;
                else if constexpr (width == 2u)
                    return j == 0u ? v.x : v.y;
                else
                    return v;
            };
            const TileLane lane = lane_of(value);
            block.target[offset + quad + j] = lane.target;
            block.inverse_pdf[offset + quad + j] = lane.inverse_pdf;
        }
    }
}
#endif

/// The loop of `evaluate_tile_block`: `lane_of(value)` is the `TileLane` of the entry whose
/// plane values `value(TilePlane)` reads. A block covers whole groups, or `Size` (1, 2 or 4)
/// consecutive entries inside one group.
template <std::uint32_t Size, class LaneOf>
RESTIR_HOST_DEVICE std::uint32_t
evaluate_tile_block_with(const LightTileArrays& tiles, std::uint32_t tile, std::uint32_t first,
                         CandidateBlock<Size>& block, const LaneOf& lane_of) {
    static_assert(Size % tile_group_size == 0u || tile_group_size % Size == 0u,
                  "blocks cover whole groups of tile entries, or a part of one");
    // Entries of one group that a block reads: all of them, or its own `Size`.
    constexpr std::uint32_t lanes = Size < tile_group_size ? Size : tile_group_size;
    RESTIR_ASSERT(tile < tiles.tile_count && first + Size <= tiles.tile_size &&
                  first % lanes == 0u);
    const std::uint32_t base = tile * tiles.tile_size + first;
    for (std::uint32_t group = 0; group < Size / lanes; ++group) {
        const std::uint64_t entry = std::uint64_t{base} + group * lanes;
        const std::uint32_t lane0 = static_cast<std::uint32_t>(entry % tile_group_size);
        // The group's planes lie one after the other, `tile_group_size` floats each; the
        // block's lanes start at `lane0` in each.
        const float* planes = tiles.group_plane(entry - lane0, TilePlane::position_x) + lane0;
#if defined(__CUDA_ARCH__)
        evaluate_tile_lanes_on_device<lanes>(planes, group * lanes, block, lane_of);
#else
        // Results go to local arrays first: `block` could alias the planes as far as the
        // compiler knows, and it will not check the planes for overlap at run time, so it
        // would not vectorise the loop.
        float target[lanes];
        float weight_scale[lanes];
        for (std::uint32_t i = 0; i < lanes; ++i) {
            const auto value = [&](TilePlane k) {
                return planes[static_cast<std::uint32_t>(k) * tile_group_size + i];
            };
            const TileLane lane = lane_of(value);
            target[i] = lane.target;
            weight_scale[i] = lane.inverse_pdf;
        }
        for (std::uint32_t i = 0; i < lanes; ++i) {
            block.target[group * lanes + i] = target[i];
            block.inverse_pdf[group * lanes + i] = weight_scale[i];
        }
#endif
    }
    return base;
}

} // namespace detail

/// Target values of the `Size` consecutive entries [first, first + Size) of tile `tile` at a
/// receiver (`position`, `normal`): p-hat_i = fold_channels<Norm>(channel_weights * E_i), E_i
/// the unshadowed irradiance (`folded_irradiance_factor` times the entry's intensity;
/// channel_weights = albedo / pi gives a diffuse receiver's reflected radiance; with
/// ChannelNorm::sum, dot(channel_weights, E_i)). `Size` and `first` are multiples of
/// `tile_group_size` (whole groups), or `Size` is 1, 2 or 4 and `first` a multiple of it (a
/// part of one group: pixels that take different parts of the same groups read the same cache
/// lines, yet their candidates are different entries). Fills `block` and returns the global
/// entry index of its lane 0, as `resample_ris_batch` expects. In device code `tiles.planes`
/// must be 16-byte aligned (as cudaMalloc's memory is): each plane's lanes are read as loads of
/// up to 16 bytes.
template <std::uint32_t Size, ChannelNorm Norm = ChannelNorm::sum>
RESTIR_HOST_DEVICE std::uint32_t
evaluate_tile_block(const LightTileArrays& tiles, std::uint32_t tile, std::uint32_t first,
                    glm::vec3 position, glm::vec3 normal, glm::vec3 channel_weights,
                    CandidateBlock<Size>& block) {
    return detail::evaluate_tile_block_with(tiles, tile, first, block, [&](const auto& value) {
        return detail::tile_lane(
            value, detail::tile_entry_target<Norm>(value, position, normal, channel_weights));
    });
}

/// The same at any `Receiver`: p-hat_i = fold_channels<Norm>(E_i cos(theta_light) falloff
/// f(wo, wi) max(0, n.wi)), the entry's unshadowed radiance towards the receiver's viewer
/// (`unshadowed_radiance`). A `LambertianReceiver` takes the folded diffuse form above; any
/// other calls `receiver.reflected(wi)` once per lane inside the loop, which stays one
/// vectorised loop when `reflected` has no branches.
template <std::uint32_t Size, ChannelNorm Norm = ChannelNorm::sum, Receiver R>
RESTIR_HOST_DEVICE std::uint32_t
evaluate_tile_block(const LightTileArrays& tiles, std::uint32_t tile, std::uint32_t first,
                    const R& receiver, CandidateBlock<Size>& block) {
    if constexpr (std::same_as<R, LambertianReceiver>) {
        return evaluate_tile_block<Size, Norm>(tiles, tile, first, receiver.position,
                                               receiver.normal, receiver.albedo * inv_pi, block);
    } else {
        const glm::vec3 position = receiver.position;
        return detail::evaluate_tile_block_with(tiles, tile, first, block, [&](const auto& value) {
            return detail::tile_lane(
                value, detail::tile_entry_radiance_target<Norm>(value, position, receiver));
        });
    }
}

} // namespace restir
