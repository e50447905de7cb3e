// Reading and writing images by their extension: the checks every format shares (the format,
// a writable image, a readable file of a bounded size) before the format's own reader or
// writer (image_formats.hpp), and the measures of an image read (non-finite pixels, exposure).
#include "image_io.hpp"
#include "image_formats.hpp"

#include <algorithm>
#include <cctype>
#include <cerrno>
#include <cmath>
#include <cstdint>
#include <cstdio>
#include <limits>
#include <memory>
#include <string>
#include <string_view>
#include <system_error>
#include <vector>

namespace pt {
namespace {

enum class Format { exr, pfm, png };

std::string lowercase(std::string s) {
    std::transform(s.begin(), s.end(), s.begin(),
                   [](unsigned char c) { return static_cast<char>(std::tolower(c)); });
    return s;
}

std::string errno_message(int error) { return std::generic_category().message(error); }

struct FileCloser {
    void operator()(std::FILE* file) const { std::fclose(file); }
};
using File = std::unique_ptr<std::FILE, FileCloser>;

} // namespace

namespace image_formats {

std::string name(const std::filesystem::path& path) { return path.string(); }

std::string shown(std::string_view token) {
    std::string text;
    for (char c : token.substr(0, 32)) {
        text += std::isprint(static_cast<unsigned char>(c)) != 0 ? c : '?';
    }
    return token.size() > 32 ? text + "..." : text;
}

void write_file(const std::filesystem::path& path, const void* data, std::size_t size) {
    errno = 0;
    File file(std::fopen(path.string().c_str(), "wb"));
    if (!file) {
        throw ImageError("cannot write " + name(path) + ": " + errno_message(errno));
    }
    const bool written = std::fwrite(data, 1, size, file.get()) == size;
    const int write_error = errno;
    const bool closed = std::fclose(file.release()) == 0;
    if (!written || !closed) {
        throw ImageError("cannot write " + name(path) + ": " +
                         errno_message(written ? errno : write_error));
    }
}

} // namespace image_formats

namespace {

using image_formats::name;

Format format_of(const std::filesystem::path& path, std::string_view supported) {
    const std::string extension = lowercase(path.extension().string());
    if (extension == ".exr") {
        return Format::exr;
    }
    if (extension == ".pfm") {
        return Format::pfm;
    }
    if (extension == ".png") {
        return Format::png;
    }
    const std::string shown = extension.empty() ? "(no extension)" : "'" + extension + "'";
    throw ImageError("unknown image format " + shown + " for " + name(path) + ": use " +
                     std::string(supported));
}

void check_consistent(const Image& image, const std::filesystem::path& path) {
    if (image.pixels.size() != std::size_t{image.width} * image.height) {
        throw ImageError("cannot write " + name(path) + ": image is " +
                         std::to_string(image.width) + "x" + std::to_string(image.height) +
                         " but holds " + std::to_string(image.pixels.size()) + " pixels");
    }
}

void check_writable(const std::filesystem::path& path, const Image& image) {
    check_consistent(image, path);
    if (image.width == 0 || image.height == 0) {
        throw ImageError("cannot write " + name(path) + ": the image is empty (" +
                         std::to_string(image.width) + "x" + std::to_string(image.height) + ")");
    }
    constexpr auto max_int = static_cast<std::uint32_t>(std::numeric_limits<int>::max());
    if (image.width > max_int || image.height > max_int) {
        throw ImageError("cannot write " + name(path) + ": the image is too large (" +
                         std::to_string(image.width) + "x" + std::to_string(image.height) + ")");
    }
}

void create_parent_directory(const std::filesystem::path& path) {
    const std::filesystem::path parent = path.parent_path();
    if (parent.empty()) {
        return;
    }
    std::error_code error;
    std::filesystem::create_directories(parent, error);
    if (error) {
        throw ImageError("cannot create the directory " + name(parent) + " for " + name(path) +
                         ": " + error.message());
    }
}

} // namespace

void check_output_format(const std::filesystem::path& path) {
    format_of(path, ".exr, .png or .pfm");
}

void write_image(const std::filesystem::path& path, const Image& image, float exposure) {
    const Format format = format_of(path, ".exr, .png or .pfm");
    check_writable(path, image);
    create_parent_directory(path);
    switch (format) {
    case Format::exr:
        image_formats::write_exr(path, image);
        break;
    case Format::pfm:
        image_formats::write_pfm(path, image);
        break;
    case Format::png:
        image_formats::write_png(path, image, exposure);
        break;
    }
}

Image decode_image(std::span<const char> bytes, const std::filesystem::path& path,
                   const ReadLimits& limits) {
    const Format format = format_of(path, ".exr or .pfm");
    if (format == Format::png) {
        throw ImageError("cannot read " + name(path) +
                         ": PNG is not a linear format, use .exr or .pfm");
    }
    return format == Format::exr ? image_formats::read_exr(bytes, name(path), limits)
                                 : image_formats::read_pfm(bytes, name(path), limits);
}

Image read_image(const std::filesystem::path& path, const ReadLimits& limits) {
    format_of(path, ".exr or .pfm");
    std::error_code error;
    const auto status = std::filesystem::status(path, error);
    if (!std::filesystem::exists(status)) {
        throw ImageError("cannot read " + name(path) + ": no such file");
    }
    if (std::filesystem::is_directory(status)) {
        throw ImageError("cannot read " + name(path) + ": it is a directory");
    }
    errno = 0;
    File file(std::fopen(path.string().c_str(), "rb"));
    if (!file) {
        throw ImageError("cannot read " + name(path) + ": " + errno_message(errno));
    }
    // No image of the allowed size needs more than 16 bytes a pixel (uncompressed float RGBA)
    // and its chunk tables: a larger file is refused before it is read into memory.
    const std::uint64_t max_bytes = limits.max_pixels * 32u + (std::uint64_t{1} << 20);
    std::vector<char> data;
    char buffer[1 << 16];
    std::size_t got = 0;
    while ((got = std::fread(buffer, 1, sizeof buffer, file.get())) > 0) {
        if (data.size() + got > max_bytes) {
            throw ImageError("cannot read " + name(path) + ": the file is larger than " +
                             std::to_string(max_bytes) + " bytes, the most an image of " +
                             std::to_string(limits.max_pixels) + " pixels needs");
        }
        data.insert(data.end(), buffer, buffer + got);
    }
    if (std::ferror(file.get()) != 0) {
        throw ImageError("cannot read " + name(path) + ": " + errno_message(errno));
    }
    return decode_image(data, path, limits);
}

std::size_t non_finite_pixels(const Image& image) {
    return static_cast<std::size_t>(
        std::count_if(image.pixels.begin(), image.pixels.end(), [](const glm::vec3& p) {
            return !(std::isfinite(p.x) && std::isfinite(p.y) && std::isfinite(p.z));
        }));
}

float auto_exposure(const Image& image) {
    if (image.pixels.empty()) {
        return 0.0f;
    }
    double sum = 0.0;
    for (const glm::vec3& p : image.pixels) {
        sum += 0.2126 * static_cast<double>(p.r) + 0.7152 * static_cast<double>(p.g) +
               0.0722 * static_cast<double>(p.b);
    }
    const double mean = sum / static_cast<double>(image.pixels.size());
    if (!(mean > 0.0) || !std::isfinite(mean)) {
        return 0.0f;
    }
    return static_cast<float>(std::log2(0.18 / mean));
}

} // namespace pt
