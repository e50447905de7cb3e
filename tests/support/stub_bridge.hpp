// The smallest types that satisfy every bridge concept. The conformance test instantiates
// each library template with them, so the headers cannot rely on anything the concepts do
// not require.
#pragma once

#include <restir/concepts.hpp>
#include <restir/core/discrete_sample.hpp>
#include <restir/light/light_sample.hpp>
#include <restir/reuse/image_view.hpp>
#include <restir/vpl/photon_shooter.hpp>

#include <glm/vec2.hpp>
#include <glm/vec3.hpp>

#include <cstdint>

namespace stub {

/// A 32-bit LCG: enough to satisfy UniformRng, not meant for statistics.
struct Rng {
    std::uint32_t state = 1u;
};
inline float next_float(Rng& rng) {
    rng.state = rng.state * 1664525u + 1013904223u;
    return static_cast<float>(rng.state >> 8u) * 0x1p-24f;
}

/// A sample that is only an index.
struct Sample {
    std::uint32_t id = 0u;
    /// Only the frame recipe's tiles ask (they match traced answers to samples).
    friend bool operator==(const Sample&, const Sample&) = default;
};

/// A surface known only through the four free functions.
struct Surface {
    float height = 0.0f;
};
inline glm::vec3 surface_position(const Surface& s) { return {0.0f, s.height, 0.0f}; }
inline glm::vec3 surface_normal(const Surface&) { return {0.0f, 1.0f, 0.0f}; }
inline float surface_depth(const Surface& s) { return s.height; }
inline bool is_valid_surface(const Surface&) { return true; }

/// p-hat(sample, surface).
struct Target {
    float operator()(const Sample& s, const Surface& x) const {
        return static_cast<float>(s.id + 1u) / (1.0f + x.height);
    }
};

/// Point lights on a line.
struct LightSet {
    std::uint32_t count = 4u;
    std::uint32_t light_count() const { return count; }
    restir::LightSample sample_point(std::uint32_t id, glm::vec2) const {
        restir::LightSample point;
        point.position = {static_cast<float>(id), 1.0f, 0.0f};
        point.radiance = glm::vec3(1.0f);
        point.area_pdf = 1.0f;
        point.is_delta = true;
        return point;
    }
};

/// A light sampler with a single light.
struct LightSampler {
    restir::DiscreteSample sample(float, float) const { return {0u, 1.0f}; }
    float pmf(std::uint32_t id) const { return id == 0u ? 1.0f : 0.0f; }
    std::uint32_t light_count() const { return 1u; }
};

/// Every sample is visible from every surface.
struct Visibility {
    bool operator()(const Sample&, const Surface&) const { return true; }
};

/// Every pixel was at the same place in the previous frame.
struct Reprojection {
    restir::PixelCoord operator()(restir::PixelCoord p) const { return p; }
};

/// Every ray hits the same surface.
struct ClosestHit {
    Surface closest_hit(glm::vec3, glm::vec3) const { return Surface{}; }
};

/// Absorbs every photon after depositing it.
struct Scatter {
    template <class AnyRng>
    restir::Scattering operator()(const Surface&, glm::vec3, AnyRng&) const {
        return {{0.0f, 1.0f, 0.0f}, glm::vec3(0.0f), glm::vec3(0.5f), true, false};
    }
};

/// Nothing ever blocks.
struct RayQuery {
    bool occluded(glm::vec3, glm::vec3) const { return false; }
};

} // namespace stub
