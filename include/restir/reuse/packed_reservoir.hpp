/// @file reuse/packed_reservoir.hpp
/// Storage forms of reservoirs for the history that temporal reuse reads: a
/// `Reservoir<LightSampleRef>` in 20 bytes instead of 28, a `Reservoir<LightPointSample>` in 28
/// instead of 64, and histories of them with a light-id translation (or a light decoder).
#pragma once

#include "restir/concepts.hpp"
#include "restir/config.hpp"
#include "restir/core/math.hpp"
#include "restir/core/reservoir.hpp"
#include "restir/light/light_point_sample.hpp"
#include "restir/light/light_sample.hpp"
#include "restir/reuse/history.hpp"
#include "restir/reuse/image_view.hpp"

#include <glm/vec3.hpp>

#include <cstdint>
#include <type_traits>

namespace restir {

/// A stored reservoir: what reuse reads of it (the sample, W, p-hat at its own surface and
/// M), without the weight sum. The uv keeps 24 bits per coordinate, all that `next_float`
/// draws, so a sample drawn from the library's generators comes back exactly; other uv values
/// are truncated to a multiple of 2^-24. M saturates at 65535.
struct PackedReservoir {
    std::uint32_t light_id = 0u;
    std::uint32_t u_and_v_low = 0u;   ///< u's 24 bits, then v's low 8 bits.
    std::uint32_t v_high_and_m = 0u;  ///< v's high 16 bits, then M's 16 bits.
    float contribution_weight = 0.0f; ///< W.
    float target_value = 0.0f;        ///< p-hat(y) at the surface that owns the reservoir.
};

static_assert(std::is_trivially_copyable_v<PackedReservoir>);
static_assert(sizeof(PackedReservoir) == 20u);

/// The largest M a packed reservoir holds.
inline constexpr std::uint32_t packed_max_candidate_count = 0xffffu;

namespace detail {
// M, W and p-hat of a stored reservoir; the weight sum, which reuse does not read, set to
// M p-hat W (what `finalize` divides), so that `has_sample` answers as before packing.
template <class Sample>
RESTIR_HOST_DEVICE constexpr void set_stored_weights(Reservoir<Sample>& r, std::uint32_t m,
                                                     float contribution_weight,
                                                     float target_value) noexcept {
    r.candidate_count = m;
    r.contribution_weight = contribution_weight;
    r.target_value = target_value;
    const float sum = static_cast<float>(m) * target_value * contribution_weight;
    r.weight_sum = sum < 3.0e38f ? sum : 3.0e38f; // finite even where the product overflows
    r.sanitize();
}
} // namespace detail

/// `r` in storage form; a reservoir with a NaN, infinite or negative field is stored empty
/// (as `Reservoir::sanitize` leaves it).
RESTIR_HOST_DEVICE constexpr PackedReservoir
pack_reservoir(const Reservoir<LightSampleRef>& r) noexcept {
    if (!r.is_well_formed())
        return {};
    const std::uint32_t u = unit_bits24(r.sample.uv.x);
    const std::uint32_t v = unit_bits24(r.sample.uv.y);
    const std::uint32_t m = min_of(r.candidate_count, packed_max_candidate_count);
    return {r.sample.light_id, u | (v << 24u), (v >> 8u) | (m << 16u), r.contribution_weight,
            r.target_value};
}

/// The working reservoir of a stored one (its weight sum set to M p-hat W, which reuse does not
/// read).
RESTIR_HOST_DEVICE constexpr Reservoir<LightSampleRef>
unpack_reservoir(const PackedReservoir& p) noexcept {
    Reservoir<LightSampleRef> r;
    const std::uint32_t u = p.u_and_v_low & 0xffffffu;
    const std::uint32_t v = (p.u_and_v_low >> 24u) | ((p.v_high_and_m & 0xffffu) << 8u);
    r.sample.light_id = p.light_id;
    r.sample.uv = {static_cast<float>(u) * 0x1p-24f, static_cast<float>(v) * 0x1p-24f};
    detail::set_stored_weights(r, p.v_high_and_m >> 16u, p.contribution_weight, p.target_value);
    return r;
}

/// `stored` unpacked, its light id mapped from last frame's light set to this frame's by
/// `translate` (empty when `translate` returns `removed_light`: the light is gone).
template <class Translate>
RESTIR_HOST_DEVICE constexpr Reservoir<LightSampleRef>
unpack_reservoir(const PackedReservoir& stored, const Translate& translate) {
    Reservoir<LightSampleRef> r = unpack_reservoir(stored);
    const std::uint32_t id = static_cast<std::uint32_t>(translate(r.sample.light_id));
    if (id == removed_light)
        return {};
    r.sample.light_id = id;
    return r;
}

/// A stored `Reservoir<LightPointSample>`: the light, the point's position, W, p-hat at its own
/// surface and M, exactly; the rest of the sample (the light's normal, intensity and falloff) is
/// decoded from the light id when the history is read (`PackedPointHistory`).
struct PackedPointReservoir {
    std::uint32_t light_id = 0u;
    glm::vec3 position{0.0f};
    float contribution_weight = 0.0f; ///< W.
    float target_value = 0.0f;        ///< p-hat(y) at the surface that owns the reservoir.
    std::uint32_t candidate_count = 0u;
};

static_assert(std::is_trivially_copyable_v<PackedPointReservoir>);
static_assert(sizeof(PackedPointReservoir) == 28u);

/// `r` in storage form; a reservoir with a NaN, infinite or negative field is stored empty.
RESTIR_HOST_DEVICE constexpr PackedPointReservoir
pack_reservoir(const Reservoir<LightPointSample>& r) noexcept {
    if (!r.is_well_formed())
        return {};
    return {r.sample.light_id, r.sample.position, r.contribution_weight, r.target_value,
            r.candidate_count};
}

/// A decoder of stored light points: `decode(light_id, position)` -> the `LightPointSample` of
/// that light at that point, with `light_id` `removed_light` when the light no longer exists.
/// Exact for lights whose normal, radiance and pdf are the same over the whole light (flat
/// triangles of one radiance, sampled uniformly by area; point lights and VPLs): then the
/// light id and the position determine the sample.
template <class D>
concept LightPointDecoder = requires(const D& decode, std::uint32_t id, glm::vec3 position) {
    { decode(id, position) } -> std::convertible_to<LightPointSample>;
};

/// The `LightPointDecoder` of a `LightPointLookup` light set (this frame's): light `id`'s point
/// at `position` (`lights.point_at`) folded with `falloff`, the one the samples were made with;
/// `removed_light` for an id past the set's lights. `Lights` is held by value: a view such as
/// `UnifiedLightSet`, which a GPU kernel takes as it is.
template <LightPointLookup Lights>
struct LightSetDecoder {
    Lights lights{};
    Falloff falloff{};
    RESTIR_HOST_DEVICE LightPointSample operator()(std::uint32_t id, glm::vec3 position) const {
        if (id >= lights.light_count())
            return {.light_id = removed_light};
        return make_light_point_sample(id, lights.point_at(id, position), falloff);
    }
};

/// The working reservoir of a stored one, its sample decoded by `decode` (only where it holds
/// one: a reservoir without a sample keeps its M and is not decoded); empty when the light is
/// gone.
template <LightPointDecoder Decode>
RESTIR_HOST_DEVICE constexpr Reservoir<LightPointSample>
unpack_reservoir(const PackedPointReservoir& p, const Decode& decode) {
    Reservoir<LightPointSample> r;
    detail::set_stored_weights(r, p.candidate_count, p.contribution_weight, p.target_value);
    if (!r.has_sample())
        return r;
    r.sample = decode(p.light_id, p.position);
    return r.sample.light_id == removed_light ? Reservoir<LightPointSample>{} : r;
}

/// Last frame's packed reservoirs as a `ReservoirHistory` for `DiFrame`, each loaded with
/// `unpack_reservoir(stored, translate)`:
///  - `PackedReservoir`s (the default): `translate` maps a light id of last frame's light set to
///    this frame's (`removed_light`: the light is gone, the pixel lends nothing), so that a
///    renderer that renumbers its lights or removes some keeps its history through it;
///  - `PackedPointReservoir`s (`PackedPointHistory`): `translate` is a `LightPointDecoder`
///    of this frame's light set.
/// Lights added since last frame are not covered: the history could not have drawn them, but
/// its MIS weight assumes it could (they would come out too dark), so treat additions as a
/// light change (an empty history). Trivially copyable when `Translate` is.
template <class Translate = SameLightIds, class Packed = PackedReservoir>
struct PackedHistory {
    ImageView<const Packed> reservoirs{};
    Translate translate{};

    RESTIR_HOST_DEVICE constexpr bool empty() const noexcept { return reservoirs.data == nullptr; }
    RESTIR_HOST_DEVICE constexpr bool contains(PixelCoord p) const noexcept {
        return reservoirs.contains(p);
    }
    RESTIR_HOST_DEVICE constexpr auto load(PixelCoord p) const {
        return unpack_reservoir(reservoirs[p], translate);
    }
};

/// Last frame's `PackedPointReservoir`s, decoded by `decode` (`PackedHistory`).
template <LightPointDecoder Decode>
using PackedPointHistory = PackedHistory<Decode, PackedPointReservoir>;

static_assert(ReservoirHistory<PackedHistory<>, LightSampleRef>);

} // namespace restir
