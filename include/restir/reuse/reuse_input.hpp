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

/// A reservoir borrowed from another pixel or frame, with the surface it was computed for:
/// `Held` is `const SurfaceT*` (a pointer into the caller's buffer, the default) or `SurfaceT`
/// (a copy, for surfaces that a `SurfaceDecoder` decodes). `reservoir` is null when there is
/// nothing to borrow. (Small, so that functions return it in registers.)
template <class Sample, class SurfaceT, class Held = const SurfaceT*>
struct ReuseInput {
    const Reservoir<Sample>* reservoir = nullptr;
    Held surface{};
};

/// A reservoir borrowed with a copy of its surface (reuse/surface_source.hpp).
template <class Sample, class SurfaceT>
using DecodedReuseInput = ReuseInput<Sample, SurfaceT, SurfaceT>;

/// An input as reuse visits it: a `ReuseInput` as it is, anything else as the `ReuseInput` it
/// converts to.
template <class Sample, class SurfaceT, class Held>
RESTIR_HOST_DEVICE constexpr ReuseInput<Sample, SurfaceT, Held>
lent_input(const ReuseInput<Sample, SurfaceT, Held>& input) {
    return input;
}
template <class Sample, class SurfaceT, class Input>
RESTIR_HOST_DEVICE constexpr ReuseInput<Sample, SurfaceT> lent_input(const Input& input) {
    return input;
}

/// The surface that an input lends (which must lend a reservoir).
template <class Sample, class SurfaceT, class Held>
RESTIR_HOST_DEVICE constexpr const SurfaceT&
lent_surface(const ReuseInput<Sample, SurfaceT, Held>& input) noexcept {
    if constexpr (std::is_pointer_v<Held>)
        return *input.surface;
    else
        return input.surface;
}

/// Largest number of reservoirs one reuse step combines (the canonical one included).
inline constexpr std::uint32_t max_reuse_inputs = 16u;

/// No cap on the M an input lends.
inline constexpr std::uint32_t no_candidate_cap = 0xffffffffu;

/// Borrowed reservoirs that a reuse step visits one at a time, as many times as it needs:
/// `inputs.size()` slots, `inputs[i]` the input of slot i (a `ReuseInput`, with a pointer to
/// its surface or a copy; a null reservoir when the slot lends nothing), the same input at
/// every visit. The library's sets are `ReuseInputSpan` (an array) and `SpatialNeighbours`
/// (computed on demand, so that a GPU thread keeps them in registers); what reuse knows of a
/// set beyond this is in `ReuseSetTraits`.
template <class T, class Sample, class SurfaceT>
concept ReuseInputs = requires(const T& inputs, std::uint32_t i) {
    { inputs.size() } -> std::convertible_to<std::uint32_t>;
    requires std::convertible_to<decltype(inputs[i]), ReuseInput<Sample, SurfaceT>> ||
        std::same_as<std::remove_cvref_t<decltype(inputs[i])>, DecodedReuseInput<Sample, SurfaceT>>;
};

/// Inputs in an array: the caller's, or the one that host code gathers a streamed set into.
/// `candidate_cap` caps the M of every reservoir lent (W unchanged: the temporal history cap);
/// `all_lend` says that every slot lends a well-formed reservoir, so that reuse skips the checks.
template <class Sample, class SurfaceT, class Held = const SurfaceT*>
struct ReuseInputSpan {
    const ReuseInput<Sample, SurfaceT, Held>* inputs = nullptr;
    std::uint32_t count = 0u;
    std::uint32_t candidate_cap = no_candidate_cap;
    bool all_lend = false;
    RESTIR_HOST_DEVICE constexpr std::uint32_t size() const noexcept { return count; }
    RESTIR_HOST_DEVICE constexpr const ReuseInput<Sample, SurfaceT, Held>&
    operator[](std::uint32_t i) const {
        return inputs[i];
    }
};

