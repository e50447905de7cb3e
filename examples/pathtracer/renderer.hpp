// The example renderer: a G-buffer of primary hits, then direct (and VPL) lighting by one of
// the library's methods, optional path-traced indirect light, accumulated over frames.
#pragma once

#include "image_io.hpp"
#include "scene.hpp"

#include <restir/restir.hpp>

#include <cstdint>
#include <memory>
#include <vector>

namespace pt {

enum class Method {
    uniform,  ///< One light chosen uniformly per sample, estimate f / p.
    ris,      ///< Resampled importance sampling from `candidates` candidates.
    restir,   ///< RIS + temporal + spatial reuse.
    reference ///< Unbiased path tracer with next-event estimation and MIS.
};
enum class GlobalIllumination {
    none, ///< Direct light only.
    vpl,  ///< Direct light + VPLs (photons shot once), through one unified light set.
    path, ///< Direct light + path-traced indirect light.
    /// Direct light + ReSTIR GI: path samples reused with the reconnection shift (--method
    /// restir; the reference renders the same integral as `path`).
    restir_gi,
    /// Direct light + ReSTIR PT: whole paths reused with the hybrid shift (random replay, then
    /// reconnection; --method restir; the reference renders the same integral as `path`).
    restir_pt,
    /// Direct light + VPL GI without bias (restir::VplPartition): VPLs on Lambertian surfaces
    /// with the falloff 1 / max(d, r)^2 through the receivers' diffuse lobes, in ReSTIR DI's
    /// light set; path samples carry the rest (`vpl_path_part`; --method restir; the reference
    /// renders the same integral as `path`).
    vpl_unbiased
};
/// Whether `gi` shoots photons and puts VPLs in the light set (vpl, vpl-unbiased).
inline bool uses_vpls(GlobalIllumination gi) {
    return gi == GlobalIllumination::vpl || gi == GlobalIllumination::vpl_unbiased;
}
/// Whether `gi` adds path-traced indirect light (gi path, and the path samples that restir-gi
/// and restir-pt reuse, whose reference is the path tracer's).
inline bool traces_indirect_paths(GlobalIllumination gi) {
    return gi == GlobalIllumination::path || gi == GlobalIllumination::restir_gi ||
           gi == GlobalIllumination::restir_pt;
}
/// Whether `gi` reuses path samples in a ReSTIR frame of its own (restir-gi, restir-pt, and
/// the path part of vpl-unbiased unless independent path samples estimate it), so that it needs
/// --method restir (or reference).
inline bool reuses_paths(GlobalIllumination gi) {
    return gi == GlobalIllumination::restir_gi || gi == GlobalIllumination::restir_pt ||
           gi == GlobalIllumination::vpl_unbiased;
}
/// Where RIS candidates come from: lights in proportion to their power (from light tiles), or
/// uniformly (from light tiles), or by their importance at the pixel's surface (a light BVH,
/// drawn per pixel), or by their importance in the pixel's cell of a world-space grid (tiles
/// per cell resampled from power-proportional candidates every frame, ReGIR; `grid_cells`).
/// `automatic` is resolved per scene when the renderer is built (`resolved_candidates`).
enum class CandidateSource { power, uniform, bvh, grid, automatic };
/// How the point on an emitter of a RIS candidate is drawn: uniformly in its area, or uniformly
/// in the solid angle it subtends from the pixel's surface (restir::sample_triangle_from, a
/// light shape's own sampling; the light tiles keep area points and draw the chosen candidate's
/// point of a triangle again). `automatic` is resolved per scene when the renderer is built
/// (`resolved_light_points`).
enum class LightPoints { area, solid_angle, automatic };
/// How RIS candidates find the environment: as one light of the light set, its directions drawn
/// by the map's importance sampling (restir::EnvironmentMapView::sample), or only through
/// BSDF-sampled candidates (cosine-weighted at diffuse pixels), which is what importance
/// sampling is measured against.
enum class EnvironmentSampling { importance, bsdf };
/// How gi vpl-unbiased estimates the path part of the indirect light (restir::VplPartition):
/// path samples reused by ReSTIR GI's frame, or one independent path sample a pixel a frame.
enum class VplPathPart { reuse, independent };
/// A still camera, or one that turns about its look-at point a little every frame.
enum class CameraMotion { none, orbit };

/// Everything one render uses: the image, the method, and the library's parameters as the
/// library's own structs.
struct RenderSettings {
    std::uint32_t width = 640;
    std::uint32_t height = 480;
    std::uint32_t spp = 1; ///< Samples per pixel per frame (restir: 1).
    Method method = Method::restir;
    GlobalIllumination gi = GlobalIllumination::vpl;
    CandidateSource source = CandidateSource::automatic;
    LightPoints light_points = LightPoints::automatic;
    std::uint64_t seed = 0;
    CameraSetup camera{};
    CameraMotion motion = CameraMotion::none;
    std::uint32_t threads = 0; ///< 0: all hardware threads.
    bool antialias = false;    ///< Jitter primary rays in the pixel (off: pixel centres, so
                               ///< that error measurements see lighting noise only).
    /// RIS candidates per pixel (ris, restir); 0: the source's default (`resolved_candidates`).
    std::uint32_t candidates = 0;
    /// BSDF-sampled candidates per glossy pixel smoother than `bsdf_max_roughness` (ris,
    /// restir), combined by MIS with the `candidates` light candidates of `source`
    /// (bsdf_candidates.hpp); 0: light candidates alone.
    std::uint32_t bsdf_candidates = 1;
    /// BSDF candidates at glossy pixels whose roughness is below this: narrow lobes, which
    /// light candidates rarely hit (docs/noise-and-bias.md, "Narrow lobes"); 1: every glossy
    /// pixel.
    float bsdf_max_roughness = 0.1f;
    /// Light candidates beside the BSDF candidates at those pixels: at most this many of
    /// `candidates` (0: all of them). A narrow lobe's light comes mostly through its BSDF
    /// candidate (docs/noise-and-bias.md, "Narrow lobes").
    std::uint32_t bsdf_light_candidates = 4;
    /// The environment's share of the light candidates drawn by power, in (0, 1); 0 takes it in
    /// proportion to its power (restir::environment_power over the scene's bounding sphere).
    float environment_share = 0.0f;
    /// --env-sampling: importance (the default) or bsdf (BSDF candidates at every pixel, the
    /// environment out of the power table; needs bsdf_candidates > 0).
    EnvironmentSampling environment_sampling = EnvironmentSampling::importance;
    /// --source grid: cells along the longest side of the scene's box (the other sides in
    /// cells of about the same size). Finer cells give candidates closer to each pixel's
    /// lights, and cost more cells to fill every frame (docs/performance.md).
    std::uint32_t grid_cells = 32;
    /// Keep the temporal history packed (restir::PackedPointReservoir: 28 bytes a pixel
    /// instead of 64), its light points decoded from the light set when read: the same image,
    /// with less memory and a light lookup per pixel.
    bool packed_history = false;
    /// The ReSTIR frame (restir::DiFrame), as restir-render's defaults have it; the boiling
    /// filter runs when `di_frame.boiling_filter` is set (restir-render: --boiling-filter > 0).
    /// ReSTIR GI's frame (gi restir-gi) runs with the same settings.
    restir::DiFrameParams di_frame = default_di_frame_settings();
    /// The preset `di_frame` came from (--preset); where `di_frame.spatial.radius` is 0 the
    /// renderer takes two thirds of this preset's radius per 1080 rows (`frame_params`).
    restir::DiFramePreset preset = restir::DiFramePreset::unbiased;
    std::uint32_t vpls = 100'000; ///< About this many VPLs (gi vpl).
    /// The photons of a VPL set: `max_bounces` and `seed` (the first set's; later sets follow
    /// it) are settings; the renderer sets `photon_count` (from `vpls`) and `ray_offset`.
    restir::PhotonParams photons = default_photon_settings();
    /// A new, independent VPL set every this many frames (0: one set for the whole render), so
    /// that the accumulated image converges to the path-traced answer, not to one set's.
    std::uint32_t vpl_reshoot_interval = 0;
    float attenuation_radius = 0.0f; ///< Yuksel radius for VPLs; 0: 2 % of the scene's size.
    /// The radius of restir::VplPartition (gi vpl-unbiased) as a share of the scene's size:
    /// within it, and from surfaces without VPLs, path samples carry the light; beyond it VPLs
    /// (docs/vpl-unbiased.md measures the choice).
    float partition_radius = 0.05f;
    /// How gi vpl-unbiased estimates the path part (--vpl-path-part).
    VplPathPart vpl_path_part = VplPathPart::independent;
    std::uint32_t max_depth = 8; ///< Path length limit (reference, gi path, restir-gi, restir-pt).
    /// The shift of ReSTIR GI's samples (its `min_roughness`: which sample points reconnect).
    restir::ReconnectionShift reconnection{};
    /// Which vertices ReSTIR PT's paths reconnect at: `min_roughness` as is, `min_distance` as a
    /// fraction of the scene's size (the renderer scales it).
    restir::ReconnectionCriterion pt_reconnection{0.3f, 0.01f};
    /// Frames hold indirect light only (gi path and restir-gi, and the reference): no
    /// emission, no direct light, nothing where camera rays leave the scene. For measuring the
    /// indirect light's error alone; the time still includes the direct light's frame.
    bool indirect_only = false;
    /// The path tracer's next-event estimation of the environment, with MIS against BSDF
    /// sampling; false leaves the environment to BSDF-sampled rays alone (for tests: both
    /// estimate the same image).
    bool environment_nee = true;

