// What the README's snippets take from the application, as stubs, so that a test compiles
// the snippets exactly as the README shows them (tests/readme_snippets.cmake).
#pragma once

#include <restir/restir.hpp>

#include "support/stub_bridge.hpp"

#include <cstdint>
#include <vector>

namespace readme {

using MyLights = stub::LightSet;
using MyTexel = stub::Surface;
using MyRays = stub::RayQuery;
using stub::is_valid_surface;
using stub::surface_depth;
using stub::surface_normal;
using stub::surface_position;

inline glm::vec3 albedo(const MyTexel&) { return glm::vec3(0.5f); }
inline float luminance(glm::vec3 c) { return 0.2126f * c.x + 0.7152f * c.y + 0.0722f * c.z; }

/// The application's state at one pixel of one frame.
struct Frame {
    MyLights lights;
    MyRays rays;
    std::vector<float> light_powers{1.0f, 2.0f, 3.0f, 4.0f};
    std::uint32_t pixel_index = 0u, frame = 0u, w = 1u, h = 1u;
    restir::PixelCoord pixel{0, 0};
    MyTexel texel;
    std::vector<restir::Reservoir<restir::LightSampleRef>> reservoirs{2};
    std::vector<MyTexel> texels{2};
    const restir::Reservoir<restir::LightSampleRef>* history = &reservoirs[0];
    const MyTexel* old_texels = &texels[0];
    restir::ImageView<restir::Reservoir<restir::LightSampleRef>> current{&reservoirs[1], 1u, 1u};
    restir::ImageView<const MyTexel> gbuffer{&texels[1], 1u, 1u};
    stub::Reprojection reproject;
    stub::ClosestHit photon_rays;
    stub::Scatter my_bsdf;
    float radius = 0.1f;
    float scene_extent = 550.0f; ///< The diagonal of the scene's bounding box.

    /// The README's snippets, in order, as one function body.
    void snippets();
};

} // namespace readme
