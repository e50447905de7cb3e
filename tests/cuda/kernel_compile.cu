// Compile check: the core templates inside a __global__ kernel (built by scripts/test.sh
// when nvcc is available; never run in CI).
#include <restir/restir.hpp>

#include <glm/geometric.hpp>

#include <cstdint>

namespace {

struct UniformDraw {
    std::uint32_t light_count;
    RESTIR_HOST_DEVICE restir::SourceSample<restir::LightSampleRef>
    operator()(restir::Pcg32& rng) const {
        const restir::UniformLightSampler sampler{light_count};
        const restir::DiscreteSample choice = restir::sample_light(sampler, rng);
        const float u = next_float(rng);
        const float v = next_float(rng);
        return {{choice.index, glm::vec2(u, v)}, choice.pmf};
    }
};

struct DistanceTarget {
    const glm::vec3* light_positions;
    glm::vec3 receiver;
    RESTIR_HOST_DEVICE float operator()(const restir::LightSampleRef& ref) const {
        const glm::vec3 d = light_positions[ref.light_id] - receiver;
        return restir::yuksel_falloff(glm::length(d), 0.1f);
    }
};

// A G-buffer texel and the reuse bridge for it.
struct GBufferTexel {
    glm::vec3 position;
    glm::vec3 normal;
    float depth;
};
RESTIR_HOST_DEVICE glm::vec3 surface_position(const GBufferTexel& t) { return t.position; }
RESTIR_HOST_DEVICE glm::vec3 surface_normal(const GBufferTexel& t) { return t.normal; }
RESTIR_HOST_DEVICE float surface_depth(const GBufferTexel& t) { return t.depth; }
RESTIR_HOST_DEVICE bool is_valid_surface(const GBufferTexel& t) { return t.depth > 0.0f; }

struct SurfaceTarget {
    const glm::vec3* light_positions;
    RESTIR_HOST_DEVICE float operator()(const restir::LightSampleRef& ref,
                                        const GBufferTexel& texel) const {
        const glm::vec3 d = light_positions[ref.light_id] - texel.position;
        return restir::yuksel_falloff(glm::length(d), 0.1f);
    }
};

struct HeightVisibility {
    RESTIR_HOST_DEVICE bool operator()(const restir::LightSampleRef& ref,
                                       const GBufferTexel& texel) const {
        return surface_position(texel).y < 10.0f || ref.light_id % 2u == 0u;
    }
};

struct StaticCamera {
    RESTIR_HOST_DEVICE restir::PixelCoord operator()(restir::PixelCoord p) const { return p; }
};

// Photon tracing against one plane, with a Lambertian hook.
struct PlaneHit {
    glm::vec3 position;
    bool found;
};
RESTIR_HOST_DEVICE glm::vec3 surface_position(const PlaneHit& h) { return h.position; }
RESTIR_HOST_DEVICE glm::vec3 surface_normal(const PlaneHit&) { return {0.0f, 1.0f, 0.0f}; }
// Required by the Surface concept; the shooter never asks for depth.
[[maybe_unused]] RESTIR_HOST_DEVICE float surface_depth(const PlaneHit&) { return 1.0f; }
RESTIR_HOST_DEVICE bool is_valid_surface(const PlaneHit& h) { return h.found; }

struct GroundPlane {
    RESTIR_HOST_DEVICE PlaneHit closest_hit(glm::vec3 origin, glm::vec3 direction) const {
        const float t = -origin.y / direction.y;
        return {origin + t * direction, t > 0.0f};
    }
};

struct Grey {
    template <class Rng>
    RESTIR_HOST_DEVICE restir::Scattering operator()(const PlaneHit& hit, glm::vec3,
                                                     Rng& rng) const {
        const float u0 = next_float(rng);
        const float u1 = next_float(rng);
        return {restir::sample_diffuse_direction(surface_normal(hit), u0, u1), glm::vec3(0.5f),
                glm::vec3(0.5f), true, false};
    }
};

struct PointEmitters {
    const glm::vec3* positions;
    std::uint32_t count;
    RESTIR_HOST_DEVICE std::uint32_t light_count() const { return count; }
    RESTIR_HOST_DEVICE restir::LightSample sample_point(std::uint32_t id, glm::vec2) const {
        restir::LightSample s;
        s.position = positions[id];
        s.normal = glm::vec3(0.0f);
        s.radiance = glm::vec3(1.0f);
        s.area_pdf = 1.0f;
        s.is_delta = true;
        return s;
    }
};

} // namespace

__global__ void photon_kernel(restir::PhotonSource source, restir::PhotonParams params,
                              restir::Vpl* out, std::uint32_t* counts, const glm::vec3* emitters,
                              std::uint32_t emitter_count, float* irradiance) {
    const auto photon = static_cast<std::uint32_t>(blockIdx.x * blockDim.x + threadIdx.x);
    counts[photon] = restir::trace_photon(photon, source, GroundPlane{}, Grey{}, params,
                                          out + photon * params.max_bounces);
    const PointEmitters lights{emitters, emitter_count};
    const restir::UnifiedLightSet<PointEmitters> unified{&lights, out, counts[photon]};
    const restir::Falloff falloff{};
    irradiance[photon] =
        restir::unshadowed_irradiance(unified.sample_point(0u, glm::vec2(0.5f)), glm::vec3(0.0f),
                                      glm::vec3(0.0f, 1.0f, 0.0f), falloff)
            .x;
}

