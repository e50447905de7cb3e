#include "candidate_sources.hpp"

#include <tbb/blocked_range.h>
#include <tbb/parallel_for.h>

#include <algorithm>
#include <bit>
#include <optional>
#include <vector>

namespace pt {

namespace {

constexpr std::uint32_t group_size = 8; // candidates per batch-RIS candidate group

// The candidate groups a pixel takes from the `size` entries from tile `tile` on: from a random
// start with a random odd stride, so that every candidate is a uniformly random entry (its
// density is the entry's pdf) and no group repeats within a pixel while there are enough of
// them. They may span consecutive tiles (the grid's tiles of more than one group of a tile
// array).
struct TileWalk {
    std::uint32_t base; // tile * tile_size
    std::uint32_t group_mask;
    std::uint32_t start;
    std::uint32_t stride;

    TileWalk(const restir::LightTileArrays& from, std::uint32_t tile, std::uint32_t size,
             restir::Pcg32& rng)
        : base(tile * from.tile_size), group_mask(size / group_size - 1u), start(rng.next_uint()),
          stride(rng.next_uint() | 1u) {}

    // The global index of group g's first entry.
    std::uint32_t first_entry(std::uint32_t g) const {
        return base + ((start + g * stride) & group_mask) * group_size;
    }
};

// Batch RIS over the `size` entries from tile `tile` of `from` on (Alg. 3 of Bitterli et al.
// 2020, in candidate groups of 8 consecutive entries: sampling/ris_batch.hpp).
Reservoir tile_reservoir(const restir::LightTileArrays& from, std::uint32_t tile,
                         std::uint32_t size, std::uint32_t candidates, const GSurface& s,
                         restir::Pcg32& rng) {
    const TileWalk walk(from, tile, size, rng);
    const auto picked = with_receiver(s, [&](const auto& receiver) {
        return restir::resample_ris_batch<group_size>(
            rng, candidates, [&](std::uint32_t g, restir::CandidateBlock<group_size>& group) {
                const std::uint32_t first = walk.first_entry(g);
                return restir::evaluate_tile_block<group_size, target_norm>(
                    from, first / from.tile_size, first % from.tile_size, receiver, group);
            });
    });
    return picked.with_sample(from.point_sample(picked.sample));
}

// `chosen` (RIS over a light tile at surface `s`) with its emitter point drawn again, uniform in
// the solid angle the emitter subtends from `s` (--light-points solid-angle), where that pays
// off (SceneEmitters::redraw_pays_off: triangles only). Unbiased by the argument of
// restir::redraw_point_from_receiver, for each emitter either kept or redrawn by a rule of the
// emitter and the surface alone (never of the tile's point): the tiles' target is positive
// exactly on the part of a one-sided emitter triangle above the surface's tangent plane, so the
// coverage that divides W is that part's share of its area (1 where the rule redraws). Redrawing
// everywhere doubled the error in the Cornell box: at a grazing part of an emitter the area
// point's target is small, and W, which divides by it, no longer cancels against the new
// point's contribution (docs/noise-and-bias.md). VPLs and the environment keep their point.
Reservoir with_point_from_surface(const Reservoir& chosen, const LightSet& lights,
                                  const GSurface& s, restir::Pcg32& rng) {
    if (!chosen.has_sample())
        return chosen;
    const float u = next_float(rng); // named: the order of the draws is fixed
    const float v = next_float(rng);
    const std::uint32_t id = chosen.sample.light_id;
    if (id >= lights.emitters().light_count() ||
        !lights.emitters().redraw_pays_off(id, s.position, s.normal))
        return chosen;
    const float coverage = lights.emitters().area_fraction_above(id, s.position, s.normal);
    return restir::redraw_point_from_receiver(
        chosen, coverage, lights.lights(), glm::vec2(u, v), s.position, lights.falloff(),
        [&](const restir::LightPointSample& x) { return point_target(x, s); });
}

// Presampled light tiles (power, uniform), refilled for every frame (and sample), in the
// structure-of-arrays layout of batch RIS: candidates come from one tile per 8 x 8 pixel
// block, which stays in cache. (Tiles of 256 lights for 16 x 16 pixel blocks were 15 % faster
// but left visible block patterns: a block sees too few lights.) Pixels take whole runs of 8
// entries, so two pixels of a block share 8 candidates at a time when their runs meet: 128
// tiles of 2048 lights (256 runs each) keep that as rare as single shared entries were with
// random entries of 1024-light tiles (256 tiles of 1024 gave ReSTIR 9 % more error after 20
// frames).
class TileCandidates final : public InitialCandidates {
public:
    TileCandidates(const RenderSettings& settings, const LightSet& lights,
                   const PixelBlocks& blocks)
        : settings_(settings), lights_(lights), blocks_(blocks),
          by_power_(settings.source == CandidateSource::power) {}

