/// @file light/light_bvh_split.hpp
/// The splits of the light BVH's builder (internal to light/light_bvh.hpp): the bounds of lights
/// as the build carries them, and a node's lights split in two by the orientation-aware surface
/// area heuristic (Conty Estevez and Kulla 2018), or at the median.
#pragma once

#include "restir/config.hpp"
#include "restir/light/light_bounds.hpp"
#include "restir/light/light_bvh_items.hpp"
#include "restir/light/light_bvh_view.hpp"

#include <glm/common.hpp>
#include <glm/vec3.hpp>

#include <algorithm>
#include <array>
#include <cmath>
#include <cstdint>
#include <limits>
#include <vector>

RESTIR_VECTORIZE_REGION_BEGIN

namespace restir::detail {

// acos(x) for x in [-1, 1] (Abramowitz and Stegun 4.4.45, error below 7e-5) for the split
// cost, which only ranks splits: branch-free, so that a loop over candidates vectorises.
inline float fast_acos(float x) {
    const float a = std::min(std::abs(x), 1.0f);
    const float p = 1.5707288f + a * (-0.2121144f + a * (0.0742610f + a * -0.0187293f));
    const float magnitude = std::sqrt(1.0f - a) * p;
    return x < 0.0f ? 3.14159265358979f - magnitude : magnitude;
}

/// The builder's splits, all static: `LightBvh` derives from it privately.
struct LightBvhSplits : LightBvhItems {
    // Lights (mod arity - 1): a subtree of g full groups holds (arity - 1) g + 1 lights.
    static std::uint32_t residue(std::size_t n) {
        return static_cast<std::uint32_t>(n % (LightBvhView::arity - 1u));
    }

    // Groups below a node of `n` lights when every split is at the median: ceil(log_arity n).
    static std::uint32_t levels_for(std::size_t n) {
        std::uint32_t levels = 0u;
        for (std::size_t reach = 1u; reach < n; reach *= LightBvhView::arity)
            ++levels;
        return levels;
    }

    // Splits `whole` (at least two lights) in two, by the least SAOH cost over the bucket
    // boundaries of the three axes (buckets across the part's box), with `below` holding
    // `residue_a` or `residue_b` (`residue`) lights: lights of the buckets at the boundary
    // cross it to make the count so.
    static void split(std::vector<Item>& items, const Part& whole, std::uint32_t residue_a,
                      std::uint32_t residue_b, Part& below, Part& above) {
        if (whole.size() == 2u) { // nothing to choose
            below = part_of(items, whole.begin, whole.begin + 1u);
            above = part_of(items, whole.begin + 1u, whole.end);
            return;
        }
        if (whole.size() <= few) {
            split_few(items, whole, residue_a, residue_b, below, above);
            return;
        }
        const auto buckets =
            static_cast<std::uint32_t>(std::min<std::size_t>(whole.size(), bucket_count));
        Choice choice;
        best_split(items, whole, buckets, choice);
        if (choice.axis < 0) { // every centre the same: any halves of the wanted counts
            const std::size_t middle =
                whole.begin + nearest_count(whole.size() / 2u, whole.size(), residue_a, residue_b);
            below = part_of(items, whole.begin, middle);
            above = part_of(items, middle, whole.end);
            return;
        }
        partition(items, whole, buckets, choice, below, above);
        const std::size_t wanted = whole.begin + nearest_count(below.end - whole.begin,
                                                               whole.size(), residue_a, residue_b);
        cross_to(items, whole, buckets, choice, wanted, below, above);
    }

