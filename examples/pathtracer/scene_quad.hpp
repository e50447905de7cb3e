// Quads as pairs of triangles: how the built-in scenes (scene_cornell.cpp,
// scene_many_lights.cpp) add their geometry.
#pragma once

#include "scene.hpp"

#include <glm/vec3.hpp>

#include <array>
#include <cstdint>

namespace pt {

using Quad = std::array<glm::vec3, 4>;

/// Appends `quad` as the triangles (a, b, c) and (a, c, d), reversing its winding first when
/// its normal does not point along `towards`.
void add_quad(Scene& scene, Quad quad, glm::vec3 towards, std::uint32_t material);

} // namespace pt
