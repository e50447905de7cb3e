// Compile check: the core templates inside a __global__ kernel (built by scripts/test.sh
// when nvcc is available; never run in CI).
#include <restir/restir.hpp>

#include <glm/geometric.hpp>

#include <cstdint>

namespace {

struct UniformDraw {
    std::uint32_t light_count;
    RESTIR_HOST_DEVICE restir::SourceSample<restir::LightSampleRef>
    operator()(restir::Pcg32& rng) const {
        const restir::UniformLightSampler sampler{light_count};
        const restir::DiscreteSample choice = restir::sample_light(sampler, rng);
        const float u = next_float(rng);
        const float v = next_float(rng);
        return {{choice.index, glm::vec2(u, v)}, choice.pmf};
    }
};

struct DistanceTarget {
    const glm::vec3* light_positions;
    glm::vec3 receiver;
    RESTIR_HOST_DEVICE float operator()(const restir::LightSampleRef& ref) const {
        const glm::vec3 d = light_positions[ref.light_id] - receiver;
        return restir::yuksel_attenuation(glm::length(d), 0.1f);
    }
};

} // namespace

__global__ void ris_kernel(const glm::vec3* light_positions, std::uint32_t light_count,
                           const restir::AliasEntry* alias_entries, float* out) {
    const auto pixel = static_cast<std::uint32_t>(blockIdx.x * blockDim.x + threadIdx.x);
    restir::Pcg32 rng = restir::make_pixel_rng(pixel, 0u, 0u, 7u);
    const DistanceTarget target{light_positions, glm::vec3(static_cast<float>(pixel), 0.0f, 0.0f)};
    restir::Reservoir<restir::LightSampleRef> reservoir =
        restir::resample_ris(rng, 32u, UniformDraw{light_count}, target);

    restir::Reservoir<restir::LightSampleRef> other = reservoir;
    other.cap_candidate_count(20u);
    reservoir.merge(other, target(other.sample), next_float(rng));
    reservoir.finalize();
    reservoir.sanitize();

    const restir::PowerLightSampler power{restir::AliasTableView{alias_entries, light_count}};
    const restir::DiscreteSample choice = restir::sample_light(power, rng);
    out[pixel] = reservoir.contribution_weight * target(reservoir.sample) + choice.pmf +
                 restir::attenuate(restir::Attenuation::clamped_inverse_square, 1.0f, 0.5f);
}