    // `split` for at most `few` lights: the least SAOH cost over every position of the lights'
    // centres sorted along each axis whose count below is `residue_a` or `residue_b`
    // (`residue`).
    static void split_few(std::vector<Item>& items, const Part& whole, std::uint32_t residue_a,
                          std::uint32_t residue_b, Part& below, Part& above) {
        const auto n = static_cast<std::uint32_t>(whole.size());
        std::uint32_t order[3][few];
        Bounds before[3][few], after[3][few]; // [k]: the first k, the last n - k
        std::uint32_t counts[few];
        const std::uint32_t count_total = allowed_counts(n, residue_a, residue_b, counts);
        const glm::vec3 extent = whole.bounds.upper() - whole.bounds.lower();
        const float longest = std::max(extent.x, std::max(extent.y, extent.z));
        Features features;
        std::uint32_t slot = 0u;
        for (int a = 0; a < 3; ++a) {
            const std::uint32_t* sorted = order[a];
            sort_by_centre(items, whole, a, order[a]);
            Bounds running = Bounds::empty();
            for (std::uint32_t k = 1u; k < n; ++k) {
                running.add(items[whole.begin + sorted[k - 1u]]);
                before[a][k] = running;
            }
            running = Bounds::empty();
            for (std::uint32_t k = n - 1u; k >= 1u; --k) {
                running.add(items[whole.begin + sorted[k]]);
                after[a][k] = running;
            }
            const float thin = extent[a] > 0.0f ? longest / extent[a] : 1.0f;
            for (std::uint32_t c = 0u; c < count_total; ++c) {
                features.set(slot++, before[a][counts[c]], thin);
                features.set(slot++, after[a][counts[c]], thin);
            }
        }
        features.saoh_costs(slot);
        int axis = 0;
        std::uint32_t best = 0u;
        for (std::uint32_t k = 0u; k < slot; k += 2u)
            if (features.cost[k] + features.cost[k + 1u] <
                features.cost[best] + features.cost[best + 1u])
                best = k;
        axis = static_cast<int>(best / (2u * count_total));
        const std::uint32_t count = counts[best % (2u * count_total) / 2u];
        Item moved[few];
        for (std::uint32_t i = 0u; i < n; ++i)
            moved[i] = items[whole.begin + order[axis][i]];
        std::copy(moved, moved + n, items.begin() + static_cast<std::ptrdiff_t>(whole.begin));
        below = {whole.begin, whole.begin + count, before[axis][count]};
        above = {whole.begin + count, whole.end, after[axis][count]};
    }

    /// The counts in [1, n) of lights below a split of `split_few` that are `residue_a` or
    /// `residue_b` (`residue`), in `counts`, ascending; where there is none, the one nearest n / 2.
    /// Returns how many there are.
    static std::uint32_t allowed_counts(std::uint32_t n, std::uint32_t residue_a,
                                        std::uint32_t residue_b, std::uint32_t (&counts)[few]) {
        std::uint32_t count_total = 0u;
        for (std::uint32_t k = 1u; k < n; ++k)
            if (residue(k) == residue_a || residue(k) == residue_b)
                counts[count_total++] = k;
        if (count_total == 0u)
            counts[count_total++] =
                static_cast<std::uint32_t>(nearest_count(n / 2u, n, residue_a, residue_b));
        return count_total;
    }

    /// The lights of `whole` (at most `few`) in order of their centres along axis `a`, as
    /// offsets from whole.begin in `sorted`: through each light's rank (the lights before it,
    /// ties by index), without branches, which a sort of so few would mispredict.
    RESTIR_FORCE_INLINE static void sort_by_centre(const std::vector<Item>& items,
                                                   const Part& whole, int a,
                                                   std::uint32_t (&sorted)[few]) {
        const auto n = static_cast<std::uint32_t>(whole.size());
        float key[few];
        for (std::uint32_t i = 0u; i < few; ++i) // past n: behind every light
            key[i] =
                i < n ? items[whole.begin + i].centre(a) : std::numeric_limits<float>::infinity();
        std::uint32_t rank[few] = {};
        for (std::uint32_t j = 0u; j < n; ++j) {
            const float other = key[j];
            for (std::uint32_t i = 0u; i < few; ++i)
                rank[i] += static_cast<std::uint32_t>(other < key[i]) |
                           (static_cast<std::uint32_t>(other == key[i]) &
                            static_cast<std::uint32_t>(j < i));
        }
        for (std::uint32_t i = 0u; i < n; ++i)
            sorted[rank[i]] = i;
    }

