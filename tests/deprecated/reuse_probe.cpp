// Uses every deprecated name of the reuse and sampling headers once; compiled with
// -Werror=deprecated-declarations it must fail with one error per name (deprecation.warns).
#include <restir/reuse/bias_correction.hpp>
#include <restir/reuse/di_frame.hpp>
#include <restir/reuse/di_frame_tiles.hpp>
#include <restir/reuse/neighbour_offsets.hpp>
#include <restir/reuse/spatial.hpp>
#include <restir/reuse/spatiotemporal.hpp>
#include <restir/reuse/temporal.hpp>
#include <restir/sampling/diffuse_direction.hpp>

#include "support/stub_bridge.hpp"

#include <vector>

restir::Reservoir<stub::Sample> probe_reuse(const restir::Reservoir<stub::Sample>& current,
                                            const stub::Surface& surface) {
    const restir::NeighborOffsets offsets = restir::make_neighbor_offsets();
    stub::Rng rng{static_cast<std::uint32_t>(offsets[restir::neighbor_offset_count - 1u].x) +
                  restir::DiStream::initial};
    const restir::ReuseBridge bridge{stub::Target{}, stub::Visibility{}};
    rng.state += static_cast<std::uint32_t>(
        restir::sample_emission_direction(glm::vec3(0.0f, 0.0f, 1.0f), 0.5f, 0.5f).z);
    return restir::spatiotemporal_resample(
        {0, 0}, current, surface, {&current, 1u, 1u}, {&surface, 1u, 1u}, stub::Reprojection{},
        restir::default_temporal_params(), restir::default_spatial_params(), offsets, bridge, rng);
}

std::uint32_t probe_reuse_inputs(const restir::Reservoir<stub::Sample>& current,
                                 const stub::Surface& surface) {
    const restir::NeighbourSearch search{3u, 30.0f};
    const restir::SingleReuseInput<stub::Sample, stub::Surface> single{{&current, &surface}};
    const restir::LoadedHistoryInput<stub::Sample, stub::Surface> history{current, &surface};
    return search.neighbour_count + single.size() + history.reservoir.candidate_count;
}

// A set of the application's that declares its cap and packing as members (0.2's form).
struct MemberTraitsSet {
    static constexpr bool packed = true;
    std::uint32_t candidate_cap = 4u;
    restir::ReuseInput<stub::Sample, stub::Surface> input{};
    std::uint32_t size() const { return 1u; }
    restir::ReuseInput<stub::Sample, stub::Surface> operator[](std::uint32_t) const {
        return input;
    }
};

bool probe_neighbour_members() {
    using Set = restir::SpatialNeighbours<stub::Sample, stub::Surface>;
    return Set::packed && Set::streamed;
}

restir::Reservoir<stub::Sample> probe_set_members(const restir::Reservoir<stub::Sample>& current,
                                                  const stub::Surface& surface) {
    stub::Rng rng{1u};
    const restir::ReuseBridge bridge{stub::Target{}, stub::Visibility{}};
    return restir::combine_inputs(current, surface, MemberTraitsSet{4u, {&current, &surface}},
                                  restir::ReuseParams{}, bridge, rng);
}

// The frame recipe's callbacks one by one, the forms before `DiBridge`.
void probe_frame(std::vector<restir::Reservoir<stub::Sample>>& out,
                 std::vector<restir::Reservoir<stub::Sample>>& scratch,
                 const std::vector<stub::Surface>& surfaces) {
    restir::DiFrame<stub::Sample, stub::Surface, stub::Reprojection> frame;
    frame.surfaces = {surfaces.data(), 1u, 1u};
    const restir::DiBuffers<stub::Sample> buffers{{out.data(), 1u, 1u}, {scratch.data(), 1u, 1u}};
    const auto initial = [](restir::PixelCoord, const stub::Surface&, stub::Rng&) {
        return restir::Reservoir<stub::Sample>{};
    };
    const auto rng_for = [](restir::PixelCoord, std::uint32_t) { return stub::Rng{}; };
    const auto each_pixel = [](const auto& body) { body(restir::PixelCoord{0, 0}); };
    const auto each_tile = [](const restir::DiStep&, const auto& body) {
        body(restir::PixelTile{{0, 0}, {1, 1}});
    };
    const restir::ReuseBridge pixels{stub::Target{}, stub::Visibility{}};
    const restir::ReuseBridge tiles{stub::Target{}, restir::OneByOne<stub::Visibility>{}};
    restir::run_di_frame(frame, buffers, each_pixel, initial, pixels, rng_for);
    restir::run_di_frame(frame, buffers.out, buffers.scratch, each_pixel, initial, pixels, rng_for);
    restir::run_di_frame(frame, buffers, each_tile, initial, tiles, rng_for);
    const restir::DiStep step = frame.step(0u);
    restir::run_di_step(frame, step, restir::PixelTile{{0, 0}, {1, 1}}, buffers, initial, tiles,
                        rng_for);
    frame.run_pixel(step, {0, 0}, buffers, initial, pixels, rng_for);
    frame.run_stage<restir::DiStage::initial>(step, {0, 0}, buffers, initial, pixels, rng_for);
    const restir::ReuseInput<stub::Sample, stub::Surface> lent{&out[0], &surfaces[0]};
    stub::Rng rng;
    out[0] = restir::combine_reservoirs(out[0], surfaces[0], &lent, 1u, restir::ReuseParams{},
                                        pixels, rng);
}
