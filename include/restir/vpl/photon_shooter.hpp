/// @file vpl/photon_shooter.hpp
/// Steps 2 and 3 of instant radiosity (Keller 1997): photons leave the emitter points in
/// proportion to their flux, or the sky (an environment map) through a disk that covers the
/// scene, are traced through the scene with the application's ray query, and leave a VPL at
/// every diffuse hit; Russian roulette on the throughput ends their paths.
#pragma once

#include "restir/bsdf/shading_frame.hpp"
#include "restir/concepts.hpp"
#include "restir/config.hpp"
#include "restir/core/math.hpp"
#include "restir/core/rng.hpp"
#include "restir/light/environment_light.hpp"
#include "restir/light/environment_map.hpp"
#include "restir/sampling/alias_table.hpp"
#include "restir/sampling/diffuse_direction.hpp"
#include "restir/sampling/light_sampler.hpp"
#include "restir/vpl/emitter_points.hpp"
#include "restir/vpl/vpl.hpp"

#include <glm/geometric.hpp>
#include <glm/vec3.hpp>

#include <algorithm>
#include <cmath>
#include <concepts>
#include <cstdint>
#include <optional>
#include <stdexcept>
#include <type_traits>
#include <utility>
#include <vector>

namespace restir {

/// Closest-hit ray casting for photons. Required expression:
///   `query.closest_hit(origin, direction)` -> a `Surface` (position, normal, ...), with
///   `is_valid_surface(hit)` false when the ray leaves the scene. `direction` is unit length;
///   the shooter offsets `origin` off the surface it starts on.
template <class Q>
concept ClosestHitQuery = requires(const Q& query, glm::vec3 origin, glm::vec3 direction) {
    { query.closest_hit(origin, direction) } -> Surface;
};

/// What the application's BSDF does to a photon at a hit.
struct Scattering {
    glm::vec3 direction{0.0f};      ///< Sampled continuation direction (unit).
    glm::vec3 weight{0.0f};         ///< BSDF * cos / pdf of `direction` (the albedo, for a
                                    ///< Lambertian surface sampled by cosine); 0 absorbs.
    glm::vec3 diffuse_albedo{0.0f}; ///< Diffuse reflectance, stored with a VPL deposited here.
    bool is_diffuse = true;         ///< VPLs are deposited at diffuse hits only.
    bool is_emissive = false;       ///< No VPL on emitters: their light is direct light.
};

/// The scatter hook. Required expression:
///   `scatter(hit, incoming, rng)` -> Scattering, where `incoming` is the photon's unit
///   direction of travel and `rng` a UniformRng for sampling the continuation (the shooter
///   passes the generator it was given: `Pcg32` through `trace_photon`; a template over the
///   generator works everywhere).
template <class F, class Hit, class Rng>
concept ScatterFunction = requires(const F& scatter, const Hit& hit, glm::vec3 incoming, Rng& rng) {
    { scatter(hit, incoming, rng) } -> std::convertible_to<Scattering>;
};

/// The hit type a `ClosestHitQuery` returns.
template <class Query>
using HitOf = std::remove_cvref_t<decltype(std::declval<const Query&>().closest_hit(
    std::declval<glm::vec3>(), std::declval<glm::vec3>()))>;

/// Settings of a photon pass.
struct PhotonParams {
    std::uint32_t photon_count = 100'000u;  ///< Photons shot in total (the budget).
    std::uint32_t max_bounces = 4u;         ///< Diffuse hits per photon that may hold a VPL
                                            ///< (1 = one-bounce indirect light only).
    std::uint32_t points_per_emitter = 16u; ///< Stratified point lights per area emitter.
    float ray_offset = 1e-4f;               ///< Origin offset off surfaces, in scene units.
    std::uint64_t seed = 0u;                ///< Every photon's random stream derives from it.
};

RESTIR_HOST_DEVICE constexpr PhotonParams default_photon_params() noexcept { return {}; }

/// Where photons come from: the emitter points and an alias table over their flux, and
/// optionally the sky: an environment map and a sphere that bounds the scene. Views, so they can
/// live in device memory. A photon comes from the sky with probability `sky_probability`, from
/// the emitter points otherwise; without a sky (`sky_probability` 0, an empty map or a radius
/// of 0) it always leaves an emitter point and draws no number for the choice.
struct PhotonSource {
    const EmitterPoint* points = nullptr;
    AliasTableView table{};
    EnvironmentMapView environment{}; ///< The sky; empty: none.
    glm::vec3 scene_centre{0.0f};     ///< Centre of a sphere that holds all the geometry.
    float scene_radius = 0.0f;        ///< Its radius.
    float sky_probability = 0.0f;     ///< Probability that a photon comes from the sky.

