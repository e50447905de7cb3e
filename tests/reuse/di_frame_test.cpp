// The frame recipe (reuse/di_frame.hpp, reuse/di_frame_tiles.hpp): `run_di_frame` per pixel
// and per tile with batched rays against the passes called by hand in the documented order, the
// steps and their buffers, the visibility rules, frame 0 and camera cuts, and unbiasedness of
// whole frames on the synthetic image (synthetic_image.hpp).
#include <restir/reuse/di_frame.hpp>
#include <restir/reuse/di_frame_tiles.hpp>

#include <restir/restir.hpp>

#include "reuse/synthetic_image.hpp"
#include "support/statistics.hpp"

#include <gtest/gtest.h>

#include <algorithm>
#include <cstdint>
#include <span>
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

// Batched visibility that counts its batches and questions.
struct CountingBatches {
    std::uint32_t* rays = nullptr;
    std::uint32_t* batches = nullptr;
    void trace(std::span<const restir::VisibilityQuery<LightId, Patch>> queries,
               std::span<bool> visible) const {
        EXPECT_EQ(queries.size(), visible.size());
        EXPECT_GT(queries.size(), 0u);
        ++*batches;
        for (std::size_t i = 0; i < queries.size(); ++i) {
            ++*rays;
            visible[i] = Visibility{}(*queries[i].sample, *queries[i].surface);
        }
    }
};
static_assert(restir::BatchVisibility<CountingBatches, LightId, Patch>);

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

// An application's frames through `run_di_frame`: keeps the G-buffers and the history. With
// `tile_side` > 0 per tile of that side, its rays in batches; otherwise per pixel.
template <class History = restir::ImageView<const Reservoir<LightId>>,
          class Surfaces = restir::ImageView<const Patch>>
class RecipeRendererOf {
public:
    using Frame = restir::DiFrame<LightId, Patch, Reproject, History, Surfaces>;
    explicit RecipeRendererOf(const restir::DiFrameParams& params, std::uint64_t seed = 0u,
                              std::int32_t tile_side = 0)
        : params_(params), seed_(seed), tile_side_(tile_side) {}

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
        const restir::DiBuffers<LightId> buffers{{out_.data(), width, height},
                                                 {scratch_.data(), width, height}};
        const auto rngs = [&](PixelCoord p, std::uint32_t stream) {
            return rng_for(p, frame, stream, seed_);
        };
        constexpr bool tiles = std::is_same_v<Surfaces, restir::ImageView<const Patch>>;
        if (!tiles || tile_side_ == 0) {
            restir::run_di_frame(
                f, buffers,
                restir::DiBridge{initial, restir::ReuseBridge{Target{}, CountingVisibility{&rays}},
                                 rngs},
                for_each_pixel);
            return out_;
        }
        // Tiles in an order that is not the pixels' (last row of tiles first).
        const auto for_each_tile = [this](const restir::DiStep&, const auto& body) {
            const auto w = static_cast<std::int32_t>(width), h = static_cast<std::int32_t>(height);
            for (std::int32_t y = (h - 1) / tile_side_ * tile_side_; y >= 0; y -= tile_side_)
                for (std::int32_t x = 0; x < w; x += tile_side_)
                    body(restir::PixelTile{
                        {x, y}, {std::min(w, x + tile_side_), std::min(h, y + tile_side_)}});
        };
        if constexpr (tiles) // the tiles' questions point into an array of surfaces
            restir::run_di_frame(
                f, buffers,
                restir::DiBridge{
                    initial, restir::ReuseBridge{Target{}, CountingBatches{&rays, &batches}}, rngs},
                for_each_tile);
        return out_;
    }
    const std::vector<Patch>& surfaces() const { return surfaces_; }
    std::uint32_t rays = 0;
    std::uint32_t batches = 0;

