// Shared by the furnace tests: a BSDF's directional albedo from its own sampling, one pixel's
// radiance over many frames, each per channel, and the pixels' radiance over many frames.
#pragma once

#include "renderer.hpp"

#include "support/statistics.hpp"

#include <restir/restir.hpp>

namespace pt::test {

/// Statistics of each colour channel, indexed 0 to 2.
struct ChannelStats {
    restir::test::RunningStats channels[3];
    restir::test::RunningStats& operator[](int c) { return channels[c]; }
    const restir::test::RunningStats& operator[](int c) const { return channels[c]; }
};

/// A(wo), the integral of f cos over the hemisphere of `bsdf` at `normal` towards `wo`, as the
/// mean of the weights of `count` of its own samples drawn from `rng`.
inline ChannelStats directional_albedo(const restir::GlossyBsdf& bsdf, glm::vec3 normal,
                                       glm::vec3 wo, int count, restir::Pcg32 rng) {
    ChannelStats albedo;
    for (int i = 0; i < count; ++i) {
        const float u_lobe = next_float(rng), u0 = next_float(rng), u1 = next_float(rng);
        const restir::BsdfSample b = bsdf.sample(normal, wo, u_lobe, u0, u1);
        for (int c = 0; c < 3; ++c)
            albedo[c].add(b.pdf > 0.0f ? static_cast<double>(b.weight[c]) : 0.0);
    }
    return albedo;
}

/// Pixel 0's radiance in each of `frames` frames of `renderer`.
inline ChannelStats pixel_radiance(Renderer& renderer, int frames) {
    ChannelStats radiance;
    for (int frame = 0; frame < frames; ++frame) {
        renderer.render_frame();
        for (int c = 0; c < 3; ++c)
            radiance[c].add(static_cast<double>(renderer.last_frame().pixels[0][c]));
    }
    return radiance;
}

/// Every pixel's mean over the colour channels in each of `frames` frames of `renderer`.
inline restir::test::RunningStats pixel_means(Renderer& renderer, int frames) {
    restir::test::RunningStats radiance;
    for (int frame = 0; frame < frames; ++frame) {
        renderer.render_frame();
        for (const glm::vec3& p : renderer.last_frame().pixels)
            radiance.add(static_cast<double>(p.x + p.y + p.z) / 3.0);
    }
    return radiance;
}

} // namespace pt::test