    /// True when photons may come from the sky.
    RESTIR_HOST_DEVICE bool has_sky() const {
        return sky_probability > 0.0f && scene_radius > 0.0f && !environment.empty();
    }
};

/// Where one photon starts, the way it travels and the flux it carries; `power` 0: none.
struct PhotonStart {
    glm::vec3 origin{0.0f};
    glm::vec3 direction{0.0f, 1.0f, 0.0f};
    glm::vec3 power{0.0f};
};

/// A photon from the sky: direction w drawn from the map (density p_w per steradian), a point
/// uniform on the disk of radius R centred at centre + R w and perpendicular to w (density
/// 1 / (pi R^2)), travelling along -w. The radiance L(w) crosses that disk, which covers the
/// scene's bounding sphere seen from w, so the photon carries L(w) pi R^2 / (p_w p_sky N): its
/// expectation is the sky's flux into the sphere, pi R^2 times the integral of L over
/// directions, over the N photons.
template <UniformRng Rng>
RESTIR_HOST_DEVICE PhotonStart start_sky_photon(Rng& rng, const PhotonSource& source,
                                                const PhotonParams& params) {
    const float u0 = next_float(rng);
    const float u1 = next_float(rng);
    const EnvironmentSample sky = source.environment.sample({u0, u1});
    if (!(sky.pdf > 0.0f))
        return {};
    const float radius = source.scene_radius;
    const float u2 = next_float(rng);
    const float u3 = next_float(rng);
    const float r = radius * std::sqrt(u2);
    const float phi = two_pi * u3;
    const ShadingFrame frame = ShadingFrame::from_normal(sky.direction);
    const glm::vec3 origin = source.scene_centre + radius * sky.direction +
                             frame.tangent * (r * std::cos(phi)) +
                             frame.bitangent * (r * std::sin(phi));
    const float disk_area = pi * radius * radius;
    const glm::vec3 power =
        sky.radiance *
        (disk_area / (sky.pdf * source.sky_probability * static_cast<float>(params.photon_count)));
    return {origin, -sky.direction, power};
}

/// A photon from the emitter points: point j chosen with probability p_j (by flux), leaving in
/// a cosine-distributed direction about its normal (uniform for a point light), carrying
/// Phi_j / (p_j p_emitters N), p_emitters = 1 - p_sky (exactly 1 without a sky).
template <UniformRng Rng>
RESTIR_HOST_DEVICE PhotonStart start_emitter_photon(Rng& rng, const PhotonSource& source,
                                                    const PhotonParams& params,
                                                    float emitter_probability) {
    if (source.table.size == 0u)
        return {};
    const DiscreteSample choice = sample_light(PowerLightSampler{source.table}, rng);
    if (!(choice.pmf > 0.0f))
        return {};
    const EmitterPoint& emitter = source.points[choice.index];
    const glm::vec3 power =
        emitter.flux / (choice.pmf * emitter_probability * static_cast<float>(params.photon_count));
    const float u0 = next_float(rng);
    const float u1 = next_float(rng);
    const glm::vec3 direction = sample_diffuse_direction(emitter.normal, u0, u1);
    return {emitter.position + emitter.normal * params.ray_offset, direction, power};
}

/// Traces one photon of `params.photon_count` with the random numbers of `rng` and writes the
/// VPLs it deposits to `out[0 .. max_bounces)`; returns how many. Flux bookkeeping: the photon
/// leaves emitter point j, chosen with probability p_j, carrying Phi_j / (p_j N) (or the sky,
/// see `start_sky_photon`, with the emitters' share scaled by 1 - p_sky); at a diffuse
/// hit it deposits Phi * albedo (reflected flux); it continues with probability q = min(1, max
/// channel of the BSDF weight) and, if it does, carries Phi * weight / q. Every step is
/// unbiased, so the expected VPL flux equals the flux reflected by diffuse surfaces up to
/// `max_bounces` bounces.
template <UniformRng Rng, ClosestHitQuery Query, ScatterFunction<HitOf<Query>, Rng> Scatter>
RESTIR_HOST_DEVICE std::uint32_t trace_photon_with(Rng& rng, const PhotonSource& source,
                                                   const Query& query, const Scatter& scatter,
                                                   const PhotonParams& params, Vpl* out) {
    if (params.photon_count == 0u)
        return 0u;
    PhotonStart start;
    if (!source.has_sky())
        start = start_emitter_photon(rng, source, params, 1.0f);
    else if (next_float(rng) < source.sky_probability)
        start = start_sky_photon(rng, source, params);
    else
        start = start_emitter_photon(rng, source, params, 1.0f - source.sky_probability);
    glm::vec3 power = start.power;
    if (!(power.x + power.y + power.z > 0.0f))
        return 0u;
    glm::vec3 direction = start.direction;
    glm::vec3 origin = start.origin;

    std::uint32_t written = 0u;
    for (std::uint32_t bounce = 1u; bounce <= params.max_bounces; ++bounce) {
        const auto hit = query.closest_hit(origin, direction);
        if (!is_valid_surface(hit))
            break;
        const glm::vec3 position = surface_position(hit);
        glm::vec3 normal = surface_normal(hit);
        if (glm::dot(normal, direction) > 0.0f) // face the side the photon came from
            normal = -normal;
        const Scattering s = scatter(hit, direction, rng);
        const glm::vec3 reflected = power * s.diffuse_albedo;
        if (s.is_diffuse && !s.is_emissive && reflected.x + reflected.y + reflected.z > 0.0f)
            out[written++] = {position, normal, reflected, s.diffuse_albedo};
        if (bounce == params.max_bounces)
            break;
        // Russian roulette on the throughput.
        const float survival = min_of(1.0f, max_of(s.weight.x, max_of(s.weight.y, s.weight.z)));
        if (!(survival > 0.0f) || next_float(rng) >= survival)
            break;
        power *= s.weight / survival;
        direction = s.direction;
        const float side = glm::dot(direction, normal) >= 0.0f ? 1.0f : -1.0f;
        origin = position + normal * (side * params.ray_offset);
    }
    return written;
}

/// `trace_photon_with` for photon `photon_index`, its random numbers from its own stream
/// (`make_pixel_rng(photon_index, 0, RngStream::photons, params.seed)`), so the result does not
/// depend on which thread traces it.
template <ClosestHitQuery Query, ScatterFunction<HitOf<Query>, Pcg32> Scatter>
RESTIR_HOST_DEVICE std::uint32_t
trace_photon(std::uint32_t photon_index, const PhotonSource& source, const Query& query,
             const Scatter& scatter, const PhotonParams& params, Vpl* out) {
    Pcg32 rng = make_pixel_rng(photon_index, 0u, RngStream::photons, params.seed);
    return trace_photon_with(rng, source, query, scatter, params, out);
}

/// What photons leave from, built on the host: the emitter points of a light set and an alias
/// table over their flux (summed over the channels), and optionally the sky
/// (`set_environment`). `source()` is the view `trace_photon` takes; to shoot on a GPU, copy
/// `points()` and `table().entries()` (and the environment map's arrays) to device memory and
/// build a `PhotonSource` over the copies.
class PhotonEmitters {
public:
    PhotonEmitters() = default;

