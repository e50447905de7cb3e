// The example renderer's ReSTIR DI frame as the library's frame recipe (restir::DiFrame) with
// this benchmark's collaborators (initial candidates, generators, shading), run unchanged per
// pixel in a CUDA kernel and in a CPU loop (benchmarks/cuda/di_pipeline.cu): the reservoirs,
// reprojection, target function, the context a pass reads and writes, the passes that are not
// the recipe's (G-buffer, light tiles) and the timing table's rows. The light tiles, target
// function and recipe settings are restir-render's; the scenes and cameras are
// analytic_scene.hpp.
#pragma once

#include "analytic_scene.hpp"

#include <restir/restir.hpp>

#include <glm/geometric.hpp>
#include <glm/vec2.hpp>
#include <glm/vec3.hpp>

#include <algorithm>
#include <cstddef>
#include <cstdint>

namespace box {

// --- The frame ------------------------------------------------------------------------------

using Reservoir = restir::Reservoir<restir::LightPointSample>;
using Packed = restir::PackedPointReservoir;

/// Reprojection through last frame's camera (restir::Reprojection), restir-render's.
using CameraReprojection = common::CameraReprojection<Texel>;

/// A stored light point back as its sample (exact here: flat emitters of one radiance, VPLs).
using LightPointDecoder = restir::LightSetDecoder<Lights>;

/// This frame's G-buffer as the recipe reads it: a texel whole, in two 16-byte loads through
/// the read-only cache on a GPU (a `SurfaceDecoder`). Reuse gathers neighbours at random, so
/// each load of a warp touches 32 cache lines: one load of 16 bytes costs the L1 what one of 4
/// bytes does, and field by field a texel took eight.
struct LoadedTexels {
    restir::ImageView<const Texel> texels{};
    RESTIR_HOST_DEVICE bool contains(restir::PixelCoord p) const { return texels.contains(p); }
    RESTIR_HOST_DEVICE Texel surface(restir::PixelCoord p) const {
        const Texel* t = &texels[p];
#if defined(__CUDA_ARCH__)
        const float4 a = __ldg(reinterpret_cast<const float4*>(t));
        const float4 b = __ldg(reinterpret_cast<const float4*>(t) + 1);
        Texel r;
        r.position = {a.x, a.y, a.z};
        r.normal = {a.w, b.x, b.y};
        r.depth = b.z;
        r.material = __float_as_uint(b.w);
        return r;
#else
        return *t;
#endif
    }
};
static_assert(sizeof(Texel) == 32u && alignof(Texel) == 16u && offsetof(Texel, normal) == 12u &&
              offsetof(Texel, depth) == 24u && offsetof(Texel, material) == 28u);

using PlainFrame =
    restir::DiFrame<restir::LightPointSample, Texel, CameraReprojection,
                    restir::ImageView<const restir::Reservoir<restir::LightPointSample>>,
                    LoadedTexels>;
using PackedFrame = restir::DiFrame<restir::LightPointSample, Texel, CameraReprojection,
                                    restir::PackedPointHistory<LightPointDecoder>, LoadedTexels>;

/// p-hat: the Euclidean norm of the unshadowed reflected radiance's channels (restir-render's).
inline constexpr restir::ChannelNorm target_norm = restir::ChannelNorm::euclidean;
struct Target {
    RESTIR_HOST_DEVICE float operator()(const restir::LightPointSample& x, const Texel& s) const {
        return restir::fold_channels<target_norm>(
            albedo_of(s.material) * restir::inv_pi *
            restir::unshadowed_irradiance(x, s.position, s.normal));
    }
};

inline constexpr std::uint32_t tile_count = 128u; // restir-render's light tiles
inline constexpr std::uint32_t tile_size = 2048u; // a power of two
inline constexpr std::uint32_t tile_stream = restir::RngStream::application;
inline constexpr std::uint32_t shared_groups_stream = restir::RngStream::application + 1u;

/// Everything a pass reads and writes, as pointers (device pointers for a kernel, host
/// pointers for the CPU); passed by value.
struct Context {
    std::uint32_t width = 0u, height = 0u;
    std::uint32_t frame = 0u;
    bool has_history = false; // whether last frame's reservoirs apply
    bool packed = false;      // history as `Packed` (28 B) instead of `Reservoir` (64 B)
    std::uint32_t candidates = 32u;
    std::uint64_t seed = 1u;
    restir::DiFrameParams params{};
    View view{};
    Camera camera, previous_camera;
    const Scene* scene = nullptr;     // the G-buffer's and the photons' rays
    const Scene* occluders = nullptr; // the shadow rays': `scene`, or an empty one
    Lights lights{};
    restir::AliasTableView power{};
    restir::Falloff falloff{};
    float ray_offset = 0.1f;
    restir::LightTileArrays tiles{};
    std::uint32_t tile_group = 16u; // pixels per side of the square groups that share a tile
    std::uint32_t lanes = 4u;       // tile entries a pixel takes of each group of 8 that it reads
    bool bvh_source = false;        // candidates drawn per pixel from the light BVH, not the tiles
    restir::LightBvhView bvh{};     // over `lights`
    Texel* surfaces = nullptr;      // this frame's G-buffer
    Texel* previous_surfaces = nullptr; // last frame's
    Reservoir* out = nullptr;           // the recipe's `DiBuffers::out`: the final reservoirs
    Reservoir* scratch = nullptr;       // the other side of its ping-pong
    Reservoir* history = nullptr;       // last frame's final reservoirs (plain layout)
    Packed* packed_history = nullptr;   // the same, packed (written by shading)
    glm::vec3* image = nullptr;
    std::uint8_t* visible = nullptr; // the shadow-ray row's answers

