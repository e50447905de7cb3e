// The frame recipe (reuse/di_frame.hpp): `run_di_frame` against the passes called by hand in
// the documented order, the per-pixel stages' visibility bookkeeping, frame 0 and camera cuts,
// and unbiasedness of whole frames on the synthetic image (synthetic_image.hpp).
#include <restir/reuse/di_frame.hpp>

#include <restir/restir.hpp>

#include "reuse/synthetic_image.hpp"
#include "support/statistics.hpp"

#include <gtest/gtest.h>

#include <cstdint>
#include <string>
#include <type_traits>
#include <vector>

namespace {

using namespace restir::test::synthetic;
using restir::BiasCorrection;
using restir::Reservoir;
using restir::RngStream;
using restir::test::RunningStats;

using Frame = restir::DiFrame<LightId, Patch, Reproject>;
static_assert(std::is_trivially_copyable_v<Frame>, "a kernel takes the frame by value");
using Image = std::vector<Reservoir<LightId>>;

// Visibility that counts its rays.
struct CountingVisibility {
    std::uint32_t* rays = nullptr;
    bool operator()(const LightId& x, const Patch& p) const {
        ++*rays;
        return Visibility{}(x, p);
    }
};

Reservoir<LightId> draw_initial(const Patch& surface, restir::Pcg32& rng) {
    const restir::UniformLightSampler sampler{light_count};
    return restir::resample_ris(
        rng, initial_candidates,
        [&](restir::Pcg32& g) {
            const restir::DiscreteSample c = restir::sample_light(sampler, g);
            return restir::SourceSample<LightId>{{c.index}, c.pmf};
        },
        [&](const LightId& x) { return Target{}(x, surface); });
}

restir::Pcg32 rng_for(PixelCoord p, std::uint32_t frame, std::uint32_t stream, std::uint64_t seed) {
    const auto index = static_cast<std::uint32_t>(p.x + p.y * width);
    return restir::make_pixel_rng(index, frame, stream, seed);
}

// A history the recipe loads by value (a `ReservoirHistory`), over the same buffer.
struct LoadingHistory {
    const Reservoir<LightId>* data = nullptr;
    std::uint32_t width = 0u, height = 0u;
    bool empty() const { return data == nullptr; }
    bool contains(PixelCoord p) const { return view().contains(p); }
    Reservoir<LightId> load(PixelCoord p) const { return view()[p]; }
    restir::ImageView<const Reservoir<LightId>> view() const { return {data, width, height}; }
};
static_assert(restir::ReservoirHistory<LoadingHistory, LightId>);

// A history that also decodes last frame's surfaces (the frame gets no previous G-buffer).
struct SurfaceDecodingHistory : LoadingHistory {
    const Patch* previous_surfaces = nullptr;
    Patch surface(PixelCoord p) const { return previous_surfaces[view().index_of(p)]; }
};
static_assert(restir::HistorySurfaces<SurfaceDecodingHistory, Patch>);

// This frame's surfaces decoded on demand (a `SurfaceDecoder`: the frame holds no view of them).
struct DecodingSurfaces {
    const Patch* data = nullptr;
    std::uint32_t width = 0u, height = 0u;
    bool contains(PixelCoord p) const { return view().contains(p); }
    Patch surface(PixelCoord p) const { return data[view().index_of(p)]; }
    restir::ImageView<const Patch> view() const { return {data, width, height}; }
};
static_assert(restir::SurfaceDecoder<DecodingSurfaces, Patch>);

// An application's frames through `run_di_frame`: keeps the G-buffers and the history.
template <class History = restir::ImageView<const Reservoir<LightId>>,
          class Surfaces = restir::ImageView<const Patch>>
class RecipeRendererOf {
public:
    using Frame = restir::DiFrame<LightId, Patch, Reproject, History, Surfaces>;
    explicit RecipeRendererOf(const restir::DiFrameParams& params, std::uint64_t seed = 0u)
        : params_(params), seed_(seed) {}