    /// `make_emitter_points(lights, points_per_emitter, seed)` and the table over them. Empty
    /// when no emitter has positive finite flux.
    template <LightSet Lights>
    PhotonEmitters(const Lights& lights, std::uint32_t points_per_emitter, std::uint64_t seed)
        : points_(make_emitter_points(lights, points_per_emitter, seed)) {
        if (points_.empty())
            return;
        std::vector<float> power(points_.size());
        for (std::size_t i = 0; i < points_.size(); ++i) {
            power[i] = points_[i].flux.x + points_[i].flux.y + points_[i].flux.z;
            emitter_flux_ += static_cast<double>(power[i]);
        }
        table_.build(power);
    }

    /// Adds the sky `environment` (which must outlive the shooting) as a photon source, with the
    /// sphere (`scene_centre`, `scene_radius`) that holds the scene's geometry. A photon comes
    /// from the sky with probability `sky_probability`; by default in proportion to flux: the
    /// sky sends `environment_power(environment, scene_radius)` into the sphere, against the
    /// emitter points' total flux (1 without emitters). Throws std::invalid_argument for an
    /// empty map, a centre or radius that is not finite (radius > 0), or a probability outside
    /// [0, 1].
    void set_environment(const EnvironmentMap& environment, glm::vec3 scene_centre,
                         float scene_radius, std::optional<float> sky_probability = std::nullopt) {
        if (environment.view().empty())
            throw std::invalid_argument("photon sky: the environment map is empty");
        if (!(is_finite(scene_centre.x) && is_finite(scene_centre.y) && is_finite(scene_centre.z) &&
              is_finite(scene_radius) && scene_radius > 0.0f))
            throw std::invalid_argument(
                "photon sky: the bounding sphere needs a finite centre and a radius > 0");
        if (sky_probability && !(*sky_probability >= 0.0f && *sky_probability <= 1.0f))
            throw std::invalid_argument("photon sky: the sky probability must lie in [0, 1]");
        environment_ = environment.view();
        scene_centre_ = scene_centre;
        scene_radius_ = scene_radius;
        sky_flux_ = static_cast<double>(environment_power(environment, scene_radius));
        sky_probability_ = sky_probability
                               ? *sky_probability
                               : static_cast<float>(sky_flux_ / (sky_flux_ + emitter_flux_));
    }

