/// @file gi/hybrid_shift.hpp
/// The hybrid shift of ReSTIR PT (Lin et al. 2022): a path sample made at visible
/// point x_1 is carried to visible point y_1 by replaying its random numbers from y_1 (random
/// replay) up to y_{k-1}, then joining y_{k-1} to the path's own reconnection vertex x_k, after
/// which the path is the same. A path without a reconnection vertex is replayed whole. The
/// application replays its own path tracer (`PathReplay`); the shift checks the criterion,
/// joins the parts and gives the Jacobian
///   |dy/dx| = D(x) / D(y)   (`reconnection_density`; random replay alone: p(x) / p(y)).
#pragma once

#include "restir/concepts.hpp"
#include "restir/config.hpp"
#include "restir/core/math.hpp"
#include "restir/gi/pt_sample.hpp"
#include "restir/reuse/shift.hpp"

#include <glm/geometric.hpp>
#include <glm/vec3.hpp>

#include <concepts>

namespace restir {

/// The prefix y_1 .. y_{k-1} that the application replayed from a new visible point y_1.
template <class Vertex>
struct ReplayedPrefix {
    Vertex last{};              ///< y_{k-1}, the application's vertex (y_1 itself when k = 2).
    glm::vec3 position{0.0f};   ///< y_{k-1}'s position.
    float roughness = 0.0f;     ///< y_{k-1}'s perceptual roughness (the criterion's).
    glm::vec3 throughput{1.0f}; ///< The factors of f at y_1 .. y_{k-2} (as `PtSample` weighs).
    float density = 1.0f;       ///< The densities of the directions drawn there.
    bool valid = false;         ///< False where the replay failed (see `PathReplay`).
};

/// A whole path that the application replayed from a new visible point.
struct ReplayedPath {
    glm::vec3 contribution{0.0f}; ///< f(y), visibility included.
    float density = 0.0f;         ///< The density of its sampled directions (and light point).
    bool valid = false;
};

/// The application's path tracer, replayable. For a path sample `x` and a new visible point
/// `from` (a `Surface`), with `criterion` the shift's `ReconnectionCriterion`:
///   `replay.replay_prefix(x, from, criterion)` -> `ReplayedPrefix<Vertex>`: the directions at
///       y_1 .. y_{k-2} drawn with x's random numbers (x.seed, vertex by vertex, as the path was
///       made), the rays traced; invalid where a ray misses, or where a pair (y_i, y_{i+1}) with
///       i + 1 <= k - 1 already meets the criterion (the shifted path would reconnect earlier:
///       the shift would not be invertible);
///   `replay.replay_path(x, from, criterion)` -> `ReplayedPath`: a path without reconnection
///       vertex (x.rc_index 0) replayed to its light (x.length, x.end, x.end_technique);
///       invalid where it misses before its end or a pair of its vertices meets the criterion;
///   `replay.reconnect(v, x)` -> `glm::vec3`: the factors of f(y) that the join changes: f_s
///       cos at v = y_{k-1} towards x_k, times f_s cos at x_k from v towards x.rc_direction
///       times `rc_mis_weight` (nothing where x.end is `PathEnd::reflected`), times the
///       visibility of the segment v - x_k.
/// Every factor and density as the path's own sampler computed them (`PtSample`).
template <class R, class S>
concept PathReplay = requires(const R& replay, const PtSample& x, const S& from,
                              const ReconnectionCriterion& criterion,
                              const typename R::Vertex& vertex) {
    {
        replay.replay_prefix(x, from, criterion)
        } -> std::same_as<ReplayedPrefix<typename R::Vertex>>;
    { replay.replay_path(x, from, criterion) } -> std::same_as<ReplayedPath>;
    { replay.reconnect(vertex, x) } -> std::convertible_to<glm::vec3>;
};

/// The weight of f at the reconnection vertex x_k for its outgoing direction w_k, given the
/// density `bsdf_pdf` with which x_k's BSDF draws w_k for the new incoming direction: where w_k
/// reaches the light (k = n - 1), the balance heuristic of the technique that found it against
/// the other (Veach 1997, Eq. 9.10, light density `x.rc_light_pdf`); 1 where the path goes on.
RESTIR_HOST_DEVICE inline float rc_mis_weight(const PtSample& x, float bsdf_pdf) {
    if (x.rc_index + 1u != x.length || x.end == PathEnd::reflected)
        return 1.0f;
    const float light_pdf = x.rc_light_pdf;
    return safe_divide(x.end == PathEnd::light_sampled ? light_pdf : bsdf_pdf,
                       bsdf_pdf + light_pdf);
}

/// The hybrid shift as a `ShiftMapping` of `PtSample`s between `Surface`s: random replay to
/// y_{k-1}, the criterion at (y_{k-1}, x_k), then reconnection; random replay of the whole path
/// where it has no reconnection vertex. The shifted sample carries f(y) and D(y), so shifting
/// it back gives x and the inverse Jacobian. Between surfaces at the same position with the
/// same normal (a pixel's own history under a still camera) the sample is kept, Jacobian 1:
/// its view direction is taken to be the same. `replay` (a `PathReplay`) must outlive it.
template <class Replay>
struct HybridShift {
    const Replay* replay = nullptr;
    ReconnectionCriterion criterion{};

    template <Surface S>
    RESTIR_HOST_DEVICE ShiftedSample<PtSample> operator()(const PtSample& x, const S& from,
                                                          const S& to) const {
        const glm::vec3 q = surface_position(from);
        const glm::vec3 r = surface_position(to);
        const glm::vec3 nq = surface_normal(from);
        const glm::vec3 nr = surface_normal(to);
        ShiftedSample<PtSample> y{x, 0.0f};
        y.sample.visible_point = r;
        if (x.length == 0u || x.rc_index == 1u || !(x.density > 0.0f))
            return y;
        if (q == r && nq == nr) {
            y.jacobian = 1.0f;
            return y;
        }
        if (x.rc_index == 0u) {
            const ReplayedPath path = replay->replay_path(x, to, criterion);
            if (!path.valid || !(path.density > 0.0f))
                return y;
            y.sample.contribution = path.contribution;
            y.sample.density = path.density;
        } else {
            const auto prefix = replay->replay_prefix(x, to, criterion);
            if (!prefix.valid || !criterion(prefix.roughness, x.rc_roughness,
                                            glm::length(x.rc_position - prefix.position)))
                return y;
            y.sample.density =
                reconnection_density(prefix.density, prefix.position, x.rc_position, x.rc_normal);
            if (!(y.sample.density > 0.0f))
                return y;
            y.sample.contribution =
                prefix.throughput * glm::vec3(replay->reconnect(prefix.last, x)) * x.suffix;
        }
        const float jacobian = x.density / y.sample.density;
        y.jacobian = is_valid_weight(jacobian) ? jacobian : 0.0f;
        return y;
    }
};

} // namespace restir
