/// @file bsdf/ggx.hpp
/// The GGX (Trowbridge-Reitz) microfacet distribution, its Smith masking-shadowing terms and
/// the sampling of its visible normals. All in the local frame (z = normal), isotropic, with
/// alpha = roughness^2.
#pragma once

#include "restir/config.hpp"
#include "restir/core/math.hpp"

#include <glm/geometric.hpp>
#include <glm/vec3.hpp>

#include <cmath>

namespace restir {

/// The smallest GGX alpha: `ggx_alpha` clamps to it (roughness below about 0.0316). The
/// distribution's peak 1 / (pi alpha^2) stays finite down to alpha = 0, but float dot products
/// cannot resolve the lobe there: its width in 1 - cos(theta_m) is about alpha^2 / 2, and a
/// cosine near 1 computed from float vectors is off by about 1e-7, so at alpha = 1e-3 the
/// peak is already within about 10 % (roughness 0.02, alpha 4e-4, would be within 40 %).
inline constexpr float ggx_min_alpha = 1e-3f;

/// GGX alpha from a perceptual roughness (the usual remapping, Burley 2012): roughness^2, with
/// roughness clamped to [0, 1] and alpha to at least `ggx_min_alpha`. NaN gives the minimum.
RESTIR_HOST_DEVICE inline float ggx_alpha(float roughness) {
    const float r = min_of(max_of(0.0f, roughness), 1.0f); // max_of(0, NaN) is 0
    return max_of(r * r, ggx_min_alpha);
}

/// D(m) from cos^2 and sin^2 of theta_m, which callers may compute more accurately than
/// 1 - cos^2 near the normal (from the tangential components of m): Walter et al. 2007,
/// eq. 33, as alpha^2 / (pi (alpha^2 cos^2 + sin^2)^2). The bracket is clamped to at least
/// alpha^2, its exact minimum for a unit m and alpha <= 1, so that rounding or a degenerate m
/// cannot make D infinite. The caller selects 0 where cos(theta_m) <= 0.
RESTIR_HOST_DEVICE inline float ggx_ndf_from_squares(float cos2, float sin2, float alpha) {
    const float a2 = alpha * alpha;
    const float s = max_of(a2 * cos2 + sin2, a2);
    return a2 / (pi * s * s);
}

/// D(m), the GGX / Trowbridge-Reitz distribution of normals (Walter et al. 2007, "Microfacet
/// Models for Refraction through Rough Surfaces", eq. 33): alpha^2 / (pi cos^4 (alpha^2 +
/// tan^2)^2) for cos_theta_m > 0, else 0. Normalised: integral of D(m) cos(theta_m) dm = 1.
RESTIR_HOST_DEVICE inline float ggx_ndf(float cos_theta_m, float alpha) {
    const float c = min_of(max_of(cos_theta_m, 0.0f), 1.0f);
    // 1 - c^2 without cancellation for c near 1 (1 - c is exact there, Sterbenz).
    const float d = ggx_ndf_from_squares(c * c, (1.0f - c) * (1.0f + c), alpha);
    return cos_theta_m > 0.0f ? d : 0.0f;
}

/// sqrt(alpha^2 + (1 - alpha^2) cos^2): the one square root of a Smith term of GGX.
RESTIR_HOST_DEVICE inline float smith_root(float cos_theta, float alpha) {
    const float a2 = alpha * alpha;
    return std::sqrt(a2 + (1.0f - a2) * (cos_theta * cos_theta));
}

/// Smith's Lambda of GGX (Heitz 2014, "Understanding the Masking-Shadowing Function in
/// Microfacet-Based BRDFs", eq. 72): (-1 + sqrt(1 + alpha^2 tan^2 theta)) / 2, written as
/// (sqrt(alpha^2 + (1 - alpha^2) cos^2) / cos - 1) / 2. For cos_theta > 0; a cos_theta <= 0
/// is taken as 1e-30 (grazing: a large finite Lambda, G1 of about 0).
RESTIR_HOST_DEVICE inline float smith_lambda(float cos_theta, float alpha) {
    const float c = min_of(max_of(cos_theta, 1e-30f), 1.0f);
    return 0.5f * (smith_root(c, alpha) / c - 1.0f);
}

/// Smith's masking term G1 = 1 / (1 + Lambda) (Heitz 2014, eq. 43), as
/// 2 cos / (cos + sqrt(alpha^2 + (1 - alpha^2) cos^2)); 0 for cos_theta <= 0.
RESTIR_HOST_DEVICE inline float smith_g1(float cos_theta, float alpha) {
    const float c = min_of(max_of(cos_theta, 0.0f), 1.0f);
    const float g = 2.0f * c / (c + smith_root(c, alpha));
    return cos_theta > 0.0f ? g : 0.0f;
}

/// ci root(co) + co root(ci) for cosines in [0, 1]: G2 (below) is 2 co ci over it, and a BSDF
/// that folds G2 / (4 co ci) into one division divides by it alone (`glossy_evaluate_cos`).
RESTIR_HOST_DEVICE RESTIR_FORCE_INLINE float smith_g2_denominator(float co, float ci, float alpha) {
    return ci * smith_root(co, alpha) + co * smith_root(ci, alpha);
}

/// The height-correlated masking-shadowing term G2 = 1 / (1 + Lambda(o) + Lambda(i)) (Heitz
/// 2014, eq. 99) for reflection, as 2 co ci / (ci root(co) + co root(ci)); 0 when either
/// direction is at or below the surface.
RESTIR_HOST_DEVICE inline float smith_g2(float cos_theta_o, float cos_theta_i, float alpha) {
    const float co = min_of(max_of(cos_theta_o, 0.0f), 1.0f);
    const float ci = min_of(max_of(cos_theta_i, 0.0f), 1.0f);
    const float denominator = smith_g2_denominator(co, ci, alpha);
    const float g = 2.0f * co * ci / max_of(denominator, 1e-30f);
    return cos_theta_o > 0.0f && cos_theta_i > 0.0f ? g : 0.0f;
}

/// A normal m drawn from the distribution of normals visible from the unit `wo_local`
/// (wo_local.z > 0: a view at or below the surface has no visible normals; check it first),
/// D_wo(m) = G1(wo) max(0, wo.m) D(m) / wo.z: Heitz 2018, "Sampling the GGX Distribution of
/// Visible Normals" (JCGT 7(4)), listing 1. The view is stretched to the hemisphere
/// configuration (alpha = 1), a point is drawn on the projected disk of visible normals, then
/// mapped back to the ellipsoid. `ggx_vndf_pdf` is its density. u0, u1 uniform in [0, 1).
RESTIR_HOST_DEVICE inline glm::vec3 sample_ggx_vndf(glm::vec3 wo_local, float alpha, float u0,
                                                    float u1) {
    // Stretched view (sec. 3.2, step 1).
    const glm::vec3 v =
        glm::normalize(glm::vec3(alpha * wo_local.x, alpha * wo_local.y, wo_local.z));
    // Orthonormal basis about it (T1 = x when v is the pole).
    const float length2 = v.x * v.x + v.y * v.y;
    const glm::vec3 t1 = length2 > 0.0f ? glm::vec3(-v.y, v.x, 0.0f) / std::sqrt(length2)
                                        : glm::vec3(1.0f, 0.0f, 0.0f);
    const glm::vec3 t2 = glm::cross(v, t1);
    // A point of the unit disk, its lower half squeezed onto the visible part of the
    // projected hemisphere (step 2).
    const float r = std::sqrt(u0);
    const float phi = two_pi * u1;
    const float p1 = r * std::cos(phi);
    const float s = 0.5f * (1.0f + v.z);
    const float p2 = (1.0f - s) * std::sqrt(max_of(0.0f, 1.0f - p1 * p1)) + s * (r * std::sin(phi));
    // Reprojection onto the hemisphere (step 3), then unstretching (step 4).
    const glm::vec3 nh = p1 * t1 + p2 * t2 + std::sqrt(max_of(0.0f, 1.0f - p1 * p1 - p2 * p2)) * v;
    return glm::normalize(glm::vec3(alpha * nh.x, alpha * nh.y, max_of(0.0f, nh.z)));
}

/// The density of `sample_ggx_vndf(wo_local, alpha, ...)` at the unit normal `m_local`
/// (Heitz 2018, eq. 1): G1(wo) max(0, wo.m) D(m) / wo.z; 0 when wo or m is at or below the
/// surface. D is computed from the tangential components of m (accurate near the normal).
RESTIR_HOST_DEVICE inline float ggx_vndf_pdf(glm::vec3 wo_local, glm::vec3 m_local, float alpha) {
    const float d = ggx_ndf_from_squares(m_local.z * m_local.z,
                                         m_local.x * m_local.x + m_local.y * m_local.y, alpha);
    // G1(wo) / wo.z = 2 / (wo.z + root(wo.z)): no division by a small cosine.
    const float co = min_of(max_of(wo_local.z, 0.0f), 1.0f);
    const float pdf =
        2.0f * max_of(0.0f, glm::dot(wo_local, m_local)) * d / (co + smith_root(co, alpha));
    return wo_local.z > 0.0f && m_local.z > 0.0f ? pdf : 0.0f;
}

} // namespace restir