__global__ void tile_kernel(restir::PresampledLight* entries, const glm::vec3* emitters,
                            std::uint32_t emitter_count, const restir::AliasEntry* alias_entries,
                            float* out) {
    const auto i = static_cast<std::uint32_t>(blockIdx.x * blockDim.x + threadIdx.x);
    restir::Pcg32 rng = restir::make_pixel_rng(i, 0u, restir::RngStream::application);
    const PointEmitters lights{emitters, emitter_count};
    const restir::PowerLightSampler sampler{restir::AliasTableView{alias_entries, emitter_count}};
    entries[i] = restir::presample_light(sampler, lights, rng);
    restir::presample_lights( // the batched fill: one entry a thread, as the line above
        sampler, lights, 1u,
        [&](std::uint32_t) {
            return restir::make_pixel_rng(i, 0u, restir::RngStream::application);
        },
        [&](std::uint32_t, const restir::PresampledLight& e) { entries[i] = e; });
    const restir::LightTilesView tiles{entries, 4u, 64u};
    const float u0 = next_float(rng);
    const float u1 = next_float(rng);
    const restir::PresampledLight& e = tiles.draw(tiles.tile_for(i / 64u, 0u), u0, u1);
    restir::Reservoir<std::uint32_t> r;
    r.stream(i, 1.0f, e.pdf, next_float(rng));
    r.finalize();
    out[i] = r.with_sample(e.reference).contribution_weight;
}

// Spatially aware candidates: a draw and a pmf from the light BVH at a shading point, four
// draws at once, and a grid cell's tile entry drawn for a region (ReGIR).
__global__ void light_bvh_kernel(restir::LightBvhView bvh, const glm::vec3* emitters,
                                 restir::PresampledLight* cell_entries, float* out) {
    const auto i = static_cast<std::uint32_t>(blockIdx.x * blockDim.x + threadIdx.x);
    restir::Pcg32 rng = restir::make_pixel_rng(i, 0u, restir::RngStream::application);
    const restir::ShadingPoint at{glm::vec3(static_cast<float>(i), 1.0f, 0.0f),
                                  glm::vec3(0.0f, 1.0f, 0.0f)};
    const restir::SourceSample<restir::LightSampleRef> c =
        restir::draw_light_candidate(bvh, at, rng);
    const restir::ShadingPoint cell{at.position, glm::vec3(0.0f), 0.5f};
    const PointEmitters lights{emitters, bvh.light_count()};
    cell_entries[i] = restir::presample_light(bvh, cell, lights, rng);
    const float u0[4] = {0.1f, 0.3f, 0.6f, 0.9f}, u1[4] = {0.2f, 0.4f, 0.7f, 0.8f};
    restir::DiscreteSample four[4];
    bvh.sample(at, u0, u1, four);
    out[i] = c.pdf + bvh.pmf(at, c.sample.light_id) + four[0].pmf + four[3].pmf;
}

// A grid cell's tile (ReGIR): one thread resamples one cell's entries from power candidates
// by the lights' importance bounds at the cell's region, into structure-of-arrays tiles.
__global__ void light_grid_kernel(restir::LightGridLayout grid, const restir::LightBvhNode* nodes,
                                  const glm::vec3* emitters, std::uint32_t emitter_count,
                                  const restir::AliasEntry* alias_entries,
                                  restir::GridCandidate* scratch, float* planes,
                                  restir::LightSampleRef* references) {
    const auto cell = static_cast<std::uint32_t>(blockIdx.x * blockDim.x + threadIdx.x);
    if (cell >= grid.cell_count())
        return;
    constexpr std::uint32_t entries = 8u, per_entry = 4u;
    restir::Pcg32 rng = restir::make_pixel_rng(cell, 0u, restir::RngStream::application);
    const restir::PowerLightSampler sampler{restir::AliasTableView{alias_entries, emitter_count}};
    const PointEmitters lights{emitters, emitter_count};
    const restir::LightTileArrays tiles{planes, references, grid.cell_count(), entries};
    const auto node_of = [nodes](std::uint32_t id) -> const restir::LightBvhNode& {
        return nodes[id];
    };
    restir::resample_grid_tile(sampler, grid.cell_region(cell), node_of, lights, rng, entries,
                               per_entry, scratch + cell * entries * per_entry,
                               [&](std::uint32_t j, const restir::PresampledLight& entry) {
                                   tiles.store(cell, j, entry, restir::Falloff{});
                               });
}

