#include "gbuffer.hpp"

#include "environment.hpp"

#include <glm/geometric.hpp>
#include <glm/vec2.hpp>

#include <algorithm>
#include <cmath>
#include <cstdint>

namespace pt {

namespace {

// [-1, 1] to 16 bits and back (rounded to nearest).
std::uint32_t to_snorm16(float v) {
    return static_cast<std::uint32_t>((std::clamp(v, -1.0f, 1.0f) * 0.5f + 0.5f) * 65535.0f + 0.5f);
}
float from_snorm16(std::uint32_t v) { return static_cast<float>(v) * (2.0f / 65535.0f) - 1.0f; }

// [0, 1] to `max` steps.
template <class T>
T to_unorm(float v, float max) {
    return static_cast<T>(std::clamp(v, 0.0f, 1.0f) * max + 0.5f);
}

// The octahedral map: the unit sphere onto the square [-1, 1]^2 (Cigolle et al. 2014).
std::uint32_t octahedral(glm::vec3 wo) {
    const glm::vec3 p = wo / (std::abs(wo.x) + std::abs(wo.y) + std::abs(wo.z));
    glm::vec2 e{p.x, p.y};
    if (p.z < 0.0f)
        e = {(1.0f - std::abs(p.y)) * (p.x >= 0.0f ? 1.0f : -1.0f),
             (1.0f - std::abs(p.x)) * (p.y >= 0.0f ? 1.0f : -1.0f)};
    return to_snorm16(e.x) | (to_snorm16(e.y) << 16u);
}

} // namespace

void set_view_and_material(GSurface& s, glm::vec3 wo, const Material& m, std::uint32_t index) {
    s.wo_octahedral = octahedral(wo);
    set_material(s, m, index);
}

void set_view(GSurface& s, glm::vec3 wo) { s.wo_octahedral = octahedral(wo); }

void set_material(GSurface& s, const Material& m, std::uint32_t index) {
    s.albedo = m.albedo;
    s.material = index;
    s.specular = to_unorm<std::uint16_t>(m.specular, 65535.0f);
    s.roughness = to_unorm<std::uint16_t>(m.roughness, 65535.0f);
    s.metallic = to_unorm<std::uint8_t>(m.metallic, 255.0f);
}

glm::vec3 view_direction(const GSurface& s) {
    const glm::vec2 e{from_snorm16(s.wo_octahedral & 0xffffu),
                      from_snorm16(s.wo_octahedral >> 16u)};
    glm::vec3 v{e.x, e.y, 1.0f - std::abs(e.x) - std::abs(e.y)};
    if (v.z < 0.0f)
        v = {(1.0f - std::abs(e.y)) * (e.x >= 0.0f ? 1.0f : -1.0f),
             (1.0f - std::abs(e.x)) * (e.y >= 0.0f ? 1.0f : -1.0f), v.z};
    return glm::normalize(v);
}

GSurface surface_at(const Scene& scene, const Hit& hit, glm::vec3 direction) {
    GSurface s;
    const std::uint32_t material = scene.material_of(hit.primitive);
    s.front = glm::dot(hit.normal, direction) < 0.0f;
    s.valid = true;
    s.position = hit.position;
    s.normal = s.front ? hit.normal : -hit.normal;
    set_view_and_material(s, -direction, scene.materials[material], material);
    s.depth = hit.distance;
    return s;
}

GSurface escaped_surface(glm::vec3 direction) {
    GSurface s;
    s.wo_octahedral = octahedral(-direction);
    return s;
}

glm::vec3 escaped_radiance(const Scene& scene, const GSurface& s) {
    return scene.environment ? scene.environment->radiance(-view_direction(s)) : glm::vec3(0.0f);
}

GBuffer::GBuffer(const Scene& scene, const EmbreeScene& rays, const PixelBlocks& blocks,
                 std::size_t pixels, float ray_offset, bool antialias, std::uint64_t seed)
    : scene_(&scene), rays_(&rays), blocks_(&blocks), ray_offset_(ray_offset),
      antialias_(antialias), seed_(seed), surfaces_(pixels), previous_(pixels) {}

void GBuffer::trace(const Camera& camera, std::uint32_t frame_index) {
    blocks_->for_each_block(
        [&](const PixelBlock& block) { trace_primary(block, camera, frame_index); });
}

void GBuffer::trace_shadows(std::span<const ShadowQuery> queries, std::span<bool> visible) const {
    std::array<glm::vec3, restir::max_tile_queries> from, to;
    std::array<std::uint8_t, restir::max_tile_queries> blocked;
    const std::size_t n = queries.size();
    const restir::LightPointVisibility<EmbreeScene> visibility = point_visibility();
    for (std::size_t i = 0; i < n; ++i) {
        const restir::ShadowSegment segment =
            visibility.segment(*queries[i].sample, *queries[i].surface);
        from[i] = segment.from;
        to[i] = segment.to;
    }
    rays_->occluded_segments(std::span(from.data(), n), std::span(to.data(), n),
                             std::span(blocked.data(), n));
    for (std::size_t i = 0; i < n; ++i)
        visible[i] = blocked[i] == 0u;
}

// A block's primary hits as one packet query.
void GBuffer::trace_primary(const PixelBlock& block, const Camera& camera,
                            std::uint32_t frame_index) {
    std::array<glm::vec3, pixels_per_block> directions;
    std::array<Hit, pixels_per_block> hits;
    std::size_t n = 0;
    blocks_->for_each_pixel_of(block, [&](std::uint32_t x, std::uint32_t y, std::uint32_t i) {
        float jx = 0.5f, jy = 0.5f;
        if (antialias_) {
            restir::Pcg32 rng =
                restir::make_pixel_rng(i, frame_index, RenderStream::pixel_jitter, seed_);
            jx = next_float(rng);
            jy = next_float(rng);
        }
        directions[n++] =
            camera.direction({static_cast<float>(x) + jx, static_cast<float>(y) + jy});
    });
    rays_->closest_hits(camera.position(), std::span(directions.data(), n),
                        std::span(hits.data(), n));
    n = 0;
    blocks_->for_each_pixel_of(block, [&](std::uint32_t, std::uint32_t, std::uint32_t i) {
        surfaces_[i] = hits[n].found ? surface_at(*scene_, hits[n], directions[n])
                                     : escaped_surface(directions[n]);
        ++n;
    });
}

} // namespace pt