    RESTIR_HOST_DEVICE restir::PixelCoord pixel(std::uint32_t x, std::uint32_t y) const {
        return {static_cast<std::int32_t>(x), static_cast<std::int32_t>(y)};
    }
    /// The light tile of the pixels in group (gx, gy) (`tile_group` pixels per side).
    RESTIR_HOST_DEVICE std::uint32_t tile_of_group(std::uint32_t gx, std::uint32_t gy) const {
        const std::uint32_t columns = (width + tile_group - 1u) / tile_group;
        return tiles.tile_for(gx + gy * columns, frame);
    }
    RESTIR_HOST_DEVICE std::uint32_t index(restir::PixelCoord p) const {
        return static_cast<std::uint32_t>(p.x) + static_cast<std::uint32_t>(p.y) * width;
    }
    RESTIR_HOST_DEVICE restir::ReuseBridge<Target, restir::LightPointVisibility<Scene>>
    bridge() const {
        return {Target{}, {occluders, ray_offset}};
    }
    RESTIR_HOST_DEVICE restir::DiBuffers<restir::LightPointSample> buffers() const {
        return {{out, width, height}, {scratch, width, height}};
    }
    /// This frame's recipe in the layout `Frame` (`PlainFrame`, `PackedFrame`): a few hundred
    /// bytes (the offset table is the library's, by pointer), built on the host once per
    /// step and passed to the kernel by value.
    template <class Frame>
    Frame recipe() const {
        Frame f{.params = params,
                .frame_index = frame,
                .surfaces = {surfaces, width, height},
                .reproject = {previous_camera, {surfaces, width, height}}};
        if (has_history) {
            f.previous_surfaces = {previous_surfaces, width, height};
            if constexpr (Frame::loads_history)
                f.history = {{packed_history, width, height}, {lights, falloff}};
            else
                f.history = {history, width, height};
        }
        return f;
    }
};

/// The recipe's settings for this benchmark: the library's defaults (pairwise MIS, visibility
/// reuse, history cap 20 without permutation sampling) with 5 neighbours in one spatial pass of
/// `radius` px per 1080 rows, at least 3 (restir-render's radius is 20). Not restir-render's
/// unbiased preset, whose history cap of 4 with permutation sampling it leaves out. `mis_rays`
/// traces the MIS weights' shadow rays (`ReuseVisibility::traced`); without it the reuse passes are
/// ray-free (`assumed`, RTXDI's default), so that only the initial and finish stages trace rays.
inline restir::DiFrameParams recipe_params(std::uint32_t height, float radius, bool mis_rays) {
    restir::DiFrameParams p = restir::default_di_frame_params();
    p.spatial.neighbour_count = 5u;
    p.spatial.radius = std::max(3.0f, radius * static_cast<float>(height) / 1080.0f);
    p.visibility = mis_rays ? restir::ReuseVisibility::traced : restir::ReuseVisibility::assumed;
    return p;
}

// The passes that are not the recipe's, at one item (a pixel (x, y); for the tiles, entry x of
// row 0).

RESTIR_HOST_DEVICE inline void gbuffer_pixel(const Context& c, std::uint32_t x, std::uint32_t y) {
    const glm::vec3 d =
        c.camera.direction({static_cast<float>(x) + 0.5f, static_cast<float>(y) + 0.5f});
    c.surfaces[x + y * c.width] = c.scene->closest_hit(c.camera.position, d);
}

RESTIR_HOST_DEVICE inline void tile_entry(const Context& c, std::uint32_t i, std::uint32_t) {
    restir::Pcg32 rng = restir::make_pixel_rng(i, c.frame, tile_stream, c.seed);
    const restir::PowerLightSampler power{c.power};
    c.tiles.store(i / c.tiles.tile_size, i % c.tiles.tile_size,
                  restir::presample_light(power, c.lights, rng), c.falloff);
}

// The recipe's collaborators, each reading the context it was made from.

// Streaming RIS over candidates drawn from the light BVH for the surface (restir-render's
// bvh_reservoir; the source pdf is the light's pmf there).
RESTIR_HOST_DEVICE inline Reservoir bvh_candidates(const Context& c, const Texel& s,
                                                   restir::Pcg32& rng) {
    const restir::ShadingPoint at{s.position, s.normal};
    return restir::resample_ris(
        rng, c.candidates,
        [&](restir::Pcg32& g) {
            const restir::SourceSample<restir::LightSampleRef> x =
                restir::draw_light_candidate(c.bvh, at, g);
            restir::SourceSample<restir::LightPointSample> candidate{{}, x.pdf};
            if (x.pdf > 0.0f)
                candidate.sample = restir::make_light_point_sample(
                    x.sample.light_id, c.lights.sample_point(x.sample.light_id, x.sample.uv),
                    c.falloff);
            return candidate;
        },
        [&](const restir::LightPointSample& x) { return Target{}(x, s); });
}

/// Batch RIS over the pixel block's light tile, `Lanes` entries of each group of the tile that
/// the pixel reads (`restir::tile_group_size` = 8: restir-render's blocks of 8 consecutive
/// entries). With fewer, 8 / Lanes pixels (a pair along x for 4 lanes, 2 x 2 pixels for 2) read
/// the same groups, each its own lanes of them: a warp's loads touch 8 / Lanes times fewer
/// cache lines, and the pixels' candidates are still different entries. The tile's entries are
/// independent draws of one density, so a pixel's candidates are distributed as with 8.
template <std::uint32_t Lanes>
RESTIR_HOST_DEVICE Reservoir tile_candidates(const Context& c, std::uint32_t x, std::uint32_t y,
                                             const Texel& s, restir::Pcg32& rng) {
    constexpr std::uint32_t sharing = restir::tile_group_size / Lanes; // pixels per group
    const std::uint32_t tile = c.tile_of_group(x / c.tile_group, y / c.tile_group);
    const std::uint32_t group_mask = c.tiles.tile_size / restir::tile_group_size - 1u;
    // The groups' positions in the tile: the pixel's own, or those of its pixel group (and the
    // pixel's part of each group).
    std::uint32_t start = 0u, stride = 0u, rank = 0u;
    if constexpr (sharing == 1u) {
        start = rng.next_uint();
        stride = rng.next_uint() | 1u;
    } else {
        const std::uint32_t columns = (c.width + 1u) / 2u;
        restir::Pcg32 pixels = restir::make_pixel_rng(
            x / 2u + (sharing == 2u ? y : y / 2u) * columns, c.frame, shared_groups_stream, c.seed);
        start = pixels.next_uint();
        stride = pixels.next_uint() | 1u;
        rank = sharing == 2u ? x % 2u : x % 2u + 2u * (y % 2u);
    }
    const glm::vec3 channel_weights = albedo_of(s.material) * restir::inv_pi;
    const auto picked = restir::resample_ris_batch<Lanes>(
        rng, c.candidates, [&](std::uint32_t b, restir::CandidateBlock<Lanes>& block) {
            const std::uint32_t first =
                ((start + b * stride) & group_mask) * restir::tile_group_size + rank * Lanes;
            return restir::evaluate_tile_block<Lanes, target_norm>(
                c.tiles, tile, first, s.position, s.normal, channel_weights, block);
        });
    return picked.with_sample(c.tiles.point_sample(picked.sample));
}

/// The initial stage's candidates (restir-render's tile_reservoir): batch RIS over the pixel
/// block's light tile (`tile_candidates<Lanes>`; `Context::lanes` chooses the kernel), or
/// streaming RIS from the light BVH (`bvh_source`).
template <std::uint32_t Lanes>
struct InitialCandidates {
    const Context& c;
    RESTIR_HOST_DEVICE Reservoir operator()(restir::PixelCoord pixel, const Texel& s,
                                            restir::Pcg32& rng) const {
        if (c.bvh_source)
            return bvh_candidates(c, s, rng);
        return tile_candidates<Lanes>(c, static_cast<std::uint32_t>(pixel.x),
                                      static_cast<std::uint32_t>(pixel.y), s, rng);
    }
};

/// A pixel's generator for a stream (`RngStream`): the same numbers on both sides.
struct PixelRngs {
    const Context& c;
    RESTIR_HOST_DEVICE restir::Pcg32 operator()(restir::PixelCoord p, std::uint32_t stream) const {
        return restir::make_pixel_rng(c.index(p), c.frame, stream, c.seed);
    }
};

/// The finish stage's shading: emission plus f(y) W where the sample is visible (under
/// visibility reuse the stage has set W = 0 where it is occluded); the final reservoir packed
/// as the next frame's history in the packed layout (the plain one keeps `out`).
struct Shading {
    const Context& c;
    RESTIR_HOST_DEVICE void operator()(restir::PixelCoord p, const Reservoir& r,
                                       bool visible) const {
        const std::uint32_t i = c.index(p);
        const Texel& s = c.surfaces[i];
        glm::vec3 color(0.0f);
        if (is_valid_surface(s)) {
            color = emission_of(s.material);
            if (visible && r.contribution_weight > 0.0f)
                color += albedo_of(s.material) * restir::inv_pi *
                         restir::unshadowed_irradiance(r.sample, s.position, s.normal) *
                         r.contribution_weight;
        }
        c.image[i] = color;
        if (c.packed)
            c.packed_history[i] = restir::pack_reservoir(r);
    }
};

/// The frame's bridge: our collaborators, the candidates drawn `Lanes` at a time.
template <std::uint32_t Lanes>
RESTIR_HOST_DEVICE auto frame_bridge(const Context& c) {
    return restir::DiBridge{InitialCandidates<Lanes>{c}, c.bridge(), PixelRngs{c}, Shading{c}};
}

/// Step `step` of `frame` (stage `Stage`) at pixel (x, y): the recipe's code, nothing of ours
/// but the collaborators.
template <restir::DiStage Stage, std::uint32_t Lanes, class Frame>
RESTIR_HOST_DEVICE void run_step(const Frame& frame, const restir::DiStep& step, const Context& c,
                                 std::uint32_t x, std::uint32_t y) {
    frame.template run_stage<Stage>(step, c.pixel(x, y), c.buffers(), frame_bridge<Lanes>(c));
}

/// The rows of the timing table: the passes that are not the recipe's, then one per stage of
/// the recipe (`DiStage`, in its order; several spatial passes add up in one row).
/// The visibility rays have no rows of their own: the initial stage traces each initial
/// sample's ray and the finish stage the final one, under ray-free reuse (`assumed`, the
/// default) as under traced MIS (`--mis-rays`, `traced`), where the temporal and spatial
/// stages also trace their MIS rays and retest the samples they bring in.
enum class Pass : std::uint32_t {
    gbuffer,
    tiles,
    initial,
    temporal,
    spatial,
    boiling,
    finish,
    shadow_rays, // after the frame: what one shadow ray per pixel costs alone
    count
};
inline constexpr std::uint32_t pass_count = static_cast<std::uint32_t>(Pass::count);
inline constexpr Pass row_of(restir::DiStage stage) {
    return static_cast<Pass>(static_cast<std::uint32_t>(Pass::initial) +
                             static_cast<std::uint32_t>(stage));
}
static_assert(row_of(restir::DiStage::finish) == Pass::finish);
inline const char* pass_name(Pass p) {
    constexpr const char* names[] = {"G-buffer (analytic rays)",
                                     "light tiles",
                                     "initial (candidates, visibility)",
                                     "temporal reuse",
                                     "spatial reuse",
                                     "boiling filter",
                                     "finish (visibility, shading)",
                                     "one shadow ray a pixel (analytic)"};
    return names[static_cast<std::uint32_t>(p)];
}
/// Whether the pass traces rays of the analytic scene only (its cost is not the library's).
inline bool is_ray_pass(Pass p) { return p == Pass::gbuffer || p == Pass::shadow_rays; }

/// The shadow ray of pixel (x, y) to its final sample, alone: the cost of each of the two
/// visibility tests inside the initial and finish rows, which the library does not set.
RESTIR_HOST_DEVICE inline void shadow_ray_pixel(const Context& c, std::uint32_t x,
                                                std::uint32_t y) {
    const std::uint32_t i = x + y * c.width;
    const Texel& s = c.surfaces[i];
    const Reservoir& r = c.out[i];
    c.visible[i] = is_valid_surface(s) && r.has_sample() && c.bridge().visibility(r.sample, s);
}

/// Pass `P` (G-buffer, tiles or the shadow rays) at item (x, y).
template <Pass P>
RESTIR_HOST_DEVICE void run_item(const Context& c, std::uint32_t x, std::uint32_t y) {
    static_assert(P == Pass::gbuffer || P == Pass::tiles || P == Pass::shadow_rays);
    if constexpr (P == Pass::gbuffer)
        gbuffer_pixel(c, x, y);
    else if constexpr (P == Pass::tiles)
        tile_entry(c, x, y);
    else
        shadow_ray_pixel(c, x, y);
}

} // namespace box
