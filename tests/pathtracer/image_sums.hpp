// The brightness of a small render: what the renderer's statistical tests compare across
// methods and seeds.
#pragma once

#include "renderer.hpp"
#include "scene.hpp"

#include <cstdint>

namespace pt::test {

/// Sum of the pixels' channels of the accumulated image after `frames` frames of `s`.
inline double brightness(const pt::Scene& scene, const pt::RenderSettings& s,
                         std::uint32_t frames) {
    pt::Renderer renderer(scene, s);
    for (std::uint32_t f = 0; f < frames; ++f)
        renderer.render_frame();
    double sum = 0.0;
    for (const glm::vec3& p : renderer.accumulated().pixels)
        sum += static_cast<double>(p.x + p.y + p.z);
    return sum;
}

} // namespace pt::test
