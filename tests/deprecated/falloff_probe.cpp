// Uses every deprecated name of light/falloff.hpp once; compiled with
// -Werror=deprecated-declarations it must fail with one error per name (deprecation.warns).
#include <restir/light/falloff.hpp>

float probe_attenuation(float distance) {
    const restir::Attenuation kind = restir::Attenuation::yuksel;
    return restir::attenuate(kind, distance, 0.1f) + restir::yuksel_attenuation(distance, 0.1f) +
           restir::smallest_attenuation_divisor;
}
