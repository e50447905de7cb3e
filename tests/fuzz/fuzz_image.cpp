// libFuzzer target: bytes decoded as an image in the format FUZZ_IMAGE_NAME names (.exr or
// .pfm), under a limit of 2^20 pixels, and whatever decodes built as an environment map (as
// --env builds one: restir::EnvironmentMap's validation and tables). Refusals are
// ImageErrors; anything else (a crash, a sanitizer report, another exception, an image whose
// size disagrees with its pixels, an accepted map that draws a NaN, infinite or negative density
// or radiance) is a finding.
#include "environment.hpp"
#include "image_io.hpp"

#include <glm/geometric.hpp>

#include <cmath>
#include <cstddef>
#include <cstdint>
#include <span>

namespace {

bool finite(glm::vec3 v) { return std::isfinite(v.x) && std::isfinite(v.y) && std::isfinite(v.z); }

// An accepted map draws unit directions and finite radiance with a finite density, >= 0 (a
// density can underflow to 0 for a texel far dimmer than the map's brightest).
void check_environment(const pt::Image& image) {
    const auto environment =
        pt::make_environment(image.pixels, image.width, image.height, "fuzz", 1.0f, 0.0f);
    const restir::EnvironmentMapView view = environment->view();
    for (const float u : {0.0f, 0.3f, 0.999f}) {
        const restir::EnvironmentSample s = view.sample({u, 1.0f - u});
        const bool unit = std::abs(glm::dot(s.direction, s.direction) - 1.0f) < 1e-3f;
        if (!(s.pdf >= 0.0f) || !std::isfinite(s.pdf) || !finite(s.radiance) || !unit ||
            !(view.pdf(s.direction) >= 0.0f))
            __builtin_trap();
    }
}

} // namespace

extern "C" int LLVMFuzzerTestOneInput(const std::uint8_t* data, std::size_t size) {
    const std::span<const char> bytes(reinterpret_cast<const char*>(data), size);
    const pt::ReadLimits limits{std::uint64_t{1} << 20};
    try {
        const pt::Image image = pt::decode_image(bytes, FUZZ_IMAGE_NAME, limits);
        if (image.width == 0 || image.height == 0 ||
            image.pixels.size() != std::size_t{image.width} * image.height ||
            image.pixels.size() > limits.max_pixels)
            __builtin_trap();
        check_environment(image);
    } catch (const pt::ImageError&) {
    }
    return 0;
}
