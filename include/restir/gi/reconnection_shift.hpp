/// @file gi/reconnection_shift.hpp
/// The reconnection shift of ReSTIR GI (Ouyang et al. 2021, Sec. 4.2; Lin et al. 2022, Sec. 6):
/// a path sample made at visible point q is reused at visible point r by connecting r to the
/// same sample point s. Its density changes with the solid angle that s subtends; Jacobian
///   |dw_r / dw_q| = (cos theta_r / cos theta_q) (|q - s|^2 / |r - s|^2),
/// theta the angle at s between its normal and the direction to q or r (Eq. 11).
#pragma once

#include "restir/concepts.hpp"
#include "restir/config.hpp"
#include "restir/core/math.hpp"
#include "restir/gi/path_sample.hpp"
#include "restir/light/shadow_segment.hpp"
#include "restir/reuse/shift.hpp"

#include <glm/geometric.hpp>
#include <glm/vec3.hpp>

#include <cmath>

namespace restir {

/// The Jacobian determinant of reconnecting sample point `s` (unit normal `n_s`, towards the
/// side it is seen from) from visible point `q` to visible point `r` (Ouyang et al. 2021,
/// Eq. 11); 0 where either point lies behind s's surface or on it, where the shift fails.
RESTIR_HOST_DEVICE inline float reconnection_jacobian(glm::vec3 q, glm::vec3 r, glm::vec3 s,
                                                      glm::vec3 n_s) {
    const glm::vec3 to_q = q - s;
    const glm::vec3 to_r = r - s;
    const float q2 = glm::dot(to_q, to_q);
    const float r2 = glm::dot(to_r, to_r);
    // cos theta times the distance, so that one square root serves both cosines.
    const float cos_q_d = glm::dot(n_s, to_q);
    const float cos_r_d = glm::dot(n_s, to_r);
    if (!(cos_q_d > 0.0f) || !(cos_r_d > 0.0f) || !(q2 > 0.0f) || !(r2 > 0.0f))
        return 0.0f;
    // (cos_r / cos_q) (q2 / r2) = (cos_r_d / cos_q_d) sqrt(q2 / r2) q2 / r2.
    const float ratio = q2 / r2;
    const float jacobian = (cos_r_d / cos_q_d) * std::sqrt(ratio) * ratio;
    return is_valid_weight(jacobian) ? jacobian : 0.0f;
}

/// The reconnection shift as a `ShiftMapping` for `PathSample`s between any `Surface`s: the
/// sample's point, normal and Lo kept, its visible point moved to the receiver's position, with
/// `reconnection_jacobian`. Lo is the radiance leaving s towards the original visible point,
/// reused towards the new one: exact where s reflects the same radiance in every direction
/// (Lambertian), an approximation elsewhere. The rule: a sample reconnects only where its
/// point's roughness is at least `min_roughness`; any other sample shifts only to a surface at
/// the same position (the same pixel under a still camera, Jacobian 1) and fails elsewhere.
struct ReconnectionShift {
    /// Default 0.5: GGX alpha = 0.25, a lobe wide enough that Lo changes little over the
    /// directions of a spatial neighbourhood; 1 allows Lambertian sample points only; 0 every
    /// sample point (biased on glossy ones).
    float min_roughness = 0.5f;

    template <Surface S>
    RESTIR_HOST_DEVICE ShiftedSample<PathSample> operator()(const PathSample& x, const S& from,
                                                            const S& to) const {
        const glm::vec3 q = surface_position(from);
        const glm::vec3 r = surface_position(to);
        ShiftedSample<PathSample> y{x, 0.0f};
        y.sample.visible_point = r;
        if (q.x == r.x && q.y == r.y && q.z == r.z)
            y.jacobian = 1.0f;
        else if (x.sample_roughness >= min_roughness)
            y.jacobian = reconnection_jacobian(q, r, x.sample_point, x.sample_normal);
        return y;
    }
};

/// Visibility of a path sample's reconnection, as a `VisibilityFunction` for reuse: whether the
/// segment from a surface to the sample point is open (`shadow_segment`, both ends pushed
/// `ray_offset` off their surfaces). A `RayQuery` pointer, which must outlive it.
template <RayQuery Query>
struct ReconnectionVisibility {
    const Query* query = nullptr;
    float ray_offset = 0.0f; ///< World-space, > 0 (1e-4 of the scene's extent is usual).

    template <Surface S>
    RESTIR_HOST_DEVICE bool operator()(const PathSample& x, const S& surface) const {
        const ShadowSegment segment =
            shadow_segment(surface_position(surface), surface_normal(surface), x.sample_point,
                           x.sample_normal, ray_offset);
        return !query->occluded(segment.from, segment.to);
    }
};

} // namespace restir
