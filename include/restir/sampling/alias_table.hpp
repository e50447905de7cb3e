/// @file sampling/alias_table.hpp
/// Walker's alias method with Vose's O(n) construction: O(1) sampling of an index with
/// probability proportional to a weight (Vose 1991, "A linear algorithm for generating
/// random numbers with a given distribution").
#pragma once

#include "restir/config.hpp"
#include "restir/core/discrete_sample.hpp"
#include "restir/core/math.hpp"

#include <cstddef>
#include <cstdint>
#include <limits>
#include <span>
#include <stdexcept>
#include <string>
#include <type_traits>
#include <vector>

namespace restir {

/// One bucket of the table: keep the bucket's own index when the second uniform number is
/// below `threshold`, otherwise take `alias`. `pmf` makes the probability lookup O(1);
/// `alias_pmf` repeats the alias's pmf so that a draw reads one 16-byte entry, a single
/// cache line, which matters once the table no longer fits in cache.
struct AliasEntry {
    float threshold = 1.0f;
    std::uint32_t alias = 0u;
    float pmf = 0.0f;
    float alias_pmf = 0.0f;
};

static_assert(std::is_trivially_copyable_v<AliasEntry>);
static_assert(sizeof(AliasEntry) == 16);

/// `keep ? a : b` without a branch: in a draw, which side wins is random, so a branch would
/// mispredict.
RESTIR_HOST_DEVICE constexpr std::uint32_t select_bits(bool keep, std::uint32_t a,
                                                       std::uint32_t b) noexcept {
    return b ^ ((a ^ b) & (0u - static_cast<std::uint32_t>(keep)));
}

/// Non-owning, device-callable view of an alias table (for instance a copy of
/// `AliasTable::entries()` uploaded to GPU memory).
struct AliasTableView {
    const AliasEntry* entries = nullptr;
    std::uint32_t size = 0u;

    /// Draws an index from two uniform numbers in [0, 1): their 48 bits pick a bucket
    /// uniformly and what is left of them decides between the bucket and its alias
    /// (`wide_uniform_index`), so every index's probability matches `pmf` to a relative
    /// size / 2^48 in the bucket and the precision of a float threshold in the choice,
    /// however many entries there are. Branch-free.
    RESTIR_HOST_DEVICE constexpr DiscreteSample sample(float u0, float u1) const noexcept {
        if (size == 0u)
            return {};
        RESTIR_ASSERT(entries != nullptr);
        const WideIndex bucket = wide_uniform_index(u0, u1, size);
        const AliasEntry entry = entries[bucket.index];
        // Exact in float on both sides; a threshold of 1 always keeps the bucket.
        const bool keep = static_cast<float>(bucket.fraction) < entry.threshold * 16777216.0f;
        return {select_bits(keep, bucket.index, entry.alias),
                __builtin_bit_cast(
                    float, select_bits(keep, __builtin_bit_cast(std::uint32_t, entry.pmf),
                                       __builtin_bit_cast(std::uint32_t, entry.alias_pmf)))};
    }

    /// Probability that `sample` returns `index`; 0 outside the table.
    RESTIR_HOST_DEVICE constexpr float pmf(std::uint32_t index) const noexcept {
        return index < size ? entries[index].pmf : 0.0f;
    }
};

/// Owning alias table, built on the host. Construction throws `std::invalid_argument` for
/// an empty weight list, a negative or non-finite weight, or weights that are all zero.
class AliasTable {
public:
    AliasTable() = default;

    explicit AliasTable(std::span<const float> weights) { build(weights); }

    /// Builds the table in O(n) (Vose's method, with double-precision bookkeeping).
    void build(std::span<const float> weights) {
        if (weights.empty())
            throw std::invalid_argument("alias table: the weight list is empty");
        if (weights.size() > std::numeric_limits<std::uint32_t>::max())
            throw std::invalid_argument("alias table: more than 2^32 - 1 weights");
        double total = 0.0;
        for (std::size_t i = 0; i < weights.size(); ++i) {
            if (!is_valid_weight(weights[i]))
                throw std::invalid_argument("alias table: weight " + std::to_string(i) +
                                            " is negative or not finite");
            total += static_cast<double>(weights[i]);
        }
        if (!(total > 0.0))
            throw std::invalid_argument("alias table: all weights are zero");

        const std::size_t n = weights.size();
        entries_.assign(n, AliasEntry{});
        std::vector<double> scaled(n);
        std::vector<std::uint32_t> small, large;
        small.reserve(n);
        large.reserve(n);
        for (std::size_t i = 0; i < n; ++i) {
            const double weight = static_cast<double>(weights[i]);
            entries_[i].pmf = static_cast<float>(weight / total);
            scaled[i] = weight * static_cast<double>(n) / total;
            (scaled[i] < 1.0 ? small : large).push_back(static_cast<std::uint32_t>(i));
        }
        // Each step fills one under-full bucket from an over-full one.
        while (!small.empty() && !large.empty()) {
            const std::uint32_t under = small.back();
            small.pop_back();
            const std::uint32_t over = large.back();
            entries_[under].threshold = static_cast<float>(scaled[under]);
            entries_[under].alias = over;
            scaled[over] -= 1.0 - scaled[under];
            if (scaled[over] < 1.0) {
                large.pop_back();
                small.push_back(over);
            }
        }
        // What is left is full up to rounding: keep it.
        for (std::uint32_t i : large)
            entries_[i] = {1.0f, i, entries_[i].pmf};
        for (std::uint32_t i : small)
            entries_[i] = {1.0f, i, entries_[i].pmf};
        for (AliasEntry& entry : entries_)
            entry.alias_pmf = entries_[entry.alias].pmf;
    }

    /// See `AliasTableView::sample`.
    DiscreteSample sample(float u0, float u1) const noexcept { return view().sample(u0, u1); }

    /// See `AliasTableView::pmf`.
    float pmf(std::uint32_t index) const noexcept { return view().pmf(index); }

    std::uint32_t size() const noexcept { return static_cast<std::uint32_t>(entries_.size()); }
    bool empty() const noexcept { return entries_.empty(); }

    /// The buckets, for copying to another memory space.
    std::span<const AliasEntry> entries() const noexcept { return entries_; }

    /// A view that stays valid while this table lives and is not rebuilt.
    AliasTableView view() const noexcept { return {entries_.data(), size()}; }

private:
    std::vector<AliasEntry> entries_;
};

} // namespace restir