    /// The library's frame recipe with restir-render's defaults: the unbiased preset
    /// (restir::DiFramePreset::unbiased: 5 neighbours, a history cap of 4 with permutation
    /// sampling, for the accumulated image as well as the frame: the paper's cap of 20 without
    /// permutation made consecutive frames so alike that averaging them gained little,
    /// docs/noise-and-bias.md) with a spatial radius of 0 (the renderer makes it two thirds of
    /// the preset's per 1080 rows, `frame_params`), and the boiling filter off with
    /// a threshold of 0 (it removes energy, so it is biased). The renderer runs it per 8 x 8
    /// tile, each stage's rays traced as Embree packets. `--preset` picks another preset.
    static restir::DiFrameParams default_di_frame_settings() {
        return di_frame_settings(restir::DiFramePreset::unbiased);
    }
    /// `preset`'s frame with the renderer's radius (0: by the image height) and no boiling.
    static restir::DiFrameParams di_frame_settings(restir::DiFramePreset preset) {
        restir::DiFrameParams p = restir::di_frame_preset(preset);
        p.spatial.radius = 0.0f;
        p.boiling.threshold = 0.0f;
        return p;
    }
    /// The library's photon settings with up to 8 bounces.
    static restir::PhotonParams default_photon_settings() {
        restir::PhotonParams p = restir::default_photon_params();
        p.max_bounces = 8;
        return p;
    }
};

/// Milliseconds per phase of one frame: `tiles` is the light-tile fill, `candidates` the
/// initial RIS and its visibility ray (ris: RIS and shading are both in `shading`), `indirect`
/// the whole ReSTIR GI or PT frame (gi restir-gi, restir-pt).
struct FrameTimings {
    double primary = 0, photons = 0, tiles = 0, candidates = 0, temporal = 0, spatial = 0,
           shading = 0, indirect = 0, total = 0;
};

/// The ReSTIR frame of `settings` (ReSTIR DI's and ReSTIR GI's) at its image's size: a spatial
/// radius of 0 made two thirds of `settings.preset`'s radius per 1080 rows (20 px for unbiased,
/// 10 for balanced and fast), at least 3.
restir::DiFrameParams frame_params(const RenderSettings& settings);

/// Peak memory a render with `settings` needs, in bytes, about: per pixel 384 bytes for ReSTIR
/// (G-buffers of two frames, three reservoir buffers, the images), 216 more with ReSTIR GI (its
/// three buffers of path reservoirs), and 192 for the other methods,
/// 48 more per pixel with a reference (the reference image and the error measures), 96 per
/// VPL asked for (224 with the light BVH of --source bvh or grid), for the grid at most 4 bytes
/// a cell, 128 bytes a pixel and 2 KB a cell looked up, 32 MB besides (measured peaks: 361 and 176
/// bytes per pixel at 2048 x 2048, 79 per VPL at 1M VPLs, 124 more per VPL with the BVH).
std::uint64_t estimated_memory_bytes(const RenderSettings& settings, bool with_reference);

/// Emitters from which `CandidateSource::automatic` takes candidates from the light
/// BVH: with fewer, from light tiles by power (docs/performance.md, "Equal time").
inline constexpr std::uint32_t bvh_source_emitters = 64;
/// Candidates per pixel when `candidates` is 0: from the light BVH, where each costs a descent
/// of the tree, and from tiles or the grid.
inline constexpr std::uint32_t default_bvh_candidates = 4;
inline constexpr std::uint32_t default_tile_candidates = 32;

/// `settings` with `source` and `candidates` resolved for a scene of `emitter_count` emitters:
/// `automatic` becomes `bvh` from `bvh_source_emitters` emitters on (many emitters, some close to
/// the surfaces they light: power-proportional candidates rarely find the close ones), `power`
/// below (a few emitters and the VPLs, whose falloff is clamped); candidates 0 becomes the source's
/// default.
RenderSettings resolved_candidates(RenderSettings settings, std::uint32_t emitter_count);

/// `settings` with `light_points` resolved for a scene with `shape_emitters` emissive light
/// shapes, before `resolved_candidates`: `automatic` becomes `solid_angle` for a scene with
/// some (a sphere's points uniform in area put half the candidates on its far side), unless
/// `packed_history` (which decodes points as area samples); `area` otherwise (triangles alone:
/// Arvo's map costs more than it saves but next to lights, docs/noise-and-bias.md). With light
/// shapes drawn from the pixel, an `automatic` source becomes `bvh`: light tiles keep a shape's
/// area points (SceneEmitters::redraw_pays_off), the BVH's candidates draw theirs from the
/// pixel (RMSE against the reference 2.2x lower at about equal time in cornell-spheres,
/// docs/renderer.md).
RenderSettings resolved_light_points(RenderSettings settings, std::uint32_t shape_emitters);

/// Renders frames of one scene with one setting. Throws SceneError for a scene without
/// emitters.
class Renderer {
public:
    Renderer(const Scene& scene, const RenderSettings& settings);
    ~Renderer();
    Renderer(const Renderer&) = delete;
    Renderer& operator=(const Renderer&) = delete;

