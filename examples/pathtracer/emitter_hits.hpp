// The emitter a BSDF ray finds (restir::LightHitQuery), for BSDF-sampled RIS candidates
// (--bsdf-candidates).
#pragma once

#include "embree_scene.hpp"
#include "light_set.hpp"

#include <restir/restir.hpp>

namespace pt {

/// The inverse of SceneEmitters::sample_point (a uniform point by area on a triangle or a
/// light shape, so the light candidates' density there is 1 / area; drawn from the receiver,
/// the library asks SceneEmitters::point_pdf instead); or, where the ray leaves the scene, the
/// environment's direction (its density per steradian from the map).
struct EmitterHits {
    const EmbreeScene* rays;
    const Unified* lights;
    glm::vec3 normal;
    float ray_offset;

    restir::LightHit find_light(glm::vec3 origin, glm::vec3 direction) const {
        const Hit hit = rays->closest_hit_from(origin, normal, direction, ray_offset);
        if (!hit.found)
            return lights->environment_count() == 0u
                       ? restir::LightHit{}
                       : restir::LightHit{
                             true, lights->environment_id(),
                             restir::environment_light_point(lights->environment, direction)};
        const SceneEmitters* emitters = lights->emitters;
        const std::uint32_t emitter = emitters->emitter_of_primitive(hit.primitive);
        if (emitter == SceneEmitters::none)
            return {};
        restir::LightHit light{true, emitter, {}};
        light.point.position = hit.position;
        light.point.normal = hit.normal;
        // One-sided: the back of an emitter sends nothing.
        light.point.radiance =
            glm::dot(hit.normal, direction) < 0.0f ? emitters->radiance(emitter) : glm::vec3(0.0f);
        light.point.area_pdf = 1.0f / emitters->area(emitter);
        return light;
    }
};

} // namespace pt