// Distant lights beside the light BVH and beside a grid cell's tile: a draw and a pmf of the
// mixture at a shading point, a draw beside the power sampler, and a tile whose entries are
// distant with probability P.
__global__ void distant_lights_kernel(restir::LightBvhView bvh, restir::LightGridLayout grid,
                                      const restir::LightBvhNode* nodes, const glm::vec3* emitters,
                                      std::uint32_t emitter_count,
                                      const restir::AliasEntry* alias_entries,
                                      restir::GridCandidate* scratch,
                                      restir::PresampledLight* cell_entries, float* out) {
    const auto i = static_cast<std::uint32_t>(blockIdx.x * blockDim.x + threadIdx.x);
    restir::Pcg32 rng = restir::make_pixel_rng(i, 0u, restir::RngStream::application);
    const float p = restir::distant_light_probability(2.0f, 5.0f);
    const restir::WithDistantLights<restir::LightBvhView> sampler =
        restir::with_distant_lights(bvh, bvh.light_count() / 2u, 1u, p);
    const restir::ShadingPoint at{glm::vec3(static_cast<float>(i), 1.0f, 0.0f),
                                  glm::vec3(0.0f, 1.0f, 0.0f)};
    const restir::SourceSample<restir::LightSampleRef> c =
        restir::draw_light_candidate(sampler, at, rng);
    const restir::PowerLightSampler power{
        restir::AliasTableView{alias_entries, emitter_count - 1u}};
    const auto beside_power = restir::with_distant_lights(power, 0u, 1u, p);
    const restir::DiscreteSample d = restir::sample_light(beside_power, rng);
    const PointEmitters lights{emitters, emitter_count};
    const auto node_of = [nodes](std::uint32_t id) -> const restir::LightBvhNode& {
        return nodes[id];
    };
    constexpr std::uint32_t entries = 8u, per_entry = 4u;
    const std::uint32_t cell = i % grid.cell_count();
    restir::resample_grid_tile_with_distant(
        power, sampler.distant, grid.cell_region(cell), node_of, lights, rng, entries, per_entry,
        scratch + i * entries * per_entry,
        [&](std::uint32_t j, const restir::PresampledLight& entry) {
            cell_entries[i * entries + j] = entry;
        });
    out[i] = c.pdf + sampler.pmf(at, c.sample.light_id) + d.pmf + beside_power.pmf(d.index);
}

// Batch RIS over structure-of-arrays tiles, with reservoirs that carry their light point:
// the tile fill, the block evaluation, the selection, the point sample and its visibility.
struct NeverOccluded {
    RESTIR_HOST_DEVICE bool occluded(glm::vec3, glm::vec3) const { return false; }
};

__global__ void batch_ris_kernel(float* planes, restir::LightSampleRef* references,
                                 const glm::vec3* emitters, std::uint32_t emitter_count,
                                 const restir::AliasEntry* alias_entries, float* out) {
    const auto i = static_cast<std::uint32_t>(blockIdx.x * blockDim.x + threadIdx.x);
    const restir::LightTileArrays tiles{planes, references, 4u, 64u};
    restir::Pcg32 rng = restir::make_pixel_rng(i, 0u, restir::RngStream::application);
    const PointEmitters lights{emitters, emitter_count};
    const restir::PowerLightSampler sampler{restir::AliasTableView{alias_entries, emitter_count}};
    const restir::Falloff falloff{restir::FalloffKind::yuksel, 0.05f};
    tiles.store(i / 64u % 4u, i % 64u, restir::presample_light(sampler, lights, rng), falloff);
    const glm::vec3 receiver(static_cast<float>(i), 0.0f, 0.0f);
    const glm::vec3 normal(0.0f, 1.0f, 0.0f);
    const restir::Reservoir<std::uint32_t> picked = restir::resample_ris_batch<8u>(
        rng, 32u, [&](std::uint32_t b, restir::CandidateBlock<8u>& block) {
            return restir::evaluate_tile_block(tiles, i % 4u, (b % 8u) * 8u, receiver, normal,
                                               glm::vec3(1.0f), block);
        });
    restir::Reservoir<restir::LightPointSample> r =
        picked.with_sample(tiles.point_sample(picked.sample));
    const NeverOccluded query;
    const restir::LightPointVisibility<NeverOccluded> visible{&query, 1e-3f};
    const GBufferTexel texel{receiver, normal, 1.0f};
    restir::apply_visibility(r, texel, visible);
    // Parts of groups (4, 2 and 1 of their 8 entries), as pixels that share groups read them.
    const auto parts = [&]<std::uint32_t Lanes>() {
        return restir::resample_ris_batch<Lanes>(
                   rng, 4u * Lanes,
                   [&](std::uint32_t b, restir::CandidateBlock<Lanes>& block) {
                       return restir::evaluate_tile_block(tiles, i % 4u,
                                                          b * 8u + (i % (8u / Lanes)) * Lanes,
                                                          receiver, normal, glm::vec3(1.0f), block);
                   })
            .contribution_weight;
    };
    out[i] = r.contribution_weight * restir::unshadowed_irradiance(r.sample, receiver, normal).x +
             parts.template operator()<4u>() + parts.template operator()<2u>() +
             parts.template operator()<1u>();
}

