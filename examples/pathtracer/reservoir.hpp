// The renderer's reservoir, its storage, and a sample's target function at a G-buffer surface.
#pragma once

#include "buffer_allocator.hpp"
#include "gbuffer.hpp"

#include <restir/restir.hpp>

namespace pt {

/// Reservoirs keep their light point (restir::LightPointSample): reuse evaluates p-hat at other
/// surfaces without reading the light and VPL arrays again.
using Reservoir = restir::Reservoir<restir::LightPointSample>;
static_assert(sizeof(Reservoir) == 64u, "one reservoir per cache line");

/// A reservoir per pixel.
using ReservoirBuffer = PixelBuffer<Reservoir>;

/// p-hat folds the reflected radiance's channels by their Euclidean norm, which minimises the
/// summed channel variance of one sample (the channel sum left 6-8 % more error per frame in the
/// Cornell box, mostly colour noise; luminance would weigh blue 0.07, so a saturated blue light
/// would be drawn 14 times too rarely). The initial candidates use the same function in its
/// batch form (restir::evaluate_tile_block at the surface's receiver).
inline constexpr restir::ChannelNorm target_norm = restir::ChannelNorm::euclidean;

/// The smallest GGX alpha (roughness 0.5) with which VPLs, spheres of Yuksel's radius, light a
/// glossy surface (restir::GlossyReceiver::sphere_min_alpha): a regularisation, biased as the
/// falloff is, without which a narrow lobe shows single VPLs as sparkles that light candidates
/// rarely find (docs/noise-and-bias.md). Emitters light every surface through its own BSDF.
inline constexpr float vpl_min_alpha = 0.25f;

/// Surface `s` as a glossy receiver, seen from its viewer. The VPLs of gi vpl-unbiased (the
/// only lights with the clamped falloff here) reach its diffuse lobe alone, their specular
/// share left to path samples (restir::VplPartition).
inline restir::GlossyReceiver glossy_receiver(const GSurface& s) {
    return {s.position, s.normal, view_direction(s), surface_bsdf(s), vpl_min_alpha, true};
}

/// body(receiver) at surface `s`: a Lambertian surface as restir::LambertianReceiver (the
/// library's folded diffuse formulas, as fast as before glossy materials), any other with its
/// GGX + Lambert BSDF seen from its viewer (restir::GlossyReceiver).
template <class Body>
decltype(auto) with_receiver(const GSurface& s, Body&& body) {
    if (is_lambertian(s))
        return body(restir::LambertianReceiver{s.position, s.normal, s.albedo});
    return body(glossy_receiver(s));
}

namespace detail {
// The glossy branch of point_target and unshadowed, out of line: reuse evaluates p-hat for
// every neighbour (pair), and the GGX evaluation inlined there made the diffuse path's loops
// larger and slower (docs/performance.md).
[[gnu::noinline]] inline float glossy_target(const restir::LightPointSample& sample,
                                             const GSurface& s) {
    return restir::fold_channels<target_norm>(
        restir::unshadowed_radiance(sample, glossy_receiver(s)));
}
[[gnu::noinline]] inline glm::vec3 glossy_radiance(const restir::LightPointSample& sample,
                                                   const GSurface& s) {
    return restir::unshadowed_radiance(sample, glossy_receiver(s));
}
} // namespace detail

/// p-hat of a light point at surface `s`: its unshadowed reflected radiance, folded.
inline float point_target(const restir::LightPointSample& sample, const GSurface& s) {
    if (is_lambertian(s)) [[likely]]
        return restir::fold_channels<target_norm>(restir::unshadowed_radiance(
            sample, restir::LambertianReceiver{s.position, s.normal, s.albedo}));
    return detail::glossy_target(sample, s);
}

/// f(y) W without visibility, for a reservoir whose sample is known to be visible.
inline glm::vec3 unshadowed(const Reservoir& reservoir, const GSurface& s) {
    if (!reservoir.has_sample() || !(reservoir.contribution_weight > 0.0f))
        return glm::vec3(0.0f);
    const glm::vec3 radiance =
        is_lambertian(s)
            ? restir::unshadowed_radiance(
                  reservoir.sample, restir::LambertianReceiver{s.position, s.normal, s.albedo})
            : detail::glossy_radiance(reservoir.sample, s);
    return radiance * reservoir.contribution_weight;
}

} // namespace pt
