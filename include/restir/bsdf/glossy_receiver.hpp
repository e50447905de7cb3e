/// @file bsdf/glossy_receiver.hpp
/// A surface with the library's microfacet BSDF as a receiver: what target functions, the batch
/// target loop and BSDF-sampled candidates evaluate at a glossy pixel.
#pragma once

#include "restir/bsdf/glossy_bsdf.hpp"
#include "restir/config.hpp"
#include "restir/light/receiver.hpp"

#include <glm/vec3.hpp>

namespace restir {

/// A receiver with a `GlossyBsdf` (diffuse + GGX specular), seen from `wo`.
struct GlossyReceiver {
    glm::vec3 position{0.0f};
    glm::vec3 normal{0.0f, 0.0f, 1.0f}; ///< Unit shading normal.
    glm::vec3 wo{0.0f, 0.0f, 1.0f};     ///< Unit, towards the viewer.
    GlossyBsdf bsdf{};

    /// f(wo, wi) max(0, n.wi) (`GlossyBsdf::evaluate_cos`: branch-free, for the batch loop).
    RESTIR_HOST_DEVICE glm::vec3 reflected(glm::vec3 wi) const {
        return bsdf.evaluate_cos(normal, wo, wi);
    }
    /// A direction from the BSDF's lobes (`GlossyBsdf::sample`).
    RESTIR_HOST_DEVICE DirectionSample sample_direction(float u_lobe, float u0, float u1) const {
        const BsdfSample s = bsdf.sample(normal, wo, u_lobe, u0, u1);
        return {s.wi, s.pdf};
    }
    /// The solid-angle density of `sample_direction` at `wi`.
    RESTIR_HOST_DEVICE float direction_pdf(glm::vec3 wi) const { return bsdf.pdf(normal, wo, wi); }
};

static_assert(SamplingReceiver<GlossyReceiver>);

} // namespace restir