__global__ void reuse_kernel(const glm::vec3* light_positions, const GBufferTexel* texels,
                             const restir::Reservoir<restir::LightSampleRef>* previous,
                             restir::Reservoir<restir::LightSampleRef>* temporal_out,
                             restir::Reservoir<restir::LightSampleRef>* spatial_out,
                             std::uint32_t width, std::uint32_t height) {
    const auto x = static_cast<std::int32_t>(blockIdx.x * blockDim.x + threadIdx.x);
    const auto y = static_cast<std::int32_t>(blockIdx.y * blockDim.y + threadIdx.y);
    const restir::ImageView<const GBufferTexel> surfaces{texels, width, height};
    const restir::ImageView<const restir::Reservoir<restir::LightSampleRef>> history{previous,
                                                                                     width, height};
    if (!surfaces.contains({x, y}))
        return;
    const std::uint32_t index = surfaces.index_of({x, y});
    restir::Pcg32 rng = restir::make_pixel_rng(index, 1u, restir::RngStream::initial);
    const restir::ReuseBridge bridge{SurfaceTarget{light_positions}, HeightVisibility{}};
    restir::Reservoir<restir::LightSampleRef> current = history[{x, y}];
    restir::apply_visibility(current, texels[index], bridge.visibility);
    const restir::TemporalParams temporal = restir::default_temporal_params();
    const restir::SpatialParams spatial = restir::default_spatial_params();
    const restir::ReuseParams reuse{restir::BiasCorrection::balance_heuristic};
    temporal_out[index] =
        restir::temporal_resample({x, y}, current, texels[index], history, surfaces, StaticCamera{},
                                  temporal, reuse, 1u, bridge, rng);
    spatial_out[index] =
        restir::spatiotemporal_resample({x, y}, current, texels[index], history, surfaces,
                                        StaticCamera{}, temporal, spatial, reuse, 1u, bridge, rng);
    spatial_out[index] =
        restir::spatial_resample({x, y}, history, surfaces, spatial, reuse, bridge, rng);
    spatial_out[index] =
        restir::boiling_filter({x, y}, history, restir::default_boiling_filter_params());
}

// ReSTIR GI on the device: spatial reuse of path samples through the reconnection shift (the
// neighbours streamed), p-hat from the path sample's contribution at a Lambertian texel, the
// reconnections' visibility traced through a device ray query, under the mode chosen at run
// time.
struct GiTexel {
    glm::vec3 position;
    glm::vec3 normal;
    glm::vec3 albedo;
    float depth;
};
RESTIR_HOST_DEVICE glm::vec3 surface_position(const GiTexel& t) { return t.position; }
RESTIR_HOST_DEVICE glm::vec3 surface_normal(const GiTexel& t) { return t.normal; }
RESTIR_HOST_DEVICE float surface_depth(const GiTexel& t) { return t.depth; }
RESTIR_HOST_DEVICE bool is_valid_surface(const GiTexel& t) { return t.depth > 0.0f; }

struct GiTarget {
    RESTIR_HOST_DEVICE float operator()(const restir::PathSample& x, const GiTexel& t) const {
        const restir::LambertianReceiver receiver{t.position, t.normal, t.albedo};
        return restir::fold_channels<restir::ChannelNorm::sum>(
            restir::path_sample_radiance(x, receiver));
    }
};

// Blocks every segment that rises above a ceiling (a stand-in for the renderer's ray query).
struct CeilingQuery {
    float ceiling;
    RESTIR_HOST_DEVICE bool occluded(glm::vec3 from, glm::vec3 to) const {
        return from.y > ceiling || to.y > ceiling;
    }
};

__global__ void gi_reuse_kernel(const GiTexel* texels,
                                const restir::Reservoir<restir::PathSample>* reservoirs,
                                restir::Reservoir<restir::PathSample>* spatial_out,
                                restir::PackedPathSample* packed_out, std::uint32_t width,
                                std::uint32_t height, float ceiling, restir::ReuseParams reuse) {
    const auto x = static_cast<std::int32_t>(blockIdx.x * blockDim.x + threadIdx.x);
    const auto y = static_cast<std::int32_t>(blockIdx.y * blockDim.y + threadIdx.y);
    const restir::ImageView<const GiTexel> surfaces{texels, width, height};
    const restir::ImageView<const restir::Reservoir<restir::PathSample>> input{reservoirs, width,
                                                                               height};
    if (!surfaces.contains({x, y}))
        return;
    const std::uint32_t index = surfaces.index_of({x, y});
    restir::Pcg32 rng = restir::make_pixel_rng(index, 1u, restir::RngStream::spatial);
    const CeilingQuery query{ceiling};
    const restir::ReuseBridge bridge{GiTarget{},
                                     restir::ReconnectionVisibility<CeilingQuery>{&query, 1e-3f},
                                     restir::AnyMaterial{}, restir::ReconnectionShift{}};
    const restir::Reservoir<restir::PathSample> result = restir::spatial_resample(
        {x, y}, input, surfaces, restir::default_spatial_params(), reuse, bridge, rng);
    spatial_out[index] = result;
    packed_out[index] = restir::pack_path_sample(result.sample);
}

