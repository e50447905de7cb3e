// Microbenchmarks of the weighted reservoir and the alias table.
//
// BM_Reservoir_Stream and BM_Baseline_HandWrittenStream stream the same precomputed
// candidates (weights, target values and uniform numbers live in arrays, so random number
// generation is not measured) and must stay in this one binary: docs/performance.md reports
// the ratio of their throughputs as measured in a single run.
#include "restir/core/math.hpp"
#include "restir/core/reservoir.hpp"
#include "restir/sampling/alias_table.hpp"

#include <benchmark/benchmark.h>

#include <bit>
#include <cstddef>
#include <cstdint>
#include <limits>
#include <random>
#include <vector>

namespace {

constexpr std::size_t kStreamLength = 4096;    // Candidates per reservoir in the stream benchmarks.
constexpr std::size_t kMergeCount = 4096;      // Reservoirs merged into one per iteration.
constexpr std::size_t kSampleBatch = 4096;     // Alias-table draws per iteration.
constexpr std::size_t kUniformPool = 1u << 20; // Precomputed uniform pairs for alias sampling.

// Candidates of a stream: one resampling weight, target value and uniform number each.
// About 1 in 32 weights is zero (a candidate whose target function vanishes) and about 1 in
// 128 is invalid (NaN, infinite or negative), so both rejection paths are exercised.
struct StreamData {
    std::vector<std::uint32_t> candidates;
    std::vector<float> weights;
    std::vector<float> targets;
    std::vector<float> uniforms;
};

const StreamData& stream_data() {
    static const StreamData data = [] {
        std::mt19937 engine(0x5eed0001u);
        std::uniform_real_distribution<float> unit(0.0f, 1.0f);
        std::uniform_real_distribution<float> positive(0.05f, 4.0f);
        StreamData d;
        d.candidates.resize(kStreamLength);
        d.weights.resize(kStreamLength);
        d.targets.resize(kStreamLength);
        d.uniforms.resize(kStreamLength);
        for (std::size_t i = 0; i < kStreamLength; ++i) {
            d.candidates[i] = static_cast<std::uint32_t>(engine());
            d.targets[i] = positive(engine);
            const float pdf = positive(engine);
            float weight = d.targets[i] / pdf;
            const std::uint32_t kind = engine() % 128u;
            if (kind < 4u) {
                weight = 0.0f;
            } else if (kind == 4u) {
                weight = std::numeric_limits<float>::quiet_NaN();
            } else if (kind == 5u) {
                weight = std::numeric_limits<float>::infinity();
            } else if (kind == 6u) {
                weight = -weight;
            }
            d.weights[i] = weight;
            d.uniforms[i] = unit(engine);
        }
        return d;
    }();
    return data;
}

// What a stream leaves: its fields, read out after the loop in both benchmarks.
struct HandWrittenResult {
    std::uint32_t sample;
    float weight_sum;
    float target_value;
    float contribution_weight;
    std::uint32_t candidate_count;
};

// The library's streaming update, then finalisation (Alg. 2 and Eq. 6).
void BM_Reservoir_Stream(benchmark::State& state) {
    const StreamData& d = stream_data();
    const std::uint32_t* candidates = d.candidates.data();
    const float* weights = d.weights.data();
    const float* targets = d.targets.data();
    const float* uniforms = d.uniforms.data();
    for (auto _ : state) {
        restir::Reservoir<std::uint32_t> reservoir;
        for (std::size_t i = 0; i < kStreamLength; ++i)
            reservoir.stream(candidates[i], weights[i], targets[i], uniforms[i]);
        reservoir.finalize();
        HandWrittenResult result{reservoir.sample, reservoir.weight_sum, reservoir.target_value,
                                 reservoir.contribution_weight, reservoir.candidate_count};
        benchmark::DoNotOptimize(result);
    }
    state.SetItemsProcessed(state.iterations() * static_cast<std::int64_t>(kStreamLength));
}
BENCHMARK(BM_Reservoir_Stream);

// The same weighted-reservoir update as a plain loop: a weight counts towards M whatever its
// value, and enters the sum only when it is finite and >= 0 (the same bit-pattern test as
// the library); W = w_sum / (M * target), 0 where that is not finite. `Checked` adds the
// library's other guarantees, so that the two loops compute the same thing: M saturates
// instead of wrapping, a sum that would overflow keeps its value (the candidate is not taken),
// and a kept target that is not a valid weight reads 0.
inline bool finite_bits(float x) {
    return (std::bit_cast<std::uint32_t>(x) & 0x7f800000u) != 0x7f800000u;
}

template <bool Checked>
void hand_written_stream(benchmark::State& state) {
    const StreamData& d = stream_data();
    const std::uint32_t* candidates = d.candidates.data();
    const float* weights = d.weights.data();
    const float* targets = d.targets.data();
    const float* uniforms = d.uniforms.data();
    for (auto _ : state) {
        std::uint32_t kept = 0u;
        float kept_target = 0.0f;
        float w_sum = 0.0f;
        std::uint32_t m = 0u;
        for (std::size_t i = 0; i < kStreamLength; ++i) {
            const float w = weights[i];
            m += Checked ? (m != 0xffffffffu ? 1u : 0u) : 1u;
            if (!(finite_bits(w) && w >= 0.0f))
                continue;
            const float sum = w_sum + w;
            if (Checked && !(sum <= std::numeric_limits<float>::max()))
                continue;
            w_sum = sum;
            if (uniforms[i] * w_sum < w) {
                kept = candidates[i];
                const float t = targets[i];
                kept_target = !Checked || (finite_bits(t) && t >= 0.0f) ? t : 0.0f;
            }
        }
        const float denominator = static_cast<float>(m) * kept_target;
        float contribution = 0.0f;
        if (denominator != 0.0f) {
            contribution = w_sum / denominator;
            if (!finite_bits(contribution))
                contribution = 0.0f;
        }
        HandWrittenResult result{kept, w_sum, kept_target, contribution, m};
        benchmark::DoNotOptimize(result);
    }
    state.SetItemsProcessed(state.iterations() * static_cast<std::int64_t>(kStreamLength));
}

// The fair baseline of BM_Reservoir_Stream: the same checks, written by hand.
void BM_Baseline_HandWrittenStream(benchmark::State& state) { hand_written_stream<true>(state); }
BENCHMARK(BM_Baseline_HandWrittenStream);

// Without the checks (M may wrap, the sum may overflow to infinity): what they cost.
void BM_Baseline_UncheckedStream(benchmark::State& state) { hand_written_stream<false>(state); }
BENCHMARK(BM_Baseline_UncheckedStream);

// Finalised reservoirs (each from 32 streamed candidates), with the target value of each
// one's sample at the receiving surface and a uniform number per merge.
struct MergeData {
    std::vector<restir::Reservoir<std::uint32_t>> inputs;
    std::vector<float> targets_at_receiver;
    std::vector<float> uniforms;
};

const MergeData& merge_data() {
    static const MergeData data = [] {
        std::mt19937 engine(0x5eed0002u);
        std::uniform_real_distribution<float> unit(0.0f, 1.0f);
        std::uniform_real_distribution<float> positive(0.05f, 4.0f);
        MergeData d;
        d.inputs.resize(kMergeCount);
        d.targets_at_receiver.resize(kMergeCount);
        d.uniforms.resize(kMergeCount);
        for (std::size_t i = 0; i < kMergeCount; ++i) {
            restir::Reservoir<std::uint32_t> r;
            for (int c = 0; c < 32; ++c) {
                const float target = positive(engine);
                r.stream(static_cast<std::uint32_t>(engine()), target / positive(engine), target,
                         unit(engine));
            }
            r.finalize();
            d.inputs[i] = r;
            d.targets_at_receiver[i] = positive(engine);
            d.uniforms[i] = unit(engine);
        }
        return d;
    }();
    return data;
}

// Spatial/temporal reuse step: many finalised reservoirs combined into one (Alg. 4).
void BM_Reservoir_Merge(benchmark::State& state) {
    const MergeData& d = merge_data();
    const restir::Reservoir<std::uint32_t>* inputs = d.inputs.data();
    const float* targets = d.targets_at_receiver.data();
    const float* uniforms = d.uniforms.data();
    for (auto _ : state) {
        restir::Reservoir<std::uint32_t> reservoir;
        for (std::size_t i = 0; i < kMergeCount; ++i)
            reservoir.merge(inputs[i], targets[i], uniforms[i]);
        reservoir.finalize();
        benchmark::DoNotOptimize(reservoir);
    }
    state.SetItemsProcessed(state.iterations() * static_cast<std::int64_t>(kMergeCount));
}
BENCHMARK(BM_Reservoir_Merge);

std::vector<float> random_weights(std::size_t count, std::uint32_t seed) {
    std::mt19937 engine(seed);
    std::uniform_real_distribution<float> weight(0.01f, 1.0f);
    std::vector<float> weights(count);
    for (float& w : weights)
        w = weight(engine);
    return weights;
}

// Pairs of uniform numbers for alias sampling; large enough that a 1M-entry table is
// visited at random rather than through the same few cached buckets.
struct UniformPairs {
    std::vector<float> bucket;
    std::vector<float> choice;
};

const UniformPairs& uniform_pairs() {
    static const UniformPairs pairs = [] {
        std::mt19937 engine(0x5eed0003u);
        std::uniform_real_distribution<float> unit(0.0f, 1.0f);
        UniformPairs p;
        p.bucket.resize(kUniformPool);
        p.choice.resize(kUniformPool);
        for (std::size_t i = 0; i < kUniformPool; ++i) {
            p.bucket[i] = unit(engine);
            p.choice[i] = unit(engine);
        }
        return p;
    }();
    return pairs;
}

// O(1) draws from an alias table over range(0) random weights.
void BM_AliasTable_Sample(benchmark::State& state) {
    const auto count = static_cast<std::size_t>(state.range(0));
    const std::vector<float> weights = random_weights(count, 0x5eed0004u);
    const restir::AliasTable table(weights);
    const restir::AliasTableView view = table.view();
    const UniformPairs& pairs = uniform_pairs();
    std::size_t offset = 0;
    for (auto _ : state) {
        const float* u_bucket = pairs.bucket.data() + offset;
        const float* u_choice = pairs.choice.data() + offset;
        // Integer xor keeps the accumulation off the critical path (a float sum would
        // serialise the draws on the adder's latency).
        std::uint32_t digest = 0u;
        for (std::size_t i = 0; i < kSampleBatch; ++i) {
            const restir::DiscreteSample s = view.sample(u_bucket[i], u_choice[i]);
            digest ^= s.index ^ std::bit_cast<std::uint32_t>(s.pmf);
        }
        benchmark::DoNotOptimize(digest);
        offset = (offset + kSampleBatch) % kUniformPool;
    }
    state.SetItemsProcessed(state.iterations() * static_cast<std::int64_t>(kSampleBatch));
}
BENCHMARK(BM_AliasTable_Sample)->Arg(1000)->Arg(1000000);

// Vose construction over range(0) random weights (allocation included).
void BM_AliasTable_Build(benchmark::State& state) {
    const auto count = static_cast<std::size_t>(state.range(0));
    const std::vector<float> weights = random_weights(count, 0x5eed0005u);
    for (auto _ : state) {
        restir::AliasTable table(weights);
        benchmark::DoNotOptimize(table.entries().data());
        benchmark::ClobberMemory();
    }
    state.SetItemsProcessed(state.iterations() * static_cast<std::int64_t>(count));
}
BENCHMARK(BM_AliasTable_Build)->Arg(1000000)->Unit(benchmark::kMillisecond);

} // namespace