private:
    restir::DiFrameParams params_;
    std::uint64_t seed_;
    std::int32_t tile_side_;
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
        // Every input of a pass is tested where it lives, so traced weights need no ray for it.
        const restir::ReuseVisibility visibility =
            p_.visibility == restir::ReuseVisibility::traced
                ? restir::ReuseVisibility::traced_inputs_tested
                : p_.visibility;
        const bool visibility_reuse = restir::carries_visibility(visibility);
        const bool retest = restir::traces_mis_rays(visibility) &&
                            p_.spatial_bias_correction != BiasCorrection::none;
        const bool history = p_.temporal_reuse && frame > 0 && !cut;
        Image current(pixel_count);
        for (std::uint32_t i = 0; i < pixel_count; ++i) {
            if (!surfaces[i].valid)
                continue;
            restir::Pcg32 rng = rng_for(pixel_of(i), frame, RngStream::initial, 0u);
            current[i] = draw_initial(surfaces[i], rng);
            if (visibility_reuse)
                restir::apply_visibility(current[i], surfaces[i], Visibility{});
            if (!history)
                continue;
            restir::Pcg32 temporal_rng = rng_for(pixel_of(i), frame, RngStream::temporal, 0u);
            const LightId before = current[i].sample;
            current[i] = restir::temporal_resample(
                pixel_of(i), current[i], surfaces[i],
                restir::ImageView<const Reservoir<LightId>>{history_.data(), width, height},
                restir::ImageView<const Patch>{previous_surfaces_.data(), width, height},
                Reproject{}, p_.temporal, {p_.temporal_bias_correction, visibility}, frame, bridge,
                temporal_rng);
            if (retest && p_.spatial_passes > 0 && !(current[i].sample == before))
                restir::apply_visibility(current[i], surfaces[i], Visibility{});
        }
        const restir::ReuseParams spatial_reuse{p_.spatial_bias_correction, visibility};
        for (std::uint32_t pass = 0; pass < p_.spatial_passes; ++pass) {
            Image next(pixel_count);
            for (std::uint32_t i = 0; i < pixel_count; ++i) {
                restir::Pcg32 rng = rng_for(pixel_of(i), frame, RngStream::spatial + pass, 0u);
                next[i] = restir::spatial_resample(
                    pixel_of(i),
                    restir::ImageView<const Reservoir<LightId>>{current.data(), width, height},
                    gbuffer, p_.spatial, spatial_reuse, bridge, rng, offsets_);
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
            if (visibility_reuse && surfaces[i].valid)
                restir::apply_visibility(current[i], surfaces[i], Visibility{});
        history_ = current;
        previous_surfaces_ = surfaces;
        return history_;
    }

private:
    restir::DiFrameParams p_;
    const restir::NeighbourOffsets& offsets_ = restir::default_neighbour_offsets();
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
        q.temporal_bias_correction = mode;
        q.spatial_bias_correction = mode;
        v.push_back({"bias correction " + std::to_string(static_cast<int>(mode)), q});
    }
    restir::DiFrameParams q = p;
    q.spatial_bias_correction = BiasCorrection::balance_heuristic;
    v.push_back({"pairwise temporal, balance heuristic spatial", q});
    q = p;
    q.visibility = restir::ReuseVisibility::none;
    v.push_back({"no visibility reuse", q});
    q = p;
    q.visibility = restir::ReuseVisibility::assumed;
    v.push_back({"ray-free MIS", q});
    q = p;
    q.spatial_passes = 2u;
    q.spatial_draw_span = 3u;
    v.push_back({"2 spatial passes, one neighbour draw per 3 pixels", q});
    q = p;
    q.temporal_reuse = false;
    v.push_back({"no temporal reuse", q});
    return v;
}

