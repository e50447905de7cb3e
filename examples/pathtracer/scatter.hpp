// The photon shooter's scatter hook for the renderer's materials: Lambertian reflection of
// the hit primitive's base colour (Material::albedo), sampled by cosine about the normal facing
// the photon. Glossy materials reflect photons diffusely too, a metal in its F0 colour, and
// their VPLs are diffuse emitters (docs/renderer.md). Emitters reflect too but hold no VPL
// (restir::ScatterFunction).
#pragma once

#include "embree_scene.hpp"
#include "scene.hpp"

#include <restir/core/rng.hpp>
#include <restir/vpl/photon_shooter.hpp>

#include <glm/geometric.hpp>

namespace pt {

struct LambertianScatter {
    const Scene* scene = nullptr;

    restir::Scattering operator()(const Hit& hit, glm::vec3 incoming, restir::Pcg32& rng) const {
        const Material& m = scene->materials[scene->material_of(hit.primitive)];
        const glm::vec3 facing = glm::dot(hit.normal, incoming) < 0.0f ? hit.normal : -hit.normal;
        const float u0 = next_float(rng);
        const float u1 = next_float(rng);
        return {restir::sample_diffuse_direction(facing, u0, u1), m.albedo, m.albedo, true,
                m.is_emissive()};
    }
};

} // namespace pt
