// Uses every deprecated name of the reuse and sampling headers once; compiled with
// -Werror=deprecated-declarations it must fail with one error per name (deprecation.warns).
#include <restir/reuse/di_frame.hpp>
#include <restir/reuse/neighbour_offsets.hpp>
#include <restir/reuse/spatial.hpp>
#include <restir/reuse/spatiotemporal.hpp>
#include <restir/reuse/temporal.hpp>
#include <restir/sampling/diffuse_direction.hpp>

#include "support/stub_bridge.hpp"

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
