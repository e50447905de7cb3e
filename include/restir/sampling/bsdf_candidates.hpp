/// @file sampling/bsdf_candidates.hpp
/// RIS candidates drawn from the receiver's BSDF as well as from the lights, combined by the
/// balance heuristic (multi-strategy RIS): light candidates miss the few lights inside a narrow
/// glossy lobe, a BSDF-sampled ray finds them. The ray's hit is turned into a light sample
/// (which light, which point): the inverse of `sample_point`, answered by the application's
/// ray query.
#pragma once

#include "restir/concepts.hpp"
#include "restir/config.hpp"
#include "restir/core/channels.hpp"
#include "restir/core/math.hpp"
#include "restir/core/reservoir.hpp"
#include "restir/core/rng.hpp"
#include "restir/light/falloff.hpp"
#include "restir/light/light_point_sample.hpp"
#include "restir/light/light_sample.hpp"
#include "restir/light/receiver.hpp"
#include "restir/light/solid_angle.hpp"
#include "restir/sampling/light_sampler.hpp"

#include <glm/geometric.hpp>
#include <glm/vec2.hpp>
#include <glm/vec3.hpp>

#include <concepts>
#include <cstdint>

namespace restir {

/// What a ray from a receiver hit first, when it is an emitter: the inverse of `sample_point`.
/// `point.radiance` is the radiance emitted towards the ray's origin (0 on an emitter's back),
/// `point.normal` the emitter's normal there, and `point.area_pdf` the density per unit area
/// with which the light candidates of the same RIS produce that point of light `light_id`
/// (1 / area for uniform area sampling). A ray that leaves the scene towards a distant light (an
/// environment) finds it: `point.is_distant`, `point.position` the ray's direction and
/// `point.area_pdf` the light's density per steradian there. `found` is false for a miss (no
/// distant light) or a hit on a surface that does not emit.
struct LightHit {
    bool found = false;
    std::uint32_t light_id = 0u;
    LightSample point{};
};

/// Finds the emitter along a ray. Required expression:
///   `query.find_light(origin, direction)` -> convertible to LightHit: the first surface hit
///   from `origin` (a receiver's position; the query offsets the ray's start off that surface,
///   as the application does for its own BSDF rays) along the unit `direction`.
/// Point lights and VPLs cannot be hit: only light candidates reach them, and the MIS weights
/// below give them to that strategy alone.
template <class Q>
concept LightHitQuery = requires(const Q& query, glm::vec3 origin, glm::vec3 direction) {
    { query.find_light(origin, direction) } -> std::convertible_to<LightHit>;
};

/// How many candidates each strategy draws.
struct CandidateCounts {
    std::uint32_t light = 32u; ///< M_light: lights from the sampler, a uniform uv on each.
    std::uint32_t bsdf = 1u;   ///< M_bsdf: directions from the receiver's BSDF.
};

namespace detail {
/// Density of the BSDF strategy in the light's own measure: per unit area at a point of an area
/// light (the solid-angle pdf of the direction to it, converted by `solid_angle_to_area_pdf`),
/// per steradian for a distant light's direction.
template <SamplingReceiver R>
RESTIR_HOST_DEVICE float bsdf_light_pdf(const R& receiver, const LightPointSample& light) {
    if (light.is_distant()) {
        const float pdf = static_cast<float>(receiver.direction_pdf(light.position));
        return is_valid_weight(pdf) ? pdf : 0.0f;
    }
    const glm::vec3 point = light.position;
    const glm::vec3 light_normal = light.normal;
    const glm::vec3 from = receiver.position;
    const glm::vec3 x = point - from;
    const float d2 = glm::dot(x, x);
    if (!(d2 > 0.0f))
        return 0.0f;
    const float pdf = solid_angle_to_area_pdf(
        static_cast<float>(receiver.direction_pdf(x * (1.0f / std::sqrt(d2)))), from, point,
        light_normal);
    return is_valid_weight(pdf) ? pdf : 0.0f;
}
} // namespace detail

/// How `resample_lights_and_bsdf` draws a light candidate's point on its light.
enum class LightPoints : std::uint8_t {
    /// `lights.sample_point(id, uv)`: uniform in area, as the light set maps uv.
    area,
    /// `lights.sample_point(id, uv, from)` from the receiver (uniform in the solid angle the
    /// light subtends, say; `ReceiverLightDensity`): bounded candidates next to a light. A BSDF
    /// candidate's light-strategy density is then `lights.point_pdf(id, point, from)`.
    from_receiver,
};

namespace detail {
/// The light strategy's density per unit area (per steradian for a distant light) of the point
/// a BSDF ray found, with points drawn as `Points` says.
template <LightPoints Points, class Lights>
RESTIR_HOST_DEVICE float light_point_pdf(const Lights& lights, const LightHit& hit,
                                         glm::vec3 from) {
    if constexpr (Points == LightPoints::from_receiver) {
        const float pdf =
            static_cast<float>(lights.point_pdf(hit.light_id, hit.point.position, from));
        return is_valid_weight(pdf) ? pdf : 0.0f;
    } else {
        (void)lights;
        (void)from;
        return static_cast<float>(hit.point.area_pdf);
    }
}
} // namespace detail

namespace detail {
/// Streams `counts.bsdf` BSDF candidates (a direction from `receiver`, the light it hits from
/// `query`) into `reservoir` with the balance heuristic against `counts.light` light candidates:
///   w = p-hat(x) / (M_light p_light(x) + M_bsdf p_bsdf(x)),
/// `light_pdf(hit)` being p_light of the hit's point (per unit area; per steradian for a distant
/// light's direction). Uses 3 numbers per candidate and 1 to stream it.
template <ChannelNorm Norm, UniformRng Rng, SamplingReceiver R, LightHitQuery Query, class LightPdf>
RESTIR_HOST_DEVICE void stream_bsdf_candidates(Rng& rng, Reservoir<LightPointSample>& reservoir,
                                               const CandidateCounts& counts,
                                               const Falloff& falloff, const R& receiver,
                                               const Query& query, const LightPdf& light_pdf) {
    const glm::vec3 from = glm::vec3(receiver.position);
    const float m_light = static_cast<float>(counts.light);
    const float m_bsdf = static_cast<float>(counts.bsdf);
    for (std::uint32_t i = 0; i < counts.bsdf; ++i) {
        const float u_lobe = next_float(rng);
        const float u0 = next_float(rng);
        const float u1 = next_float(rng);
        const DirectionSample direction = receiver.sample_direction(u_lobe, u0, u1);
        LightPointSample x;
        float weight = 0.0f;
        float target_value = 0.0f;
        if (direction.pdf > 0.0f) {
            const LightHit hit = query.find_light(from, direction.wi);
            if (hit.found && !hit.point.is_delta) {
                const float area_pdf = static_cast<float>(hit.point.area_pdf);
                x = make_light_point_sample(hit.light_id, hit.point, falloff);
                target_value =
                    fold_channels<Norm>(unshadowed_radiance(x, receiver)); // p-hat / area_pdf
                const float p_light = static_cast<float>(light_pdf(hit));
                // The direction's own density, converted: no second evaluation of the pdf.
                const float p_bsdf = x.is_distant() ? direction.pdf
                                                    : solid_angle_to_area_pdf(direction.pdf, from,
                                                                              x.position, x.normal);
                weight = safe_divide(target_value * area_pdf, m_light * p_light + m_bsdf * p_bsdf);
            }
        }
        reservoir.stream(x, weight, target_value, next_float(rng));
    }
}
} // namespace detail

/// Multi-strategy RIS over `counts.light` light candidates (a light from `sampler` at `at`, a
/// uniform uv on it, `lights.sample_point`) and `counts.bsdf` BSDF candidates (a direction from
/// `receiver`, the light it hits from `query`), with the balance heuristic over candidate counts
/// (Lin et al. 2022, Eq. 3.4; `resample_ris_mis`): in the area measure, with x a point on a light,
///   w_i = p-hat(x_i) / (M_light p_light(x_i) + M_bsdf p_bsdf(x_i)),
///   p_light(x) = pmf(light at `at`) area_pdf(x),  p_bsdf(x) = pdf_wi(x) |cos theta_light| / d^2,
/// and in the solid-angle measure for a distant light's direction (p_light = pmf pdf_light(wi),
/// p_bsdf = pdf_wi(wi): both strategies meet there in the same measure, docs/bridge.md),
/// p-hat(x) = |Le f G| (fold_channels<Norm>), W = w_sum / p-hat(y). Delta lights (points, VPLs) are
/// in the counting measure with p_bsdf = 0: a BSDF ray never hits them, so their MIS weight is 1
/// for light candidates, and RIS stays unbiased for them through the light strategy alone (as it
/// does for area lights outside every BSDF lobe).
///
/// The samples are made by `make_light_point_sample` from the light set's own point (intensity
/// radiance / area_pdf, as every other candidate and a packed history's decoder have them), so
/// the stored p-hat and W are those of the primary sample space, p-hat / area_pdf and W
/// area_pdf: f(y) W is the same. Shade with `unshadowed_radiance(sample, receiver) * W` as for
/// any reservoir. A hit's `point.area_pdf` must be positive (an emitter that the light set
/// cannot sample is not supported).
/// Uses 3 + 2 numbers per light candidate, 3 per BSDF candidate, 1 per candidate to stream.
///
/// With `Points` = `LightPoints::from_receiver` a light candidate's point comes from
/// `lights.sample_point(id, uv, from)` (`from` the receiver's position) and p_light(x) =
/// pmf(light at `at`) `lights.point_pdf(id, x, from)`, the density of the map the light strategy
/// sampled, for the BSDF candidates' weights too; the stored samples keep the light set's
/// intensity (radiance / area_pdf of their own point), which cancels in p-hat W as before.
template <ChannelNorm Norm = ChannelNorm::sum, LightPoints Points = LightPoints::area,
          UniformRng Rng, ContextLightSampler Sampler, LightSet Lights, SamplingReceiver R,
          LightHitQuery Query>
requires(Points == LightPoints::area || ReceiverLightDensity<Lights>)
    RESTIR_HOST_DEVICE Reservoir<LightPointSample> resample_lights_and_bsdf(
        Rng& rng, const CandidateCounts& counts, const Sampler& sampler, const ShadingPoint& at,
        const Lights& lights, const Falloff& falloff, const R& receiver, const Query& query) {
    const glm::vec3 from = glm::vec3(receiver.position);
    const float m_light = static_cast<float>(counts.light);
    const float m_bsdf = static_cast<float>(counts.bsdf);
    const auto target = [&](const LightPointSample& s) {
        return fold_channels<Norm>(unshadowed_radiance(s, receiver));
    };
    Reservoir<LightPointSample> reservoir;
    for (std::uint32_t i = 0; i < counts.light; ++i) {
        const DiscreteSample choice = sample_light(sampler, at, rng);
        const float u = next_float(rng); // named: the order of the draws is fixed
        const float v = next_float(rng);
        LightPointSample x;
        float weight = 0.0f;
        float target_value = 0.0f;
        if (choice.pmf > 0.0f) {
            const auto point = [&] {
                if constexpr (Points == LightPoints::from_receiver)
                    return lights.sample_point(choice.index, glm::vec2(u, v), from);
                else
                    return lights.sample_point(choice.index, glm::vec2(u, v));
            }();
            const bool is_delta = static_cast<bool>(point.is_delta);
            const float area_pdf = is_delta ? 1.0f : static_cast<float>(point.area_pdf);
            x = make_light_point_sample(choice.index, point, falloff);
            target_value = target(x); // p-hat / area_pdf
            const float p_bsdf = is_delta ? 0.0f : detail::bsdf_light_pdf(receiver, x);
            weight = safe_divide(target_value * area_pdf,
                                 m_light * choice.pmf * area_pdf + m_bsdf * p_bsdf);
        }
        reservoir.stream(x, weight, target_value, next_float(rng));
    }
    detail::stream_bsdf_candidates<Norm>(
        rng, reservoir, counts, falloff, receiver, query, [&](const LightHit& hit) {
            return sampler.pmf(at, hit.light_id) *
                   detail::light_point_pdf<Points>(lights, hit, from);
        });
    reservoir.finalize_normalized(1.0f);
    return reservoir;
}

} // namespace restir
