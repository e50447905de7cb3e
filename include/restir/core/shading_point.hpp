/// @file core/shading_point.hpp
/// Where a light is chosen for: the context that spatially aware light samplers read.
#pragma once

#include <glm/vec3.hpp>

#include <type_traits>

namespace restir {

/// A shading point: its position and unit normal (the side light is gathered on). A zero
/// normal means "any direction". A positive `radius` makes it a region, every point within
/// `radius` of `position` (a cell of a world-space grid, ReGIR): a sampler then serves all of
/// them, its pmf positive for every light that can light any of them.
struct ShadingPoint {
    glm::vec3 position{0.0f};
    glm::vec3 normal{0.0f};
    float radius = 0.0f;
};

static_assert(std::is_trivially_copyable_v<ShadingPoint>);

} // namespace restir