    // Renders frame `frame`; `cut`: a camera cut (no history).
    const Image& render(std::uint32_t frame, bool cut = false) {
        std::swap(surfaces_, previous_surfaces_);
        for (std::uint32_t i = 0; i < pixel_count; ++i)
            surfaces_[i] = patch_seen(pixel_of(i), frame);
        std::swap(out_, history_);
        Frame f{
            .params = params_, .frame_index = frame, .surfaces = {surfaces_.data(), width, height}};
        if (frame > 0 && !cut) {
            if constexpr (std::is_same_v<History, SurfaceDecodingHistory>) {
                f.history = {{history_.data(), width, height}, previous_surfaces_.data()};
            } else {
                f.previous_surfaces = {previous_surfaces_.data(), width, height};
                f.history = {history_.data(), width, height};
            }
        }
        const auto for_each_pixel = [](const auto& body) {
            for (std::uint32_t i = 0; i < pixel_count; ++i)
                body(pixel_of(i));
        };
        const auto initial = [](PixelCoord, const Patch& s, restir::Pcg32& rng) {
            return draw_initial(s, rng);
        };
        const restir::ReuseBridge bridge{Target{}, CountingVisibility{&rays}};
        restir::run_di_frame(
            f, restir::ImageView<Reservoir<LightId>>{out_.data(), width, height},
            restir::ImageView<Reservoir<LightId>>{scratch_.data(), width, height}, for_each_pixel,
            initial, bridge,
            [&](PixelCoord p, std::uint32_t stream) { return rng_for(p, frame, stream, seed_); });
        return out_;
    }
    const std::vector<Patch>& surfaces() const { return surfaces_; }
    std::uint32_t rays = 0;

private:
    restir::DiFrameParams params_;
    std::uint64_t seed_;
    std::vector<Patch> surfaces_ = std::vector<Patch>(pixel_count);
    std::vector<Patch> previous_surfaces_ = std::vector<Patch>(pixel_count);
    Image out_ = Image(pixel_count), history_ = Image(pixel_count), scratch_ = Image(pixel_count);
};
using RecipeRenderer = RecipeRendererOf<>;

// The same frames written out with the passes themselves, in the order docs/integration.md
// gives, one fresh vector per pass; every pass output that feeds another is tested again.
class HandWrittenRenderer {
public:
    explicit HandWrittenRenderer(const restir::DiFrameParams& params) : p_(params) {}

