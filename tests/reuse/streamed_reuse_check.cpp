// Runs the frame recipe per pixel and the standalone spatial pass over a small synthetic image,
// in every bias correction, and prints one hash of every reservoir they produce. Built twice
// (tests/CMakeLists.txt): as host code gathers reuse inputs, and with RESTIR_STREAMED_REUSE=1,
// as a GPU thread streams them. The test `reuse.streamed_equals_gathered` compares the two
// outputs: the device's form of the algorithm, run on this host, must give the host's
// reservoirs bit for bit.
#include <restir/reuse/di_frame.hpp>
#include <restir/reuse/spatial.hpp>
#include <restir/sampling/ris.hpp>

#include "support/stub_bridge.hpp"

#include <cstdint>
#include <cstdio>
#include <cstring>
#include <vector>

namespace {

constexpr std::uint32_t size = 24u;
constexpr std::uint32_t light_count = 16u;

// Some samples hidden from some surfaces, so that visibility enters the weights.
struct PartialVisibility {
    bool operator()(const stub::Sample& s, const stub::Surface& x) const {
        return (s.id * 7u + static_cast<std::uint32_t>(x.height * 10.0f)) % 5u != 0u;
    }
};

stub::Rng rng_at(restir::PixelCoord p, std::uint32_t stream, std::uint32_t frame) {
    return stub::Rng{(static_cast<std::uint32_t>(p.x) * 73856093u) ^
                     (static_cast<std::uint32_t>(p.y) * 19349663u) ^ (stream * 83492791u) ^
                     (frame * 2654435761u) ^ 1u};
}

struct Hash {
    std::uint64_t value = 1469598103934665603ull; // FNV-1a
    void add(const void* data, std::size_t bytes) {
        const auto* p = static_cast<const unsigned char*>(data);
        for (std::size_t i = 0; i < bytes; ++i)
            value = (value ^ p[i]) * 1099511628211ull;
    }
    void add(const restir::Reservoir<stub::Sample>& r) {
        add(&r.sample.id, sizeof r.sample.id);
        add(&r.weight_sum, sizeof r.weight_sum);
        add(&r.target_value, sizeof r.target_value);
        add(&r.contribution_weight, sizeof r.contribution_weight);
        add(&r.candidate_count, sizeof r.candidate_count);
    }
};

std::vector<stub::Surface> make_surfaces() {
    std::vector<stub::Surface> surfaces(size * size);
    for (std::uint32_t i = 0; i < size * size; ++i)
        surfaces[i].height = static_cast<float>((i * 2654435761u) % 23u) * 0.1f;
    return surfaces;
}

restir::Reservoir<stub::Sample> initial(restir::PixelCoord, const stub::Surface& s,
                                        stub::Rng& rng) {
    return restir::resample_ris(
        rng, 8u,
        [](stub::Rng& g) {
            const auto id = static_cast<std::uint32_t>(next_float(g) * light_count);
            return restir::SourceSample<stub::Sample>{{id < light_count ? id : 0u},
                                                      1.0f / light_count};
        },
        stub::Target{}, s);
}

// Four frames of the recipe per pixel, with `mode` in both passes and two spatial passes.
std::uint64_t frames_hash(restir::BiasCorrection mode) {
    const std::vector<stub::Surface> surfaces = make_surfaces();
    std::vector<restir::Reservoir<stub::Sample>> history(size * size), out(size * size),
        scratch(size * size);
    restir::DiFrame<stub::Sample, stub::Surface, stub::Reprojection> frame{
        .surfaces = {surfaces.data(), size, size},
        .previous_surfaces = {surfaces.data(), size, size}};
    frame.params.temporal_bias_correction = mode;
    frame.params.spatial_bias_correction = mode;
    frame.params.spatial_passes = 2u;
    frame.params.spatial.neighbour_count = 5u;
    frame.params.spatial.radius = 3.0f;
    const restir::ReuseBridge bridge{stub::Target{}, PartialVisibility{}};
    const auto for_each_pixel = [](const auto& body) {
        for (std::uint32_t i = 0; i < size * size; ++i)
            body(restir::PixelCoord{static_cast<std::int32_t>(i % size),
                                    static_cast<std::int32_t>(i / size)});
    };
    Hash hash;
    for (std::uint32_t f = 0; f < 4u; ++f) {
        frame.frame_index = f;
        frame.history =
            f > 0u ? restir::ImageView<const restir::Reservoir<stub::Sample>>{history.data(), size,
                                                                              size}
                   : restir::ImageView<const restir::Reservoir<stub::Sample>>{};
        const restir::DiBuffers<stub::Sample> buffers{{out.data(), size, size},
                                                      {scratch.data(), size, size}};
        const auto rng_for = [&](restir::PixelCoord p, std::uint32_t stream) {
            return rng_at(p, stream, f);
        };
        restir::run_di_frame(frame, buffers, restir::DiBridge{initial, bridge, rng_for},
                             for_each_pixel);
        for (const auto& r : out)
            hash.add(r);
        std::swap(history, out);
    }
    return hash.value;
}

// The standalone spatial pass over the last frame's reservoirs of `frames_hash`'s kind.
std::uint64_t spatial_hash(restir::BiasCorrection mode) {
    const std::vector<stub::Surface> surfaces = make_surfaces();
    std::vector<restir::Reservoir<stub::Sample>> reservoirs(size * size);
    for (std::uint32_t i = 0; i < size * size; ++i) {
        const restir::PixelCoord p{static_cast<std::int32_t>(i % size),
                                   static_cast<std::int32_t>(i / size)};
        stub::Rng rng = rng_at(p, 9u, 0u);
        reservoirs[i] = initial(p, surfaces[i], rng);
    }
    restir::SpatialParams spatial;
    spatial.neighbour_count = 5u;
    spatial.radius = 3.0f;
    restir::ReuseParams reuse;
    reuse.bias_correction = mode;
    const restir::ReuseBridge bridge{stub::Target{}, PartialVisibility{}};
    Hash hash;
    for (std::uint32_t i = 0; i < size * size; ++i) {
        const restir::PixelCoord p{static_cast<std::int32_t>(i % size),
                                   static_cast<std::int32_t>(i / size)};
        stub::Rng rng = rng_at(p, 10u, 0u);
        hash.add(restir::spatial_resample(
            p,
            restir::ImageView<const restir::Reservoir<stub::Sample>>{reservoirs.data(), size, size},
            restir::ImageView<const stub::Surface>{surfaces.data(), size, size}, spatial, reuse,
            bridge, rng));
    }
    return hash.value;
}

} // namespace

int main() {
    const restir::BiasCorrection modes[] = {
        restir::BiasCorrection::none, restir::BiasCorrection::one_over_z,
        restir::BiasCorrection::balance_heuristic, restir::BiasCorrection::pairwise,
        restir::BiasCorrection::defensive_pairwise};
    for (const restir::BiasCorrection mode : modes)
        std::printf("mode %d: frames %016llx spatial %016llx\n", static_cast<int>(mode),
                    static_cast<unsigned long long>(frames_hash(mode)),
                    static_cast<unsigned long long>(spatial_hash(mode)));
    return 0;
}
