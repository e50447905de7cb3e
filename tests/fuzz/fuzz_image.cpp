// libFuzzer target: bytes decoded as an image in the format FUZZ_IMAGE_NAME names (.exr or
// .pfm), under a limit of 2^20 pixels. Refusals are ImageErrors; anything else (a crash, a
// sanitizer report, another exception, an image whose size disagrees with its pixels) is a
// finding.
#include "image_io.hpp"

#include <cstddef>
#include <cstdint>
#include <span>

extern "C" int LLVMFuzzerTestOneInput(const std::uint8_t* data, std::size_t size) {
    const std::span<const char> bytes(reinterpret_cast<const char*>(data), size);
    const pt::ReadLimits limits{std::uint64_t{1} << 20};
    try {
        const pt::Image image = pt::decode_image(bytes, FUZZ_IMAGE_NAME, limits);
        if (image.width == 0 || image.height == 0 ||
            image.pixels.size() != std::size_t{image.width} * image.height ||
            image.pixels.size() > limits.max_pixels)
            __builtin_trap();
    } catch (const pt::ImageError&) {
    }
    return 0;
}