// ReSTIR PT's hybrid shift on the device: a replayable path tracer in which a path reconnecting
// at x_2 has the visible point itself as its prefix, and a path without reconnection vertex is
// one glossy bounce from the visible point (its numbers drawn from the seed, the lobe's branch
// density kept) that escapes to a white sky.
struct SkyReplay {
    using Vertex = GiTexel;
    restir::GlossyBsdf bsdf;
    RESTIR_HOST_DEVICE restir::ReplayedPrefix<GiTexel>
    replay_prefix(const restir::PtSample& x, const GiTexel& from,
                  const restir::ReconnectionCriterion&) const {
        return {from, from.position, bsdf.roughness, glm::vec3(1.0f), 1.0f, x.rc_index == 2u};
    }
    RESTIR_HOST_DEVICE restir::ReplayedPath
    replay_path(const restir::PtSample& x, const GiTexel& from,
                const restir::ReconnectionCriterion&) const {
        restir::Pcg32 rng = restir::make_pixel_rng(x.seed, 0u, restir::RngStream::application);
        const float u_lobe = next_float(rng);
        const float u0 = next_float(rng);
        const float u1 = next_float(rng);
        const glm::vec3 n = from.normal;
        const restir::BsdfSample s = bsdf.sample(n, n, u_lobe, u0, u1);
        const float density = bsdf.lobe_pdf(n, n, s.wi, bsdf.samples_specular(n, n, u_lobe));
        return {s.weight * density, density, s.pdf > 0.0f && x.length == 2u};
    }
    RESTIR_HOST_DEVICE glm::vec3 reconnect(const GiTexel& v, const restir::PtSample& x) const {
        const float cos_v =
            fmaxf(0.0f, glm::dot(v.normal, glm::normalize(x.rc_position - v.position)));
        const float cos_k = fmaxf(0.0f, glm::dot(x.rc_normal, x.rc_direction));
        return v.albedo * (cos_v * restir::inv_pi) *
               (cos_k * restir::inv_pi * restir::rc_mis_weight(x, cos_k * restir::inv_pi));
    }
};
static_assert(restir::PathReplay<SkyReplay, GiTexel>);

// One path sample per thread shifted from its texel to the next one's.
__global__ void hybrid_shift_kernel(const GiTexel* texels, const restir::PtSample* samples,
                                    std::uint32_t count, glm::vec3* out) {
    const auto i = static_cast<std::uint32_t>(blockIdx.x * blockDim.x + threadIdx.x);
    if (i >= count)
        return;
    const SkyReplay replay{
        restir::GlossyBsdf::from_metallic_roughness(glm::vec3(0.8f, 0.6f, 0.4f), 0.0f, 0.5f)};
    const restir::HybridShift<SkyReplay> shift{&replay, {0.3f, 0.01f}};
    const restir::ShiftedSample<restir::PtSample> y =
        shift(samples[i], texels[i], texels[(i + 1u) % count]);
    out[i] = y.sample.contribution * y.jacobian +
             restir::pt_sample_contribution(samples[i], texels[i].position);
}

// The frame recipe as a GPU renderer runs it: one kernel per stage, the frame by value.
using RecipeFrame = restir::DiFrame<restir::LightSampleRef, GBufferTexel, StaticCamera>;
using RecipeReservoir = restir::Reservoir<restir::LightSampleRef>;

template <class Frame>
__device__ bool recipe_pixel(const Frame& frame, restir::PixelCoord& pixel) {
    pixel = {static_cast<std::int32_t>(blockIdx.x * blockDim.x + threadIdx.x),
             static_cast<std::int32_t>(blockIdx.y * blockDim.y + threadIdx.y)};
    return frame.surfaces.contains(pixel);
}

// The recipe's collaborators on the device: initial candidates by RIS, a generator per pixel
// and stream, and shading that packs the final reservoir as the next frame's history.
struct InitialRis {
    const glm::vec3* light_positions = nullptr;
    std::uint32_t light_count = 0u;
    __device__ RecipeReservoir operator()(restir::PixelCoord, const GBufferTexel& s,
                                          restir::Pcg32& rng) const {
        return restir::resample_ris(rng, 32u, UniformDraw{light_count},
                                    DistanceTarget{light_positions, surface_position(s)});
    }
};
struct PixelRngs {
    std::uint32_t frame = 0u, width = 0u;
    __device__ restir::Pcg32 operator()(restir::PixelCoord p, std::uint32_t stream) const {
        return restir::make_pixel_rng(static_cast<std::uint32_t>(p.x) +
                                          static_cast<std::uint32_t>(p.y) * width,
                                      frame, stream);
    }
};
struct PackAsHistory {
    restir::ImageView<restir::PackedReservoir> history{};
    __device__ void operator()(restir::PixelCoord p, const RecipeReservoir& r, bool) const {
        history[p] = restir::pack_reservoir(r);
    }
};

