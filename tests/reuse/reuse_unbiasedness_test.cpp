// Unbiasedness of temporal, spatial and combined reuse under every bias correction, on the
// synthetic image of synthetic_image.hpp (a known answer per pixel).
#include <restir/restir.hpp>

#include "reuse/synthetic_image.hpp"
#include "support/statistics.hpp"

#include <gtest/gtest.h>

#include <array>
#include <cmath>
#include <cstdint>
#include <cstdio>
#include <ostream>
#include <string>
#include <vector>

namespace {

using restir::BiasCorrection;
using restir::PixelCoord;
using restir::Reservoir;
using restir::test::RunningStats;

using namespace restir::test::synthetic;

// both: temporal then spatial; fused: one spatiotemporal pass over the previous frame;
// two_spatial: two spatial passes in one frame, the second reusing the first's output.
enum class Passes { spatial, temporal, both, fused, two_spatial };

struct ReuseSetup {
    BiasCorrection mode;
    Passes passes;
    bool visibility_reuse = true;
    // Visibility tested again after every pass that feeds another, and the passes told that
    // their inputs' own samples are tested (ReuseVisibility::traced_inputs_tested).
    bool retest = false;
    bool mis_rays = true; // false: ReuseVisibility::assumed
    bool glossy = false;  // the glossy world (GGX receivers) instead of the plain one
    // Initial candidates from two strategies (resample_ris_mis): lights uniformly, and lights
    // in proportion to the receiver's BSDF density towards them (the glossy world's guided_pmf).
    bool guided = false;
    bool sky = false; // the sky world: a third of the lights distant (directions)
    // Permutation sampling, and receivers smoother than 0.3 (the first two columns) take
    // neither spatial neighbours nor a permuted history (`min_roughness`,
    // `permutation_min_roughness`).
    bool smooth_apart = false;
};

std::string name_of(const ReuseSetup& s) {
    const char* modes[] = {"none", "one_over_z", "balance_heuristic", "pairwise",
                           "defensive_pairwise"};
    const char* passes[] = {"spatial", "temporal", "both", "fused", "two_spatial"};
    return std::string(modes[static_cast<int>(s.mode)]) + "/" + passes[static_cast<int>(s.passes)] +
           (s.visibility_reuse ? "" : "/no-visibility-reuse") + (s.retest ? "/retested" : "") +
           (s.mis_rays ? "" : "/ray-free") + (s.glossy ? "/glossy" : "") +
           (s.guided ? "/bsdf-candidates" : "") + (s.sky ? "/sky" : "") +
           (s.smooth_apart ? "/smooth-apart" : "");
}

void PrintTo(const ReuseSetup& setup, std::ostream* os) { *os << name_of(setup); }

// Runs `frames` frames of the pipeline (initial RIS, visibility, temporal, spatial, final
// visibility) and returns the per-pixel estimates f(y) W of the last frame for each trial.
class Pipeline {
public:
    explicit Pipeline(const ReuseSetup& setup)
        : setup_(setup), world_(setup.sky      ? &sky_world()
                                : setup.glossy ? &glossy_world()
                                               : &world()) {
        reuse_.bias_correction = setup.mode;
        reuse_.visibility = !setup.visibility_reuse ? restir::ReuseVisibility::none
                            : !setup.mis_rays       ? restir::ReuseVisibility::assumed
                            : setup.retest          ? restir::ReuseVisibility::traced_inputs_tested
                                                    : restir::ReuseVisibility::traced;
        spatial_.neighbour_count = 3u;
        spatial_.radius = 2.0f;
        if (setup.smooth_apart) {
            temporal_.permutation_sampling = true;
            temporal_.permutation_min_roughness = 0.3f;
            spatial_.min_roughness = 0.3f;
        }
    }

