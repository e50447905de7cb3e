/// @file light/light_bvh_view.hpp
/// A bounding volume hierarchy over lights for spatially aware light selection (Conty Estevez
/// and Kulla 2018, "Importance Sampling of Many Lights with Adaptive Tree Splitting"), as device
/// code reads it: flat groups of eight children, sampled by `LightBvhView`. Every node bounds its
/// lights' positions (a box, weighed through its centre and half diagonal), their emitted power,
/// and the directions they emit in (a cone of normals of half-angle theta_o, plus the emission
/// spread theta_e beyond them). A light is drawn for a shading point by one stochastic descent
/// that picks each child in proportion to an importance bound of its lights at the point; the
/// pmf of a light is the product of the choices on its path, found by the same descent from the
/// path's bits, so it is exact and RIS with it stays unbiased. The groups are quantised (128
/// bytes for eight children): boxes in 8-bit steps of the parent's box, octahedral cone axes,
/// 8-bit cone angles and bfloat16 powers, every bound rounded outward; the draw and the pmf read
/// the same numbers. The host builder is `LightBvh` (light/light_bvh.hpp).
#pragma once

#include "restir/config.hpp"
#include "restir/core/discrete_sample.hpp"
#include "restir/core/math.hpp"
#include "restir/core/shading_point.hpp"
#include "restir/light/light_bvh_group.hpp"

#include <glm/geometric.hpp>
#include <glm/vec3.hpp>

#include <cmath>
#include <cstdint>
#include <type_traits>

// Whether a descent works out every child's grid beside the bounds, so that the chosen one is a
// load after the choice: in host code built by Clang, which vectorises that loop. GCC leaves it
// scalar, and its draws are faster with the chosen child's grid alone, computed after the choice
// as on a GPU (docs/performance.md, "Light BVH").
#if !defined(__CUDA_ARCH__) && defined(__clang__)
#define RESTIR_LIGHT_BVH_LANE_GRIDS 1
#else
#define RESTIR_LIGHT_BVH_LANE_GRIDS 0
#endif

RESTIR_VECTORIZE_REGION_BEGIN

namespace restir {

/// The flat tree as a `ContextLightSampler` (concepts.hpp). A view: the `LightBvh` it came
/// from must outlive it (for a kernel, copy its arrays to the device and point a copy of
/// `view()` at them: the root's box travels in the view).
struct LightBvhView {
    /// Children per interior node. A wider node means fewer dependent levels in a draw (about
    /// log8 n), each weighing its children side by side, and each choice weighs tighter bounds
    /// (docs/performance.md, "Light BVH").
    static constexpr std::uint32_t arity = LightBvhGroup::lanes;

    /// Group 0 holds the root's children (for one light: the light and seven unused lanes).
    const LightBvhGroup* groups = nullptr;
    /// Per light: the path from the root, bits [2k, 2k + 2) the lane taken in the k-th group
    /// of the descent, and the number of groups passed in the top `depth_shift` bits.
    const std::uint64_t* paths = nullptr;
    std::uint32_t count = 0u; ///< Lights.
    /// The root's box: group 0's children are stored on its grid (`LightBvhGrid::over`).
    glm::vec3 root_lower{0.0f};
    glm::vec3 root_upper{0.0f};
    /// The near-field length l of the importance bounds (`light_importance`): a node's
    /// 1 / d^2 is 1 / max(d^2, r l), r its half diagonal; 0 keeps Conty Estevez and Kulla's
    /// 1 / max(d^2, r^2). `LightBvh` sets 16 times the median light's half diagonal, which
    /// took the many-light scene's heavy tails away (docs/noise-and-bias.md, "Heavy tails").
    float near_length = 0.0f;

    static constexpr std::uint32_t depth_shift = 58u;
    /// The most groups a path passes (`LightBvhGroup::lane_bits` bits each below
    /// `depth_shift`).
    static constexpr std::uint32_t max_depth = depth_shift / LightBvhGroup::lane_bits;
    /// `u0` steers the first `levels_per_number` levels, `u1` the deeper ones: each level
    /// spends about `LightBvhGroup::lane_bits` bits of its number.
    static constexpr std::uint32_t levels_per_number = 12u / LightBvhGroup::lane_bits;

    RESTIR_HOST_DEVICE constexpr std::uint32_t light_count() const noexcept { return count; }

    /// The grid of group 0's children.
    RESTIR_HOST_DEVICE LightBvhGrid root_grid() const noexcept {
        return LightBvhGrid::over(root_lower, root_upper);
    }

    /// One light for `at`, by a descent that takes each child with probability proportional to
    /// its `light_importance`; pmf 0 when no light can light `at`.
    RESTIR_HOST_DEVICE DiscreteSample sample(const ShadingPoint& at, float u0, float u1) const {
        if (count == 0u)
            return {};
        Descent descent{u0, u1, false, root_grid()};
        while (!descent.done)
            step(at, descent);
        return descent.result;
    }

