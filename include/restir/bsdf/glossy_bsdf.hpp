/// @file bsdf/glossy_bsdf.hpp
/// The usual metallic-roughness material: a Lambertian lobe under a GGX specular lobe with
/// Schlick's Fresnel, reflection only. Evaluation (the batch RIS hot path, branchless), the
/// density of its sampler, and the sampler: a lobe by `specular_probability`, then the GGX
/// visible normals (Heitz 2018) or a cosine-weighted direction.
#pragma once

#include "restir/bsdf/fresnel.hpp"
#include "restir/bsdf/ggx.hpp"
#include "restir/bsdf/shading_frame.hpp"
#include "restir/config.hpp"
#include "restir/core/math.hpp"
#include "restir/sampling/diffuse_direction.hpp"

#include <glm/common.hpp>
#include <glm/geometric.hpp>
#include <glm/vec3.hpp>

#include <cmath>

namespace restir {

/// Sampled direction of a BSDF: wi (unit, world), weight = f(wo, wi) |n.wi| / pdf, pdf (solid
/// angle); pdf == 0 means no sample (the direction is invalid).
struct BsdfSample {
    glm::vec3 wi{0.0f};     ///< Unit direction towards the light, world space.
    glm::vec3 weight{0.0f}; ///< f(wo, wi) |n.wi| / pdf.
    float pdf = 0.0f;       ///< Solid-angle density; 0: no sample.
};

/// The lowest probability of either lobe in `GlossyBsdf::specular_probability` when both
/// reflect something, so that neither is left almost unsampled where the estimate of the other
/// was too low.
inline constexpr float glossy_lobe_probability_floor = 0.1f;

namespace detail {

/// Rec. 709 luminance, the weight of a colour when choosing a lobe.
RESTIR_HOST_DEVICE inline float glossy_luminance(glm::vec3 c) {
    return 0.2126f * c.x + 0.7152f * c.y + 0.0722f * c.z;
}

/// One channel of `glossy_evaluate_cos`: the diffuse part albedo * coupling * cos_i plus the
/// specular part F * D V cos_i, or 0 below the surface (a select, not a branch).
RESTIR_HOST_DEVICE inline float glossy_channel(bool above, float albedo, float diffuse_cos,
                                               float f0, float f90, float weight_h,
                                               float specular_cos) {
    const float value = albedo * diffuse_cos + (f0 + (f90 - f0) * weight_h) * specular_cos;
    return select_float(above, value, 0.0f);
}

} // namespace detail

/// f(wo, wi) max(0, n.wi) of the diffuse + GGX reflection model (see `GlossyBsdf`) from the
/// dot products of one pair of directions, with H = wo + wi (the unnormalised half vector):
/// cos_o = n.wo, cos_i = n.wi, half_length2 = H.H, half_cross2 = |n x H|^2. The half vector's
/// sin^2 comes from |n x H|^2 rather than from 1 - cos^2: near the normal the latter cancels
/// to a few ulps and would lose a narrow lobe. Branchless (selects only), three square roots
/// (two Smith terms, |H|), no pow; finite for every input, 0 when wo or wi is at or below
/// the surface and for the degenerate wi = -wo. Always inlined: a loop over candidate
/// directions vectorises only with the body inside it (Clang finds it too large otherwise).
/// `specular_weight` scales the specular lobe: 1 the whole model, 0 its diffuse lobe alone.
RESTIR_HOST_DEVICE RESTIR_FORCE_INLINE glm::vec3
glossy_evaluate_cos(glm::vec3 diffuse_albedo, glm::vec3 specular_f0, float alpha, float cos_o,
                    float cos_i, float half_length2, float half_cross2,
                    float specular_weight = 1.0f) {
    // `&`, not `&&`: both comparisons unconditionally, no control flow in a loop.
    const bool above = (cos_o > 0.0f) & (cos_i > 0.0f);
    const float co = max_of(cos_o, 0.0f);
    const float ci = max_of(cos_i, 0.0f);
    // D(h) (Walter et al. 2007, eq. 33), cos^2 = (n.H)^2 / H.H with n.H = co + ci.
    const float hh = max_of(half_length2, 1e-30f);
    const float inv_hh = 1.0f / hh;
    const float nh = co + ci;
    const float d = ggx_ndf_from_squares(nh * nh * inv_hh, half_cross2 * inv_hh, alpha);
    // G2 / (4 co ci) times ci, height-correlated Smith (Heitz 2014, eq. 99):
    // 0.5 ci / (ci root(co) + co root(ci)), one square root per Smith term.
    const float smith = smith_g2_denominator(co, ci, alpha);
    const float specular_cos = d * (0.5f * ci / max_of(smith, 1e-30f)) * specular_weight;
    // Schlick at wo.h = |H| / 2 (Schlick 1994, eq. 24).
    const float weight_h = schlick_weight(0.5f * std::sqrt(hh));
    const float f90 = fresnel_f90(specular_f0);
    // Diffuse (1 - F(n.wi)) (1 - F(n.wo)) / pi with a scalar Fresnel on the largest F0
    // (the reciprocal coupling of Shirley et al. 1997 and Ashikhmin & Shirley 2000).
    const float f0_max = max_of(max_of(specular_f0.x, specular_f0.y), specular_f0.z);
    const float coupling =
        (1.0f - fresnel_schlick(f0_max, f90, ci)) * (1.0f - fresnel_schlick(f0_max, f90, co));
    const float diffuse = inv_pi * coupling;
    return {detail::glossy_channel(above, diffuse_albedo.x * diffuse, ci, specular_f0.x, f90,
                                   weight_h, specular_cos),
            detail::glossy_channel(above, diffuse_albedo.y * diffuse, ci, specular_f0.y, f90,
                                   weight_h, specular_cos),
            detail::glossy_channel(above, diffuse_albedo.z * diffuse, ci, specular_f0.z, f90,
                                   weight_h, specular_cos)};
}

/// The solid-angle density of the specular lobe's sampler (visible normals, then reflection)
/// at wi, from the same dot products as `glossy_evaluate_cos`: D_wo(h) / (4 wo.h) =
/// G1(wo) D(h) / (4 n.wo) (Heitz 2018, eq. 1 and the reflection Jacobian 1 / (4 wo.h),
/// Walter et al. 2007, eq. 14) = D(h) / (2 (n.wo + root(n.wo))). 0 below the surface.
RESTIR_HOST_DEVICE inline float glossy_specular_pdf(float alpha, float cos_o, float cos_i,
                                                    float half_length2, float half_cross2) {
    // `&`, not `&&`: both comparisons unconditionally, no control flow in a loop.
    const bool above = (cos_o > 0.0f) & (cos_i > 0.0f);
    const float co = max_of(cos_o, 0.0f);
    const float ci = max_of(cos_i, 0.0f);
    const float inv_hh = 1.0f / max_of(half_length2, 1e-30f);
    const float nh = co + ci;
    const float d = ggx_ndf_from_squares(nh * nh * inv_hh, half_cross2 * inv_hh, alpha);
    const float pdf = 0.5f * d / (co + smith_root(co, alpha));
    return select_float(above, pdf, 0.0f);
}

/// Diffuse (Lambert) + specular (GGX with Schlick Fresnel) reflection, the usual metallic-roughness
/// material: metals have diffuse_albedo 0 and specular_f0 = base colour.
///
/// f(wo, wi) = diffuse_albedo / pi (1 - F(n.wi)) (1 - F(n.wo))
///           + F(wo.h) D(h) G2(wo, wi) / (4 n.wo n.wi),
/// with D the GGX distribution (Walter et al. 2007), G2 the height-correlated Smith term (Heitz
/// 2014), F Schlick's approximation with f90 = min(1, 50 average(F0)) (Lagarde & de Rousiers
/// 2014) and the diffuse F the scalar Schlick of the largest F0 component. Reciprocal (every
/// factor is symmetric in wo and wi: wo.h = wi.h), and energy-safe: the diffuse lobe keeps only
/// what the Fresnel term leaves at both ends; the specular lobe is single scattering (it loses
/// the energy of multiple bounces at high roughness). F0 = 0 is exactly a Lambertian surface.
struct GlossyBsdf {
    glm::vec3 diffuse_albedo{0.8f}; ///< Lambertian albedo (0 for metals).
    glm::vec3 specular_f0{0.04f};   ///< Reflectance at normal incidence, per channel.
    float roughness = 0.5f;         ///< perceptual; alpha = ggx_alpha(roughness)