    // Per-pixel statistics of the last frame's estimates over `trials` independent runs.
    std::vector<RunningStats> run(std::uint32_t frames, std::uint32_t trials) {
        std::vector<RunningStats> stats(pixel_count);
        for (std::uint32_t trial = 0; trial < trials; ++trial) {
            history_.assign(pixel_count, Reservoir<LightId>{});
            for (std::uint32_t frame = 0; frame < frames; ++frame)
                render_frame(frame, trial);
            for (std::uint32_t p = 0; p < pixel_count; ++p) {
                const Reservoir<LightId>& r = final_[p];
                const Patch& s = surfaces_[p];
                const double estimate = s.valid ? world_->integrand(s.id, r.sample.id) *
                                                      static_cast<double>(r.contribution_weight)
                                                : 0.0;
                stats[p].add(estimate);
            }
        }
        return stats;
    }

    double truth(std::uint32_t pixel, std::uint32_t last_frame) const {
        const Patch s = patch_seen(pixel_of(pixel), last_frame);
        return s.valid ? world_->truth[s.id] : 0.0;
    }

private:
    void render_frame(std::uint32_t frame, std::uint32_t trial) {
        const restir::ReuseBridge bridge{Target{world_}, Visibility{world_}};
        std::vector<Patch> surfaces(pixel_count);
        std::vector<Reservoir<LightId>> current(pixel_count);
        const restir::UniformLightSampler sampler{light_count};
        for (std::uint32_t i = 0; i < pixel_count; ++i) {
            surfaces[i] = patch_seen(pixel_of(i), frame);
            if (!surfaces[i].valid)
                continue;
            restir::Pcg32 rng = restir::make_pixel_rng(i, frame, 0u, trial);
            const Patch surface = surfaces[i];
            current[i] = initial_reservoir(surface, sampler, rng);
            if (setup_.visibility_reuse)
                restir::apply_visibility(current[i], surface, Visibility{world_});
        }

        const restir::ImageView<const Patch> surface_view{surfaces.data(), width, height};
        if (frame > 0 && setup_.passes == Passes::fused) {
            const restir::ImageView<const Reservoir<LightId>> previous{history_.data(), width,
                                                                       height};
            const restir::ImageView<const Patch> previous_surfaces{surfaces_.data(), width, height};
            std::vector<Reservoir<LightId>> fused(pixel_count);
            for (std::uint32_t i = 0; i < pixel_count; ++i) {
                restir::Pcg32 rng = restir::make_pixel_rng(i, frame, 1u, trial);
                fused[i] = restir::spatiotemporal_resample(
                    pixel_of(i), current[i], surfaces[i], previous, previous_surfaces, Reproject{},
                    temporal_, spatial_, reuse_, frame, bridge, rng, offsets_);
            }
            current = fused;
        }
        if (frame > 0 && (setup_.passes == Passes::temporal || setup_.passes == Passes::both)) {
            const restir::ImageView<const Reservoir<LightId>> previous{history_.data(), width,
                                                                       height};
            const restir::ImageView<const Patch> previous_surfaces{surfaces_.data(), width, height};
            std::vector<Reservoir<LightId>> temporal(pixel_count);
            for (std::uint32_t i = 0; i < pixel_count; ++i) {
                const PixelCoord p = pixel_of(i);
                restir::Pcg32 rng = restir::make_pixel_rng(i, frame, 1u, trial);
                temporal[i] = restir::temporal_resample(p, current[i], surfaces[i], previous,
                                                        previous_surfaces, Reproject{}, temporal_,
                                                        reuse_, frame, bridge, rng);
            }
            current = temporal;
            if (setup_.retest)
                test_visibility(current, surfaces);
        }
        const std::uint32_t spatial_passes =
            setup_.passes == Passes::two_spatial                                ? 2u
            : setup_.passes == Passes::spatial || setup_.passes == Passes::both ? 1u
                                                                                : 0u;
        for (std::uint32_t pass = 0; pass < spatial_passes; ++pass) {
            const restir::ImageView<const Reservoir<LightId>> input{current.data(), width, height};
            std::vector<Reservoir<LightId>> spatial(pixel_count);
            for (std::uint32_t i = 0; i < pixel_count; ++i) {
                const PixelCoord p = pixel_of(i);
                restir::Pcg32 rng = restir::make_pixel_rng(i, frame, 2u + pass, trial);
                spatial[i] = restir::spatial_resample(p, input, surface_view, spatial_, reuse_,
                                                      bridge, rng, offsets_);
            }
            current = spatial;
            if (setup_.retest)
                test_visibility(current, surfaces);
        }
        // Final shading ray; with visibility reuse it also zeroes W for the next frame.
        if (setup_.visibility_reuse)
            for (std::uint32_t i = 0; i < pixel_count; ++i)
                if (surfaces[i].valid)
                    restir::apply_visibility(current[i], surfaces[i], Visibility{world_});
        final_ = current;
        history_ = current;
        surfaces_ = surfaces;
    }