    // The count in [1, n) nearest `count` that is `residue_a` or `residue_b` (`residue`).
    static std::size_t nearest_count(std::size_t count, std::size_t n, std::uint32_t residue_a,
                                     std::uint32_t residue_b) {
        constexpr std::size_t period = LightBvhView::arity - 1u;
        std::size_t best = std::clamp<std::size_t>(count, 1u, n - 1u);
        std::size_t best_distance = std::numeric_limits<std::size_t>::max();
        for (std::size_t candidate = count > period ? count - period : 1u;
             candidate <= count + period; ++candidate) {
            if (candidate < 1u || candidate >= n)
                continue;
            const std::uint32_t r = residue(candidate);
            const std::size_t distance = candidate > count ? candidate - count : count - candidate;
            if ((r == residue_a || r == residue_b) && distance < best_distance) {
                best = candidate;
                best_distance = distance;
            }
        }
        return best;
    }

    // Splits `whole` at index `middle` by the centres along its box's widest axis.
    static void median_split(std::vector<Item>& items, const Part& whole, std::size_t middle,
                             Part& below, Part& above) {
        const glm::vec3 extent = whole.bounds.upper() - whole.bounds.lower();
        const int axis = extent.x >= extent.y && extent.x >= extent.z ? 0
                         : extent.y >= extent.z                       ? 1
                                                                      : 2;
        std::nth_element(
            items.begin() + static_cast<std::ptrdiff_t>(whole.begin),
            items.begin() + static_cast<std::ptrdiff_t>(middle),
            items.begin() + static_cast<std::ptrdiff_t>(whole.end),
            [axis](const Item& a, const Item& b) { return a.centre(axis) < b.centre(axis); });
        below = part_of(items, whole.begin, middle);
        above = part_of(items, middle, whole.end);
    }

    static std::uint32_t bucket_of(float centre, float origin, float scale, std::uint32_t buckets) {
        const float at = (centre - origin) * scale;
        return at < static_cast<float>(buckets - 1u) ? static_cast<std::uint32_t>(at)
                                                     : buckets - 1u;
    }

    // Lights [begin, end) as a part.
    static Part part_of(const std::vector<Item>& items, std::size_t begin, std::size_t end) {
        Part p{begin, end, Bounds::empty()};
        for (std::size_t i = begin; i < end; ++i)
            p.bounds.add(items[i]);
        return p;
    }

    // A split: its axis (-1 where every centre is the same), the last bucket below it, the
    // last nonempty bucket below and the first above, and the bounds of both sides.
    struct Choice {
        int axis = -1;
        float origin = 0.0f, scale = 0.0f; // of the buckets along the axis
        std::uint32_t bucket = 0u;
        std::uint32_t edges[2] = {0u, 0u};
        Bounds below = Bounds::empty(), above = Bounds::empty();
    };

    /// The bucket of light i along `choice`'s axis, of `buckets`, as a function of i.
    static auto bucket_along(const std::vector<Item>& items, const Choice& choice,
                             std::uint32_t buckets) {
        const int axis = choice.axis;
        return [&items, &choice, axis, buckets](std::size_t i) {
            return bucket_of(items[i].centre(axis), choice.origin, choice.scale, buckets);
        };
    }

    /// The lights of `whole` moved to either side of `choice` (of `buckets` buckets): `below`
    /// those of its buckets up to choice.bucket, `above` the others, with the choice's bounds.
    /// Lomuto's partition without a branch (a split is random to a branch predictor):
    /// [middle, i) stays above, so swapping light i in is right whichever side it is on.
    RESTIR_FORCE_INLINE static void partition(std::vector<Item>& items, const Part& whole,
                                              std::uint32_t buckets, const Choice& choice,
                                              Part& below, Part& above) {
        const auto bucket_at = bucket_along(items, choice, buckets);
        std::size_t middle = whole.begin;
        for (std::size_t i = whole.begin; i < whole.end; ++i) {
            const bool goes_below = bucket_at(i) <= choice.bucket;
            std::swap(items[i], items[middle]);
            middle += goes_below ? 1u : 0u;
        }
        below = {whole.begin, middle, choice.below};
        above = {middle, whole.end, choice.above};
    }

