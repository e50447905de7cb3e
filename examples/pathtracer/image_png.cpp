// PNG images: tone-mapped to 8-bit sRGB and encoded with stb_image_write.
#include "image_formats.hpp"

#pragma GCC diagnostic push
#if defined(__clang__)
#pragma clang diagnostic ignored "-Wunknown-warning-option"
#endif
#pragma GCC diagnostic ignored "-Wconversion"
#pragma GCC diagnostic ignored "-Wold-style-cast"
#pragma GCC diagnostic ignored "-Wmissing-field-initializers"
#pragma GCC diagnostic ignored "-Wsign-conversion"
#pragma GCC diagnostic ignored "-Wdouble-promotion"
#pragma GCC diagnostic ignored "-Wshadow"
#pragma GCC diagnostic ignored "-Wcast-qual"
#pragma GCC diagnostic ignored "-Wuseless-cast"
#define STB_IMAGE_WRITE_IMPLEMENTATION
#include <stb/stb_image_write.h>
#pragma GCC diagnostic pop

#include <algorithm>
#include <cmath>
#include <cstddef>
#include <cstdint>
#include <limits>
#include <vector>

namespace pt::image_formats {
namespace {

std::uint8_t to_srgb8(float linear, float scale) {
    float v = linear * scale;
    v = v > 0.0f ? std::min(v, 1.0f) : 0.0f; // Also maps NaN to 0.
    const float encoded = v <= 0.0031308f ? 12.92f * v : 1.055f * std::pow(v, 1.0f / 2.4f) - 0.055f;
    return static_cast<std::uint8_t>(std::lround(std::clamp(encoded, 0.0f, 1.0f) * 255.0f));
}

} // namespace

void write_png(const std::filesystem::path& path, const Image& image, float exposure) {
    if (image.width > static_cast<std::uint32_t>(std::numeric_limits<int>::max() / 3)) {
        throw ImageError("cannot write " + name(path) + ": the image is too wide for PNG");
    }
    const int width = static_cast<int>(image.width);
    const int height = static_cast<int>(image.height);
    const float scale = std::exp2(exposure);
    std::vector<std::uint8_t> bytes(image.pixels.size() * 3);
    for (std::size_t i = 0; i < image.pixels.size(); ++i) {
        for (int c = 0; c < 3; ++c) {
            bytes[3 * i + static_cast<std::size_t>(c)] = to_srgb8(image.pixels[i][c], scale);
        }
    }
    std::vector<unsigned char> encoded;
    const auto append = [](void* context, void* data, int size) {
        auto* out = static_cast<std::vector<unsigned char>*>(context);
        const auto* begin = static_cast<const unsigned char*>(data);
        out->insert(out->end(), begin, begin + size);
    };
    if (stbi_write_png_to_func(append, &encoded, width, height, 3, bytes.data(), width * 3) == 0) {
        throw ImageError("cannot write " + name(path) + ": PNG encoding failed");
    }
    write_file(path, encoded.data(), encoded.size());
}

} // namespace pt::image_formats