    void test_visibility(std::vector<Reservoir<LightId>>& reservoirs,
                         const std::vector<Patch>& surfaces) const {
        for (std::uint32_t i = 0; i < pixel_count; ++i)
            if (surfaces[i].valid)
                restir::apply_visibility(reservoirs[i], surfaces[i], Visibility{world_});
    }

    // RIS over uniformly chosen lights, or (guided) multi-strategy RIS that adds candidates
    // chosen by the receiver's BSDF density.
    Reservoir<LightId> initial_reservoir(const Patch& surface,
                                         const restir::UniformLightSampler& sampler,
                                         restir::Pcg32& rng) const {
        const Target target{world_};
        const auto uniform = [&](restir::Pcg32& g) {
            const restir::DiscreteSample c = restir::sample_light(sampler, g);
            return restir::SourceSample<LightId>{{c.index}, c.pmf};
        };
        if (!setup_.guided)
            return restir::resample_ris(rng, initial_candidates, uniform,
                                        [&](const LightId& x) { return target(x, surface); });
        const auto& guided = world_->guided_pmf[surface.id];
        const restir::SourceStrategy lights{
            initial_candidates, [&](restir::Pcg32& g) { return uniform(g).sample; },
            [&](const LightId&) { return 1.0f / static_cast<float>(light_count); }};
        const restir::SourceStrategy bsdf{2u,
                                          [&](restir::Pcg32& g) {
                                              float u = next_float(g);
                                              std::uint32_t l = 0;
                                              while (l + 1u < light_count && u >= guided[l])
                                                  u -= guided[l++];
                                              return LightId{l};
                                          },
                                          [&](const LightId& x) { return guided[x.id]; }};
        return restir::resample_ris_mis(
            rng, [&](const LightId& x) { return target(x, surface); }, lights, bsdf);
    }

