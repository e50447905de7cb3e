// The image formats behind image_io.hpp: each format's reader and writer (image_exr.cpp,
// image_pfm.cpp, image_png.cpp), called by image_io.cpp once it has checked the path, the
// image and the file's size, and the helpers they share (defined in image_io.cpp).
#pragma once

#include "image_io.hpp"

#include <cstddef>
#include <filesystem>
#include <span>
#include <string>
#include <string_view>

namespace pt::image_formats {

/// The path as it appears in messages.
std::string name(const std::filesystem::path& path);

/// A header token as shown in a message: printable and short.
std::string shown(std::string_view token);

/// Writes `size` bytes to `path`. Throws ImageError when the file cannot be written.
void write_file(const std::filesystem::path& path, const void* data, std::size_t size);

/// The writers, of an image write_image has checked: non-empty, its pixel count matching its
/// size, each side within an int.
void write_exr(const std::filesystem::path& path, const Image& image);
void write_pfm(const std::filesystem::path& path, const Image& image);
void write_png(const std::filesystem::path& path, const Image& image, float exposure);

/// The readers, of untrusted bytes; `file` names the file in messages.
Image read_exr(std::span<const char> bytes, const std::string& file, const ReadLimits& limits);
Image read_pfm(std::span<const char> data, const std::string& file, const ReadLimits& limits);

} // namespace pt::image_formats