// One step of the frame at a pixel, compiled for stage `Stage` only.
template <restir::DiStage Stage, class Frame, class Shade = restir::NoShading>
__global__ void recipe_step_kernel(Frame frame, restir::DiStep step,
                                   const glm::vec3* light_positions, std::uint32_t light_count,
                                   restir::DiBuffers<restir::LightSampleRef> buffers,
                                   Shade shade = {}) {
    restir::PixelCoord pixel;
    if (!recipe_pixel(frame, pixel))
        return;
    const restir::DiBridge bridge{
        InitialRis{light_positions, light_count},
        restir::ReuseBridge{SurfaceTarget{light_positions}, HeightVisibility{}},
        PixelRngs{frame.frame_index, buffers.out.width}, shade};
    frame.template run_stage<Stage>(step, pixel, buffers, bridge);
}

// The whole frame as a GPU renderer runs it: the recipe's steps in order, a kernel each.
template <class Frame, class Shade = restir::NoShading>
void launch_recipe(const Frame& frame, const glm::vec3* light_positions, std::uint32_t light_count,
                   restir::DiBuffers<restir::LightSampleRef> buffers, Shade shade = {}) {
    const dim3 block(8u, 8u);
    const dim3 grid((buffers.out.width + 7u) / 8u, (buffers.out.height + 7u) / 8u);
    for (std::uint32_t i = 0; i < frame.step_count(); ++i) {
        const restir::DiStep s = frame.step(i);
        restir::visit_stage(s.stage, [&](auto stage) {
            recipe_step_kernel<decltype(stage)::value>
                <<<grid, block>>>(frame, s, light_positions, light_count, buffers, shade);
        });
    }
}

// A light list that moved every light one place down and removed the first.
struct LightIdShift {
    __host__ __device__ std::uint32_t operator()(std::uint32_t id) const {
        return id == 0u ? restir::removed_light : id - 1u;
    }
};
using PackedRecipeFrame = restir::DiFrame<restir::LightSampleRef, GBufferTexel, StaticCamera,
                                          restir::PackedHistory<LightIdShift>>;
template void launch_recipe<RecipeFrame>(const RecipeFrame&, const glm::vec3*, std::uint32_t,
                                         restir::DiBuffers<restir::LightSampleRef>,
                                         restir::NoShading);
template void launch_recipe<PackedRecipeFrame, PackAsHistory>(
    const PackedRecipeFrame&, const glm::vec3*, std::uint32_t,
    restir::DiBuffers<restir::LightSampleRef>, PackAsHistory);

// A packed history that also decodes last frame's surfaces (here: reads them from an array;
// a renderer would decode its own G-buffer), so the frame has no previous-surface view.
struct DecodingPackedHistory : restir::PackedHistory<> {
    const GBufferTexel* previous_texels = nullptr;
    __host__ __device__ GBufferTexel surface(restir::PixelCoord p) const {
        return previous_texels[reservoirs.index_of(p)];
    }
};
using DecodingRecipeFrame =
    restir::DiFrame<restir::LightSampleRef, GBufferTexel, StaticCamera, DecodingPackedHistory>;
template void launch_recipe<DecodingRecipeFrame, PackAsHistory>(
    const DecodingRecipeFrame&, const glm::vec3*, std::uint32_t,
    restir::DiBuffers<restir::LightSampleRef>, PackAsHistory);

// This frame's surfaces decoded from a compact G-buffer (depth and an octahedral normal in 16
// bits per coordinate, the position from the pixel and the depth), so that the frame keeps no
// array of surfaces of either frame.
struct CompactGBuffer {
    const float* depths = nullptr;
    const std::uint32_t* octahedral_normals = nullptr;
    std::uint32_t width = 0u, height = 0u;
    __host__ __device__ bool contains(restir::PixelCoord p) const {
        return restir::ImageView<const float>{depths, width, height}.contains(p);
    }
    __host__ __device__ GBufferTexel surface(restir::PixelCoord p) const {
        const std::uint32_t i =
            static_cast<std::uint32_t>(p.x) + static_cast<std::uint32_t>(p.y) * width;
        const std::uint32_t bits = octahedral_normals[i];
        const float u = static_cast<float>(bits & 0xffffu) * (2.0f / 65535.0f) - 1.0f;
        const float v = static_cast<float>(bits >> 16u) * (2.0f / 65535.0f) - 1.0f;
        glm::vec3 n(u, v, 1.0f - fabsf(u) - fabsf(v));
        if (n.z < 0.0f)
            n = glm::vec3(copysignf(1.0f - fabsf(v), u), copysignf(1.0f - fabsf(u), v), n.z);
        const float depth = depths[i];
        return {glm::vec3(static_cast<float>(p.x), static_cast<float>(p.y), depth),
                glm::normalize(n), depth};
    }
};
static_assert(restir::SurfaceDecoder<CompactGBuffer, GBufferTexel>);
using ArrayFreeRecipeFrame = restir::DiFrame<restir::LightSampleRef, GBufferTexel, StaticCamera,
                                             DecodingPackedHistory, CompactGBuffer>;
template void launch_recipe<ArrayFreeRecipeFrame, PackAsHistory>(
    const ArrayFreeRecipeFrame&, const glm::vec3*, std::uint32_t,
    restir::DiBuffers<restir::LightSampleRef>, PackAsHistory);

