#include "gbuffer.hpp"

#include <glm/geometric.hpp>

namespace pt {

GSurface surface_at(const Scene& scene, const Hit& hit, glm::vec3 direction) {
    GSurface s;
    const Material& m = scene.materials[scene.triangle_materials[hit.triangle]];
    const bool front = glm::dot(hit.normal, direction) < 0.0f;
    s.valid = true;
    s.position = hit.position;
    s.normal = front ? hit.normal : -hit.normal;
    s.wo = -direction;
    s.bsdf = m.bsdf();
    s.albedo = s.bsdf.diffuse_albedo;
    s.emitted = front ? m.emission : glm::vec3(0.0f);
    s.depth = hit.distance;
    return s;
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
        surfaces_[i] = hits[n].found ? surface_at(*scene_, hits[n], directions[n]) : GSurface{};
        ++n;
    });
}

} // namespace pt