namespace detail {
/// Room for `N` values that a pass writes before it reads them, left unset: a pass that gathers
/// up to 15 inputs a pixel would otherwise clear them all first.
template <class T, std::uint32_t N>
union UnsetArray {
    T items[N];
    RESTIR_HOST_DEVICE UnsetArray() {}
};

/// One input, its M capped at `candidate_cap`: the set of temporal reuse before 0.2, kept for
/// its deprecated public name (`ReuseInputSpan` of one input replaces it).
template <class Sample, class SurfaceT>
struct SingleReuseInput {
    ReuseInput<Sample, SurfaceT> input{};
    std::uint32_t candidate_cap = no_candidate_cap;
    RESTIR_HOST_DEVICE constexpr std::uint32_t size() const noexcept { return 1u; }
    RESTIR_HOST_DEVICE constexpr ReuseInput<Sample, SurfaceT> operator[](std::uint32_t) const {
        return input;
    }
};

template <class Inputs>
[[deprecated("specialise restir::ReuseSetTraits for a set instead of giving it members "
             "packed and candidate_cap")]] RESTIR_HOST_DEVICE constexpr bool
set_members_read() noexcept {
    return true;
}
} // namespace detail

/// The one-input set's name before 0.2, when it was public.
template <class Sample, class SurfaceT>
using SingleReuseInput [[deprecated("pass a ReuseInputSpan of one input")]] =
    detail::SingleReuseInput<Sample, SurfaceT>;

/// What reuse knows of a `ReuseInputs` set beyond its slots. This primary template describes an
/// application's set: slots that may lend nothing, visited as they are, M uncapped. Specialise
/// it for a set of your own that says more; `ReuseInputSpan` and `SpatialNeighbours` have
/// theirs. (Sets that declare members `packed` or `candidate_cap`, the form of 0.2, are still
/// read, with a deprecation warning; to be removed in 0.4.)
template <class Inputs>
struct ReuseSetTraits {
    /// Whether every slot of `inputs` lends a well-formed reservoir (reuse then skips the
    /// checks of each).
    RESTIR_HOST_DEVICE static constexpr bool all_lend(const Inputs& inputs) noexcept {
        static_cast<void>(inputs);
        if constexpr (requires { requires Inputs::packed; })
            return detail::set_members_read<Inputs>();
        else
            return false;
    }
    /// The cap on the M of every reservoir lent.
    RESTIR_HOST_DEVICE static constexpr std::uint32_t candidate_cap(const Inputs& inputs) noexcept {
        if constexpr (requires { inputs.candidate_cap; })
            return detail::set_members_read<Inputs>() ? inputs.candidate_cap : no_candidate_cap;
        else
            return no_candidate_cap;
    }
    /// Whether a visit computes its input anew (host code gathers such a set into a
    /// `ReuseInputSpan` once rather than at every visit).
    static constexpr bool streamed = false;
};

template <class Sample, class SurfaceT, class Held>
struct ReuseSetTraits<ReuseInputSpan<Sample, SurfaceT, Held>> {
    RESTIR_HOST_DEVICE static constexpr bool
    all_lend(const ReuseInputSpan<Sample, SurfaceT, Held>& inputs) noexcept {
        return inputs.all_lend;
    }
    RESTIR_HOST_DEVICE static constexpr std::uint32_t
    candidate_cap(const ReuseInputSpan<Sample, SurfaceT, Held>& inputs) noexcept {
        return inputs.candidate_cap;
    }
    static constexpr bool streamed = false;
};

template <class Sample, class SurfaceT>
struct ReuseSetTraits<detail::SingleReuseInput<Sample, SurfaceT>> {
    RESTIR_HOST_DEVICE static constexpr bool
    all_lend(const detail::SingleReuseInput<Sample, SurfaceT>&) noexcept {
        return false;
    }
    RESTIR_HOST_DEVICE static constexpr std::uint32_t
    candidate_cap(const detail::SingleReuseInput<Sample, SurfaceT>& inputs) noexcept {
        return inputs.candidate_cap;
    }
    static constexpr bool streamed = false;
};

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
