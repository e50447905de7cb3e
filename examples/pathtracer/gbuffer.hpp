// The G-buffer: each pixel's primary hit as a surface, traced per pixel block as one packet,
// and the shadow rays from those surfaces, also traced per block as packets.
#pragma once

#include "camera.hpp"
#include "embree_scene.hpp"
#include "pixel_blocks.hpp"
#include "scene.hpp"

#include <restir/bsdf/glossy_bsdf.hpp>
#include <restir/restir.hpp>

#include <array>
#include <cstdint>
#include <span>
#include <utility>
#include <vector>

namespace pt {

/// A G-buffer texel: the primary hit of a pixel (or a path's vertex). Satisfies
/// restir::Surface.
struct GSurface {
    glm::vec3 position{0.0f};
    glm::vec3 normal{0.0f, 1.0f, 0.0f}; ///< Geometric normal, turned towards the viewer.
    glm::vec3 wo{0.0f, 1.0f, 0.0f};     ///< Unit direction towards the viewer (-ray direction).
    /// The diffuse albedo (bsdf.diffuse_albedo: the base colour of a dielectric, 0 for a metal),
    /// which VPLs and the photons' bounces use.
    glm::vec3 albedo{0.0f};
    glm::vec3 emitted{0.0f}; ///< Radiance the surface emits towards the viewer.
    /// The surface's reflection (Material::bsdf); specular_f0 == 0 is Lambertian, albedo / pi.
    restir::GlossyBsdf bsdf{glm::vec3(0.0f), glm::vec3(0.0f), 1.0f};
    float depth = 0.0f;
    bool valid = false;
};
inline glm::vec3 surface_position(const GSurface& s) { return s.position; }
inline glm::vec3 surface_normal(const GSurface& s) { return s.normal; }
inline float surface_depth(const GSurface& s) { return s.depth; }
inline bool is_valid_surface(const GSurface& s) { return s.valid; }
/// True when the surface reflects as albedo / pi alone (no specular lobe).
inline bool is_lambertian(const GSurface& s) { return s.bsdf.specular_f0 == glm::vec3(0.0f); }
/// Perceptual roughness, 1 for a Lambertian surface (restir::SimilarRoughness reads it).
inline float surface_roughness(const GSurface& s) {
    return is_lambertian(s) ? 1.0f : s.bsdf.roughness;
}

/// The surface that a ray travelling along `direction` (unit) found, seen from -direction;
/// emission only on an emitter's front side.
GSurface surface_at(const Scene& scene, const Hit& hit, glm::vec3 direction);

/// This frame's and last frame's surfaces, and the packet rays from them.
class GBuffer {
public:
    /// `ray_offset`: how far shadow rays start off the surface; `antialias` jitters primary
    /// rays inside the pixel (with `seed`).
    GBuffer(const Scene& scene, const EmbreeScene& rays, const PixelBlocks& blocks,
            std::size_t pixels, float ray_offset, bool antialias, std::uint64_t seed);

    /// This frame's surfaces become last frame's (the previous ones are overwritten next).
    void keep_as_previous() { std::swap(surfaces_, previous_); }
    /// Primary hits of every pixel seen by `camera` (centres, or random points with
    /// antialiasing, drawn for `frame_index`), one packet per pixel block.
    void trace(const Camera& camera, std::uint32_t frame_index);

    const std::vector<GSurface>& surfaces() const { return surfaces_; }
    const std::vector<GSurface>& previous_surfaces() const { return previous_; }
    const EmbreeScene& rays() const { return *rays_; }
    float ray_offset() const { return ray_offset_; }
    /// Shadow rays towards light points, off the surfaces by `ray_offset`.
    restir::LightPointVisibility<EmbreeScene> point_visibility() const {
        return {rays_, ray_offset_};
    }

    /// A shadow-ray question: is a light point visible from a surface (the frame recipe's form).
    using ShadowQuery = restir::VisibilityQuery<restir::LightPointSample, GSurface>;
    /// Answers `queries` as Embree packets (at most restir::max_tile_queries of them):
    /// `visible[i]` for `queries[i]`, each segment off its surface by `ray_offset`.
    void trace_shadows(std::span<const ShadowQuery> queries, std::span<bool> visible) const;
    /// The G-buffer's shadow rays as the recipe's `BatchVisibility`.
    struct ShadowPackets {
        const GBuffer* gbuffer = nullptr;
        void trace(std::span<const ShadowQuery> queries, std::span<bool> visible) const {
            gbuffer->trace_shadows(queries, visible);
        }
    };
    ShadowPackets shadow_packets() const { return {this}; }

    /// Visibility reuse for a block: every pixel's reservoir (`reservoir(i)`) whose sample is
    /// occluded from its surface gets W = 0, the shadow rays traced as one packet query;
    /// pixels for which `needs_test(i)` is false (their sample is known to be visible) are
    /// skipped.
    template <class ReservoirAt, class NeedsTest>
    void test_visibility(const PixelBlock& block, ReservoirAt&& reservoir,
                         NeedsTest&& needs_test) const {
        std::array<ShadowQuery, pixels_per_block> queries;
        std::array<std::uint32_t, pixels_per_block> pixel;
        std::array<bool, pixels_per_block> visible;
        std::size_t n = 0;
        blocks_->for_each_pixel_of(block, [&](std::uint32_t, std::uint32_t, std::uint32_t i) {
            const auto& res = reservoir(i);
            if (!surfaces_[i].valid || !res.has_sample() || !needs_test(i))
                return;
            queries[n] = {&res.sample, &surfaces_[i]};
            pixel[n++] = i;
        });
        trace_shadows(std::span(queries.data(), n), std::span(visible.data(), n));
        for (std::size_t k = 0; k < n; ++k)
            restir::apply_visibility(reservoir(pixel[k]), visible[k]);
    }
    /// test_visibility for every pixel of the block.
    template <class ReservoirAt>
    void test_visibility(const PixelBlock& block, ReservoirAt&& reservoir) const {
        test_visibility(block, reservoir, [](std::uint32_t) { return true; });
    }

private:
    void trace_primary(const PixelBlock& block, const Camera& camera, std::uint32_t frame_index);

    const Scene* scene_;
    const EmbreeScene* rays_;
    const PixelBlocks* blocks_;
    float ray_offset_;
    bool antialias_;
    std::uint64_t seed_;
    std::vector<GSurface> surfaces_, previous_;
};

} // namespace pt
