// ReSTIR PT's paths (--gi restir-pt): the path tracer's indirect light as whole path samples
// (restir::PtSample) whose random numbers are a pure function of a seed and the vertex, so that
// the hybrid shift (restir/gi/hybrid_shift.hpp) can replay them from another visible point.
#pragma once

#include "embree_scene.hpp"
#include "environment.hpp"
#include "gbuffer.hpp"
#include "light_set.hpp"
#include "scene.hpp"

#include <restir/restir.hpp>

#include <cstdint>

namespace pt {

/// Paths from visible points through the scene to its emitters and sky, and their replay: the
/// application's side of restir::HybridShift (a restir::PathReplay). Each vertex draws its
/// direction (three numbers: lobe, then direction, on every material) and its light samples
/// from streams of its own, seeded by the path's seed and the vertex's index. Russian roulette
/// only past the reconnection vertex, which the shift does not replay (`max_depth` bounds the
/// rest).
class PtPaths {
public:
    using Vertex = GSurface;

    PtPaths(const Scene& scene, const EmbreeScene& rays, const LightSet& lights, float ray_offset,
            std::uint32_t max_depth, bool environment_nee);

    /// The initial reservoir at visible point `s` (x_1): the path drawn from `seed`, each of its
    /// light connections (light sampling at x_2 .. x_n and the lights its BSDF rays find from
    /// x_2 on) a candidate of streaming RIS with target f (the indirect light: x_1's own direct
    /// light is ReSTIR DI's); W = w_sum / p-hat, M = 1 (Lin et al. 2022).
    restir::Reservoir<restir::PtSample> initial(const GSurface& s, std::uint32_t seed,
                                                const restir::ReconnectionCriterion& rule) const;

    // restir::PathReplay.
    restir::ReplayedPrefix<GSurface> replay_prefix(const restir::PtSample& x, const GSurface& from,
                                                   const restir::ReconnectionCriterion& rule) const;
    restir::ReplayedPath replay_path(const restir::PtSample& x, const GSurface& from,
                                     const restir::ReconnectionCriterion& rule) const;
    glm::vec3 reconnect(const GSurface& v, const restir::PtSample& x) const;

    /// The ways a path's light is found by light sampling (PtSample::end_technique).
    enum Technique : std::uint8_t { emitter_sampling = 0u, sky_sampling = 1u };

    /// A light connection at a vertex: f cos towards its direction and the radiance arriving
    /// along it (0 where blocked), the BSDF's mixture density there, the density of the lobe
    /// that drew it (BSDF sampling), and light sampling's density of the same direction (0
    /// where none samples it).
    struct Connection {
        glm::vec3 f_cos{0.0f};
        glm::vec3 radiance{0.0f};
        glm::vec3 direction{0.0f};
        float bsdf_pdf = 0.0f;
        float lobe_pdf = 0.0f;
        float light_pdf = 0.0f;
    };
    /// A direction drawn from a vertex's BSDF with the vertex's numbers, and what it found.
    struct Bounce {
        glm::vec3 wi{0.0f};
        glm::vec3 f_cos{0.0f};
        float pdf = 0.0f;      ///< The mixture's density (0: no direction).
        float lobe_pdf = 0.0f; ///< The density of the lobe's branch (lobe probability included).
        Hit hit;
        GSurface next; ///< Valid where the ray found a surface.
    };

private:
    struct Walk;
    Bounce bounce(const GSurface& s, std::uint32_t seed, std::uint32_t vertex) const;
    /// Light sampling at `s` (vertex `vertex`) by `technique`.
    Connection light_sampled(const GSurface& s, std::uint32_t seed, std::uint32_t vertex,
                             Technique technique) const;
    /// The light that bounce `b` from `s` found: an emitter's front, or the sky where it left.
    Connection bsdf_sampled(const GSurface& s, const Bounce& b) const;
    void offer(restir::Reservoir<restir::PtSample>& r, Walk& walk, const Connection& c,
               restir::PathEnd end, std::uint8_t technique, std::uint32_t vertex,
               restir::Pcg32& rng) const;
    /// Takes bounce `b` from `s`, vertex `vertex`, into the walk's products; finds the
    /// reconnection vertex where the segment meets `rule` first.
    static void advance(Walk& walk, const GSurface& s, const Bounce& b, std::uint32_t vertex,
                        const restir::ReconnectionCriterion& rule);
    /// Russian roulette after bounce `vertex` once the path is past its reconnection vertex.
    static bool survives(Walk& walk, std::uint32_t seed, std::uint32_t vertex);
    /// Replays the bounces at y_1 .. y_{last - 1}: false where one misses or a pair meets `rule`.
    bool replay_bounces(const restir::PtSample& x, const restir::ReconnectionCriterion& rule,
                        std::uint32_t last, GSurface& s, glm::vec3& throughput,
                        float& density) const;

    const Scene& scene_;
    const EmbreeScene& rays_;
    const LightSet& lights_;
    const float ray_offset_;
    const std::uint32_t max_depth_;
    const restir::EnvironmentMapView environment_;
    const bool environment_nee_;
    const float escape_distance_;
};

} // namespace pt
