#include "path_tracer.hpp"

#include "reservoir.hpp"

#include <glm/geometric.hpp>

#include <algorithm>
#include <cmath>

namespace pt {

namespace {

float max_component(glm::vec3 c) { return std::max(c.x, std::max(c.y, c.z)); }

// The next direction of a path at `s`, drawn from its BSDF: on a Lambertian surface by cosine
// from two random numbers (weight = albedo), as every surface was before glossy materials, so
// that diffuse scenes keep their images; otherwise GlossyBsdf::sample from three.
restir::BsdfSample sample_bounce(const GSurface& s, restir::Pcg32& rng) {
    if (is_lambertian(s)) {
        const float u0 = next_float(rng);
        const float u1 = next_float(rng);
        const glm::vec3 wi = restir::sample_diffuse_direction(s.normal, u0, u1);
        return {wi, s.albedo, restir::diffuse_direction_pdf(s.normal, wi)};
    }
    const float u_lobe = next_float(rng);
    const float u0 = next_float(rng);
    const float u1 = next_float(rng);
    return surface_bsdf(s).sample(s.normal, view_direction(s), u_lobe, u0, u1);
}

} // namespace

glm::vec3 PathTracer::reflected(const GSurface& s, const restir::LightSample& light) const {
    if (is_lambertian(s))
        return s.albedo * restir::inv_pi *
               restir::unshadowed_irradiance(light, s.position, s.normal, lights_.falloff());
    // The same function as the light samples' target and shading (reservoir.hpp), VPLs with
    // their regularised lobe, so that the reference of a VPL set is that set's integrand.
    return restir::unshadowed_radiance(
        restir::make_light_point_sample(0u, light, lights_.falloff()), glossy_receiver(s));
}

// The segment restir::LightVisibility tests for a point of an emitter or a VPL.
bool PathTracer::visible(const restir::LightSample& light, const GSurface& s) const {
    const restir::ShadowSegment segment =
        restir::shadow_segment(s.position, s.normal, light.position, light.normal, ray_offset_);
    return !rays_.occluded(segment.from, segment.to);
}

// One emitter by power with MIS (balance heuristic) against the BSDF's sampling: a triangle's
// point uniform in area, a light shape's uniform in the solid angle it subtends from `s` (the
// shape's own sampling, SceneEmitters::is_shape). Kept inline in path_radiance: the compiler
// fuses multiplies and adds across the call (FMA), so the image's last bits depend on it.
[[gnu::always_inline]] inline glm::vec3 PathTracer::emitter_nee(const GSurface& s,
                                                                restir::Pcg32& rng) const {
    const restir::DiscreteSample c =
        restir::sample_light(restir::PowerLightSampler{lights_.emitter_table().view()}, rng);
    const float u = next_float(rng);
    const float v = next_float(rng);
    if (!(c.pmf > 0.0f))
        return glm::vec3(0.0f);
    const SceneEmitters& emitters = lights_.emitters();
    const restir::LightSample light = emitters.is_shape(c.index)
                                          ? emitters.sample_point(c.index, {u, v}, s.position)
                                          : emitters.sample_point(c.index, {u, v});
    const glm::vec3 to_light = light.position - s.position;
    const float d2 = glm::dot(to_light, to_light);
    const glm::vec3 w = to_light / std::sqrt(d2);
    const float cos_light = -glm::dot(light.normal, w);
    const float cos_surface = glm::dot(s.normal, w);
    if (!(cos_light > 0.0f) || !(cos_surface > 0.0f) || !(light.area_pdf > 0.0f) ||
        !visible(light, s))
        return glm::vec3(0.0f);
    const float light_pdf = c.pmf * light.area_pdf * d2 / cos_light; // solid angle
    const float bsdf_pdf = bounce_pdf(s, w);
    return reflected(s, light) / c.pmf * (light_pdf / (light_pdf + bsdf_pdf));
}

glm::vec3 PathTracer::environment_nee(const GSurface& s, restir::Pcg32& rng) const {
    const float u0 = next_float(rng);
    const float u1 = next_float(rng);
    const restir::EnvironmentSample sky = environment_.sample({u0, u1});
    if (!(sky.pdf > 0.0f) || !(glm::dot(s.normal, sky.direction) > 0.0f))
        return glm::vec3(0.0f);
    const restir::ShadowSegment way_out = restir::distant_shadow_segment(
        s.position, s.normal, sky.direction, ray_offset_, escape_distance_);
    if (rays_.occluded(way_out.from, way_out.to))
        return glm::vec3(0.0f);
    // f L cos / p_sky times the balance heuristic p_sky / (p_sky + p_bsdf) (Veach 1997, 9.2).
    return reflected(s, restir::environment_light_sample(sky)) *
           (sky.pdf / (sky.pdf + bounce_pdf(s, sky.direction)));
}

glm::vec3 PathTracer::escaped(const restir::BsdfSample& bounce) const {
    const glm::vec3 radiance = environment_.radiance(bounce.wi);
    if (!environment_nee_)
        return radiance;
    return radiance * (bounce.pdf / (bounce.pdf + environment_.pdf(bounce.wi)));
}

glm::vec3 PathTracer::vpl_nee(const GSurface& s, restir::Pcg32& rng) const {
    if (lights_.vpls().empty())
        return glm::vec3(0.0f);
    const restir::DiscreteSample c =
        restir::sample_light(restir::PowerLightSampler{lights_.vpl_table().view()}, rng);
    if (!(c.pmf > 0.0f))
        return glm::vec3(0.0f);
    const restir::LightSample vpl =
        lights_.lights().sample_point(lights_.lights().first_vpl() + c.index, glm::vec2(0.0f));
    if (!visible(vpl, s))
        return glm::vec3(0.0f);
    return reflected(s, vpl) / c.pmf;
}

glm::vec3 PathTracer::path_radiance(const GSurface& start, restir::Pcg32& rng, bool direct,
                                    bool bounce_further) const {
    return radiance_from(start, rng, direct, bounce_further, 0u);
}

restir::PathSample PathTracer::path_sample(const GSurface& s, restir::Pcg32& rng,
                                           const restir::VplPartition* partition) const {
    restir::PathSample sample;
    const restir::BsdfSample bounce = sample_bounce(s, rng);
    if (!(bounce.pdf > 0.0f) || max_depth_ < 2u)
        return sample;
    const Hit hit = rays_.closest_hit_from(s.position, s.normal, bounce.wi, ray_offset_);
    if (!hit.found)
        return sample;
    const GSurface next = surface_at(scene_, hit, bounce.wi);
    sample.visible_point = s.position;
    sample.sample_point = next.position;
    sample.sample_normal = next.normal;
    sample.source_pdf = bounce.pdf;
    // 1 marks a Lambertian surface alone (restir::holds_vpls): a glossy one reports less.
    sample.sample_roughness =
        is_lambertian(next)
            ? 1.0f
            : std::min(static_cast<float>(next.roughness) * (1.0f / 65535.0f), 0.99999994f);
    // A Lambertian pixel's light from a Lambertian surface at least r away is all the VPLs'
    // (restir::partitioned_path_radiance is 0): its radiance is not traced.
    if (partition != nullptr && is_lambertian(s) && is_lambertian(next) &&
        partition->vpl_share(hit.distance) >= 1.0f)
        return sample;
    sample.radiance = radiance_from(next, rng, true, true, 1u);
    return sample;
}

glm::vec3 PathTracer::partitioned_indirect(const GSurface& s, restir::Pcg32& rng,
                                           const restir::VplPartition& partition) const {
    const restir::PathSample x = path_sample(s, rng, &partition);
    if (!(x.source_pdf > 0.0f))
        return glm::vec3(0.0f);
    return with_receiver(s, [&](const auto& receiver) {
        return restir::partitioned_path_radiance(x, receiver, partition) / x.source_pdf;
    });
}

glm::vec3 PathTracer::radiance_from(const GSurface& start, restir::Pcg32& rng, bool direct,
                                    bool bounce_further, std::uint32_t first_depth) const {
    const SceneEmitters& emitters = lights_.emitters();
    glm::vec3 radiance(0.0f);
    glm::vec3 throughput(1.0f);
    GSurface s = start;
    for (std::uint32_t depth = first_depth;; ++depth) {
        if (direct)
            radiance += throughput * emitter_nee(s, rng);
        if (direct && environment_nee_)
            radiance += throughput * environment_nee(s, rng);
        if (depth + 1 >= max_depth_ || (!direct && !bounce_further && depth > 0))
            break;
        const restir::BsdfSample bounce = sample_bounce(s, rng);
        if (!(bounce.pdf > 0.0f))
            break;
        const glm::vec3 direction = bounce.wi;
        const Hit hit = rays_.closest_hit_from(s.position, s.normal, direction, ray_offset_);
        if (!hit.found) {
            if (direct && !environment_.empty())
                radiance += throughput * bounce.weight * escaped(bounce);
            break;
        }
        throughput *= bounce.weight; // f cos / pdf
        const std::uint32_t emitter = emitters.emitter_of_primitive(hit.primitive);
        if (direct && emitter != SceneEmitters::none && glm::dot(hit.normal, direction) < 0.0f) {
            const float cos_light = -glm::dot(hit.normal, direction);
            const float light_pdf = lights_.emitter_hit_pdf(emitter, hit, s.position, cos_light);
            radiance +=
                throughput * emitters.radiance(emitter) * (bounce.pdf / (bounce.pdf + light_pdf));
        }
        if (!bounce_further)
            break;
        if (depth >= 2) { // Russian roulette
            const float survival = std::min(0.95f, max_component(throughput));
            if (!(survival > 0.0f) || next_float(rng) >= survival)
                break;
            throughput /= survival;
        }
        s = surface_at(scene_, hit, direction);
        direct = true;
    }
    return radiance;
}

} // namespace pt
