// The G-buffer: each pixel's primary hit as a surface, traced per pixel block as one packet,
// and the shadow rays from those surfaces, also traced per block as packets.
#pragma once

#include "buffer_allocator.hpp"
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

/// A G-buffer texel: the primary hit of a pixel (or a path's vertex), or where the pixel's ray
/// left the scene (`valid` false, `wo_octahedral` towards the camera). Satisfies
/// restir::Surface. 56 bytes: its material and view direction packed (`surface_bsdf`,
/// `view_direction`, `emitted`), since reuse reads this frame's and last frame's texels of every
/// neighbour (at 96 bytes, with the BSDF, the direction and the emission as floats, the diffuse
/// README render was 6-9 % slower).
struct GSurface {
    glm::vec3 position{0.0f};
    glm::vec3 normal{0.0f, 1.0f, 0.0f}; ///< Geometric normal, turned towards the viewer.
    /// The base colour: the albedo of a Lambertian surface, a metal's F0 (Material::albedo).
    glm::vec3 albedo{0.0f};
    float depth = 0.0f;
    std::uint32_t wo_octahedral = 0u; ///< Unit direction towards the viewer, octahedral 2 x 16 bit.
    std::uint32_t material = 0u;      ///< Index in Scene::materials (its emission, `emitted`).
    std::uint16_t specular = 0u;      ///< Material::specular (dielectric F0) in units of 1/65535.
    std::uint16_t roughness = 65535u; ///< Material::roughness in units of 1/65535.
    std::uint8_t metallic = 0u;       ///< Material::metallic in units of 1/255.
    bool front = true;                ///< The viewer sees the side the triangle's normal faces.
    bool valid = false;
};
static_assert(sizeof(GSurface) <= 56u, "as small as the diffuse texel was");
inline glm::vec3 surface_position(const GSurface& s) { return s.position; }
inline glm::vec3 surface_normal(const GSurface& s) { return s.normal; }
inline float surface_depth(const GSurface& s) { return s.depth; }
inline bool is_valid_surface(const GSurface& s) { return s.valid; }
/// True when the surface reflects as albedo / pi alone (no specular lobe).
inline bool is_lambertian(const GSurface& s) { return s.specular == 0u && s.metallic == 0u; }
/// The perceptual roughness that reuse decisions read (restir::reuse_roughness): the
/// material's, 1 for a Lambertian surface.
inline float surface_roughness(const GSurface& s) {
    return is_lambertian(s) ? 1.0f : static_cast<float>(s.roughness) * (1.0f / 65535.0f);
}
/// The surface's reflection (Material::bsdf, from the packed material); F0 = 0 for a
/// Lambertian surface.
inline restir::GlossyBsdf surface_bsdf(const GSurface& s) {
    return restir::GlossyBsdf::from_metallic_roughness(
        s.albedo, static_cast<float>(s.metallic) * (1.0f / 255.0f),
        static_cast<float>(s.roughness) * (1.0f / 65535.0f),
        static_cast<float>(s.specular) * (1.0f / 65535.0f));
}
/// Radiance the surface emits towards the viewer (an emitter's front side only).
inline glm::vec3 emitted(const Scene& scene, const GSurface& s) {
    return s.front ? scene.materials[s.material].emission : glm::vec3(0.0f);
}
/// The unit direction towards the viewer (Cigolle et al. 2014, octahedral encoding).
glm::vec3 view_direction(const GSurface& s);
/// The solid-angle density with which a path's bounce from `s` draws `wi`: by cosine on a
/// Lambertian surface, GlossyBsdf::sample's mixture on any other.
inline float bounce_pdf(const GSurface& s, glm::vec3 wi) {
    return is_lambertian(s) ? restir::diffuse_direction_pdf(s.normal, wi)
                            : surface_bsdf(s).pdf(s.normal, view_direction(s), wi);
}
/// Sets the direction towards the viewer and material `m`, Scene::materials[index], of `s`.
void set_view_and_material(GSurface& s, glm::vec3 wo, const Material& m, std::uint32_t index);
/// Each half of it: the direction towards the viewer, and the material.
void set_view(GSurface& s, glm::vec3 wo);
void set_material(GSurface& s, const Material& m, std::uint32_t index);

/// The surface that a ray travelling along `direction` (unit) found, seen from -direction;
/// emission only on an emitter's front side.
GSurface surface_at(const Scene& scene, const Hit& hit, glm::vec3 direction);
/// The texel of a ray travelling along `direction` (unit) that found no surface: not valid,
/// its view direction -direction, so that `escaped_radiance` can look up the sky it sees.
GSurface escaped_surface(glm::vec3 direction);
/// What the ray of an escaped texel (`s.valid` false) sees: the scene's environment towards
/// -view_direction(s) (as packed, within 2^-15 of the octahedral square), black without one.
glm::vec3 escaped_radiance(const Scene& scene, const GSurface& s);

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

    const PixelBuffer<GSurface>& surfaces() const { return surfaces_; }
    const PixelBuffer<GSurface>& previous_surfaces() const { return previous_; }
    const Scene& scene() const { return *scene_; }
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

private:
    void trace_primary(const PixelBlock& block, const Camera& camera, std::uint32_t frame_index);

    const Scene* scene_;
    const EmbreeScene* rays_;
    const PixelBlocks* blocks_;
    float ray_offset_;
    bool antialias_;
    std::uint64_t seed_;
    PixelBuffer<GSurface> surfaces_, previous_;
};

} // namespace pt
