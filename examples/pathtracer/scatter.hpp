// The photon shooter's scatter hooks for the renderer's materials (restir::ScatterFunction).
// LambertianScatter (gi vpl): Lambertian reflection of the hit primitive's base colour
// (Material::albedo), sampled by cosine about the normal facing the photon; glossy materials
// reflect photons diffusely too, a metal in its F0 colour, and their VPLs are diffuse emitters
// (docs/renderer.md). BsdfScatter (gi vpl-unbiased): each material's own BSDF, VPLs on
// Lambertian surfaces alone. Emitters reflect too but hold no VPL.
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

/// Photons reflected by the material's BSDF, drawn as the path tracer draws bounces: by cosine
/// on a Lambertian surface (weight = albedo), GlossyBsdf::sample otherwise (weight f cos / p,
/// the BSDF being reciprocal). Only Lambertian surfaces hold VPLs: a VPL's flux Phi albedo is
/// then exactly what the surface reflects, in every direction. An emitter's surface holds VPLs
/// of the light it reflects as any Lambertian surface does: a path sample that finds it carries
/// its reflected light alone, as a VPL does.
struct BsdfScatter {
    const Scene* scene = nullptr;

    restir::Scattering operator()(const Hit& hit, glm::vec3 incoming, restir::Pcg32& rng) const {
        const Material& m = scene->materials[scene->material_of(hit.primitive)];
        const glm::vec3 facing = glm::dot(hit.normal, incoming) < 0.0f ? hit.normal : -hit.normal;
        if (m.is_lambertian()) {
            const float u0 = next_float(rng);
            const float u1 = next_float(rng);
            return {restir::sample_diffuse_direction(facing, u0, u1), m.albedo, m.albedo, true,
                    false};
        }
        const float u_lobe = next_float(rng);
        const float u0 = next_float(rng);
        const float u1 = next_float(rng);
        const restir::BsdfSample s = m.bsdf().sample(facing, -incoming, u_lobe, u0, u1);
        const glm::vec3 weight = s.pdf > 0.0f ? s.weight : glm::vec3(0.0f);
        return {s.wi, weight, glm::vec3(0.0f), false, false};
    }
};

} // namespace pt