    void prepare_frame(std::uint32_t frame_index, std::span<const GSurface>) override {
        planes_.resize(std::size_t{tile_count} * tile_size * restir::tile_plane_count);
        references_.resize(std::size_t{tile_count} * tile_size);
        tiles_ = {planes_.data(), references_.data(), tile_count, tile_size};
        const restir::PowerLightSampler power{lights_.power_table().view()};
        const restir::UniformLightSampler uniform{lights_.lights().light_count()};
        const std::uint64_t seed = settings_.seed;
        blocks_.arena().execute([&] {
            tbb::parallel_for(
                tbb::blocked_range<std::uint32_t>(0u, tile_count * tile_size, 256u),
                [&](const tbb::blocked_range<std::uint32_t>& range) {
                    const std::uint32_t first = range.begin();
                    const auto rng_of = [&](std::uint32_t k) {
                        return restir::make_pixel_rng(first + k, frame_index,
                                                      RenderStream::light_tiles, seed);
                    };
                    const auto store = [&](std::uint32_t k, const restir::PresampledLight& e) {
                        const std::uint32_t i = first + k;
                        tiles_.store(i / tile_size, i % tile_size, e, lights_.falloff());
                    };
                    const std::uint32_t count = range.end() - first;
                    if (by_power_)
                        restir::presample_lights(power, lights_.lights(), count, rng_of, store);
                    else
                        restir::presample_lights(uniform, lights_.lights(), count, rng_of, store);
                });
        });
    }

    // RIS over the tile of the pixel's block.
    Reservoir initial_reservoir(std::uint32_t x, std::uint32_t y, std::uint32_t frame_index,
                                const GSurface& s, restir::Pcg32& rng) const override {
        const Reservoir chosen =
            tile_reservoir(tiles_, tiles_.tile_for(blocks_.block_of(x, y), frame_index), tile_size,
                           settings_.candidates, s, rng);
        return settings_.light_points == LightPoints::solid_angle
                   ? with_point_from_surface(chosen, lights_, s, rng)
                   : chosen;
    }

    // The tile's entries beside BSDF candidates, each weighed against the other's density:
    // the tiles' (power or uniform, points uniform in area) where a BSDF ray hits an emitter.
    std::optional<Reservoir> with_bsdf_candidates(std::uint32_t x, std::uint32_t y,
                                                  std::uint32_t frame_index,
                                                  const restir::CandidateCounts& counts,
                                                  const restir::GlossyReceiver& receiver,
                                                  const EmitterHits& hits,
                                                  restir::Pcg32& rng) const override {
        if (settings_.light_points == LightPoints::solid_angle)
            return std::nullopt;
        const TileWalk walk(tiles_, tiles_.tile_for(blocks_.block_of(x, y), frame_index), tile_size,
                            rng);
        const auto first_entry = [&](std::uint32_t g) { return walk.first_entry(g); };
        const auto resample = [&](const auto& source) {
            return restir::resample_tiles_and_bsdf<group_size, target_norm>(
                rng, counts, tiles_, first_entry, source, lights_.falloff(), receiver, hits);
        };
        if (by_power_)
            return resample(restir::PowerLightSampler{lights_.power_table().view()});
        return resample(restir::UniformLightSampler{lights_.lights().light_count()});
    }

protected:
    const restir::LightTileArrays& block_tiles() const override { return tiles_; }

private:
    static constexpr std::uint32_t tile_count = light_tile_count;
    static constexpr std::uint32_t tile_size = 2048; // a power of two

    const RenderSettings& settings_;
    const LightSet& lights_;
    const PixelBlocks& blocks_;
    const bool by_power_;
    std::vector<float> planes_;
    std::vector<restir::LightSampleRef> references_;
    restir::LightTileArrays tiles_;
};

// Candidates drawn from a light BVH over the local lights for the pixel's surface (the source
// pdf: the light's pmf there), the environment beside it with its share of the power table
// (restir::WithDistantLights).
class BvhCandidates final : public InitialCandidates {
public:
    BvhCandidates(const RenderSettings& settings, const LightSet& lights)
        : settings_(settings), lights_(lights) {
        build();
    }