    /// Moves the boundary between `below` and `above` (the parts of `whole` that `partition`
    /// made) to index `wanted`: lights of the buckets at the boundary (`choice.edges`) cross it. A
    /// side that gains lights takes their bounds; one that loses them keeps bounds that still
    /// hold it, made exact again below `exact_below` lights (a large side hardly shrinks).
    static void cross_to(std::vector<Item>& items, const Part& whole, std::uint32_t buckets,
                         const Choice& choice, std::size_t wanted, Part& below, Part& above) {
        const auto bucket_at = bucket_along(items, choice, buckets);
        constexpr std::size_t exact_below = 64u;
        while (below.end < wanted) {
            std::size_t crossing = below.end;
            while (crossing + 1u < whole.end && bucket_at(crossing) != choice.edges[1])
                ++crossing;
            std::swap(items[below.end], items[crossing]);
            below.bounds.add(items[below.end]);
            ++below.end;
            above.begin = below.end;
            if (below.end == wanted && above.size() < exact_below)
                above = part_of(items, above.begin, above.end);
        }
        while (below.end > wanted) {
            std::size_t crossing = below.end - 1u;
            while (crossing > whole.begin && bucket_at(crossing) != choice.edges[0])
                --crossing;
            std::swap(items[below.end - 1u], items[crossing]);
            --below.end;
            above.begin = below.end;
            above.bounds.add(items[above.begin]);
            if (below.end == wanted && below.size() < exact_below)
                below = part_of(items, below.begin, below.end);
        }
    }

    // The bucket boundary of least SAOH cost over `buckets` buckets per axis.
    static void best_split(const std::vector<Item>& items, const Part& whole, std::uint32_t buckets,
                           Choice& choice) {
        Bounds bucket[2][3][bucket_count];
        float origin[3], scale[3];
        fill_buckets(items, whole, buckets, bucket, origin, scale);
        Features features;
        const std::uint32_t candidates = buckets - 1u;
        const glm::vec3 extent = whole.bounds.upper() - whole.bounds.lower();
        features.set_sides(bucket[0], extent, candidates);
        features.saoh_costs(6u * candidates);
        features.choose(scale, candidates, choice);
        if (choice.axis < 0)
            return;
        choice.origin = origin[choice.axis];
        choice.scale = scale[choice.axis];
        choice.edges[0] = 0u;
        choice.edges[1] = buckets;
        for (std::uint32_t b = 0u; b < buckets; ++b) {
            const Bounds& in = bucket[0][choice.axis][b];
            (b <= choice.bucket ? choice.below : choice.above).add(in);
            if (in.count > 0u && b <= choice.bucket)
                choice.edges[0] = b;
            if (in.count > 0u && b > choice.bucket)
                choice.edges[1] = std::min(choice.edges[1], b);
        }
    }