    /// `Count` draws for one shading point at once: draw k is `sample(at, u0[k], u1[k])`,
    /// exactly. The descents advance a level at a time side by side, so that a CPU overlaps
    /// their chains of dependent levels (and their cache misses) instead of waiting on each in
    /// turn (the chains, not the arithmetic, bound a single draw). On a CPU, draws that reach
    /// the same group weigh its children once (every draw starts at the root). In device code
    /// its loops over the draws unroll, so the descents stay in registers.
    template <std::uint32_t Count>
    RESTIR_HOST_DEVICE void sample(const ShadingPoint& at, const float (&u0)[Count],
                                   const float (&u1)[Count], DiscreteSample (&out)[Count]) const {
        Descent descents[Count];
        const LightBvhGrid root = count > 0u ? root_grid() : LightBvhGrid{};
        RESTIR_UNROLL
        for (std::uint32_t k = 0u; k < Count; ++k)
            descents[k] = Descent{u0[k], u1[k], count == 0u, root};
        for (bool active = count > 0u; active;)
            active = advance(at, descents);
        RESTIR_UNROLL
        for (std::uint32_t k = 0u; k < Count; ++k)
            out[k] = descents[k].result;
    }

    /// The probability that `sample(at, ...)` returns light `id`: the same descent along the
    /// light's path.
    RESTIR_HOST_DEVICE float pmf(const ShadingPoint& at, std::uint32_t id) const {
        if (id >= count)
            return 0.0f;
        const std::uint64_t path = paths[id];
        const auto depth = static_cast<std::uint32_t>(path >> depth_shift);
        std::uint32_t group = 0u;
        LightBvhGrid grid = root_grid();
        float pmf = 1.0f;
        for (std::uint32_t level = 0u; level < depth; ++level) {
            const LightBvhGroup& g = groups[group];
            float importance[arity];
            g.bounds(at, grid, importance, near_length);
            const float total = detail::pairwise_total(importance);
            if (!(total > 0.0f))
                return 0.0f;
            const auto child = static_cast<std::uint32_t>(
                path >> (LightBvhGroup::lane_bits * level) & (arity - 1u));
            float chosen = 0.0f;
            RESTIR_UNROLL
            for (std::uint32_t c = 0u; c < arity; ++c)
                chosen = c == child ? importance[c] : chosen;
            pmf *= chosen / total;
            group = g.child_or_light[child];
            grid = g.child_grid(child, grid);
        }
        return pmf;
    }

private:
    // A draw under way: its numbers, the group it is at and the grid of that group's boxes, its
    // depth and its pmf so far.
    struct Descent {
        float u = 0.0f;
        float u_deep = 0.0f; // steers the levels from `levels_per_number` on
        bool done = false;
        LightBvhGrid grid{};
        std::uint32_t group = 0u;
        std::uint32_t depth = 0u;
        float pmf = 1.0f;
        DiscreteSample result{};
    };

    // One level of every descent of a batch still under way; whether any still is. All of them
    // are at the same depth. On a CPU, descents at the same group share its weights (the same
    // bounds, bit for bit): all of them at the root, and most at the levels below it where the
    // lights near `at` dominate. In device code each descent weighs its own group, one after
    // the other, so that one group's weights are live at a time (fewer registers).
    template <std::uint32_t Count>
    RESTIR_HOST_DEVICE bool advance(const ShadingPoint& at, Descent (&descents)[Count]) const {
        bool active = false;
#if defined(__CUDA_ARCH__)
        RESTIR_UNROLL
        for (std::uint32_t k = 0u; k < Count; ++k) {
            if (!descents[k].done)
                step(at, descents[k]);
            active = active || !descents[k].done;
        }
#else
        Weights weights[Count];
        std::uint32_t weighed_by[Count];
        for (std::uint32_t k = 0u; k < Count; ++k) {
            weighed_by[k] = k;
            if (descents[k].done)
                continue;
            for (std::uint32_t j = 0u; j < k; ++j)
                if (!descents[j].done && descents[j].group == descents[k].group) {
                    weighed_by[k] = j;
                    break;
                }
            if (weighed_by[k] == k)
                weigh(at, descents[k], weights[k]);
        }
        for (std::uint32_t k = 0u; k < Count; ++k) {
            if (!descents[k].done)
                choose(weights[weighed_by[k]], descents[k]);
            active = active || !descents[k].done;
        }
#endif
        return active;
    }

    // The weights of the children of a descent's group: their importance bounds at the point
    // and, where the lanes' grids are worked out beside them, those grids.
    struct Weights {
        float importance[arity];
#if RESTIR_LIGHT_BVH_LANE_GRIDS
        float origins[3][arity], cells[3][arity];
#endif
    };

    // One level of a draw: weighs the children of its group and takes one, in proportion to
    // their importance; ends the draw at a leaf, or where no child can light `at`.
    RESTIR_HOST_DEVICE void step(const ShadingPoint& at, Descent& d) const {
        Weights w;
        weigh(at, d, w);
        choose(w, d);
    }