    /// Flux the sky sends into the bounding sphere (`environment_power`); 0 without a sky.
    double sky_flux() const noexcept { return sky_flux_; }

    /// Total flux of the emitter points, summed over the channels.
    double emitter_flux() const noexcept { return emitter_flux_; }

    /// No emitter points and no sky: nothing to shoot from.
    bool empty() const noexcept { return points_.empty() && !source().has_sky(); }
    const std::vector<EmitterPoint>& points() const noexcept { return points_; }
    const AliasTable& table() const noexcept { return table_; }
    /// Probability that a photon comes from the sky (0 without one).
    float sky_probability() const noexcept { return sky_probability_; }
    PhotonSource source() const noexcept {
        return {points_.data(), table_.view(), environment_,
                scene_centre_,  scene_radius_, sky_probability_};
    }

private:
    std::vector<EmitterPoint> points_;
    AliasTable table_;
    double emitter_flux_ = 0.0;
    double sky_flux_ = 0.0;
    EnvironmentMapView environment_{};
    glm::vec3 scene_centre_{0.0f};
    float scene_radius_ = 0.0f;
    float sky_probability_ = 0.0f;
};

/// Calls `body(i)` for i in [0, count) on the calling thread; pass your own (a thread pool's
/// parallel for) to `shoot_photons` to trace in parallel.
struct SequentialFor {
    template <class Body>
    void operator()(std::uint32_t count, Body&& body) const {
        for (std::uint32_t i = 0; i < count; ++i)
            body(i);
    }
};

/// Shoots `params.photon_count` photons from `emitters` (their points, and their sky if they
/// have one) and returns the VPLs, ordered by photon and bounce, so the result is the same
/// whatever `parallel_for` does (`parallel_for(count, body)` must call `body(i)` once for every
/// i in [0, count), on any threads). Empty emitters or a budget of 0 give an empty set.
/// (`params.points_per_emitter` is not read: the emitters were built already.)
template <ClosestHitQuery Query, ScatterFunction<HitOf<Query>, Pcg32> Scatter,
          class ParallelFor = SequentialFor>
std::vector<Vpl> shoot_photons(const PhotonEmitters& emitters, const Query& query,
                               const Scatter& scatter, const PhotonParams& params,
                               ParallelFor&& parallel_for = {}) {
    std::vector<Vpl> vpls;
    if (params.photon_count == 0u || params.max_bounces == 0u || emitters.empty())
        return vpls;
    const PhotonSource source = emitters.source();
    // Room for two VPLs per photon (a closed scene of albedo 0.5 averages two) before regrowth.
    vpls.reserve(2u * static_cast<std::size_t>(params.photon_count));

    // Batches bound the scratch memory; each photon owns max_bounces slots in its batch.
    constexpr std::uint32_t batch_size = 1u << 11u;
    const std::uint32_t slots = params.max_bounces;
    std::vector<Vpl> scratch(static_cast<std::size_t>(batch_size) * slots);
    std::vector<std::uint32_t> counts(batch_size);
    for (std::uint32_t first = 0; first < params.photon_count; first += batch_size) {
        const std::uint32_t n = min_of(batch_size, params.photon_count - first);
        parallel_for(n, [&](std::uint32_t i) {
            counts[i] = trace_photon(first + i, source, query, scatter, params,
                                     scratch.data() + static_cast<std::size_t>(i) * slots);
        });
        for (std::uint32_t i = 0; i < n; ++i)
            vpls.insert(vpls.end(), scratch.begin() + static_cast<std::ptrdiff_t>(i * slots),
                        scratch.begin() + static_cast<std::ptrdiff_t>(i * slots + counts[i]));
    }
    return vpls;
}

/// Shoots `params.photon_count` photons from the emitters of `lights` (`PhotonEmitters(lights,
/// params.points_per_emitter, params.seed)`, no sky) and returns the VPLs as the overload above
/// does. No emitters, emitters without flux, or a budget of 0 give an empty set.
template <LightSet Lights, ClosestHitQuery Query, ScatterFunction<HitOf<Query>, Pcg32> Scatter,
          class ParallelFor = SequentialFor>
std::vector<Vpl> shoot_photons(const Lights& lights, const Query& query, const Scatter& scatter,
                               const PhotonParams& params, ParallelFor&& parallel_for = {}) {
    if (params.photon_count == 0u || params.max_bounces == 0u)
        return {};
    const PhotonEmitters emitters(lights, params.points_per_emitter, params.seed);
    return shoot_photons(emitters, query, scatter, params, std::forward<ParallelFor>(parallel_for));
}

} // namespace restir
