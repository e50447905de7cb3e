/// @file core/alias_buckets.hpp
/// Vose's O(n) construction of Walker's alias buckets (Vose 1991, "A linear algorithm for
/// generating random numbers with a given distribution"), host only: the one construction behind
/// `AliasTable` (sampling/alias_table.hpp) and the environment map's tables
/// (light/environment_map.hpp), which store the buckets in their own entries.
#pragma once

#include <cstddef>
#include <cstdint>
#include <span>
#include <vector>

namespace restir {

/// Working memory of `build_alias_buckets`, kept between calls that build many tables.
struct AliasScratch {
    std::vector<double> scaled;
    std::vector<std::uint32_t> small, large;
};

/// Buckets over `weights` (none negative or NaN; `total` their sum, > 0): bucket i keeps index i
/// with probability `threshold` and passes to `alias` otherwise, so that index i is drawn with
/// probability weights[i] / total. `store(i, threshold, alias)` receives each bucket once. Each
/// step fills an under-full bucket from an over-full one, in double; what is left is full up to
/// rounding and keeps its own index, except a weight of 0, which passes to a weighted index
/// (threshold 0): a weightless index is never drawn.
template <class Weight, class Store>
void build_alias_buckets(std::span<const Weight> weights, double total, AliasScratch& scratch,
                         Store&& store) {
    const std::size_t n = weights.size();
    std::vector<double>& scaled = scratch.scaled;
    std::vector<std::uint32_t>& small = scratch.small;
    std::vector<std::uint32_t>& large = scratch.large;
    scaled.resize(n);
    small.clear();
    large.clear();
    std::uint32_t weighted = 0u; // some index of positive weight
    for (std::size_t i = 0; i < n; ++i) {
        const auto weight = static_cast<double>(weights[i]);
        scaled[i] = weight * static_cast<double>(n) / total;
        (scaled[i] < 1.0 ? small : large).push_back(static_cast<std::uint32_t>(i));
        weighted = weight > 0.0 ? static_cast<std::uint32_t>(i) : weighted;
    }
    while (!small.empty() && !large.empty()) {
        const std::uint32_t under = small.back();
        small.pop_back();
        const std::uint32_t over = large.back();
        store(under, static_cast<float>(scaled[under]), over);
        scaled[over] -= 1.0 - scaled[under];
        if (scaled[over] < 1.0) {
            large.pop_back();
            small.push_back(over);
        }
    }
    for (const std::vector<std::uint32_t>* rest : {&small, &large})
        for (const std::uint32_t i : *rest) {
            if (weights[i] > Weight{0})
                store(i, 1.0f, i);
            else
                store(i, 0.0f, weighted);
        }
}

} // namespace restir
