/// @file reuse/neighbour_offsets.hpp
/// A fixed low-discrepancy set of points in the unit disk, from which spatial reuse picks its
/// neighbours: a random starting index per pixel, then consecutive entries, scaled by the
/// radius. Consecutive points of the R2 sequence (Roberts 2018) cover the disk evenly, so any k
/// consecutive ones are well spread, and the table is built at compile time.
#pragma once

#include "restir/config.hpp"

#include <cstdint>

namespace restir {

/// A point of the unit disk.
struct DiskOffset {
    float x = 0.0f;
    float y = 0.0f;
};

/// How many offsets the table holds (a power of two, so wrapping is a mask).
inline constexpr std::uint32_t neighbour_offset_count = 64u;

/// The offset table; trivially copyable, 512 bytes. Passes and the frame recipe take it by
/// reference (`default_neighbour_offsets()` unless you bring your own), so that no kernel copies
/// it to local memory.
struct NeighbourOffsets {
    DiskOffset offsets[neighbour_offset_count];

    /// Entry `i` modulo the table size.
    RESTIR_HOST_DEVICE constexpr DiskOffset operator[](std::uint32_t i) const noexcept {
        return offsets[i & (neighbour_offset_count - 1u)];
    }
};

/// The R2 sequence x_n = frac(0.5 + n / g, 0.5 + n / g^2), g the plastic number, mapped to
/// [-1, 1]^2; points outside the unit disk are skipped.
RESTIR_HOST_DEVICE constexpr NeighbourOffsets make_neighbour_offsets() noexcept {
    constexpr double plastic = 1.32471795724474602596;
    constexpr double a1 = 1.0 / plastic;
    constexpr double a2 = 1.0 / (plastic * plastic);
    NeighbourOffsets table{};
    std::uint32_t filled = 0u;
    for (std::uint32_t n = 1u; filled < neighbour_offset_count; ++n) {
        double u = 0.5 + a1 * n;
        double v = 0.5 + a2 * n;
        u -= static_cast<double>(static_cast<std::uint64_t>(u));
        v -= static_cast<double>(static_cast<std::uint64_t>(v));
        const double x = 2.0 * u - 1.0;
        const double y = 2.0 * v - 1.0;
        if (x * x + y * y <= 1.0)
            table.offsets[filled++] = {static_cast<float>(x), static_cast<float>(y)};
    }
    return table;
}

namespace detail {
#if defined(__CUDACC__)
// One copy per translation unit in constant memory, initialised at compile time.
static __constant__ NeighbourOffsets device_neighbour_offsets = make_neighbour_offsets();
#endif
inline constexpr NeighbourOffsets host_neighbour_offsets = make_neighbour_offsets();
} // namespace detail

/// The library's offset table: in static storage on the host, in constant memory on a GPU
/// (compiled by nvcc), so that taking it costs no stack.
RESTIR_HOST_DEVICE inline const NeighbourOffsets& default_neighbour_offsets() noexcept {
#if defined(__CUDA_ARCH__)
    return detail::device_neighbour_offsets;
#else
    return detail::host_neighbour_offsets;
#endif
}

// --- Names before 0.2, kept until at least 0.3 (spelt "neighbour" throughout since) ---------

/// Renamed `NeighbourOffsets`.
using NeighborOffsets [[deprecated("use restir::NeighbourOffsets")]] = NeighbourOffsets;
/// Renamed `neighbour_offset_count`.
[[deprecated(
    "use restir::neighbour_offset_count")]] inline constexpr std::uint32_t neighbor_offset_count =
    neighbour_offset_count;
/// Renamed `make_neighbour_offsets`.
[[deprecated("use restir::make_neighbour_offsets")]] RESTIR_HOST_DEVICE constexpr NeighbourOffsets
make_neighbor_offsets() noexcept {
    return make_neighbour_offsets();
}

} // namespace restir