    RESTIR_HOST_DEVICE void weigh(const ShadingPoint& at, const Descent& d, Weights& w) const {
        const LightBvhGroup& g = groups[d.group];
        prefetch_children(g);
        g.bounds(at, d.grid, w.importance, near_length);
#if RESTIR_LIGHT_BVH_LANE_GRIDS
        // Every lane's grid side by side, while the bounds compute: the chosen one is then a
        // load rather than a chain of operations before the next level can start.
        RESTIR_VECTORIZE
        for (std::uint32_t c = 0u; c < arity; ++c) {
            const LightBvhBox box = g.box(c, d.grid);
            w.origins[0][c] = box.lower.x;
            w.origins[1][c] = box.lower.y;
            w.origins[2][c] = box.lower.z;
            w.cells[0][c] = detail::grid_step(box.lower.x, box.upper.x);
            w.cells[1][c] = detail::grid_step(box.lower.y, box.upper.y);
            w.cells[2][c] = detail::grid_step(box.lower.z, box.upper.z);
        }
#endif
    }

    // The choice of a child from its group's weights `w`.
    RESTIR_HOST_DEVICE void choose(const Weights& w, Descent& d) const {
        if (d.depth == levels_per_number)
            d.u = d.u_deep;
        const LightBvhGroup& g = groups[d.group];
        const float(&importance)[arity] = w.importance;
        const float total = detail::pairwise_total(importance);
        if (!(total > 0.0f)) { // no child can light `at`
            d.done = true;
            return;
        }
        // The child whose interval of the cumulative importance holds u total: the number of
        // inclusive prefix sums at or below it, never past the last child of importance > 0
        // (children of importance 0 have empty intervals). Its interval's start and its
        // importance are gathered without branches: which child wins is random.
        const float x = d.u * total;
        float prefix[arity];
        float running = 0.0f;
        RESTIR_UNROLL
        for (std::uint32_t c = 0u; c < arity; ++c) {
            running += importance[c];
            prefix[c] = running;
        }
        std::uint32_t child = 0u, last_positive = 0u;
        RESTIR_UNROLL
        for (std::uint32_t c = 0u; c < arity; ++c) {
            child += c + 1u < arity && prefix[c] <= x ? 1u : 0u;
            last_positive = importance[c] > 0.0f ? c : last_positive;
        }
        child = min_of(child, last_positive);
#if defined(__CUDA_ARCH__)
        float start = 0.0f, chosen = 0.0f;
        RESTIR_UNROLL
        for (std::uint32_t c = 0u; c < arity; ++c) {
            start = select_float(c == child, c == 0u ? 0.0f : prefix[c - 1u], start);
            chosen = select_float(c == child, importance[c], chosen);
        }
#else
        // On a CPU, loads at a runtime index (compilers turn the masks into branches).
        float before_child[arity];
        RESTIR_UNROLL
        for (std::uint32_t c = 0u; c < arity; ++c)
            before_child[c] = c == 0u ? 0.0f : prefix[c - 1u];
        const float start = before_child[child];
        const float chosen = importance[child];
#endif
        d.pmf *= chosen / total;
        if (g.is_leaf(child)) {
            d.done = true;
            d.result = {g.child_or_light[child] & ~LightBvhNode::leaf_bit, d.pmf};
            return;
        }
        descend(w, g, child, d);
        d.u = min_of(max_of((x - start) / chosen, 0.0f), 0x1.fffffep-1f);
        ++d.depth;
    }

    /// Moves descent `d` down to interior child `child` of its group `g` (whose weights are
    /// `w`): that child's group, and the grid its children's boxes are stored on.
    RESTIR_HOST_DEVICE RESTIR_FORCE_INLINE static void
    descend(const Weights& w, const LightBvhGroup& g, std::uint32_t child, Descent& d) {
        d.group = g.child_or_light[child];
#if RESTIR_LIGHT_BVH_LANE_GRIDS
        d.grid = {glm::vec3(w.origins[0][child], w.origins[1][child], w.origins[2][child]),
                  glm::vec3(w.cells[0][child], w.cells[1][child], w.cells[2][child])};
#else
        (void)w;
        d.grid = g.child_grid(child, d.grid);
#endif
    }

    // On the host, asks for the group of every interior child while the children are being
    // weighed: at a million lights the groups below the top levels are not in cache, and the
    // loads would otherwise wait for the choice. Inlined by force: a function whose only
    // effects are prefetches is side-effect free to GCC 12, which deletes its calls.
    RESTIR_HOST_DEVICE RESTIR_FORCE_INLINE void prefetch_children(const LightBvhGroup& g) const {
#if !defined(__CUDA_ARCH__)
        // Without branches: a leaf's lane asks for this group again, which costs nothing.
        const auto here = static_cast<std::uint32_t>(&g - groups);
        RESTIR_UNROLL
        for (std::uint32_t c = 0u; c < arity; ++c) {
            const char* child =
                reinterpret_cast<const char*>(&groups[g.is_leaf(c) ? here : g.child_or_light[c]]);
            for (std::uint32_t line = 0u; line < sizeof(LightBvhGroup); line += 64u)
                RESTIR_PREFETCH(child + line);
        }
#else
        (void)g;
#endif
    }
};

} // namespace restir

RESTIR_VECTORIZE_REGION_END