    /// The bounds of the lights of `whole` in each of `buckets` buckets across its box along each
    /// axis, in bucket[0] (`origin` and `scale` of the buckets along each axis: scale 0 where
    /// the box is flat). Two sets of buckets for alternate lights where there are many:
    /// consecutive lights often fall in the same bucket, and each update waits for the one
    /// before; the second set is then added to the first.
    static void fill_buckets(const std::vector<Item>& items, const Part& whole,
                             std::uint32_t buckets, Bounds (&bucket)[2][3][bucket_count],
                             float (&origin)[3], float (&scale)[3]) {
        const std::uint32_t sets = whole.size() >= 256u ? 2u : 1u;
        for (std::uint32_t set = 0u; set < sets; ++set)
            for (auto& axis_buckets : bucket[set])
                for (std::uint32_t b = 0u; b < buckets; ++b)
                    axis_buckets[b] = Bounds::empty();
        const glm::vec3 lower = whole.bounds.lower(), upper = whole.bounds.upper();
        for (int a = 0; a < 3; ++a) {
            origin[a] = lower[a];
            const float extent = upper[a] - lower[a];
            scale[a] = extent > 0.0f ? static_cast<float>(buckets) / extent : 0.0f;
        }
        for (std::size_t i = whole.begin; i < whole.end; ++i) {
            const Item& l = items[i];
            auto& set = bucket[i & (sets - 1u)];
            for (int a = 0; a < 3; ++a)
                set[a][bucket_of(l.centre(a), origin[a], scale[a], buckets)].add(l);
        }
        if (sets == 2u)
            for (int a = 0; a < 3; ++a)
                for (std::uint32_t b = 0u; b < buckets; ++b)
                    bucket[0][a][b].add(bucket[1][a][b]);
    }

    // What the cost of a side needs, for every candidate of the three axes, copied out as a
    // structure of arrays: the cost loop vectorises. Only the slots in use are written, and
    // the loop runs over whole vectors of them (the rest zeroed first).
    struct Features {
        static constexpr std::uint32_t vector = 16u;
        static constexpr std::uint32_t slots =
            3u * 2u * (few > bucket_count ? few - 1u : bucket_count - 1u) + vector;
        float least[fields][slots];
        float power[slots], thin[slots], cost[slots];
        std::uint32_t count[slots];

        // Side `above` of candidate `b` of `axis`, of `candidates` per axis.
        static std::uint32_t slot(int axis, std::uint32_t b, bool above, std::uint32_t candidates) {
            return (static_cast<std::uint32_t>(axis) * 2u + (above ? 1u : 0u)) * candidates + b;
        }
        void set(std::uint32_t k, const Bounds& bounds, float thin_box) {
            for (std::size_t f = 0u; f < fields; ++f)
                least[f][k] = bounds.least[f];
            power[k] = bounds.power;
            thin[k] = thin_box;
            count[k] = bounds.count;
        }

        /// Both sides of each of the `candidates` bucket boundaries of each axis, from the
        /// buckets of `best_split` (`extent`: its part's box).
        void set_sides(const Bounds (&bucket)[3][bucket_count], glm::vec3 extent,
                       std::uint32_t candidates) {
            const float longest = std::max(extent.x, std::max(extent.y, extent.z));
            for (int a = 0; a < 3; ++a) {
                const auto& axis_buckets = bucket[a];
                // The thin-box factor: a long box is not split across its short side.
                const float thin_box = extent[a] > 0.0f ? longest / extent[a] : 1.0f;
                // Candidate b of axis a: buckets [0, b] below, (b, last] above.
                Bounds running = axis_buckets[0];
                for (std::uint32_t b = 0u; b < candidates; ++b) {
                    set(slot(a, b, false, candidates), running, thin_box);
                    running.add(axis_buckets[b + 1u]);
                }
                running = axis_buckets[candidates];
                for (std::uint32_t b = candidates; b-- > 0u;) {
                    set(slot(a, b, true, candidates), running, thin_box);
                    running.add(axis_buckets[b]);
                }
            }
        }

        /// The boundary of least cost (`saoh_costs`) with lights on both sides, of an axis along
        /// which the buckets have a `scale`, in choice.axis and choice.bucket (axis -1 where
        /// there is none).
        void choose(const float (&scale)[3], std::uint32_t candidates, Choice& choice) const {
            float best_cost = std::numeric_limits<float>::infinity();
            for (int a = 0; a < 3; ++a) {
                if (!(scale[a] > 0.0f))
                    continue;
                for (std::uint32_t b = 0u; b < candidates; ++b) {
                    const std::uint32_t k = slot(a, b, false, candidates);
                    const std::uint32_t k_above = slot(a, b, true, candidates);
                    const float side_costs = cost[k] + cost[k_above];
                    if (count[k] > 0u && count[k_above] > 0u && side_costs < best_cost) {
                        best_cost = side_costs;
                        choice.axis = a;
                        choice.bucket = b;
                    }
                }
            }
        }

