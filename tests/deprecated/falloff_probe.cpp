// Uses every deprecated name of the light headers once; compiled with
// -Werror=deprecated-declarations it must fail with one error per name (deprecation.warns).
#include <restir/light/falloff.hpp>
#include <restir/light/light_bounds.hpp>

float probe_attenuation(float distance) {
    const restir::Attenuation kind = restir::Attenuation::yuksel;
    return restir::attenuate(kind, distance, 0.1f) + restir::yuksel_attenuation(distance, 0.1f) +
           restir::smallest_attenuation_divisor;
}

float probe_light_bounds(const restir::LightBounds& a, const restir::LightBounds& b) {
    return restir::merge_light_bounds(a, b).power;
}
