/// @file sampling/alias_table.hpp
/// The host-side builder of Walker's alias tables with Vose's O(n) construction (Vose 1991,
/// "A linear algorithm for generating random numbers with a given distribution"): O(1)
/// sampling of an index with probability proportional to a weight, through the
/// device-callable `AliasTableView` (sampling/alias_table_view.hpp).
#pragma once

#include "restir/config.hpp"
#include "restir/core/alias_buckets.hpp"
#include "restir/core/discrete_sample.hpp"
#include "restir/core/math.hpp"
#include "restir/sampling/alias_table_view.hpp"

#include <cstddef>
#include <cstdint>
#include <limits>
#include <span>
#include <stdexcept>
#include <string>
#include <vector>

namespace restir {

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
        for (std::size_t i = 0; i < n; ++i)
            entries_[i].pmf = static_cast<float>(static_cast<double>(weights[i]) / total);
        AliasScratch scratch;
        build_alias_buckets(weights, total, scratch,
                            [&](std::uint32_t i, float threshold, std::uint32_t alias) {
                                entries_[i].threshold = threshold;
                                entries_[i].alias = alias;
                            });
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