        // The SAOH cost (the orientation-aware SAH of Conty Estevez and Kulla 2018) of each side:
        // its power times the orientation measure of its cone times the surface area of its box,
        // times the axis's thin-box factor. The cone is estimated as the spread of the lights' axes
        // (the half diagonal of their box seen from its centre) plus their widest own cone: a split
        // heuristic needs no exact cone.
        void saoh_costs(std::uint32_t used) {
            const std::uint32_t whole = (used + vector - 1u) / vector * vector;
            for (std::uint32_t k = used; k < whole; ++k) {
                for (auto& field : least)
                    field[k] = 0.0f;
                power[k] = thin[k] = 0.0f;
            }
            RESTIR_VECTORIZE
            for (std::uint32_t k = 0u; k < whole; ++k) {
                constexpr float pi_f = 3.14159265358979f;
                const float x =
                    max_of(-least[negated_upper_field][k] - least[lower_field][k], 0.0f);
                const float y =
                    max_of(-least[negated_upper_field + 1u][k] - least[lower_field + 1u][k], 0.0f);
                const float z =
                    max_of(-least[negated_upper_field + 2u][k] - least[lower_field + 2u][k], 0.0f);
                const float area = 2.0f * (x * y + y * z + z * x);
                // sin^2 of the spread of the axes: their box's half diagonal squared over its
                // corner's distance squared (no axes: no spread).
                float middle_squared = 0.0f, half_squared = 0.0f;
                for (std::size_t a = 0u; a < 3u; ++a) {
                    const float low = least[axis_lower_field + a][k];
                    const float high = -least[negated_axis_upper_field + a][k];
                    middle_squared += 0.25f * (low + high) * (low + high);
                    half_squared += 0.25f * (high - low) * (high - low);
                }
                const float all = middle_squared + half_squared;
                const float sin_squared = all > 0.0f ? half_squared / all : 0.0f;
                const float sin_spread = std::sqrt(sin_squared);
                const float cos_spread = std::sqrt(1.0f - sin_squared);
                // theta_o = spread + the widest own cone, by the sum of angles (pi where they
                // add up past it).
                const float cos_own = least[cos_theta_o_field][k];
                const float sin_own = std::sqrt(max_of(1.0f - cos_own * cos_own, 0.0f));
                const bool sphere = cos_own <= -cos_spread;
                const float cos_o = sphere ? -1.0f : cos_spread * cos_own - sin_spread * sin_own;
                const float sin_o = sphere ? 0.0f : sin_spread * cos_own + cos_spread * sin_own;
                // M_Omega (Conty Estevez and Kulla 2018, the SAOH) with theta_w = min(theta_o +
                // theta_e, pi): where theta_o + theta_e <= pi, theta_w - theta_o = theta_e and
                // cos(theta_o - 2 theta_w) = cos(theta_o + 2 theta_e); else pi - theta_o and
                // cos(theta_o).
                const float cos_e = least[cos_theta_e_field][k];
                const float sin_e = std::sqrt(max_of(1.0f - cos_e * cos_e, 0.0f));
                const bool within = cos_e >= -cos_o;
                const float widening = detail::fast_acos(within ? cos_e : -cos_o);
                const float cos_far =
                    within ? cos_o * (2.0f * cos_e * cos_e - 1.0f) - sin_o * (2.0f * sin_e * cos_e)
                           : cos_o;
                const float measure = 2.0f * pi_f * (1.0f - cos_o) +
                                      0.5f * pi_f * (2.0f * widening * sin_o - cos_far + cos_o);
                cost[k] = power[k] * measure * area * thin[k];
            }
        }
    };
};

} // namespace restir::detail

RESTIR_VECTORIZE_REGION_END
