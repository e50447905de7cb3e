/// @file reuse/reuse_input.hpp
/// A reservoir that a reuse step borrows, and the test that decides whether a pixel's
/// reservoir may be borrowed at all.
#pragma once

#include "restir/concepts.hpp"
#include "restir/config.hpp"
#include "restir/core/reservoir.hpp"
#include "restir/reuse/image_view.hpp"
#include "restir/reuse/similarity.hpp"
#include "restir/reuse/surface_source.hpp"

#include <concepts>
#include <cstddef>
#include <cstdint>
#include <type_traits>

namespace restir {

/// A reservoir borrowed from another pixel or frame, with the surface it was computed for.
/// Both pointers refer into the caller's buffers; null when there is nothing to borrow.
/// (Two pointers, so that functions return it in registers.)
template <class Sample, class SurfaceT>
struct ReuseInput {
    const Reservoir<Sample>* reservoir = nullptr;
    const SurfaceT* surface = nullptr;
};

/// A reservoir borrowed with a copy of its surface, for sets that decode surfaces
/// (`SurfaceDecoder`, reuse/surface_source.hpp) rather than point into an array of them.
/// `reservoir` is null when there is nothing to borrow.
template <class Sample, class SurfaceT>
struct DecodedReuseInput {
    const Reservoir<Sample>* reservoir = nullptr;
    SurfaceT surface{};
};

/// An input as reuse visits it: a `DecodedReuseInput` as it is, anything else as the
/// `ReuseInput` it converts to.
template <class Sample, class SurfaceT>
RESTIR_HOST_DEVICE constexpr DecodedReuseInput<Sample, SurfaceT>
lent_input(const DecodedReuseInput<Sample, SurfaceT>& input) {
    return input;
}
template <class Sample, class SurfaceT>
RESTIR_HOST_DEVICE constexpr ReuseInput<Sample, SurfaceT>
lent_input(const ReuseInput<Sample, SurfaceT>& input) noexcept {
    return input;
}

/// The surface that an input lends (which must lend a reservoir).
template <class Sample, class SurfaceT>
RESTIR_HOST_DEVICE constexpr const SurfaceT&
lent_surface(const ReuseInput<Sample, SurfaceT>& input) noexcept {
    return *input.surface;
}
template <class Sample, class SurfaceT>
RESTIR_HOST_DEVICE constexpr const SurfaceT&
lent_surface(const DecodedReuseInput<Sample, SurfaceT>& input) noexcept {
    return input.surface;
}

/// Largest number of reservoirs one reuse step combines (the canonical one included).
inline constexpr std::uint32_t max_reuse_inputs = 16u;

/// No cap on the M an input lends.
inline constexpr std::uint32_t no_candidate_cap = 0xffffffffu;

/// Borrowed reservoirs that a reuse step visits one at a time, as many times as it needs:
/// `inputs.size()` slots, `inputs[i]` the input of slot i (a `ReuseInput`, or a
/// `DecodedReuseInput` with a decoded surface; a null reservoir when the slot lends nothing),
/// the same input at every visit. Sets compute their inputs on demand (the spatial
/// neighbours from their offsets and a validity bit mask), so that no step copies its inputs
/// into an array: a GPU thread keeps them in registers. A set with a member `candidate_cap`
/// lends each reservoir with its M capped there (the temporal history cap; W unchanged).
template <class T, class Sample, class SurfaceT>
concept ReuseInputs = requires(const T& inputs, std::uint32_t i) {
    { inputs.size() } -> std::convertible_to<std::uint32_t>;
    requires std::convertible_to<decltype(inputs[i]), ReuseInput<Sample, SurfaceT>> ||
        std::same_as<std::remove_cvref_t<decltype(inputs[i])>, DecodedReuseInput<Sample, SurfaceT>>;
};

/// Inputs already gathered into an array (for renderers that collect them ahead of a pass).
template <class Sample, class SurfaceT>
struct ReuseInputSpan {
    const ReuseInput<Sample, SurfaceT>* inputs = nullptr;
    std::uint32_t count = 0u;
    RESTIR_HOST_DEVICE constexpr std::uint32_t size() const noexcept { return count; }
    RESTIR_HOST_DEVICE constexpr ReuseInput<Sample, SurfaceT> operator[](std::uint32_t i) const {
        return inputs[i];
    }
};

namespace detail {

/// One input (temporal reuse), its M capped at `candidate_cap`.
template <class Sample, class SurfaceT>
struct SingleReuseInput {
    static constexpr std::uint32_t capacity = 1u;
    ReuseInput<Sample, SurfaceT> input{};
    std::uint32_t candidate_cap = no_candidate_cap;
    RESTIR_HOST_DEVICE constexpr std::uint32_t size() const noexcept { return 1u; }
    RESTIR_HOST_DEVICE constexpr ReuseInput<Sample, SurfaceT> operator[](std::uint32_t) const {
        return input;
    }
};

/// The inputs of a spatial pass that lend, gathered once in order as they are found (host code): a
/// `ReuseInputs` set whose entries all take part (`packed`). Entries past `count` stay
/// uninitialised (zeroing 15 inputs per pixel is work a pass does not need).
template <class Sample, class S>
struct GatheredInputs {
    static constexpr bool packed = true;
    const Reservoir<Sample>* reservoirs[max_reuse_inputs - 1u];
    const S* surfaces[max_reuse_inputs - 1u];
    std::uint32_t count;