    const Image& render(std::uint32_t frame, bool cut = false) {
        const restir::ReuseBridge bridge{Target{}, Visibility{}};
        std::vector<Patch> surfaces(pixel_count);
        for (std::uint32_t i = 0; i < pixel_count; ++i)
            surfaces[i] = patch_seen(pixel_of(i), frame);
        const restir::ImageView<const Patch> gbuffer{surfaces.data(), width, height};
        restir::ReuseParams reuse = p_.reuse;
        reuse.inputs_visibility_tested = reuse.visibility_reuse;
        const bool retest = reuse.visibility_reuse && reuse.trace_mis_visibility &&
                            reuse.bias_correction != BiasCorrection::none;
        const bool history = p_.temporal_reuse && frame > 0 && !cut;
        Image current(pixel_count);
        for (std::uint32_t i = 0; i < pixel_count; ++i) {
            if (!surfaces[i].valid)
                continue;
            restir::Pcg32 rng = rng_for(pixel_of(i), frame, RngStream::initial, 0u);
            current[i] = draw_initial(surfaces[i], rng);
            if (reuse.visibility_reuse)
                restir::apply_visibility(current[i], surfaces[i], Visibility{});
            if (!history)
                continue;
            restir::TemporalParams temporal = p_.temporal;
            temporal.reuse = reuse;
            temporal.frame_index = frame;
            restir::Pcg32 temporal_rng = rng_for(pixel_of(i), frame, RngStream::temporal, 0u);
            current[i] = restir::temporal_resample(
                pixel_of(i), current[i], surfaces[i],
                restir::ImageView<const Reservoir<LightId>>{history_.data(), width, height},
                restir::ImageView<const Patch>{previous_surfaces_.data(), width, height},
                Reproject{}, temporal, bridge, temporal_rng);
            if (retest && p_.spatial_passes > 0)
                restir::apply_visibility(current[i], surfaces[i], Visibility{});
        }
        restir::SpatialParams spatial = p_.spatial;
        spatial.reuse = reuse;
        for (std::uint32_t pass = 0; pass < p_.spatial_passes; ++pass) {
            Image next(pixel_count);
            for (std::uint32_t i = 0; i < pixel_count; ++i) {
                restir::Pcg32 rng = rng_for(pixel_of(i), frame, RngStream::spatial + pass, 0u);
                next[i] = restir::spatial_resample(
                    pixel_of(i),
                    restir::ImageView<const Reservoir<LightId>>{current.data(), width, height},
                    gbuffer, spatial, offsets_, bridge, rng);
                if (retest && pass + 1 < p_.spatial_passes && surfaces[i].valid)
                    restir::apply_visibility(next[i], surfaces[i], Visibility{});
            }
            current = next;
        }
        if (p_.boiling_filter) {
            Image next(pixel_count);
            for (std::uint32_t i = 0; i < pixel_count; ++i)
                next[i] = restir::boiling_filter(
                    pixel_of(i),
                    restir::ImageView<const Reservoir<LightId>>{current.data(), width, height},
                    p_.boiling);
            current = next;
        }
        for (std::uint32_t i = 0; i < pixel_count; ++i)
            if (reuse.visibility_reuse && surfaces[i].valid)
                restir::apply_visibility(current[i], surfaces[i], Visibility{});
        history_ = current;
        previous_surfaces_ = surfaces;
        return history_;
    }

private:
    restir::DiFrameParams p_;
    restir::NeighbourOffsets offsets_ = restir::make_neighbour_offsets();
    Image history_ = Image(pixel_count);
    std::vector<Patch> previous_surfaces_ = std::vector<Patch>(pixel_count);
};

void expect_same(const Image& a, const Image& b, const std::string& what) {
    for (std::uint32_t i = 0; i < pixel_count; ++i) {
        EXPECT_EQ(a[i].sample.id, b[i].sample.id) << what << ", pixel " << i;
        EXPECT_EQ(a[i].candidate_count, b[i].candidate_count) << what << ", pixel " << i;
        EXPECT_EQ(a[i].contribution_weight, b[i].contribution_weight) << what << ", pixel " << i;
        EXPECT_EQ(a[i].target_value, b[i].target_value) << what << ", pixel " << i;
    }
}

struct Variant {
    std::string name;
    restir::DiFrameParams params;
};

std::vector<Variant> variants() {
    std::vector<Variant> v;
    restir::DiFrameParams p = restir::default_di_frame_params();
    p.spatial.radius = 2.0f;
    v.push_back({"default", p});
    for (std::uint32_t passes : {0u, 2u, 3u}) {
        restir::DiFrameParams q = p;
        q.spatial_passes = passes;
        v.push_back({std::to_string(passes) + " spatial passes", q});
        q.boiling_filter = true;
        q.boiling.threshold = 1.5f;
        q.boiling.radius = 1u;
        v.push_back({std::to_string(passes) + " spatial passes and boiling", q});
    }
    for (BiasCorrection mode :
         {BiasCorrection::none, BiasCorrection::one_over_z, BiasCorrection::balance_heuristic}) {
        restir::DiFrameParams q = p;
        q.reuse.bias_correction = mode;
        v.push_back({"bias correction " + std::to_string(static_cast<int>(mode)), q});
    }
    restir::DiFrameParams q = p;
    q.reuse.visibility_reuse = false;
    v.push_back({"no visibility reuse", q});
    q = p;
    q.reuse.trace_mis_visibility = false;
    v.push_back({"ray-free MIS", q});
    q = p;
    q.temporal_reuse = false;
    v.push_back({"no temporal reuse", q});
    return v;
}

TEST(DiFrame, RunDiFrameEqualsThePassesCalledByHand) {
    for (const Variant& variant : variants()) {
        RecipeRenderer recipe(variant.params);
        HandWrittenRenderer by_hand(variant.params);
        for (std::uint32_t frame = 0; frame < 6; ++frame) {
            const bool cut = frame == 3;
            expect_same(recipe.render(frame, cut), by_hand.render(frame, cut),
                        variant.name + ", frame " + std::to_string(frame));
        }
    }
}

// A history loaded by value (the form a packed or translated history takes), and surfaces of
// both frames decoded on demand, give the frames that views of the same buffers give.
TEST(DiFrame, LoadedHistoryAndDecodedSurfacesEqualTheViewedOnes) {
    for (const Variant& variant : variants()) {
        RecipeRenderer viewed(variant.params);
        RecipeRendererOf<LoadingHistory> loaded(variant.params);
        RecipeRendererOf<SurfaceDecodingHistory> decoded(variant.params);
        RecipeRendererOf<SurfaceDecodingHistory, DecodingSurfaces> array_free(variant.params);
        for (std::uint32_t frame = 0; frame < 6; ++frame) {
            const bool cut = frame == 3;
            const Image& expected = viewed.render(frame, cut);
            const std::string name = variant.name + ", frame " + std::to_string(frame);
            expect_same(loaded.render(frame, cut), expected, name);
            expect_same(decoded.render(frame, cut), expected, name + ", last frame's decoded");
            expect_same(array_free.render(frame, cut), expected, name + ", both frames' decoded");
        }
    }
}

TEST(DiFrame, WithoutHistoryTemporalReturnsItsInput) {
    const Frame no_history{};
    EXPECT_FALSE(no_history.has_history());
    Reservoir<LightId> current;
    current.stream({3u}, 2.0f, 1.0f, 0.5f);
    current.finalize();
    restir::Pcg32 rng;
    const restir::ReuseBridge bridge{Target{}, Visibility{}};
    const Reservoir<LightId> result = no_history.temporal({0, 0}, current, bridge, rng);
    EXPECT_EQ(result.sample.id, 3u);
    EXPECT_EQ(result.contribution_weight, current.contribution_weight);
    EXPECT_EQ(result.candidate_count, current.candidate_count);
    EXPECT_EQ(rng.next_uint(), restir::Pcg32{}.next_uint()) << "no random number drawn";
}

TEST(DiFrame, VisibilityIsRetestedOnlyForSamplesAPassBroughtIn) {
    Frame f{};
    Reservoir<LightId> kept, moved, empty;
    kept.stream({1u}, 1.0f, 1.0f, 0.5f);
    kept.finalize();
    moved.stream({2u}, 1.0f, 1.0f, 0.5f);
    moved.finalize();
    EXPECT_FALSE(f.needs_visibility_test(kept, kept));
    EXPECT_TRUE(f.needs_visibility_test(moved, kept));
    EXPECT_TRUE(f.needs_visibility_test(moved, empty));
    EXPECT_FALSE(f.needs_visibility_test(empty, kept));
    EXPECT_TRUE(f.needs_visibility_test(kept));
    EXPECT_FALSE(f.needs_visibility_test(empty));
    // No retest when the next pass's MIS weights trace no rays, nor any test without
    // visibility reuse.
    for (int change = 0; change < 3; ++change) {
        Frame g{};
        if (change == 0)
            g.params.reuse.bias_correction = BiasCorrection::none;
        if (change == 1)
            g.params.reuse.trace_mis_visibility = false;
        if (change == 2)
            g.params.reuse.visibility_reuse = false;
        EXPECT_FALSE(g.needs_visibility_test(moved, kept)) << "change " << change;
        EXPECT_EQ(g.needs_visibility_test(moved), change != 2) << "change " << change;
    }
}

TEST(DiFrame, DeferredVisibilityLeavesTheStageRaysToTheCaller) {
    std::uint32_t rays = 0;
    const CountingVisibility counting{&rays};
    std::vector<Patch> surfaces(pixel_count);
    for (std::uint32_t i = 0; i < pixel_count; ++i)
        surfaces[i] = patch_seen(pixel_of(i), 0u);
    Frame f{.surfaces = {surfaces.data(), width, height}};
    f.params.deferred_visibility = true;
    std::uint32_t occluded = 0;
    for (std::uint32_t i = 0; i < pixel_count; ++i) {
        if (!surfaces[i].valid)
            continue;
        restir::Pcg32 rng = rng_for(pixel_of(i), 0u, RngStream::initial, 0u);
        const Reservoir<LightId> candidates = draw_initial(surfaces[i], rng);
        const Reservoir<LightId> initial = f.initial(pixel_of(i), candidates, counting);
        const Reservoir<LightId> finished = f.finish(pixel_of(i), candidates, counting);
        EXPECT_EQ(initial.contribution_weight, candidates.contribution_weight);
        EXPECT_EQ(finished.contribution_weight, candidates.contribution_weight);
        occluded += candidates.has_sample() && !Visibility{}(candidates.sample, surfaces[i]);
    }
    EXPECT_EQ(rays, 0u);
    EXPECT_GT(occluded, 0u) << "the check above needs occluded samples";
}

TEST(DiFrame, EveryStageRayIsOneTheRecipeNeeds) {
    // Pairwise MIS, visibility reuse, one spatial pass of 3: per pixel at most 1 initial ray,
    // 1 temporal MIS ray (the history's own sample is tested), no retest of a kept sample,
    // 3 spatial MIS rays and 1 final ray.
    restir::DiFrameParams p = restir::default_di_frame_params();
    p.spatial.radius = 2.0f;
    RecipeRenderer recipe(p);
    recipe.render(0u);
    recipe.render(1u);
    const std::uint32_t shaded = pixel_count - 1u; // one background pixel
    EXPECT_GT(recipe.rays, 0u);
    EXPECT_LE(recipe.rays, 2u * shaded * (1u + 3u + 1u) + shaded * (1u + 1u));
}

// Whole frames through the recipe are unbiased at every pixel (the figure a renderer shows),
// for the unbiased modes with two spatial passes after temporal reuse, over 12 frames with a
// camera cut in frame 6.
class UnbiasedRecipe : public ::testing::TestWithParam<BiasCorrection> {};

TEST_P(UnbiasedRecipe, MeanMatchesTruthAtEveryPixel) {
    restir::DiFrameParams p = restir::default_di_frame_params();
    p.reuse.bias_correction = GetParam();
    p.spatial.radius = 2.0f;
    p.spatial_passes = 2u;
    constexpr std::uint32_t frames = 12u, trials = 3000u, cut = 6u;
    std::vector<RunningStats> stats(pixel_count);
    for (std::uint32_t trial = 0; trial < trials; ++trial) {
        RecipeRenderer recipe(p, 1000u + trial);
        for (std::uint32_t frame = 0; frame + 1u < frames; ++frame)
            recipe.render(frame, frame == cut);
        const Image& last = recipe.render(frames - 1u);
        for (std::uint32_t i = 0; i < pixel_count; ++i) {
            const Patch& s = recipe.surfaces()[i];
            stats[i].add(s.valid ? world().integrand(s.id, last[i].sample.id) *
                                       static_cast<double>(last[i].contribution_weight)
                                 : 0.0);
        }
    }
    for (std::uint32_t i = 0; i < pixel_count; ++i) {
        const Patch s = patch_seen(pixel_of(i), frames - 1u);
        EXPECT_TRUE(restir::test::agrees_with(stats[i], s.valid ? world().truth[s.id] : 0.0))
            << "pixel " << i;
    }
}

std::string mode_name(const ::testing::TestParamInfo<BiasCorrection>& param) {
    const char* const names[] = {"none", "one_over_z", "balance_heuristic", "pairwise"};
    return names[static_cast<int>(param.param)];
}

INSTANTIATE_TEST_SUITE_P(Modes, UnbiasedRecipe,
                         ::testing::Values(BiasCorrection::one_over_z,
                                           BiasCorrection::balance_heuristic,
                                           BiasCorrection::pairwise),
                         mode_name);

} // namespace