// A glossy (metallic-roughness) surface on the device: the BSDF evaluated with its density
// over candidate directions in one loop, as batch RIS does, and one sampled direction.
__global__ void glossy_bsdf_kernel(const glm::vec3* directions, std::uint32_t count, float* out) {
    const auto i = static_cast<std::uint32_t>(blockIdx.x * blockDim.x + threadIdx.x);
    restir::Pcg32 rng = restir::make_pixel_rng(i, 0u, restir::RngStream::application);
    const restir::GlossyBsdf bsdf =
        restir::GlossyBsdf::from_metallic_roughness(glm::vec3(0.8f, 0.5f, 0.2f), 0.3f, 0.4f);
    const glm::vec3 normal(0.0f, 1.0f, 0.0f);
    const glm::vec3 wo = glm::normalize(glm::vec3(0.3f, 1.0f, 0.1f));
    float sum = 0.0f;
    for (std::uint32_t k = 0; k < count; ++k)
        sum += bsdf.evaluate_cos(normal, wo, directions[k]).y + bsdf.pdf(normal, wo, directions[k]);
    const float u_lobe = next_float(rng);
    const float u0 = next_float(rng);
    const float u1 = next_float(rng);
    const restir::BsdfSample s = bsdf.sample(normal, wo, u_lobe, u0, u1);
    out[i] = sum + s.weight.x * s.pdf + bsdf.specular_probability(normal, wo);
}

__global__ void ris_kernel(const glm::vec3* light_positions, std::uint32_t light_count,
                           const restir::AliasEntry* alias_entries, float* out) {
    const auto pixel = static_cast<std::uint32_t>(blockIdx.x * blockDim.x + threadIdx.x);
    restir::Pcg32 rng = restir::make_pixel_rng(pixel, 0u, 0u, 7u);
    const DistanceTarget target{light_positions, glm::vec3(static_cast<float>(pixel), 0.0f, 0.0f)};
    restir::Reservoir<restir::LightSampleRef> reservoir =
        restir::resample_ris(rng, 32u, UniformDraw{light_count}, target);

    restir::Reservoir<restir::LightSampleRef> other = reservoir;
    other.cap_candidate_count(20u);
    reservoir.merge(other, target(other.sample), next_float(rng));
    reservoir.finalize();
    reservoir.sanitize();

    const restir::PowerLightSampler power{restir::AliasTableView{alias_entries, light_count}};
    const restir::DiscreteSample choice = restir::sample_light(power, rng);
    out[pixel] = reservoir.contribution_weight * target(reservoir.sample) + choice.pmf +
                 restir::evaluate_falloff(restir::FalloffKind::clamped_inverse_square, 1.0f, 0.5f);
}

// Points on area lights drawn in the solid angle they subtend from a receiver: each sampler and
// its density, one receiver per thread.
__global__ void solid_angle_kernel(const glm::vec3* corners, float* out) {
    const auto i = static_cast<std::uint32_t>(blockIdx.x * blockDim.x + threadIdx.x);
    restir::Pcg32 rng = restir::make_pixel_rng(i, 0u, restir::RngStream::application);
    const float u0 = next_float(rng);
    const float u1 = next_float(rng);
    const glm::vec2 u(u0, u1);
    const glm::vec3 from(static_cast<float>(i), 0.5f, -1.0f);
    const glm::vec3 a = corners[0], b = corners[1], c = corners[2];
    const glm::vec3 normal = glm::normalize(glm::cross(b - a, c - a));
    const restir::SolidAngleSample arvo = restir::sample_spherical_triangle(from, a, b, c, u);
    const restir::SolidAngleSample triangle = restir::sample_triangle_from(from, a, b, c, u);
    const restir::SolidAngleSample urena =
        restir::sample_spherical_rectangle(from, a, b - a, c - a, u);
    const restir::SolidAngleSample rectangle =
        restir::sample_rectangle_from(from, a, b - a, c - a, u);
    const restir::SolidAngleSample sphere = restir::sample_sphere_cone(from, a, 0.25f, u);
    out[i] = restir::solid_angle_to_area_pdf(arvo.pdf, from, arvo.point, normal) +
             restir::area_to_solid_angle_pdf(1.0f, from, triangle.point, normal) +
             restir::triangle_pdf_from(from, a, b, c, triangle.point) + triangle.pdf + urena.pdf +
             restir::rectangle_pdf_from(from, a, b - a, c - a, rectangle.point) +
             restir::spherical_triangle_solid_angle(from, a, b, c) +
             restir::spherical_rectangle_solid_angle(from, a, b - a, c - a) + sphere.pdf +
             restir::sphere_cone_pdf(from, a, 0.25f) +
             restir::triangle_area_fraction_above(a, b, c, from, normal);
}

// Glossy receivers: the batch target loop at a GlossyReceiver (with the widened lobe of VPL
// spheres), and multi-strategy RIS over light and BSDF candidates with an emitter query, the
// light candidates from a sampler and from light tiles.
struct NoEmitterHit {
    RESTIR_HOST_DEVICE restir::LightHit find_light(glm::vec3, glm::vec3) const { return {}; }
};