    ReuseSetup setup_;
    const World* world_;
    restir::TemporalParams temporal_ = restir::default_temporal_params();
    restir::SpatialParams spatial_ = restir::default_spatial_params();
    restir::ReuseParams reuse_{};
    restir::NeighbourOffsets offsets_ = restir::make_neighbour_offsets();
    std::vector<Reservoir<LightId>> history_, final_;
    std::vector<Patch> surfaces_;
};

constexpr std::uint32_t temporal_frames = 20;

bool single_frame(Passes passes) {
    return passes == Passes::spatial || passes == Passes::two_spatial;
}
std::uint32_t frames_for(Passes passes) { return single_frame(passes) ? 1u : temporal_frames; }
std::uint32_t trials_for(Passes passes) { return single_frame(passes) ? 40'000u : 4'000u; }

// Prints the pixel-averaged relative bias and relative standard deviation of one estimate
// (the figures in docs/noise-and-bias.md come from these lines).
void report(const std::string& label, const Pipeline& pipeline,
            const std::vector<RunningStats>& stats, std::uint32_t last_frame) {
    double bias_sum = 0.0;
    double deviation_sum = 0.0;
    std::uint32_t counted = 0;
    for (std::uint32_t p = 0; p < pixel_count; ++p) {
        const double truth = pipeline.truth(p, last_frame);
        if (truth <= 0.0)
            continue;
        bias_sum += (stats[p].mean() - truth) / truth;
        deviation_sum += std::sqrt(stats[p].variance()) / truth;
        ++counted;
    }
    std::printf("%-40s relative bias %+.4f, relative standard deviation %.3f\n", label.c_str(),
                bias_sum / static_cast<double>(counted),
                deviation_sum / static_cast<double>(counted));
}

class UnbiasedReuse : public ::testing::TestWithParam<ReuseSetup> {};

TEST_P(UnbiasedReuse, MeanMatchesTruthAtEveryPixel) {
    const ReuseSetup setup = GetParam();
    Pipeline pipeline(setup);
    const std::uint32_t frames = frames_for(setup.passes);
    const std::vector<RunningStats> stats = pipeline.run(frames, trials_for(setup.passes));
    report(name_of(setup), pipeline, stats, frames - 1u);
    for (std::uint32_t p = 0; p < pixel_count; ++p)
        EXPECT_TRUE(restir::test::agrees_with(stats[p], pipeline.truth(p, frames - 1u)))
            << name_of(setup) << ", pixel " << p;
}

std::vector<ReuseSetup> unbiased_setups() {
    std::vector<ReuseSetup> setups;
    for (BiasCorrection mode : {BiasCorrection::one_over_z, BiasCorrection::balance_heuristic,
                                BiasCorrection::pairwise, BiasCorrection::defensive_pairwise})
        for (Passes passes :
             {Passes::spatial, Passes::two_spatial, Passes::temporal, Passes::both, Passes::fused})
            setups.push_back({mode, passes, true});
    for (BiasCorrection mode :
         {BiasCorrection::one_over_z, BiasCorrection::balance_heuristic, BiasCorrection::pairwise})
        setups.push_back({mode, Passes::both, false});
    for (BiasCorrection mode :
         {BiasCorrection::one_over_z, BiasCorrection::balance_heuristic, BiasCorrection::pairwise})
        for (Passes passes : {Passes::both, Passes::two_spatial})
            setups.push_back({mode, passes, true, true});
    // Glossy receivers (roughness 0.05 to 1 along each row, a metal row), with and without
    // BSDF-guided candidates.
    for (BiasCorrection mode : {BiasCorrection::one_over_z, BiasCorrection::balance_heuristic,
                                BiasCorrection::pairwise, BiasCorrection::defensive_pairwise})
        for (Passes passes : {Passes::two_spatial, Passes::both, Passes::fused})
            for (bool guided : {false, true}) {
                ReuseSetup setup{mode, passes, true};
                setup.glossy = true;
                setup.guided = guided;
                setups.push_back(setup);
            }
    // Smooth receivers apart: no spatial neighbours, their own pixel's history.
    for (BiasCorrection mode : {BiasCorrection::balance_heuristic, BiasCorrection::pairwise,
                                BiasCorrection::defensive_pairwise})
        for (Passes passes : {Passes::two_spatial, Passes::both, Passes::fused}) {
            ReuseSetup setup{mode, passes, true};
            setup.glossy = true;
            setup.smooth_apart = true;
            setups.push_back(setup);
        }
    // Distant lights (an environment's directions) beside points, at glossy receivers.
    for (BiasCorrection mode :
         {BiasCorrection::one_over_z, BiasCorrection::balance_heuristic, BiasCorrection::pairwise})
        for (Passes passes : {Passes::two_spatial, Passes::both, Passes::fused}) {
            ReuseSetup setup{mode, passes, true};
            setup.sky = true;
            setups.push_back(setup);
        }
    return setups;
}

INSTANTIATE_TEST_SUITE_P(Modes, UnbiasedReuse, ::testing::ValuesIn(unbiased_setups()),
                         [](const ::testing::TestParamInfo<ReuseSetup>& param_info) {
                             std::string name = name_of(param_info.param);
                             for (char& c : name)
                                 if (c == '/' || c == '-')
                                     c = '_';
                             return name;
                         });

} // namespace