    /// Renders the next frame into the accumulation; the first frame's timings include photon
    /// shooting.
    FrameTimings render_frame();

    /// Average of the frames rendered so far.
    const Image& accumulated() const;
    /// The last frame alone.
    const Image& last_frame() const;
    /// Frames rendered so far.
    std::uint32_t frames_rendered() const;
    /// VPLs of the last frame's set.
    std::size_t vpl_count() const { return vpls().size(); }
    /// Photons shot per VPL set (0 when the pilot pass left no VPL, or without VPLs).
    std::uint32_t photons_per_set() const;
    /// The VPL set of the last frame (a new one every `vpl_reshoot_interval` frames).
    const std::vector<restir::Vpl>& vpls() const;
    /// Pixels whose primary ray found a surface in the last frame (the pixels that sample
    /// lights; per-pixel costs in docs/performance.md are per such pixel).
    std::size_t surface_pixel_count() const;
    /// 1 for each pixel whose surface in the last frame is glossy (a specular lobe), else 0:
    /// the pixels of the CSV's glossy columns.
    std::vector<std::uint8_t> glossy_pixels() const;
    /// Emitters of the scene: emissive triangles (degenerate ones emit nothing and are left out)
    /// and emissive light shapes.
    std::uint32_t emitter_count() const;
    /// The settings the renderer runs with: those it was given, `resolved_candidates` and
    /// `resolved_light_points`.
    const RenderSettings& settings() const;

private:
    struct Impl;
    std::unique_ptr<Impl> impl_;
};

} // namespace pt
