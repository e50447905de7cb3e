/// @file light/environment_light.hpp
/// An environment map as a distant light of a light set: its samples as `LightSample`s (a
/// direction with a density per steradian), and its power beside local lights.
#pragma once

#include "restir/config.hpp"
#include "restir/core/math.hpp"
#include "restir/light/environment_map.hpp"
#include "restir/light/light_sample.hpp"

#include <glm/vec3.hpp>

namespace restir {

/// An environment's sample as a light set's point: the direction in `position`, a zero normal,
/// the radiance arriving along it, its density per steradian in `area_pdf`, `is_distant`.
RESTIR_HOST_DEVICE inline LightSample environment_light_sample(const EnvironmentSample& s) {
    LightSample point;
    point.position = s.direction;
    point.normal = glm::vec3(0.0f);
    point.radiance = s.radiance;
    point.area_pdf = s.pdf;
    point.is_distant = true;
    return point;
}

/// The environment's light arriving from the unit `direction` as a light set's point (what a
/// ray that leaves the scene finds: a `LightHit`'s point), with the density per steradian of
/// `EnvironmentMapView::sample` there.
RESTIR_HOST_DEVICE inline LightSample environment_light_point(const EnvironmentMapView& environment,
                                                              glm::vec3 direction) {
    return environment_light_sample(
        {direction, environment.radiance(direction), environment.pdf(direction)});
}

/// The power the environment sends into a scene inside a sphere of radius `scene_radius`,
/// summed over the colour channels: pi r^2 times the integral of its radiance over the sphere
/// of directions (the light of each direction crosses a disk of area pi r^2 facing it). The
/// weight beside local lights' emitted flux in a power-proportional light distribution.
inline float environment_power(const EnvironmentMap& environment, float scene_radius) {
    const glm::vec3 integral = environment.radiance_integral();
    const float power = pi * scene_radius * scene_radius * (integral.x + integral.y + integral.z);
    return is_valid_weight(power) ? power : 0.0f;
}

} // namespace restir
