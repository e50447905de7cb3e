#include "pt_paths.hpp"

#include "reservoir.hpp"

#include <glm/geometric.hpp>

#include <algorithm>
#include <cmath>

namespace pt {

namespace {

// The purposes of a vertex's random streams.
enum Purpose : std::uint32_t {
    draw_bounce = 1u,
    draw_emitter = 2u,
    draw_sky = 3u,
    draw_pick = 4u,
    draw_roulette = 5u
};

// The stream of `purpose` at vertex `vertex` of the path drawn from `seed`.
restir::Pcg32 vertex_rng(std::uint32_t seed, std::uint32_t vertex, Purpose purpose) {
    return restir::make_pixel_rng(seed, vertex, purpose);
}

// f(wo, wi) max(0, n.wi) at `s`, wo its viewer's direction.
glm::vec3 f_cos(const GSurface& s, glm::vec3 wi) {
    if (is_lambertian(s))
        return s.albedo * (restir::inv_pi * std::max(0.0f, glm::dot(s.normal, wi)));
    return surface_bsdf(s).evaluate_cos(s.normal, view_direction(s), wi);
}

// Whether the segment a - b may be a reconnection (x_{k-1}, x_k).
bool meets(const restir::ReconnectionCriterion& rule, const GSurface& a, const GSurface& b) {
    return rule(surface_roughness(a), surface_roughness(b), glm::length(a.position - b.position));
}

} // namespace

// The products along the path being drawn: with every vertex's lobe kept (`ext`, the form of
// a path replayed whole), and once the reconnection vertex x_k is found, with the lobes kept
// before x_{k-1} only (`hybrid`: the prefix the shift replays; `rc_f`, `rc_p` as it reached
// x_k) and after x_k (`suffix`). A Lambertian x_k (`reflected`) gathers the light connections
// after it into the radiance it reflects (f / p of each after x_k: `tail`).
struct PtPaths::Walk {
    glm::vec3 ext_f{1.0f};
    float ext_p = 1.0f;
    glm::vec3 hybrid_f{1.0f};
    float hybrid_p = 1.0f;
    glm::vec3 suffix_f{1.0f};
    glm::vec3 rc_f{1.0f};
    float rc_p = 1.0f;
    bool reflected = false;
    glm::vec3 tail_f{1.0f};
    float tail_p = 1.0f;
    glm::vec3 reflected_radiance{0.0f};
    restir::PtSample rc; ///< The seed, the visible point and, once found, x_k.
};

PtPaths::PtPaths(const Scene& scene, const EmbreeScene& rays, const LightSet& lights,
                 float ray_offset, std::uint32_t max_depth, bool environment_nee)
    : scene_(scene), rays_(rays), lights_(lights), ray_offset_(ray_offset),
      max_depth_(std::min(max_depth, 64u)),
      environment_(scene.environment ? scene.environment->view() : restir::EnvironmentMapView{}),
      environment_nee_(environment_nee && !environment_.empty()),
      escape_distance_(scene.environment ? 2.0f * scene_size(scene) : 0.0f) {}

PtPaths::Bounce PtPaths::bounce(const GSurface& s, std::uint32_t seed, std::uint32_t vertex) const {
    restir::Pcg32 rng = vertex_rng(seed, vertex, draw_bounce);
    const float u_lobe = next_float(rng);
    const float u0 = next_float(rng);
    const float u1 = next_float(rng);
    Bounce b;
    if (is_lambertian(s)) {
        b.wi = restir::sample_diffuse_direction(s.normal, u0, u1);
        b.pdf = restir::diffuse_direction_pdf(s.normal, b.wi);
        b.lobe_pdf = b.pdf;
    } else {
        const restir::GlossyBsdf bsdf = surface_bsdf(s);
        const glm::vec3 wo = view_direction(s);
        const restir::BsdfSample d = bsdf.sample(s.normal, wo, u_lobe, u0, u1);
        b.wi = d.wi;
        b.pdf = d.pdf;
        b.lobe_pdf = d.pdf > 0.0f ? bsdf.lobe_pdf(s.normal, wo, d.wi,
                                                  bsdf.samples_specular(s.normal, wo, u_lobe))
                                  : 0.0f;
    }
    if (!(b.pdf > 0.0f) || !(b.lobe_pdf > 0.0f)) {
        b.pdf = 0.0f;
        return b;
    }
    b.f_cos = f_cos(s, b.wi);
    b.hit = rays_.closest_hit_from(s.position, s.normal, b.wi, ray_offset_);
    if (b.hit.found)
        b.next = surface_at(scene_, b.hit, b.wi);
    return b;
}

PtPaths::Connection PtPaths::light_sampled(const GSurface& s, std::uint32_t seed,
                                           std::uint32_t vertex, Technique technique) const {
    Connection c;
    glm::vec3 radiance(0.0f);
    bool open = false;
    if (technique == sky_sampling) {
        restir::Pcg32 rng = vertex_rng(seed, vertex, draw_sky);
        const float u0 = next_float(rng);
        const float u1 = next_float(rng);
        const restir::EnvironmentSample light = environment_.sample({u0, u1});
        c.direction = light.direction;
        c.light_pdf = light.pdf;
        radiance = light.radiance;
        const restir::ShadowSegment way_out = restir::distant_shadow_segment(
            s.position, s.normal, light.direction, ray_offset_, escape_distance_);
        open = light.pdf > 0.0f && glm::dot(s.normal, light.direction) > 0.0f &&
               !rays_.occluded(way_out.from, way_out.to);
    } else {
        restir::Pcg32 rng = vertex_rng(seed, vertex, draw_emitter);
        const restir::DiscreteSample pick =
            restir::sample_light(restir::PowerLightSampler{lights_.emitter_table().view()}, rng);
        const float u = next_float(rng);
        const float v = next_float(rng);
        if (!(pick.pmf > 0.0f))
            return c;
        const SceneEmitters& emitters = lights_.emitters();
        const restir::LightSample light =
            emitters.is_shape(pick.index) ? emitters.sample_point(pick.index, {u, v}, s.position)
                                          : emitters.sample_point(pick.index, {u, v});
        const glm::vec3 to_light = light.position - s.position;
        const float d2 = glm::dot(to_light, to_light);
        c.direction = to_light / std::sqrt(d2);
        const float cos_light = -glm::dot(light.normal, c.direction);
        if (!(cos_light > 0.0f) || !(light.area_pdf > 0.0f) || !(d2 > 0.0f))
            return {};
        c.light_pdf = pick.pmf * light.area_pdf * d2 / cos_light; // per solid angle
        radiance = emitters.radiance(pick.index);
        const restir::ShadowSegment segment =
            restir::shadow_segment(s.position, s.normal, light.position, light.normal, ray_offset_);
        open = glm::dot(s.normal, c.direction) > 0.0f && !rays_.occluded(segment.from, segment.to);
    }
    c.bsdf_pdf = bounce_pdf(s, c.direction);
    c.f_cos = f_cos(s, c.direction);
    c.radiance = open ? radiance : glm::vec3(0.0f);
    return c;
}

PtPaths::Connection PtPaths::bsdf_sampled(const GSurface& s, const Bounce& b) const {
    Connection c;
    c.direction = b.wi;
    c.bsdf_pdf = b.pdf;
    c.lobe_pdf = b.lobe_pdf;
    c.f_cos = b.f_cos;
    if (!b.hit.found) {
        if (!environment_.empty()) {
            c.radiance = environment_.radiance(b.wi);
            c.light_pdf = environment_nee_ ? environment_.pdf(b.wi) : 0.0f;
        }
        return c;
    }
    const SceneEmitters& emitters = lights_.emitters();
    const std::uint32_t emitter = emitters.emitter_of_primitive(b.hit.primitive);
    const float cos_light = -glm::dot(b.hit.normal, b.wi);
    if (emitter == SceneEmitters::none || !(cos_light > 0.0f))
        return c;
    c.light_pdf = lights_.emitter_hit_pdf(emitter, b.hit, s.position, cos_light);
    c.radiance = emitters.radiance(emitter);
    return c;
}

// One light connection of the path as a candidate: f of the path that ends there, with the
// end's MIS weight (balance heuristic) and, where the path has no reconnection vertex, the
// posterior of the lobe that drew its last direction; the density to match.
void PtPaths::offer(restir::Reservoir<restir::PtSample>& r, Walk& walk, const Connection& c,
                    restir::PathEnd end, std::uint8_t technique, std::uint32_t vertex,
                    restir::Pcg32& rng) const {
    const float u = next_float(rng);
    const bool light = end == restir::PathEnd::light_sampled;
    const float mis_sum = c.bsdf_pdf + c.light_pdf;
    if (walk.reflected && vertex >= walk.rc.rc_index) { // one more term of x_k's radiance
        // tail f times the end's weight branch / mis_sum, over tail p times branch.
        const float p = walk.tail_p * mis_sum;
        if (p > 0.0f)
            walk.reflected_radiance += walk.tail_f * c.f_cos * c.radiance / p;
        return;
    }
    restir::PtSample x = walk.rc;
    x.length = static_cast<std::uint8_t>(vertex + 1u);
    x.end = end;
    x.end_technique = technique;
    float density = 0.0f;
    if (x.rc_index == 0u) {
        const float branch = light ? c.light_pdf : c.lobe_pdf;
        x.contribution = walk.ext_f * c.f_cos * c.radiance * restir::safe_divide(branch, mis_sum);
        density = walk.ext_p * branch;
        x.density = density;
    } else {
        const float branch = light ? c.light_pdf : c.bsdf_pdf;
        const glm::vec3 last = c.f_cos * c.radiance * restir::safe_divide(branch, mis_sum);
        x.contribution = walk.hybrid_f * last;
        density = walk.hybrid_p * branch;
        if (x.rc_index == vertex) { // w_k ends the path: the suffix is the light's radiance
            x.rc_direction = c.direction;
            x.rc_light_pdf = c.light_pdf;
            x.suffix = c.radiance;
        } else {
            x.suffix = walk.suffix_f * last;
        }
    }
    const float target = restir::fold_channels<target_norm>(x.contribution);
    if (target > 0.0f && density > 0.0f)
        r.stream(x, target / density, target, u);
}

void PtPaths::advance(Walk& walk, const GSurface& s, const Bounce& b, std::uint32_t vertex,
                      const restir::ReconnectionCriterion& rule) {
    restir::PtSample& rc = walk.rc;
    if (rc.rc_index == 0u && meets(rule, s, b.next)) { // x_{vertex + 1} is x_k
        rc.rc_index = static_cast<std::uint8_t>(vertex + 1u);
        rc.rc_position = b.next.position;
        rc.rc_normal = b.next.normal;
        rc.rc_roughness = surface_roughness(b.next);
        rc.rc_material = b.next.material;
        rc.density =
            restir::reconnection_density(walk.ext_p, s.position, b.next.position, b.next.normal);
        walk.hybrid_f = walk.ext_f * b.f_cos;
        walk.hybrid_p = walk.ext_p * b.pdf;
        walk.rc_f = walk.hybrid_f;
        walk.rc_p = walk.hybrid_p;
        walk.reflected = is_lambertian(b.next);
    } else if (rc.rc_index != 0u) {
        walk.hybrid_f *= b.f_cos;
        walk.hybrid_p *= b.pdf;
        walk.tail_f *= b.f_cos;
        walk.tail_p *= b.pdf;
        if (vertex == rc.rc_index)
            rc.rc_direction = b.wi;
        else
            walk.suffix_f *= b.f_cos;
    }
    // f cos times the lobe's posterior P_l p_l / p, over the lobe's density P_l p_l.
    walk.ext_f *= b.f_cos * (b.lobe_pdf / b.pdf);
    walk.ext_p *= b.lobe_pdf;
}

// Russian roulette past the reconnection vertex, where the shift keeps the path as it is, from
// x_4 on as the path tracer's: the path goes on beyond x_{vertex + 1} with probability q =
// min(0.95, max channel of f / p), and the densities of the candidates after it take q in.
bool PtPaths::survives(Walk& walk, std::uint32_t seed, std::uint32_t vertex) {
    if (walk.rc.rc_index == 0u || vertex < walk.rc.rc_index || vertex < 3u)
        return true;
    const glm::vec3 throughput = walk.hybrid_f / walk.hybrid_p;
    const float q = std::min(0.95f, std::max(throughput.x, std::max(throughput.y, throughput.z)));
    restir::Pcg32 rng = vertex_rng(seed, vertex, draw_roulette);
    if (!(q > 0.0f) || !(next_float(rng) < q))
        return false;
    walk.hybrid_p *= q;
    walk.tail_p *= q;
    return true;
}

restir::Reservoir<restir::PtSample>
PtPaths::initial(const GSurface& x1, std::uint32_t seed,
                 const restir::ReconnectionCriterion& rule) const {
    restir::Reservoir<restir::PtSample> r;
    Walk walk;
    walk.rc.seed = seed;
    walk.rc.visible_point = x1.position;
    restir::Pcg32 pick = vertex_rng(seed, 0u, draw_pick);
    GSurface s = x1;
    for (std::uint32_t vertex = 1u;; ++vertex) {
        if (vertex >= 2u) { // x_1's own direct light is ReSTIR DI's
            offer(r, walk, light_sampled(s, seed, vertex, emitter_sampling),
                  restir::PathEnd::light_sampled, emitter_sampling, vertex, pick);
            if (environment_nee_)
                offer(r, walk, light_sampled(s, seed, vertex, sky_sampling),
                      restir::PathEnd::light_sampled, sky_sampling, vertex, pick);
        }
        if (vertex >= max_depth_)
            break;
        const Bounce b = bounce(s, seed, vertex);
        if (!(b.pdf > 0.0f))
            break;
        if (vertex >= 2u)
            offer(r, walk, bsdf_sampled(s, b), restir::PathEnd::bsdf_sampled, emitter_sampling,
                  vertex, pick);
        if (!b.hit.found)
            break;
        advance(walk, s, b, vertex, rule);
        if (!survives(walk, seed, vertex))
            break;
        s = b.next;
    }
    if (walk.reflected) { // the paths through a Lambertian x_k, as one candidate
        restir::PtSample x = walk.rc;
        x.length = static_cast<std::uint8_t>(x.rc_index + 1u);
        x.end = restir::PathEnd::reflected;
        x.suffix = walk.reflected_radiance;
        x.contribution = walk.rc_f * x.suffix;
        const float target = restir::fold_channels<target_norm>(x.contribution);
        const float u = next_float(pick);
        if (target > 0.0f && walk.rc_p > 0.0f)
            r.stream(x, target / walk.rc_p, target, u);
    }
    r.finalize_normalized();
    r.candidate_count = 1u;
    return r;
}

bool PtPaths::replay_bounces(const restir::PtSample& x, const restir::ReconnectionCriterion& rule,
                             std::uint32_t last, GSurface& s, glm::vec3& throughput,
                             float& density) const {
    for (std::uint32_t vertex = 1u; vertex < last; ++vertex) {
        const Bounce b = bounce(s, x.seed, vertex);
        if (!(b.pdf > 0.0f) || !b.hit.found || meets(rule, s, b.next))
            return false;
        throughput *= b.f_cos * (b.lobe_pdf / b.pdf);
        density *= b.lobe_pdf;
        s = b.next;
    }
    return true;
}

restir::ReplayedPrefix<GSurface>
PtPaths::replay_prefix(const restir::PtSample& x, const GSurface& from,
                       const restir::ReconnectionCriterion& rule) const {
    restir::ReplayedPrefix<GSurface> prefix;
    prefix.last = from;
    prefix.valid = x.rc_index >= 2u && replay_bounces(x, rule, x.rc_index - 1u, prefix.last,
                                                      prefix.throughput, prefix.density);
    prefix.position = prefix.last.position;
    prefix.roughness = surface_roughness(prefix.last);
    return prefix;
}

restir::ReplayedPath PtPaths::replay_path(const restir::PtSample& x, const GSurface& from,
                                          const restir::ReconnectionCriterion& rule) const {
    restir::ReplayedPath path;
    if (x.length < 3u) // indirect light: x_1, at least one vertex, the light
        return path;
    GSurface s = from;
    glm::vec3 throughput(1.0f);
    float density = 1.0f;
    const std::uint32_t last = x.length - 1u;
    if (!replay_bounces(x, rule, last, s, throughput, density))
        return path;
    Connection c;
    float branch = 0.0f;
    if (x.end == restir::PathEnd::light_sampled) {
        c = light_sampled(s, x.seed, last, static_cast<Technique>(x.end_technique));
        branch = c.light_pdf;
    } else {
        const Bounce b = bounce(s, x.seed, last);
        if (!(b.pdf > 0.0f))
            return path;
        c = bsdf_sampled(s, b);
        branch = c.lobe_pdf;
    }
    if (!(branch > 0.0f))
        return path;
    path.contribution =
        throughput * c.f_cos * c.radiance * restir::safe_divide(branch, c.bsdf_pdf + c.light_pdf);
    path.density = density * branch;
    path.valid = true;
    return path;
}

glm::vec3 PtPaths::reconnect(const GSurface& v, const restir::PtSample& x) const {
    const glm::vec3 to_rc = x.rc_position - v.position;
    const float distance = glm::length(to_rc);
    if (!(distance > 0.0f))
        return glm::vec3(0.0f);
    const glm::vec3 w = to_rc / distance;
    glm::vec3 f = f_cos(v, w);
    if (x.end != restir::PathEnd::reflected) { // x.suffix arrives at x_k along w_k
        GSurface k; // x_k, seen from v (a Lambertian surface's f ignores the view)
        k.position = x.rc_position;
        k.normal = x.rc_normal;
        k.valid = true;
        set_material(k, scene_.materials[x.rc_material], x.rc_material);
        if (!is_lambertian(k))
            set_view(k, -w);
        f *= f_cos(k, x.rc_direction) * restir::rc_mis_weight(x, bounce_pdf(k, x.rc_direction));
    }
    if (!(f.x > 0.0f) && !(f.y > 0.0f) && !(f.z > 0.0f))
        return glm::vec3(0.0f);
    const restir::ShadowSegment segment =
        restir::shadow_segment(v.position, v.normal, x.rc_position, x.rc_normal, ray_offset_);
    return rays_.occluded(segment.from, segment.to) ? glm::vec3(0.0f) : f;
}

} // namespace pt
