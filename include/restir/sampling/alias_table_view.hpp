/// @file sampling/alias_table_view.hpp
/// The device-callable side of Walker's alias method: one table entry and a non-owning view
/// that draws in O(1). The host builder is `AliasTable` (sampling/alias_table.hpp).
#pragma once

#include "restir/config.hpp"
#include "restir/core/discrete_sample.hpp"
#include "restir/core/math.hpp"

#include <cstdint>
#include <type_traits>

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
        // Selects without branches (core/math.hpp): which side wins is random, so a branch
        // would mispredict.
        return {select_bits(keep, bucket.index, entry.alias),
                select_float(keep, entry.pmf, entry.alias_pmf)};
    }

    /// The bucket that `sample(u0, u1)` reads, for a prefetch: draw the numbers of many draws
    /// first and prefetch their buckets, so that their cache misses overlap. (The caller issues
    /// the prefetch: one issued inside a member function is not guaranteed to survive inlining
    /// into every caller.)
    RESTIR_HOST_DEVICE constexpr const void* prefetch_address(float u0, float u1) const noexcept {
        return size > 0u ? &entries[wide_uniform_index(u0, u1, size).index] : entries;
    }

    /// Probability that `sample` returns `index`; 0 outside the table.
    RESTIR_HOST_DEVICE constexpr float pmf(std::uint32_t index) const noexcept {
        return index < size ? entries[index].pmf : 0.0f;
    }
};

} // namespace restir
