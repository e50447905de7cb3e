// Reading and writing images of the example renderer: linear HDR (OpenEXR, PFM) and tone-mapped PNG
// (stb_image_write).
#pragma once

#include <glm/vec3.hpp>

#include <cstddef>
#include <cstdint>
#include <filesystem>
#include <span>
#include <stdexcept>
#include <vector>

namespace pt {

/// Linear RGB, row-major, top row first.
struct Image {
    std::uint32_t width = 0;
    std::uint32_t height = 0;
    std::vector<glm::vec3> pixels;

    Image() = default;
    Image(std::uint32_t w, std::uint32_t h) : width(w), height(h), pixels(std::size_t{w} * h) {}
    glm::vec3& at(std::uint32_t x, std::uint32_t y) { return pixels[x + std::size_t{y} * width]; }
    const glm::vec3& at(std::uint32_t x, std::uint32_t y) const {
        return pixels[x + std::size_t{y} * width];
    }
};

/// An image that cannot be read or written; `what()` is a one-line message.
struct ImageError : std::runtime_error {
    using std::runtime_error::runtime_error;
};

/// Writes `image` in the format the extension names: .exr (linear, 32-bit float RGB), .pfm
/// (linear), or .png (8-bit sRGB after multiplying by 2^exposure and clamping). Creates the
/// parent directory if needed. Throws ImageError on an unknown extension or a failed write.
void write_image(const std::filesystem::path& path, const Image& image, float exposure = 0.0f);

/// Throws ImageError unless `path`'s extension names a format `write_image` writes: for
/// checking outputs before a long render.
void check_output_format(const std::filesystem::path& path);

/// Bounds on what the readers accept, checked from the header before any pixel is allocated.
struct ReadLimits {
    /// Largest width x height read (default 8192 x 4096, 0.4 GB as float RGB).
    std::uint64_t max_pixels = std::uint64_t{1} << 25;
};

/// Reads a linear .exr or .pfm image. Throws ImageError when the file is missing, malformed,
/// of another format, or larger than `limits` allow; files are treated as untrusted.
Image read_image(const std::filesystem::path& path, const ReadLimits& limits = {});

/// Decodes an .exr or .pfm image held in memory; `path` names the format (by its extension)
/// and appears in messages. Throws ImageError as `read_image` does.
Image decode_image(std::span<const char> bytes, const std::filesystem::path& path,
                   const ReadLimits& limits = {});

/// The number of pixels with a NaN or infinite channel: every error measure of an image with
/// one would be NaN, so the tools refuse such images.
std::size_t non_finite_pixels(const Image& image);

/// The exposure (in stops) that maps the image's average luminance to 0.18, the usual
/// middle grey; 0 for a black image.
float auto_exposure(const Image& image);

} // namespace pt
