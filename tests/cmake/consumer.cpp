// A downstream program: resamples one of three lights and checks the estimate is finite.
#include <restir/restir.hpp>

#include <cstdint>
#include <cstdio>

int main() {
    const float power[] = {1.0f, 2.0f, 5.0f};
    const restir::AliasTable table(power);
    const restir::PowerLightSampler sampler{table.view()};
    restir::Pcg32 rng = restir::make_pixel_rng(0u, 0u, 0u);
    const auto draw = [&](restir::Pcg32& r) {
        const restir::DiscreteSample c = restir::sample_light(sampler, r);
        return restir::SourceSample<std::uint32_t>{c.index, c.pmf};
    };
    const auto target = [&](std::uint32_t light) { return power[light]; };
    const auto reservoir = restir::resample_ris(rng, 8u, draw, target);
    const float estimate = power[reservoir.sample] * reservoir.contribution_weight;
    std::printf("restir %d.%d.%d: estimate %.3f (exact 8)\n", RESTIR_VERSION_MAJOR,
                RESTIR_VERSION_MINOR, RESTIR_VERSION_PATCH, static_cast<double>(estimate));
    // Target proportional to the source: every estimate equals the total power.
    return restir::is_finite(estimate) && estimate > 7.99f && estimate < 8.01f ? 0 : 1;
}