    /// base_color, metallic in [0,1], roughness, and the F0 of the dielectric case (0.04
    /// default): diffuse_albedo = base_color (1 - metallic), specular_f0 = mix(dielectric_f0,
    /// base_color, metallic) (Burley 2012, "Physically-Based Shading at Disney").
    RESTIR_HOST_DEVICE static GlossyBsdf from_metallic_roughness(glm::vec3 base_color,
                                                                 float metallic, float roughness,
                                                                 float dielectric_f0 = 0.04f) {
        const float m = min_of(max_of(metallic, 0.0f), 1.0f);
        return {base_color * (1.0f - m), glm::vec3(dielectric_f0) * (1.0f - m) + base_color * m,
                roughness};
    }

    /// f(wo, wi) * max(0, n.wi): n unit normal, wo unit towards the viewer, wi unit towards the
    /// light, all world space. 0 when wo or wi is below the surface. Branchless, vectorises in
    /// a loop over wi (see `glossy_evaluate_cos`); always inlined.
    RESTIR_HOST_DEVICE RESTIR_FORCE_INLINE glm::vec3 evaluate_cos(glm::vec3 n, glm::vec3 wo,
                                                                  glm::vec3 wi) const {
        return evaluate_cos(n, wo, wi, ggx_alpha(roughness));
    }
    /// The same with the specular lobe's GGX `alpha` given (a lobe widened for a light of
    /// some size, `GlossyReceiver`), and its specular lobe scaled by `specular_weight` (0: the
    /// diffuse lobe alone).
    RESTIR_HOST_DEVICE RESTIR_FORCE_INLINE glm::vec3
    evaluate_cos(glm::vec3 n, glm::vec3 wo, glm::vec3 wi, float alpha,
                 float specular_weight = 1.0f) const {
        const glm::vec3 h = wo + wi;
        const glm::vec3 n_cross_h = glm::cross(n, h);
        return glossy_evaluate_cos(diffuse_albedo, specular_f0, alpha, glm::dot(n, wo),
                                   glm::dot(n, wi), glm::dot(h, h), glm::dot(n_cross_h, n_cross_h),
                                   specular_weight);
    }

