/// @file core/shading_point.hpp
/// Where a light is chosen for: the context that spatially aware light samplers read.
#pragma once

#include <glm/vec3.hpp>

#include <type_traits>

namespace restir {

/// A shading point: its position and unit normal (the side light is gathered on). A zero
/// normal means "any direction" (a point in a volume, or a cell of a grid of points).
struct ShadingPoint {
    glm::vec3 position{0.0f};
    glm::vec3 normal{0.0f};
};

static_assert(std::is_trivially_copyable_v<ShadingPoint>);

} // namespace restir
