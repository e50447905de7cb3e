#include "light_set.hpp"

#include "environment.hpp"
#include "scatter.hpp"
#include "timing.hpp"

#include <tbb/parallel_for.h>

#include <algorithm>
#include <cmath>
#include <span>
#include <string>
#include <utility>

namespace pt {

namespace {

SceneEmitters checked_emitters(const Scene& scene) {
    SceneEmitters emitters(scene);
    if (emitters.light_count() == 0 && !scene.environment)
        throw SceneError("scene '" + scene.name +
                         "' has no emitters and no environment: give some material a positive Ke, "
                         "or light it with --env");
    return emitters;
}

// The sphere around the scene's bounding box: what the environment's light crosses.
struct BoundingSphere {
    glm::vec3 centre;
    float radius;
};
BoundingSphere bounding_sphere(const Scene& scene) {
    const SceneBounds box = bounds_of(scene);
    return {0.5f * (box.lower + box.upper), 0.5f * scene_size(scene)};
}

// Yuksel's falloff (gi vpl, --attenuation-radius or 2 % of the scene's size), or the clamped
// one of the partition (gi vpl-unbiased, --partition-radius of the scene's size).
restir::Falloff vpl_falloff(const RenderSettings& settings, float extent) {
    if (settings.gi == GlobalIllumination::vpl_unbiased)
        return restir::VplPartition{settings.partition_radius * extent}.vpl_falloff();
    return restir::Falloff::yuksel(settings.attenuation_radius > 0.0f ? settings.attenuation_radius
                                                                      : 0.02f * extent);
}

} // namespace

LightSet::LightSet(const Scene& scene, const EmbreeScene& rays, const RenderSettings& settings,
                   tbb::task_arena& arena, float ray_offset, float extent)
    : scene_(scene), rays_(rays), settings_(settings), arena_(arena), ray_offset_(ray_offset),
      falloff_(vpl_falloff(settings, extent)), emitters_(checked_emitters(scene)) {
    shoot_vpls(0u);
}

bool LightSet::reshoot_vpls(std::uint32_t frame) {
    const std::uint32_t interval = settings_.vpl_reshoot_interval;
    const bool new_vpl_set = frame > 0 && interval > 0 && frame % interval == 0;
    if (new_vpl_set)
        shoot_vpls(frame / interval);
    return new_vpl_set;
}

// Shoots VPL set `generation` (0: the first, from the photons' seed) with --gi vpl, and
// rebuilds the light set and its sampling tables.
void LightSet::shoot_vpls(std::uint32_t generation) {
    if (uses_vpls(settings_.gi) && settings_.vpls > 0) {
        const auto start = Clock::now();
        restir::PhotonParams params = settings_.photons;
        params.ray_offset = ray_offset_;
        // Without bias the VPLs hold every bounce that the path tracer's paths hold: a VPL at
        // bounce b lights paths of b + 1 reflections, the path tracer's reach max_depth (none
        // for --max-depth 1, which has no indirect light).
        if (settings_.gi == GlobalIllumination::vpl_unbiased)
            params.max_bounces = settings_.max_depth - 1u;
        // Set 0 keeps the seed itself; later sets are independent of it and of each other.
        params.seed = generation == 0u
                          ? settings_.photons.seed
                          : restir::mix64(settings_.photons.seed ^ restir::mix64(generation));
        if (!photons_per_set_)
            photons_per_set_ = pilot_photon_count(params);
        params.photon_count = *photons_per_set_;
        vpls_ = params.photon_count > 0u ? shoot_photons(params) : std::vector<restir::Vpl>{};
        photon_ms_ = milliseconds_since(start);
    }
    build_light_set(generation);
}

// A photon pass (restir::shoot_photons) on the renderer's threads: photons reflected as
// Lambertian everywhere (gi vpl), or by each surface's BSDF with VPLs on Lambertian surfaces
// alone (gi vpl-unbiased, whose path samples carry the light that glossy surfaces reflect).
std::vector<restir::Vpl> LightSet::shoot_photons(const restir::PhotonParams& params) {
    if (settings_.gi == GlobalIllumination::vpl_unbiased)
        return shoot_photons_with(BsdfScatter{&scene_}, params);
    return shoot_photons_with(LambertianScatter{&scene_}, params);
}

template <class Scatter>
std::vector<restir::Vpl> LightSet::shoot_photons_with(const Scatter& scatter,
                                                      const restir::PhotonParams& params) {
    const auto parallel_for = [this](std::uint32_t count, auto&& body) {
        arena_.execute([&] { tbb::parallel_for(0u, count, [&](std::uint32_t i) { body(i); }); });
    };
    restir::PhotonEmitters sources(emitters_, params.points_per_emitter, params.seed);
    if (scene_.environment) { // the sky's photons, in proportion to its flux into the scene
        const BoundingSphere sphere = bounding_sphere(scene_);
        sources.set_environment(scene_.environment->map, sphere.centre, sphere.radius);
    }
    return restir::shoot_photons(sources, rays_, scatter, params, parallel_for);
}

// Photons per VPL set: a pilot pass measures VPLs per photon, so that the budget gives about
// `vpls` VPLs, with at most 64 photons per VPL asked for; a pilot that leaves no VPL at all (no
// surface reflects) means no VPLs (0), not a hundred million more photons.
std::uint32_t LightSet::pilot_photon_count(restir::PhotonParams params) {
    params.photon_count = std::min<std::uint32_t>(settings_.vpls, 4096u);
    const std::size_t pilot = shoot_photons(params).size();
    const double per_photon = static_cast<double>(pilot) / params.photon_count;
    return pilot == 0u ? 0u
                       : static_cast<std::uint32_t>(std::clamp(
                             std::ceil(settings_.vpls / per_photon), 1.0,
                             std::min(4.0e9, 64.0 * static_cast<double>(settings_.vpls))));
}

// The environment's weight in the power table: its power into the scene's bounding sphere, or
// the weight that gives it --env-share of the others' total.
float LightSet::environment_weight() const {
    if (!scene_.environment)
        return 0.0f;
    const float power =
        restir::environment_power(scene_.environment->map, bounding_sphere(scene_).radius);
    const float share = settings_.environment_share;
    if (!(share > 0.0f))
        return power;
    double others = 0.0;
    for (const float p : restir::unified_light_powers(lights_, power))
        others += static_cast<double>(p);
    others -= static_cast<double>(power);
    if (!(others > 0.0)) // the environment alone: every candidate is its
        return power;
    const auto s = static_cast<double>(share);
    return static_cast<float>(others * s / (1.0 - s));
}

// The emitters, the environment and this VPL set as one light set, and its tables. Throws
// SceneError for a shining emitter whose power is no float, or an environment whose weight is
// none.
void LightSet::build_light_set(std::uint32_t generation) {
    lights_ =
        Unified{&emitters_, vpls_.data(), static_cast<std::uint32_t>(vpls_.size()),
                scene_.environment ? scene_.environment->view() : restir::EnvironmentMapView{}};
    const float environment = environment_weight();
    if (scene_.environment && !(environment > 0.0f && environment < 3.0e38f))
        throw SceneError("the environment's weight among the lights is no float (" +
                         std::to_string(environment) + "): adjust --env-scale or --env-share");
    std::vector<float> powers = restir::unified_light_powers(lights_, environment);
    if (scene_.environment && settings_.environment_sampling == EnvironmentSampling::bsdf)
        powers[lights_.environment_id()] = 0.0f; // found by BSDF candidates alone
    // unified_light_powers gives a power that overflows a float as 0; a shining emitter with
    // power 0 would never be sampled (and alone gives "all weights are zero"). Emitters do not
    // change between VPL sets: checked once.
    for (std::uint32_t e = 0; generation == 0u && e < emitters_.light_count(); ++e) {
        const glm::vec3 radiance = emitters_.radiance(e);
        if (!(powers[e] > 0.0f) && radiance.x + radiance.y + radiance.z > 0.0f)
            throw SceneError("emitter " + std::to_string(e) + " of scene '" + scene_.name +
                             "' has no float power: too bright (lower its Ke) or too small");
    }
    if (std::all_of(powers.begin(), powers.end(), [](float p) { return p == 0.0f; }))
        throw SceneError("scene '" + scene_.name +
                         "' has no light for light candidates: with --env-sampling bsdf it needs "
                         "emitters");
    light_table_.build(powers);
    build_local_table(powers);
    if (emitters_.light_count() > 0)
        emitter_table_.build(std::span<const float>(powers.data(), emitters_.light_count()));
    if (!vpls_.empty())
        vpl_table_.build(std::span<const float>(powers.data() + lights_.first_vpl(), vpls_.size()));
    powers_ = std::move(powers);
}

// The local lights' table, and the environment's share of all lights beside them.
void LightSet::build_local_table(std::vector<float> powers) {
    double total = 0.0;
    for (const float p : powers)
        total += static_cast<double>(p);
    distant_ = {};
    if (lights_.environment_count() > 0u) {
        const auto id = static_cast<std::ptrdiff_t>(lights_.environment_id());
        distant_ = {
            lights_.environment_id(),
            static_cast<float>(static_cast<double>(powers[static_cast<std::size_t>(id)]) / total),
            restir::UniformLightSampler{1u}};
        powers.erase(powers.begin() + id);
    }
    local_table_ = {};
    if (std::any_of(powers.begin(), powers.end(), [](float p) { return p > 0.0f; }))
        local_table_.build(powers);
}

std::vector<restir::LightBounds> LightSet::light_bounds() const {
    const std::vector<float>& powers = powers_;
    std::vector<restir::LightBounds> bounds;
    bounds.reserve(powers.size());
    for (std::uint32_t e = 0; e < emitters_.light_count(); ++e)
        bounds.push_back(emitters_.bounds(e, powers[e]));
    for (std::uint32_t v = 0; v < vpls_.size(); ++v)
        bounds.push_back(restir::point_light_bounds(vpls_[v].position, vpls_[v].normal,
                                                    powers[lights_.first_vpl() + v]));
    return bounds;
}

} // namespace pt