    /// Solid-angle density with which `sample` returns wi: the mixture p pdf_specular +
    /// (1 - p) max(0, n.wi) / pi, p = specular_probability(n, wo); 0 when wo or wi is below.
    /// Branchless and always inlined, as `evaluate_cos`.
    RESTIR_HOST_DEVICE RESTIR_FORCE_INLINE float pdf(glm::vec3 n, glm::vec3 wo,
                                                     glm::vec3 wi) const {
        const float cos_o = glm::dot(n, wo);
        const float cos_i = glm::dot(n, wi);
        const glm::vec3 h = wo + wi;
        const glm::vec3 n_cross_h = glm::cross(n, h);
        const float p = specular_probability(n, wo);
        const float specular = glossy_specular_pdf(ggx_alpha(roughness), cos_o, cos_i,
                                                   glm::dot(h, h), glm::dot(n_cross_h, n_cross_h));
        // The cosine lobe's density as diffuse_direction_pdf writes it: with p = 0 this is
        // that density exactly.
        const float mixed = (1.0f - p) * (max_of(0.0f, cos_i) * inv_pi) + p * specular;
        return select_float((cos_o > 0.0f) & (cos_i > 0.0f), mixed, 0.0f);
    }

    /// The density of one branch of `sample`: the lobe's probability times its density at wi,
    /// P_s p_s(wi) for the specular lobe (`specular` true), (1 - P_s) max(0, n.wi) / pi for the
    /// diffuse one; the two sum to `pdf`. A path whose lobe choices are replayed from the same
    /// random numbers changes density by the ratio of these (gi/hybrid_shift.hpp).
    RESTIR_HOST_DEVICE float lobe_pdf(glm::vec3 n, glm::vec3 wo, glm::vec3 wi,
                                      bool specular) const {
        const float cos_o = glm::dot(n, wo);
        const float cos_i = glm::dot(n, wi);
        if (!(cos_o > 0.0f) || !(cos_i > 0.0f))
            return 0.0f;
        const float p = specular_probability(n, wo);
        if (!specular)
            return (1.0f - p) * (cos_i * inv_pi);
        const glm::vec3 h = wo + wi;
        const glm::vec3 n_cross_h = glm::cross(n, h);
        return p * glossy_specular_pdf(ggx_alpha(roughness), cos_o, cos_i, glm::dot(h, h),
                                       glm::dot(n_cross_h, n_cross_h));
    }
    /// Whether `sample` draws from the specular lobe for this wo and u_lobe.
    RESTIR_HOST_DEVICE bool samples_specular(glm::vec3 n, glm::vec3 wo, float u_lobe) const {
        return u_lobe < specular_probability(n, wo);
    }