    /// Adds an input that lends (`lends_reservoir`: well-formed, similar); beyond
    /// max_reuse_inputs - 1 inputs, none.
    RESTIR_HOST_DEVICE void add(const Reservoir<Sample>* reservoir, const S* surface) {
        RESTIR_ASSERT(reservoir->is_well_formed());
        if (count + 1u < max_reuse_inputs) {
            reservoirs[count] = reservoir;
            surfaces[count++] = surface;
        }
    }
    RESTIR_HOST_DEVICE std::uint32_t size() const { return count; }
    RESTIR_HOST_DEVICE ReuseInput<Sample, S> operator[](std::uint32_t i) const {
        return {reservoirs[i], surfaces[i]};
    }
};

} // namespace detail

/// The one-input set's name before 0.2, when it was public.
template <class Sample, class SurfaceT>
using SingleReuseInput [[deprecated("pass a ReuseInputSpan of one input")]] =
    detail::SingleReuseInput<Sample, SurfaceT>;

namespace detail {
/// `r.is_well_formed()`. On a GPU, where the three weights (W-sum, p-hat, W) start an aligned
/// 16 bytes, they are read in one load: a spatial pass reads its neighbours' at random, and a
/// load costs the L1 one access per thread whatever its width.
template <class Sample>
RESTIR_HOST_DEVICE RESTIR_FORCE_INLINE bool well_formed_in_buffer(const Reservoir<Sample>& r) {
#if defined(__CUDA_ARCH__)
    using R = Reservoir<Sample>;
    constexpr std::size_t first = offsetof(R, weight_sum);
    if constexpr (std::is_standard_layout_v<R> && alignof(R) >= 16u && first % 16u == 0u &&
                  offsetof(R, target_value) == first + 4u &&
                  offsetof(R, contribution_weight) == first + 8u) {
        const float4 w = *reinterpret_cast<const float4*>(&r.weight_sum);
        return is_valid_weight(w.x) && is_valid_weight(w.y) && is_valid_weight(w.z);
    }
#endif
    return r.is_well_formed();
}
} // namespace detail

/// Whether pixel `p` may lend its reservoir to `receiver`: `p` lies in both images, the
/// reservoir is finite and the surfaces are similar; `surfaces` an `ImageView` or a
/// `SurfaceDecoder`.
template <class Sample, Surface S, class Surfaces, class MaterialTest>
requires SurfaceSource<Surfaces, S> RESTIR_HOST_DEVICE RESTIR_FORCE_INLINE bool
lends_reservoir(PixelCoord p, const S& receiver, ImageView<const Reservoir<Sample>> reservoirs,
                const Surfaces& surfaces, const SimilarityParams& similarity,
                const MaterialTest& material_test) {
    return reservoirs.contains(p) && surfaces.contains(p) &&
           detail::well_formed_in_buffer(reservoirs[p]) &&
           surfaces_similar(receiver, surface_at(surfaces, p), similarity, material_test);
}

/// The reservoir of pixel `p` with its surface, if `receiver` may borrow it
/// (`lends_reservoir`). Otherwise null pointers.
template <class Sample, Surface S, class MaterialTest>
RESTIR_HOST_DEVICE ReuseInput<Sample, S>
reusable_input(PixelCoord p, const S& receiver, ImageView<const Reservoir<Sample>> reservoirs,
               ImageView<const S> surfaces, const SimilarityParams& similarity,
               const MaterialTest& material_test) {
    if (!lends_reservoir(p, receiver, reservoirs, surfaces, similarity, material_test))
        return {};
    return {&reservoirs[p], &surfaces[p]};
}

} // namespace restir