    void use_light_set() override { build(); }
    void prepare_frame(std::uint32_t, std::span<const GSurface>) override {}
    Reservoir initial_reservoir(std::uint32_t, std::uint32_t, std::uint32_t, const GSurface& s,
                                restir::Pcg32& rng) const override {
        return bvh_reservoir(s, rng);
    }
    // The BVH's draws beside BSDF candidates, weighed by the BVH's pmf at the surface.
    std::optional<Reservoir> with_bsdf_candidates(std::uint32_t, std::uint32_t, std::uint32_t,
                                                  const restir::CandidateCounts& counts,
                                                  const restir::GlossyReceiver& receiver,
                                                  const EmitterHits& hits,
                                                  restir::Pcg32& rng) const override;

private:
    void build() {
        const std::vector<restir::LightBounds> bounds = lights_.light_bounds();
        light_bvh_.reset();
        if (!bounds.empty())
            light_bvh_.emplace(bounds);
    }
    Reservoir bvh_reservoir(const GSurface& s, restir::Pcg32& rng) const;

    const RenderSettings& settings_;
    const LightSet& lights_;
    std::optional<restir::LightBvh> light_bvh_; // by importance
};

// Streaming RIS, four draws at a time while four or more remain: their descents advance side by
// side (light/light_bvh_view.hpp), so that their memory waits overlap.
Reservoir BvhCandidates::bvh_reservoir(const GSurface& s, restir::Pcg32& rng) const {
    constexpr std::uint32_t batch = 4;
    const restir::LightBvhView bvh = light_bvh_ ? light_bvh_->view() : restir::LightBvhView{};
    const restir::DistantLights<> distant = lights_.distant_lights();
    const auto sampler =
        restir::with_distant_lights(bvh, distant.first, distant.count(), distant.probability);
    const restir::ShadingPoint at{s.position, s.normal};
    const std::uint32_t candidates = settings_.candidates;
    restir::DiscreteSample drawn[batch];
    std::uint32_t taken = 0, ready = 0; // candidates taken, and drawn ahead in `drawn`
    return restir::resample_ris(
        rng, candidates,
        [&](restir::Pcg32& g) {
            if (ready == 0u && candidates - taken >= batch && distant.count() == 0u) {
                float u0[batch], u1[batch];
                for (std::uint32_t k = 0; k < batch; ++k) {
                    u0[k] = next_float(g);
                    u1[k] = next_float(g);
                }
                bvh.sample(at, u0, u1, drawn);
                ready = batch;
            }
            const restir::DiscreteSample choice =
                ready > 0u ? drawn[batch - ready--] : restir::sample_light(sampler, at, g);
            ++taken;
            if (settings_.light_points == LightPoints::solid_angle)
                return restir::with_receiver_point(choice, lights_.lights(), s.position,
                                                   lights_.falloff(), g);
            const restir::SourceSample<restir::LightSampleRef> c =
                restir::with_uniform_point(choice, g);
            restir::SourceSample<restir::LightPointSample> candidate{{}, c.pdf};
            if (c.pdf > 0.0f)
                candidate.sample = restir::make_light_point_sample(
                    c.sample.light_id,
                    lights_.lights().sample_point(c.sample.light_id, c.sample.uv),
                    lights_.falloff());
            return candidate;
        },
        [&](const restir::LightPointSample& x) { return point_target(x, s); });
}

std::optional<Reservoir> BvhCandidates::with_bsdf_candidates(
    std::uint32_t, std::uint32_t, std::uint32_t, const restir::CandidateCounts& counts,
    const restir::GlossyReceiver& receiver, const EmitterHits& hits, restir::Pcg32& rng) const {
    const restir::LightBvhView bvh = light_bvh_ ? light_bvh_->view() : restir::LightBvhView{};
    const restir::DistantLights<> distant = lights_.distant_lights();
    return resample_lights_and_bsdf(
        restir::with_distant_lights(bvh, distant.first, distant.count(), distant.probability),
        settings_.light_points, counts, lights_, receiver, hits, rng);
}

// ReGIR (--source grid): the scene's box in about cubic cells, `settings.grid_cells` along its
// longest side (sampling/light_grid.hpp). Every frame each pixel looks its cell up with a
// jitter of up to half a cell along each axis, and each cell looked up gets a tile of lights
// resampled for every point whose lookup can land in it (`restir::resample_grid_tile`), so that
// a candidate from it can be any light that reaches the pixel. A tile has as many entries as
// the pixels that use it, between 32 and 128: most cells looked up hold a few pixels, and fewer
// entries there gave more error (docs/performance.md, with what else was tried).
class GridCandidates final : public InitialCandidates {
public:
    GridCandidates(const RenderSettings& settings, const Scene& scene, const LightSet& lights,
                   const PixelBlocks& blocks)
        : settings_(settings), scene_(scene), lights_(lights), blocks_(blocks) {
        build();
    }

