/// @file gi/pt_sample.hpp
/// The sample of ReSTIR PT (Lin et al. 2022): one whole path x_1 .. x_n from a pixel's
/// visible point x_1 to a light, stored as what the hybrid shift needs to rebuild it from
/// another visible point: the random numbers of its prefix (a seed), its reconnection vertex
/// x_k and the part of the path after it, and the rule (`ReconnectionCriterion`) that chose k.
#pragma once

#include "restir/config.hpp"
#include "restir/core/math.hpp"

#include <glm/geometric.hpp>
#include <glm/vec3.hpp>

#include <cmath>
#include <cstdint>
#include <type_traits>

namespace restir {

/// Which vertices a path may reconnect at (Lin et al. 2022): x_{k-1} and x_k
/// reconnect when both are rough enough that their reflection changes slowly with direction
/// and they are far enough apart that moving x_{k-1} turns the segment little. The path's
/// reconnection vertex x_k is the first vertex (not its light) for which the pair qualifies;
/// a path with none is shifted by random replay alone.
struct ReconnectionCriterion {
    /// Perceptual roughness both vertices need (a Lambertian surface counts as 1).
    float min_roughness = 0.3f;
    /// World-space distance between them (about 1 % of the scene's extent is usual).
    float min_distance = 0.0f;

    RESTIR_HOST_DEVICE constexpr bool operator()(float roughness_a, float roughness_b,
                                                 float distance) const {
        return roughness_a >= min_roughness && roughness_b >= min_roughness &&
               distance >= min_distance;
    }
};

/// How a path reached its light at x_n.
enum class PathEnd : std::uint8_t {
    light_sampled, ///< x_n drawn on a light from x_{n-1} (next-event estimation).
    bsdf_sampled,  ///< x_n found by a direction drawn from x_{n-1}'s BSDF (or the sky).
    /// Every path on from a Lambertian x_k at once: `suffix` is the radiance x_k reflects,
    /// the same towards every direction, as the rest of the path estimated it (ReSTIR GI's Lo,
    /// Ouyang et al. 2021); the sample stands for the paths through x_k, and `rc_direction`,
    /// `rc_light_pdf` and `end_technique` are unused.
    reflected,
};

/// A path sample. Its value is f(x), the path's contribution in the product of solid angles at
/// its vertices, extended by the weights of the choices its sampler made that the shift keeps:
/// at each replayed vertex the lobe's posterior probability P_l p_l(w) / p(w), and at the end
/// the MIS weight of how the light was found (balance heuristic, light sampling against the
/// BSDF's). Their sum over the choices is the plain contribution, so the sample's estimate
/// f(x) W stays unbiased (Lin et al. 2022).
struct PtSample {
    glm::vec3 visible_point{0.0f}; ///< x_1: where the sample belongs (after a shift, y_1).
    glm::vec3 contribution{0.0f};  ///< f(x) at x_1 per channel, visibility included.
    glm::vec3 rc_position{0.0f};   ///< x_k.
    glm::vec3 rc_normal{0.0f};     ///< n_k, unit, on the side x_{k-1} lies.
    glm::vec3 rc_direction{0.0f};  ///< w_k: unit, from x_k towards x_{k+1} (or its light).
    /// Radiance arriving at x_k along w_k: the suffix's factors of f after x_k (Le, the BSDFs
    /// and cosines at x_{k+1} .. x_{n-1}, and their weights); with `PathEnd::reflected`, the
    /// radiance leaving x_k.
    glm::vec3 suffix{0.0f};
    /// With a reconnection vertex (rc_index >= 2): the reconnection density
    /// (`reconnection_density`) of the prefix; without one, the density of the whole path (the
    /// product of the densities of its sampled directions, lobe choices included).
    float density = 0.0f;
    /// When w_k ends the path (k = n - 1): the density with which light sampling from x_k
    /// would draw w_k, for the MIS weight at x_k; 0 when the path goes on past x_{k+1}.
    float rc_light_pdf = 0.0f;
    float rc_roughness = 1.0f;      ///< x_k's perceptual roughness (the criterion's).
    std::uint32_t rc_material = 0u; ///< x_k's material, as the application numbers them.
    std::uint32_t seed = 0u;        ///< The path's random numbers: a pure function of this.
    std::uint8_t rc_index = 0u;     ///< k (x_1 the visible point); 0: no reconnection vertex.
    std::uint8_t length = 0u;       ///< n, the light's vertex; 0: no sample.
    PathEnd end = PathEnd::light_sampled;
    /// Which light sampling drew x_n when the path is replayed whole (the application's
    /// number: an emitter, the sky).
    std::uint8_t end_technique = 0u;

    friend constexpr bool operator==(const PtSample&, const PtSample&) = default;
};
static_assert(std::is_trivially_copyable_v<PtSample>);
static_assert(sizeof(PtSample) == 96u);

/// The reconnection density D of a path at its reconnection vertex x_k (normal n_k) reached
/// from x_{k-1}: the density of the replayed directions (`prefix_density`, the product over
/// x_1 .. x_{k-2}) over the geometry term that turns x_{k-1}'s solid angle into x_k's area,
///   D = prod p(w_i) * |x_{k-1} - x_k|^2 / cos theta_k.
/// The hybrid shift's Jacobian is D(x) / D(y) (Lin et al. 2022: the random
/// replay's p_x(w_i) / p_y(w'_i) and the reconnection's Eq. 11 of Ouyang et al. 2021); 0 where
/// x_{k-1} lies behind x_k's surface or on it, where the reconnection fails.
RESTIR_HOST_DEVICE inline float reconnection_density(float prefix_density, glm::vec3 from,
                                                     glm::vec3 rc_position, glm::vec3 rc_normal) {
    const glm::vec3 to_from = from - rc_position;
    const float d2 = glm::dot(to_from, to_from);
    const float cos_d = glm::dot(rc_normal, to_from); // cos theta_k times the distance
    if (!(cos_d > 0.0f) || !(d2 > 0.0f))
        return 0.0f;
    const float density = prefix_density * d2 * std::sqrt(d2) / cos_d;
    return is_valid_weight(density) ? density : 0.0f;
}

/// f(x) of a path sample at the surface it belongs to (`position` its visible point), 0 at any
/// other: a sample changes surface only through the hybrid shift, which recomputes it.
RESTIR_HOST_DEVICE inline glm::vec3 pt_sample_contribution(const PtSample& x, glm::vec3 position) {
    const bool here = x.visible_point.x == position.x && x.visible_point.y == position.y &&
                      x.visible_point.z == position.z;
    return here && x.length != 0u ? x.contribution : glm::vec3(0.0f);
}

} // namespace restir
