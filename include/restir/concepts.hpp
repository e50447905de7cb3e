/// @file concepts.hpp
/// The bridge: every expression the library requires of the application's own types.
/// The library reads user types only through these expressions, never through their
/// fields, so an existing renderer adapts its G-buffer, lights and ray tracer with a few
/// free functions or members. docs/bridge.md states each contract in full.
#pragma once

#include "restir/core/discrete_sample.hpp"
#include "restir/core/rng.hpp"
#include "restir/core/shading_point.hpp"

#include <glm/vec2.hpp>
#include <glm/vec3.hpp>

#include <concepts>
#include <cstdint>

namespace restir {

// The concepts of this file are the ones every part of the library uses. The others live
// beside the stage that asks for them (this header sits in the core layer and includes none of
// those stages):
//   UniformRng          core/rng.hpp             `next_float(rng)` -> float in [0, 1)
//   Receiver            light/receiver.hpp       a surface point and its BSDF: `reflected(wi)`
//   SamplingReceiver    light/receiver.hpp       a Receiver that draws directions from its BSDF
//   LightHitQuery       sampling/bsdf_candidates.hpp `find_light(origin, direction)`: the
//                                                emitter a BSDF ray hits
//   ShiftMapping        reuse/shift.hpp          `shift(x, from, to)`: a sample carried to
//                                                another surface, with its Jacobian
//   PathReplay          gi/hybrid_shift.hpp      a path tracer that replays a path sample's
//                                                random numbers from another visible point
//   VisibilityFunction  reuse/visibility.hpp     `visible(sample, surface)` -> bool
//   BatchVisibility     reuse/di_frame_tiles.hpp `tracer.trace(queries, visible)`
//   DiFrameBridge       reuse/di_frame_bridge.hpp a frame's callbacks: `initial`, `reuse`,
//                                                `rng_for`, `shade`
//   Reprojection        reuse/temporal.hpp       `reproject(pixel)` -> last frame's pixel
//   ReservoirHistory    reuse/history.hpp        last frame's reservoirs, loaded by value
//   HistorySurfaces     reuse/history.hpp        last frame's surfaces, decoded
//   SurfaceDecoder      reuse/surface_source.hpp this frame's surfaces, decoded
//   SurfaceSource       reuse/surface_source.hpp an ImageView of surfaces or a decoder
//   ReuseInputs         reuse/reuse_input.hpp    the reservoirs one reuse step borrows
//   LightPointDecoder   reuse/packed_reservoir.hpp a packed light point back as a sample
//   ClosestHitQuery     vpl/photon_shooter.hpp   `closest_hit(origin, direction)`
//   ScatterFunction     vpl/photon_shooter.hpp   a photon's bounce at a hit

/// Chooses a light id. Required expressions, for `const S s`, floats `u0, u1` in [0, 1) and
/// `std::uint32_t id`:
///   `s.sample(u0, u1)`  -> DiscreteSample {light id, pmf}; pmf 0 means "no light".
///   `s.pmf(id)`         -> float, the probability that `sample` returns `id`.
///   `s.light_count()`   -> std::uint32_t.
/// Sampling must cost O(1) per call so that candidate generation does not grow with the
/// number of lights.
template <class S>
concept LightSampler = requires(const S& s, float u, std::uint32_t id) {
    { s.sample(u, u) } -> std::same_as<DiscreteSample>;
    { s.pmf(id) } -> std::convertible_to<float>;
    { s.light_count() } -> std::convertible_to<std::uint32_t>;
};

/// Chooses a light id for a shading point (pbrt-v4's `Sample(ctx, u)` and `PMF(ctx, light)`), so
/// that lights that matter there are drawn more often. Required expressions, for a
/// `ShadingPoint at` and the rest as in `LightSampler`:
///   `s.sample(at, u0, u1)` -> DiscreteSample {light id, pmf at `at`}; pmf 0 means "no light".
///   `s.pmf(at, id)`        -> float, the probability that `sample(at, ...)` returns `id`; it
///                            must be positive for every light that can light `at`, or RIS
///                            with it is biased.
///   `s.light_count()`      -> std::uint32_t.
/// Every `LightSampler` of the library is one too (it ignores the point).
template <class S>
concept ContextLightSampler = requires(const S& s, const ShadingPoint& at, float u,
                                       std::uint32_t id) {
    { s.sample(at, u, u) } -> std::same_as<DiscreteSample>;
    { s.pmf(at, id) } -> std::convertible_to<float>;
    { s.light_count() } -> std::convertible_to<std::uint32_t>;
};

/// The target function p-hat of resampling at a receiving surface. Required expression:
///   `f(sample, surface)` -> float, finite and >= 0; typically the luminance of
///   Le * BSDF * G without visibility. It must be cheap: reuse evaluates it for every
///   neighbour (and, for the balance heuristic, for every pair of neighbours).
template <class F, class Sample, class SurfaceT>
concept TargetFunction = requires(const F& f, const Sample& sample, const SurfaceT& surface) {
    { f(sample, surface) } -> std::convertible_to<float>;
};

/// A shading point (a G-buffer texel). Required expressions, found by argument-dependent
/// lookup so that existing types need no new members:
///   `surface_position(s)` -> glm::vec3, world-space position;
///   `surface_normal(s)`   -> glm::vec3, unit shading normal;
///   `surface_depth(s)`    -> float, linear view depth (for reuse rejection);
///   `is_valid_surface(s)` -> bool, false for background pixels.
template <class S>
concept Surface = requires(const S& s) {
    { surface_position(s) } -> std::convertible_to<glm::vec3>;
    { surface_normal(s) } -> std::convertible_to<glm::vec3>;
    { surface_depth(s) } -> std::convertible_to<float>;
    { is_valid_surface(s) } -> std::convertible_to<bool>;
};

/// A point on a light, as returned by a light set: members `position`, `normal`, `radiance`
/// (glm::vec3), `area_pdf` (float) and `is_delta` (bool). `restir::LightSample` is one. An
/// optional `is_distant` (bool) marks a direction rather than a point (an environment's
/// sample: `position` is the unit direction towards the light, `area_pdf` a density per
/// steradian, `normal` zero); without the member every point is a point.
template <class T>
concept LightPoint = requires(const T& p) {
    { p.position } -> std::convertible_to<glm::vec3>;
    { p.normal } -> std::convertible_to<glm::vec3>;
    { p.radiance } -> std::convertible_to<glm::vec3>;
    { p.area_pdf } -> std::convertible_to<float>;
    { p.is_delta } -> std::convertible_to<bool>;
};

/// Whether a `LightPoint` is a direction (a distant light's sample): its `is_distant` member,
/// which light sets without distant lights need not have.
template <LightPoint P>
RESTIR_HOST_DEVICE constexpr bool is_distant_point(const P& p) {
    if constexpr (requires { p.is_distant; })
        return static_cast<bool>(p.is_distant);
    else
        return false;
}

/// All lights of the scene, emitters and VPLs in one id space. Required expressions:
///   `lights.light_count()`          -> std::uint32_t;
///   `lights.sample_point(id, uv)`   -> a LightPoint: the point of light `id` that the
///                                      primary sample `uv` in [0, 1)^2 maps to,
///                                      deterministic, so a stored LightSampleRef can be
///                                      evaluated again at another surface.
template <class L>
concept LightSet = requires(const L& lights, std::uint32_t id, glm::vec2 uv) {
    { lights.light_count() } -> std::convertible_to<std::uint32_t>;
    { lights.sample_point(id, uv) } -> LightPoint;
};

/// A light set that also draws a light's point from a receiver, so that the points fall where
/// the light covers the receiver's view (uniform in the solid angle it subtends, say) and a
/// light next to the receiver gives bounded candidates. Required expressions, besides those of
/// `LightSet`, for a `glm::vec3 from`:
///   `lights.sample_point(id, uv, from)` -> a LightPoint: the point of light `id` that `uv` in
///        [0, 1)^2 maps to for a receiver at `from`, deterministic in (id, uv, from); its
///        `area_pdf` is the density per unit area of that map at the point (a solid-angle
///        density through `solid_angle_to_area_pdf`), 0 where the map gives no point. Every
///        point of the light that `from` sees must have a positive density. Delta lights (VPLs,
///        point lights) ignore `from` and `uv`.
/// A sample's intensity, radiance / area_pdf, then depends on the receiver that drew it: that
/// scale cancels between the sample's p-hat and its W in RIS and in every reuse pass, which
/// evaluate p-hat with the stored intensity (docs/bridge.md).
template <class L>
concept ReceiverLightSet = LightSet<L> &&
    requires(const L& lights, std::uint32_t id, glm::vec2 uv, glm::vec3 from) {
    { lights.sample_point(id, uv, from) } -> LightPoint;
};

/// A receiver light set that also gives the density of its receiver's map at a point, so
/// that another strategy's candidate (a BSDF ray's hit) can be weighed against it by MIS.
/// Required expression, besides those of `ReceiverLightSet`, for `glm::vec3 point, from`:
///   `lights.point_pdf(id, point, from)` -> float: the density per unit area with which
///        `sample_point(id, uv, from)` returns `point` (a point of light `id`) for uniform uv,
///        as its `area_pdf` gives it; per steradian for a distant light's direction `point`.
///        Delta lights may return anything: no ray hits them.
template <class L>
concept ReceiverLightDensity = ReceiverLightSet<L> &&
    requires(const L& lights, std::uint32_t id, glm::vec3 point, glm::vec3 from) {
    { lights.point_pdf(id, point, from) } -> std::convertible_to<float>;
};

/// A light set that gives a light's point back from its position, so that a stored light point
/// needs only its light id and position (`LightSetDecoder`, reuse/packed_reservoir.hpp).
/// Required expression, besides those of `LightSet`, for a `glm::vec3 position`:
///   `lights.point_at(id, position)` -> a LightPoint: light `id`'s point at `position` (one that
///        `sample_point` returns) with the normal, radiance and area_pdf that `sample_point`
///        gives it; for a distant light `position` is the direction.
template <class L>
concept LightPointLookup = LightSet<L> &&
    requires(const L& lights, std::uint32_t id, glm::vec3 position) {
    { lights.point_at(id, position) } -> LightPoint;
};

/// Visibility between two points. Required expression:
///   `query.occluded(from, to)` -> bool, true when anything blocks the open segment
///   (the caller offsets the end points off their surfaces).
template <class Q>
concept RayQuery = requires(const Q& query, glm::vec3 from, glm::vec3 to) {
    { query.occluded(from, to) } -> std::convertible_to<bool>;
};

} // namespace restir