TEST(DiFrame, RunDiFrameEqualsThePassesCalledByHand) {
    for (const Variant& variant : variants()) {
        // By hand, each pixel draws its own neighbours (`spatial_resample`).
        if (variant.params.spatial_draw_span > 1u)
            continue;
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

// The tiles give the frames that the pixels give, whatever the tiles' order, with every ray in
// a batch of a tile's stage (or alone, where a mode asks about a sample it did not announce).
TEST(DiFrame, TilesWithBatchedRaysEqualPixels) {
    for (const Variant& variant : variants()) {
        for (std::int32_t side : {1, 3, 8}) {
            RecipeRenderer pixels(variant.params);
            RecipeRenderer tiles(variant.params, 0u, side);
            RecipeRendererOf<LoadingHistory> loaded_tiles(variant.params, 0u, side);
            for (std::uint32_t frame = 0; frame < 6; ++frame) {
                const bool cut = frame == 3;
                const Image& expected = pixels.render(frame, cut);
                const std::string name = variant.name + ", tiles of " + std::to_string(side) +
                                         ", frame " + std::to_string(frame);
                expect_same(tiles.render(frame, cut), expected, name);
                expect_same(loaded_tiles.render(frame, cut), expected, name + ", loaded history");
            }
            // The tiles answer a question asked twice (the balance heuristic's) once.
            EXPECT_LE(tiles.rays, pixels.rays) << variant.name << ": no more rays";
            if (side > 1) {
                EXPECT_LT(tiles.batches, tiles.rays) << variant.name << ": rays come in batches";
            }
        }
    }
}

TEST(DiFrame, WithoutHistoryTemporalReturnsItsInput) {
    const Frame no_history{};
    EXPECT_FALSE(no_history.has_history());
    EXPECT_EQ(no_history.step_count(), 3u) << "initial, spatial, finish";
    Reservoir<LightId> current;
    current.stream({3u}, 2.0f, 1.0f, 0.5f);
    current.finalize();
    restir::Pcg32 rng;
    const restir::ReuseBridge bridge{Target{}, Visibility{}};
    const Reservoir<LightId> result = no_history.temporal(
        {0, 0}, current, no_history.temporal_input({0, 0}, bridge), bridge, rng);
    EXPECT_EQ(result.sample.id, 3u);
    EXPECT_EQ(result.contribution_weight, current.contribution_weight);
    EXPECT_EQ(result.candidate_count, current.candidate_count);
    EXPECT_EQ(rng.next_uint(), restir::Pcg32{}.next_uint()) << "no random number drawn";
}

// The steps: stages in order, writers alternating so that the last writes `out` (buffer 0),
// each reading what the one before wrote, `finish` in place on `out`; retests before a
// spatial pass whose MIS weights trace rays (none under 1/M, which traces none), and in the last
// reuse step where that spares `finish` its rays.
TEST(DiFrame, StepsPingPongIntoOutAndRetestOnlyWhereNeeded) {
    const Reservoir<LightId> history[1]{};
    for (std::uint32_t passes : {0u, 1u, 2u, 3u})
        for (bool with_history : {false, true})
            for (bool boiling : {false, true})
                for (restir::ReuseVisibility v :
                     {restir::ReuseVisibility::none, restir::ReuseVisibility::assumed,
                      restir::ReuseVisibility::traced}) {
                    Frame f{};
                    f.params.spatial_passes = passes;
                    f.params.boiling_filter = boiling;
                    f.params.visibility = v;
                    const Patch previous[1]{};
                    if (with_history) {
                        f.history = {history, 1u, 1u};
                        f.previous_surfaces = {previous, 1u, 1u};
                    }
                    const std::string name = std::to_string(passes) + " passes, history " +
                                             std::to_string(with_history) + ", boiling " +
                                             std::to_string(boiling) + ", visibility " +
                                             std::to_string(static_cast<int>(v));
                    const std::uint32_t count = f.step_count();
                    ASSERT_EQ(count, 2u + (with_history ? 1u : 0u) + passes + (boiling ? 1u : 0u))
                        << name;
                    std::vector<restir::DiStage> stages;
                    for (std::uint32_t i = 0; i < count; ++i) {
                        const restir::DiStep s = f.step(i);
                        stages.push_back(s.stage);
                        if (i > 0u && i + 1u < count) {
                            EXPECT_EQ(s.input, f.step(i - 1u).output) << name << ", step " << i;
                        }
                        const bool before_spatial =
                            i + 1u < count && f.step(i + 1u).stage == restir::DiStage::spatial;
                        // The last reuse step, right before finish, retests for finish when
                        // its input was tested throughout: the initial stage's, or after
                        // retests for the MIS rays.
                        const std::uint32_t reuse_steps = (with_history ? 1u : 0u) + passes;
                        const bool last_reuse = i > 0u && !boiling && i + 2u == count;
                        const auto for_finish = [&](bool mis_retests) {
                            return last_reuse && restir::carries_visibility(v) &&
                                   (reuse_steps == 1u || mis_retests);
                        };
                        const bool traced = v == restir::ReuseVisibility::traced;
                        EXPECT_EQ(s.retest,
                                  (i > 0u && before_spatial && traced) || for_finish(traced))
                            << name << ", step " << i;
                        EXPECT_EQ(
                            f.finish_retests(),
                            !restir::carries_visibility(v) ||
                                (reuse_steps > 0u && (boiling || !(reuse_steps == 1u || traced))))
                            << name;
                        Frame one_over_m = f;
                        one_over_m.params.spatial_bias_correction = BiasCorrection::none;
                        EXPECT_EQ(one_over_m.step(i).retest, for_finish(false))
                            << name << ", step " << i;
                    }
                    EXPECT_EQ(f.step(count - 2u).output, 0u)
                        << name << ": the last writer writes out";
                    EXPECT_EQ(f.step(count - 1u).output, 0u) << name;
                    std::vector<restir::DiStage> expected{restir::DiStage::initial};
                    if (with_history)
                        expected.push_back(restir::DiStage::temporal);
                    for (std::uint32_t p = 0; p < passes; ++p)
                        expected.push_back(restir::DiStage::spatial);
                    if (boiling)
                        expected.push_back(restir::DiStage::boiling);
                    expected.push_back(restir::DiStage::finish);
                    EXPECT_EQ(stages, expected) << name;
                }
}

TEST(DiFrame, VisibilityIsRetestedOnlyForSamplesAPassBroughtIn) {
    Frame f{};
    Reservoir<LightId> kept, moved, empty;
    kept.stream({1u}, 1.0f, 1.0f, 0.5f);
    kept.finalize();
    moved.stream({2u}, 1.0f, 1.0f, 0.5f);
    moved.finalize();
    EXPECT_FALSE(f.retests(kept, kept));
    EXPECT_TRUE(f.retests(moved, kept));
    EXPECT_TRUE(f.retests(moved, empty));
    EXPECT_FALSE(f.retests(empty, kept));
    EXPECT_TRUE(f.tests(kept));
    EXPECT_FALSE(f.tests(empty));
    f.params.visibility = restir::ReuseVisibility::none;
    EXPECT_FALSE(f.tests(kept)) << "no visibility reuse: reservoirs are never tested";
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

// With spatial_draw_span > 1 a pixel reuses from the offsets that the first pixel of its span
// draws with the first two numbers of its generator of the pass; the pixel's own generator
// gives them only where it is that first pixel.
TEST(DiFrame, PixelsOfASpanTakeTheNeighbourDrawOfItsFirst) {
    const auto rngs = [](PixelCoord q, std::uint32_t stream) { return rng_for(q, 5u, stream, 9u); };
    for (std::uint32_t span : {1u, 2u, 4u}) {
        restir::DiFrameParams p = restir::default_di_frame_params();
        p.spatial_draw_span = span;
        const Frame f{.params = p};
        for (std::int32_t x = 0; x < 9; ++x) {
            SCOPED_TRACE(::testing::Message() << "span " << span << ", x " << x);
            const PixelCoord pixel{x, 1};
            restir::Pcg32 own = rngs(pixel, RngStream::spatial + 1u);
            restir::Pcg32 untouched = own;
            const restir::NeighbourDraw draw = f.neighbour_draw(pixel, 1u, own, rngs);
            const auto s = static_cast<std::int32_t>(span);
            restir::Pcg32 first = rngs({x - x % s, 1}, RngStream::spatial + 1u);
            const restir::NeighbourDraw expected = restir::draw_neighbours(first);
            EXPECT_EQ(draw.start, expected.start);
            EXPECT_EQ(draw.rotation.x, expected.rotation.x);
            EXPECT_EQ(draw.rotation.y, expected.rotation.y);
            if (x % s == 0)
                restir::draw_neighbours(untouched);
            EXPECT_EQ(own.next_uint(), untouched.next_uint());
        }
    }
}

// Whole frames through the recipe are unbiased at every pixel (the figure a renderer shows),
// for the unbiased modes with two spatial passes after temporal reuse, over 12 frames with a
// camera cut in frame 6.
class UnbiasedRecipe : public ::testing::TestWithParam<BiasCorrection> {};

void expect_unbiased_recipe(const restir::DiFrameParams& p) {
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

TEST_P(UnbiasedRecipe, MeanMatchesTruthAtEveryPixel) {
    restir::DiFrameParams p = restir::default_di_frame_params();
    p.temporal_bias_correction = GetParam();
    p.spatial_bias_correction = GetParam();
    p.spatial.radius = 2.0f;
    p.spatial_passes = 2u;
    expect_unbiased_recipe(p);
}

// The same with one neighbour draw per 2 and per 3 pixels of a row (pairwise MIS).
TEST(UnbiasedRecipeSharedDraws, MeanMatchesTruthAtEveryPixel) {
    for (std::uint32_t span : {2u, 3u}) {
        SCOPED_TRACE(::testing::Message() << "span " << span);
        restir::DiFrameParams p = restir::default_di_frame_params();
        p.spatial.radius = 2.0f;
        p.spatial_passes = 2u;
        p.spatial_draw_span = span;
        expect_unbiased_recipe(p);
    }
}

// The unbiased presets (restir::DiFramePreset; the radius made the synthetic image's). The
// fast preset assumes visibility in its weights and is biased near shadows by design.
TEST(UnbiasedRecipePresets, MeanMatchesTruthAtEveryPixel) {
    for (const restir::DiFramePreset preset :
         {restir::DiFramePreset::unbiased, restir::DiFramePreset::balanced}) {
        SCOPED_TRACE(::testing::Message() << "preset " << static_cast<int>(preset));
        restir::DiFrameParams p = restir::di_frame_preset(preset);
        p.spatial.radius = 2.0f;
        expect_unbiased_recipe(p);
    }
}

// What each preset changes of the paper's settings.
TEST(DiFramePresets, ChangeOnlyWhatTheyName) {
    const restir::DiFrameParams paper = restir::default_di_frame_params();
    const restir::DiFrameParams unbiased = restir::di_frame_preset(restir::DiFramePreset::unbiased);
    EXPECT_EQ(unbiased.spatial.neighbour_count, 5u);
    EXPECT_EQ(unbiased.temporal.history_cap_multiplier, 4u);
    EXPECT_TRUE(unbiased.temporal.permutation_sampling);
    EXPECT_EQ(unbiased.visibility, paper.visibility);
    const restir::DiFrameParams balanced = restir::di_frame_preset(restir::DiFramePreset::balanced);
    EXPECT_EQ(balanced.spatial.neighbour_count, paper.spatial.neighbour_count);
    EXPECT_EQ(balanced.temporal.history_cap_multiplier, paper.temporal.history_cap_multiplier);
    EXPECT_EQ(balanced.temporal.permutation_sampling, paper.temporal.permutation_sampling);
    EXPECT_EQ(balanced.visibility, restir::ReuseVisibility::traced);
    EXPECT_EQ(unbiased.spatial.radius, paper.spatial.radius);
    EXPECT_EQ(balanced.spatial.radius, paper.spatial.radius / 2.0f);
    const restir::DiFrameParams fast = restir::di_frame_preset(restir::DiFramePreset::fast);
    EXPECT_EQ(fast.visibility, restir::ReuseVisibility::assumed);
    EXPECT_EQ(fast.spatial.neighbour_count, balanced.spatial.neighbour_count);
    EXPECT_EQ(fast.spatial.radius, balanced.spatial.radius);
    EXPECT_EQ(unbiased.spatial_bias_correction, BiasCorrection::pairwise);
    EXPECT_EQ(unbiased.temporal_bias_correction, BiasCorrection::pairwise);
    EXPECT_EQ(unbiased.spatial.min_roughness, 0.1f);
    EXPECT_EQ(unbiased.temporal.permutation_min_roughness, 0.1f);
    EXPECT_EQ(paper.spatial.min_roughness, 0.0f);
    EXPECT_EQ(paper.temporal.permutation_min_roughness, 0.0f);
    for (const restir::DiFrameParams& p : {balanced, fast}) {
        EXPECT_EQ(p.spatial_bias_correction, BiasCorrection::defensive_pairwise);
        EXPECT_EQ(p.temporal_bias_correction, BiasCorrection::defensive_pairwise);
        EXPECT_EQ(p.spatial.min_roughness, 0.15f);
    }
    for (const restir::DiFrameParams& p : {unbiased, balanced, fast})
        EXPECT_FALSE(p.boiling_filter);
}

std::string mode_name(const ::testing::TestParamInfo<BiasCorrection>& param) {
    const char* const names[] = {"none", "one_over_z", "balance_heuristic", "pairwise",
                                 "defensive_pairwise"};
    return names[static_cast<int>(param.param)];
}

INSTANTIATE_TEST_SUITE_P(Modes, UnbiasedRecipe,
                         ::testing::Values(BiasCorrection::one_over_z,
                                           BiasCorrection::balance_heuristic,
                                           BiasCorrection::pairwise,
                                           BiasCorrection::defensive_pairwise),
                         mode_name);

} // namespace
