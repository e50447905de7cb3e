/// @file bsdf/glossy_receiver.hpp
/// A surface with the library's microfacet BSDF as a receiver: what target functions, the batch
/// target loop and BSDF-sampled candidates evaluate at a glossy pixel.
#pragma once

#include "restir/bsdf/ggx.hpp"
#include "restir/bsdf/glossy_bsdf.hpp"
#include "restir/config.hpp"
#include "restir/core/math.hpp"
#include "restir/light/receiver.hpp"

#include <glm/vec3.hpp>

namespace restir {

/// A receiver with a `GlossyBsdf` (diffuse + GGX specular), seen from `wo`.
struct GlossyReceiver {
    glm::vec3 position{0.0f};
    glm::vec3 normal{0.0f, 0.0f, 1.0f}; ///< Unit shading normal.
    glm::vec3 wo{0.0f, 0.0f, 1.0f};     ///< Unit, towards the viewer.
    GlossyBsdf bsdf{};
    /// The smallest GGX alpha with which light from a sphere (a point light with Yuksel's
    /// falloff, a VPL) is reflected: a regularisation (biased, like the falloff) against the
    /// sparkles of point lights in a narrow lobe, which light candidates rarely find and BSDF
    /// rays never hit (Kaplanyan and Dachsbacher 2013 regularise such paths by widening the
    /// lobe). 0: none.
    float sphere_min_alpha = 0.0f;
    /// Light from the VPLs of a `VplPartition` (points with the clamped inverse-square falloff)
    /// reaches the diffuse lobe alone: their specular share is left to path samples
    /// (`partitioned_path_radiance`), so that no VPL is a sparkle in a narrow lobe. False: the
    /// whole BSDF, as for every other light.
    bool vpls_diffuse_only = false;

    /// f(wo, wi) max(0, n.wi) (`GlossyBsdf::evaluate_cos`: branch-free, for the batch loop).
    RESTIR_HOST_DEVICE RESTIR_FORCE_INLINE glm::vec3 reflected(glm::vec3 wi) const {
        return bsdf.evaluate_cos(normal, wo, wi);
    }
    /// The same for light from a sphere of angular radius `sphere_radius` (its radius over its
    /// distance; 0 for a point of an area light): the specular lobe widened as a sphere light
    /// widens it, alpha + sphere_radius / 2 (Karis 2013, "Real Shading in Unreal Engine 4"), and
    /// to at least `sphere_min_alpha`.
    RESTIR_HOST_DEVICE RESTIR_FORCE_INLINE glm::vec3 reflected(glm::vec3 wi,
                                                               float sphere_radius) const {
        return reflected(wi, sphere_radius, false);
    }
    /// The same, where `from_vpl` marks light from a VPL of a `VplPartition`: its diffuse lobe
    /// alone where `vpls_diffuse_only` (a select, not a branch: for the batch loop).
    RESTIR_HOST_DEVICE RESTIR_FORCE_INLINE glm::vec3 reflected(glm::vec3 wi, float sphere_radius,
                                                               bool from_vpl) const {
        const float alpha = ggx_alpha(bsdf.roughness);
        const float widened = min_of(max_of(alpha + 0.5f * sphere_radius, sphere_min_alpha), 1.0f);
        const float specular_weight = select_float(from_vpl & vpls_diffuse_only, 0.0f, 1.0f);
        return bsdf.evaluate_cos(normal, wo, wi, sphere_radius > 0.0f ? widened : alpha,
                                 specular_weight);
    }
    /// A direction from the BSDF's lobes (`GlossyBsdf::sample`).
    RESTIR_HOST_DEVICE DirectionSample sample_direction(float u_lobe, float u0, float u1) const {
        const BsdfSample s = bsdf.sample(normal, wo, u_lobe, u0, u1);
        return {s.wi, s.pdf};
    }
    /// The solid-angle density of `sample_direction` at `wi`.
    RESTIR_HOST_DEVICE RESTIR_FORCE_INLINE float direction_pdf(glm::vec3 wi) const {
        return bsdf.pdf(normal, wo, wi);
    }
};

static_assert(SamplingReceiver<GlossyReceiver>);

} // namespace restir