__global__ void glossy_receiver_kernel(float* planes, restir::LightSampleRef* references,
                                       const glm::vec3* emitters, std::uint32_t emitter_count,
                                       const restir::AliasEntry* alias_entries, float* out) {
    const auto i = static_cast<std::uint32_t>(blockIdx.x * blockDim.x + threadIdx.x);
    const restir::LightTileArrays tiles{planes, references, 4u, 64u};
    restir::Pcg32 rng = restir::make_pixel_rng(i, 0u, restir::RngStream::application);
    const PointEmitters lights{emitters, emitter_count};
    const restir::PowerLightSampler sampler{restir::AliasTableView{alias_entries, emitter_count}};
    const restir::GlossyReceiver receiver{
        glm::vec3(static_cast<float>(i), 0.0f, 0.0f), glm::vec3(0.0f, 1.0f, 0.0f),
        glm::normalize(glm::vec3(0.3f, 1.0f, 0.1f)),
        restir::GlossyBsdf::from_metallic_roughness(glm::vec3(0.9f), 1.0f, 0.2f), 0.25f};
    const restir::Reservoir<std::uint32_t> picked = restir::resample_ris_batch<8u>(
        rng, 32u, [&](std::uint32_t b, restir::CandidateBlock<8u>& block) {
            return restir::evaluate_tile_block<8u, restir::ChannelNorm::euclidean>(
                tiles, i % 4u, (b % 8u) * 8u, receiver, block);
        });
    const restir::ShadingPoint at{receiver.position, receiver.normal, 0.0f};
    const restir::Reservoir<restir::LightPointSample> mixed =
        restir::resample_lights_and_bsdf(rng, {8u, 2u}, sampler, at, lights,
                                         restir::Falloff::yuksel(0.05f), receiver, NoEmitterHit{});
    const restir::Reservoir<restir::LightPointSample> from_tiles =
        restir::resample_tiles_and_bsdf<8u, restir::ChannelNorm::euclidean>(
            rng, {16u, 1u}, tiles, [&](std::uint32_t g) { return (i % 4u) * 64u + (g % 8u) * 8u; },
            sampler, restir::Falloff::yuksel(0.05f), receiver, NoEmitterHit{});
    out[i] = picked.contribution_weight +
             mixed.contribution_weight * restir::unshadowed_radiance(mixed.sample, receiver).x +
             from_tiles.contribution_weight;
}

// VPL GI without bias: a VPL of the partition (the clamped falloff) seen through a glossy
// receiver's diffuse lobe, in the batch loop and at its point, and a path sample's path part.
__global__ void vpl_partition_kernel(float* planes, restir::LightSampleRef* references,
                                     const restir::PathSample* samples, float* out) {
    const auto i = static_cast<std::uint32_t>(blockIdx.x * blockDim.x + threadIdx.x);
    const restir::LightTileArrays tiles{planes, references, 4u, 64u};
    const restir::VplPartition partition{0.1f};
    const restir::GlossyReceiver receiver{
        glm::vec3(static_cast<float>(i), 0.0f, 0.0f),
        glm::vec3(0.0f, 1.0f, 0.0f),
        glm::normalize(glm::vec3(0.3f, 1.0f, 0.1f)),
        restir::GlossyBsdf::from_metallic_roughness(glm::vec3(0.9f), 0.0f, 0.2f),
        0.0f,
        true};
    restir::CandidateBlock<8u> block;
    restir::evaluate_tile_block<8u, restir::ChannelNorm::euclidean>(tiles, i % 4u, 0u, receiver,
                                                                    block);
    restir::LightSample vpl;
    vpl.position = glm::vec3(0.0f, 1.0f, 0.0f);
    vpl.normal = glm::vec3(0.0f, -1.0f, 0.0f);
    vpl.radiance = glm::vec3(1.0f);
    vpl.area_pdf = 1.0f;
    vpl.is_delta = true;
    const restir::LightPointSample point =
        restir::make_light_point_sample(0u, vpl, partition.vpl_falloff());
    out[i] = block.target[0] + block.target[7] + restir::unshadowed_radiance(point, receiver).x +
             restir::partitioned_path_radiance(samples[i], receiver, partition).y;
}

// The environment light: a draw, the pdf and radiance of its direction, and the mapping both
// ways, one draw per thread (the view's arrays copied to device memory by the caller).
__global__ void environment_kernel(restir::EnvironmentMapView environment, float* out) {
    const auto i = static_cast<std::uint32_t>(blockIdx.x * blockDim.x + threadIdx.x);
    restir::Pcg32 rng = restir::make_pixel_rng(i, 0u, restir::RngStream::application);
    const float u0 = next_float(rng);
    const float u1 = next_float(rng);
    const restir::EnvironmentSample sample = environment.sample(glm::vec2(u0, u1));
    const glm::vec3 back = restir::equirect_direction(restir::equirect_uv(sample.direction));
    out[i] = sample.pdf + environment.pdf(sample.direction) + environment.radiance(back).y +
             sample.radiance.x;
}
