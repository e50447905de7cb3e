/// @file reuse/shift.hpp
/// Shift mappings: how a sample that one surface resampled is carried to another surface that
/// reuses it. Generalized RIS (Lin et al. 2022, Sec. 4) weighs a shifted sample y = T(x) with
/// the Jacobian determinant |dT/dx| of the shift, so that a reused sample keeps the measure
/// of the receiver's integral. A light sample means the same light point from every surface
/// (the identity, Jacobian 1); a path sample reconnects the receiver's visible point to the
/// same sample point (gi/reconnection_shift.hpp), whose Jacobian converts solid angles.
#pragma once

#include "restir/config.hpp"

#include <concepts>
#include <type_traits>

namespace restir {

/// A sample after a shift: the sample as the receiving surface sees it and |dT/dx|, the
/// Jacobian determinant of the shift at the original sample; 0 where the shift fails (no
/// sample of the receiver corresponds), which keeps the sample out of the receiver's reservoir.
template <class Sample>
struct ShiftedSample {
    Sample sample{};
    float jacobian = 0.0f;
};

/// A shift mapping between surfaces. Required expression, for a sample `x` resampled at
/// surface `from`, carried to surface `to`:
///   `shift(x, from, to)` -> `ShiftedSample<Sample>`: T(x) and |dT/dx| (0 where it fails).
/// The bias corrections call it for every input's sample towards the receiver and, for their
/// MIS weights, for the receiver's samples towards the inputs' surfaces (Lin et al. 2022,
/// Eq. 5.10: the balance heuristic over shifted targets p-hat_j(T^-1(y)) |dT^-1/dy|).
template <class F, class Sample, class SurfaceT>
concept ShiftMapping = requires(const F& shift, const Sample& x, const SurfaceT& from,
                                const SurfaceT& to) {
    { shift(x, from, to) } -> std::same_as<ShiftedSample<Sample>>;
};

/// The shift of samples that mean the same thing at every surface (light samples): T(x) = x,
/// Jacobian 1. The reuse passes recognise it (`is_identity_shift`) and compile the shift away.
struct IdentityShift {
    template <class Sample, class SurfaceT>
    RESTIR_HOST_DEVICE constexpr ShiftedSample<Sample> operator()(const Sample& x, const SurfaceT&,
                                                                  const SurfaceT&) const {
        return {x, 1.0f};
    }
};

/// Whether `Shift` is the identity, which reuse evaluates as no shift at all.
template <class Shift>
inline constexpr bool is_identity_shift = std::is_same_v<std::remove_cvref_t<Shift>, IdentityShift>;

} // namespace restir