namespace {

// "none" (1/M) gives every input the same share whether or not it can produce a sample, so a
// receiver whose neighbours cannot produce some of its lights (other patches: different
// supports and occluders) comes out darker. Spatial reuse: every shaded pixel has such
// neighbours here.
TEST(BiasedReuse, SpatialOneOverMDarkensEveryPixel) {
    Pipeline pipeline({BiasCorrection::none, Passes::spatial, true});
    const std::vector<RunningStats> stats = pipeline.run(1u, trials_for(Passes::spatial));
    report("none/spatial", pipeline, stats, 0u);
    for (std::uint32_t p = 0; p < pixel_count; ++p) {
        const double truth = pipeline.truth(p, 0u);
        if (truth == 0.0)
            continue;
        EXPECT_TRUE(restir::test::differs_from(stats[p], truth)) << "pixel " << p;
        EXPECT_LT(stats[p].mean(), truth) << "pixel " << p;
    }
}

// Temporal reuse with 1/M is unbiased where the history is the same patch (rows 0 and 2,
// correct motion vectors) and darker where it is another patch (row 1, whose motion vectors
// point one pixel too far), except where that pixel falls outside the image (no history).
TEST(BiasedReuse, TemporalOneOverMIsBiasedExactlyWhereTheHistoryIsAnotherSurface) {
    Pipeline pipeline({BiasCorrection::none, Passes::temporal, true});
    const std::uint32_t last = temporal_frames - 1u;
    const std::vector<RunningStats> stats =
        pipeline.run(temporal_frames, trials_for(Passes::temporal));
    report("none/temporal", pipeline, stats, last);
    for (std::uint32_t p = 0; p < pixel_count; ++p) {
        const double truth = pipeline.truth(p, last);
        const std::uint32_t x = p % width, y = p / width;
        const bool other_surface = y == 1u && x + 2u < width;
        if (other_surface) {
            EXPECT_TRUE(restir::test::differs_from(stats[p], truth)) << "pixel " << p;
            EXPECT_LT(stats[p].mean(), truth) << "pixel " << p;
        } else {
            EXPECT_TRUE(restir::test::agrees_with(stats[p], truth)) << "pixel " << p;
        }
    }
}

} // namespace

namespace {

// With both passes, or fused, 1/M darkens on average: reported, and the average relative bias
// over the pixels must be clearly negative.
TEST(BiasedReuse, OneOverMDarkensTheImageWithBothPasses) {
    for (Passes passes : {Passes::both, Passes::fused}) {
        const ReuseSetup setup{BiasCorrection::none, passes, true};
        Pipeline pipeline(setup);
        const std::uint32_t last = temporal_frames - 1u;
        const std::vector<RunningStats> stats = pipeline.run(temporal_frames, trials_for(passes));
        report(name_of(setup), pipeline, stats, last);
        RunningStats pixel_biases;
        for (std::uint32_t p = 0; p < pixel_count; ++p)
            if (pipeline.truth(p, last) > 0.0)
                pixel_biases.add((stats[p].mean() - pipeline.truth(p, last)) /
                                 pipeline.truth(p, last));
        EXPECT_LT(pixel_biases.mean(), -0.05) << name_of(setup);
    }
}

// Ray-free MIS weights (every sample taken as visible from every neighbour inside the weights)
// under visibility reuse: a neighbour that sees the light occluded is given weight for samples
// it could not have lent, so the image comes out darker where visibility differs between
// neighbours. Reported, and the average relative bias over the pixels must be negative beyond
// its measured spread.
TEST(BiasedReuse, RayFreeMisWeightsDarkenWhereVisibilityDiffers) {
    for (BiasCorrection mode : {BiasCorrection::balance_heuristic, BiasCorrection::pairwise}) {
        ReuseSetup setup{mode, Passes::spatial, true};
        setup.mis_rays = false;
        Pipeline pipeline(setup);
        const std::vector<RunningStats> stats = pipeline.run(1u, trials_for(Passes::spatial));
        report(name_of(setup), pipeline, stats, 0u);
        RunningStats pixel_biases;
        std::uint32_t darker = 0;
        for (std::uint32_t p = 0; p < pixel_count; ++p) {
            const double truth = pipeline.truth(p, 0u);
            if (!(truth > 0.0))
                continue;
            pixel_biases.add((stats[p].mean() - truth) / truth);
            darker += restir::test::differs_from(stats[p], truth) && stats[p].mean() < truth;
        }
        EXPECT_LT(pixel_biases.mean() + 4.0 * pixel_biases.standard_error(), 0.0) << name_of(setup);
        EXPECT_GT(darker, 0u) << name_of(setup);
    }
}

} // namespace