    void use_light_set() override { build(); }
    void prepare_frame(std::uint32_t frame_index, std::span<const GSurface> surfaces) override;
    // RIS over the tile of the pixel's cell.
    Reservoir initial_reservoir(std::uint32_t x, std::uint32_t y, std::uint32_t, const GSurface& s,
                                restir::Pcg32& rng) const override {
        const std::uint32_t tile = pixel_tiles_[x + y * settings_.width];
        return tile_reservoir(grid_tiles_, grid_starts_[tile], tile_entries_[tile],
                              settings_.candidates, s, rng);
    }

private:
    static constexpr std::uint32_t grid_tile_size = 128;      // entries at most, a power of two
    static constexpr std::uint32_t grid_tile_minimum = 32;    // entries at least, a power of two:
                                                              // the tiles of `grid_tiles_`, which a
                                                              // cell's entries fill one or more of
    static constexpr std::uint32_t grid_fill_candidates = 32; // per entry

    // Each light's own bounds, for the tiles' resampling.
    void build();
    void fill_tiles(std::uint32_t frame_index, std::uint32_t tiles_used);
    void look_up_cells(std::uint32_t frame_index, std::span<const GSurface> surfaces);

    const RenderSettings& settings_;
    const Scene& scene_;
    const LightSet& lights_;
    const PixelBlocks& blocks_;
    std::vector<restir::LightBvhNode> light_nodes_; // each light's bounds
    std::vector<float> grid_planes_;
    std::vector<restir::LightSampleRef> grid_references_;
    restir::LightTileArrays grid_tiles_;
    restir::LightGridLayout grid_; // laid out by the first frame: the scene does not change
    std::vector<std::uint32_t> cell_tiles_;   // per cell: its tile this frame, or none
    std::vector<std::uint32_t> used_cells_;   // per cell looked up this frame (a "tile"): the cell
    std::vector<std::uint32_t> tile_entries_; // per tile: its entries
    std::vector<std::uint32_t> grid_starts_;  // per tile: its first tile of `grid_tiles_`
    std::vector<std::uint32_t> pixel_tiles_;  // per pixel: its tile this frame
};

// Indexed by the light set's ids: the environment's is a placeholder, never read (the tiles
// keep it beside the grid).
void GridCandidates::build() {
    const std::vector<restir::LightBounds> bounds = lights_.light_bounds();
    const restir::DistantLights<> distant = lights_.distant_lights();
    light_nodes_.clear();
    light_nodes_.reserve(bounds.size() + distant.count());
    for (std::uint32_t i = 0; i < bounds.size(); ++i) {
        if (i == distant.first)
            light_nodes_.insert(light_nodes_.end(), distant.count(), restir::LightBvhNode{});
        light_nodes_.push_back(restir::light_bvh_node(bounds[i]));
    }
    if (light_nodes_.size() < bounds.size() + distant.count())
        light_nodes_.insert(light_nodes_.end(), distant.count(), restir::LightBvhNode{});
}

void GridCandidates::prepare_frame(std::uint32_t frame_index, std::span<const GSurface> surfaces) {
    if (cell_tiles_.empty()) {
        const SceneBounds box = bounds_of(scene_);
        grid_ = restir::LightGridLayout::over(box.lower, box.upper, settings_.grid_cells);
        cell_tiles_.assign(grid_.cell_count(), ~0u);
    }
    look_up_cells(frame_index, surfaces);
    const auto tiles_used = static_cast<std::uint32_t>(used_cells_.size());
    grid_starts_.resize(tiles_used);
    std::uint32_t stored = 0; // tiles of `grid_tiles_`, of grid_tile_minimum entries
    for (std::uint32_t t = 0; t < tiles_used; ++t) {
        tile_entries_[t] =
            std::clamp(std::bit_ceil(tile_entries_[t]), grid_tile_minimum, grid_tile_size);
        grid_starts_[t] = stored;
        stored += tile_entries_[t] / grid_tile_minimum;
    }
    grid_planes_.resize(std::size_t{stored} * grid_tile_minimum * restir::tile_plane_count);
    grid_references_.resize(std::size_t{stored} * grid_tile_minimum);
    grid_tiles_ = {grid_planes_.data(), grid_references_.data(), stored, grid_tile_minimum};
    fill_tiles(frame_index, tiles_used);
}

// The tiles of the cells looked up, resampled in parallel.
void GridCandidates::fill_tiles(std::uint32_t frame_index, std::uint32_t tiles_used) {
    const restir::PowerLightSampler local{lights_.local_power_table().view()};
    const restir::DistantLights<> distant = lights_.distant_lights();
    const auto node_of = [this](std::uint32_t id) -> const restir::LightBvhNode& {
        return light_nodes_[id];
    };
    blocks_.arena().execute([&] {
        tbb::parallel_for(
            tbb::blocked_range<std::uint32_t>(0u, tiles_used, 1u),
            [&](const tbb::blocked_range<std::uint32_t>& range) {
                std::vector<restir::GridCandidate> candidates(grid_tile_size *
                                                              grid_fill_candidates);
                for (std::uint32_t t = range.begin(); t < range.end(); ++t) {
                    const std::uint32_t cell = used_cells_[t];
                    restir::Pcg32 rng = restir::make_pixel_rng(
                        cell, frame_index, RenderStream::light_tiles, settings_.seed);
                    restir::resample_grid_tile_with_distant(
                        local, distant, grid_.cell_region(cell), node_of, lights_.lights(), rng,
                        tile_entries_[t], grid_fill_candidates, candidates.data(),
                        [&](std::uint32_t j, const restir::PresampledLight& entry) {
                            grid_tiles_.store(grid_starts_[t] + j / grid_tile_minimum,
                                              j % grid_tile_minimum, entry, lights_.falloff());
                        });
                }
            });
    });
}

// Each pixel's cell this frame, looked up with a jitter (in parallel); then, in pixel order,
// the cells looked up become the frame's tiles, each counting its pixels in `tile_entries_`
// for now.
void GridCandidates::look_up_cells(std::uint32_t frame_index, std::span<const GSurface> surfaces) {
    for (const std::uint32_t cell : used_cells_)
        cell_tiles_[cell] = ~0u;
    used_cells_.clear();
    tile_entries_.clear();
    // `pixel_tiles_` holds each pixel's cell until the pass in pixel order below replaces it
    // with the cell's tile.
    constexpr std::uint32_t no_cell = ~0u; // a pixel without a surface
    pixel_tiles_.resize(surfaces.size());
    blocks_.arena().execute([&] {
        tbb::parallel_for(
            tbb::blocked_range<std::uint32_t>(0u, static_cast<std::uint32_t>(surfaces.size())),
            [&](const tbb::blocked_range<std::uint32_t>& range) {
                for (std::uint32_t i = range.begin(); i < range.end(); ++i) {
                    restir::Pcg32 rng = restir::make_pixel_rng(
                        i, frame_index, RenderStream::grid_jitter, settings_.seed);
                    const float u = next_float(rng), v = next_float(rng), w = next_float(rng);
                    pixel_tiles_[i] = surfaces[i].valid
                                          ? grid_.jittered_cell_of(surfaces[i].position, {u, v, w})
                                          : no_cell;
                }
            });
    });
    for (std::uint32_t& tile : pixel_tiles_) {
        const std::uint32_t cell = tile;
        if (cell == no_cell) {
            tile = 0u;
            continue;
        }
        if (cell_tiles_[cell] == ~0u) {
            cell_tiles_[cell] = static_cast<std::uint32_t>(used_cells_.size());
            used_cells_.push_back(cell);
            tile_entries_.push_back(0u);
        }
        tile = cell_tiles_[cell];
        ++tile_entries_[tile];
    }
}

} // namespace

const restir::LightTileArrays& InitialCandidates::block_tiles() const {
    static const restir::LightTileArrays none{};
    return none;
}

std::optional<Reservoir> InitialCandidates::with_bsdf_candidates(
    std::uint32_t, std::uint32_t, std::uint32_t, const restir::CandidateCounts&,
    const restir::GlossyReceiver&, const EmitterHits&, restir::Pcg32&) const {
    return std::nullopt;
}

std::unique_ptr<InitialCandidates> make_initial_candidates(const RenderSettings& settings,
                                                           const Scene& scene,
                                                           const LightSet& lights,
                                                           const PixelBlocks& blocks) {
    switch (settings.source) {
    case CandidateSource::bvh:
        return std::make_unique<BvhCandidates>(settings, lights);
    case CandidateSource::grid:
        return std::make_unique<GridCandidates>(settings, scene, lights, blocks);
    case CandidateSource::power:
    case CandidateSource::uniform:
    case CandidateSource::automatic: // resolved by the renderer (resolved_candidates)
        break;
    }
    return std::make_unique<TileCandidates>(settings, lights, blocks);
}

} // namespace pt