    /// One direction from three uniform numbers in [0,1): u_lobe chooses the lobe, u0 u1 the
    /// direction. Specular: a visible normal m (`sample_ggx_vndf`), wi = reflect(wo, m);
    /// diffuse: `sample_diffuse_direction`. No sample (pdf 0) when wo or the reflected wi is at
    /// or below the surface.
    RESTIR_HOST_DEVICE BsdfSample sample(glm::vec3 n, glm::vec3 wo, float u_lobe, float u0,
                                         float u1) const {
        if (!(glm::dot(n, wo) > 0.0f))
            return {};
        glm::vec3 wi;
        if (samples_specular(n, wo, u_lobe)) {
            const ShadingFrame frame = ShadingFrame::from_normal(n);
            const glm::vec3 wo_local = frame.to_local(wo);
            const glm::vec3 m = sample_ggx_vndf(wo_local, ggx_alpha(roughness), u0, u1);
            wi = frame.to_world(2.0f * glm::dot(wo_local, m) * m - wo_local);
        } else {
            wi = sample_diffuse_direction(n, u0, u1);
        }
        BsdfSample s;
        s.pdf = pdf(n, wo, wi);
        if (!(s.pdf > 0.0f) || !is_finite(s.pdf))
            return {};
        s.wi = wi;
        s.weight = evaluate_cos(n, wo, wi) / s.pdf;
        return s;
    }

    /// The probability that `sample` picks the specular lobe for this wo (depends on wo only):
    /// the lobes' luminance at n.wo, lum(F(n.wo)) against lum(diffuse_albedo) (1 - F(n.wo)),
    /// kept in [floor, 1 - floor] (`glossy_lobe_probability_floor`) when both are non-zero;
    /// exactly 1 or 0 when one of them is black. Always inlined: a loop over wi hoists it.
    RESTIR_HOST_DEVICE RESTIR_FORCE_INLINE float specular_probability(glm::vec3 n,
                                                                      glm::vec3 wo) const {
        const float cos_o = glm::dot(n, wo);
        const float specular = detail::glossy_luminance(fresnel_schlick(specular_f0, cos_o));
        const float f0_max = max_of(max_of(specular_f0.x, specular_f0.y), specular_f0.z);
        const float diffuse = detail::glossy_luminance(diffuse_albedo) *
                              (1.0f - fresnel_schlick(f0_max, fresnel_f90(specular_f0), cos_o));
        const float total = specular + diffuse;
        // Selects and `&`, no control flow: inlined into a loop over wi, a branch here kept
        // the loop from vectorising (BM_RIS_Batch_GlossyMis).
        const float ratio = select_float(total > 0.0f, specular / total, 0.0f);
        const float floor = glossy_lobe_probability_floor;
        return select_float((specular > 0.0f) & (diffuse > 0.0f),
                            min_of(max_of(ratio, floor), 1.0f - floor), ratio);
    }
};

} // namespace restir
