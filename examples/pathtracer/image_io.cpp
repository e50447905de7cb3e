#include "image_io.hpp"

#include <tinyexr.h>

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
#include <bit>
#include <cctype>
#include <cerrno>
#include <charconv>
#include <cmath>
#include <cstdio>
#include <cstdlib>
#include <cstring>
#include <limits>
#include <memory>
#include <string>
#include <string_view>
#include <system_error>
#include <utility>

namespace pt {
namespace {

enum class Format { exr, pfm, png };

std::string lowercase(std::string s) {
    std::transform(s.begin(), s.end(), s.begin(),
                   [](unsigned char c) { return static_cast<char>(std::tolower(c)); });
    return s;
}

// The path as it appears in messages.
std::string name(const std::filesystem::path& path) { return path.string(); }

// Folds a library's message onto one line and trims it.
std::string one_line(std::string_view text) {
    std::string line;
    bool space = false;
    for (char c : text) {
        if (c == '\n' || c == '\r' || c == '\t' || c == ' ') {
            space = !line.empty();
        } else {
            if (space) {
                line += ' ';
                space = false;
            }
            line += c;
        }
    }
    return line;
}

std::string errno_message(int error) { return std::generic_category().message(error); }

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

struct FileCloser {
    void operator()(std::FILE* file) const { std::fclose(file); }
};
using File = std::unique_ptr<std::FILE, FileCloser>;

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

// ---- OpenEXR ----

struct ExrMessage {
    const char* text = nullptr;
    ExrMessage() = default;
    ExrMessage(const ExrMessage&) = delete;
    ExrMessage& operator=(const ExrMessage&) = delete;
    ~ExrMessage() {
        if (text != nullptr) {
            FreeEXRErrorMessage(text);
        }
    }
    std::string str(int code) const {
        return text != nullptr ? one_line(text) : "tinyexr error " + std::to_string(code);
    }
};

struct FreeDeleter {
    void operator()(void* p) const { std::free(p); }
};

void write_exr(const std::filesystem::path& path, const Image& image) {
    const std::size_t count = image.pixels.size();
    // Planar channels in the order B, G, R, which is how OpenEXR readers expect them.
    std::vector<float> planes[3];
    for (auto& plane : planes) {
        plane.resize(count);
    }
    for (std::size_t i = 0; i < count; ++i) {
        planes[0][i] = image.pixels[i].b;
        planes[1][i] = image.pixels[i].g;
        planes[2][i] = image.pixels[i].r;
    }
    float* plane_pointers[3] = {planes[0].data(), planes[1].data(), planes[2].data()};

    EXRImage exr_image;
    InitEXRImage(&exr_image);
    exr_image.num_channels = 3;
    exr_image.images = reinterpret_cast<unsigned char**>(plane_pointers);
    exr_image.width = static_cast<int>(image.width);
    exr_image.height = static_cast<int>(image.height);

    EXRChannelInfo channels[3]{};
    const char channel_names[3] = {'B', 'G', 'R'};
    for (int c = 0; c < 3; ++c) {
        channels[c].name[0] = channel_names[c];
        channels[c].name[1] = '\0';
    }
    int pixel_types[3] = {TINYEXR_PIXELTYPE_FLOAT, TINYEXR_PIXELTYPE_FLOAT,
                          TINYEXR_PIXELTYPE_FLOAT};
    int requested_pixel_types[3] = {TINYEXR_PIXELTYPE_FLOAT, TINYEXR_PIXELTYPE_FLOAT,
                                    TINYEXR_PIXELTYPE_FLOAT};

    EXRHeader header;
    InitEXRHeader(&header);
    header.num_channels = 3;
    header.channels = channels;
    header.pixel_types = pixel_types;
    header.requested_pixel_types = requested_pixel_types;
    header.compression_type = TINYEXR_COMPRESSIONTYPE_ZIP;

    ExrMessage message;
    unsigned char* memory = nullptr;
    const std::size_t size = SaveEXRImageToMemory(&exr_image, &header, &memory, &message.text);
    const std::unique_ptr<unsigned char, FreeDeleter> owner(memory);
    if (size == 0 || memory == nullptr) {
        throw ImageError("cannot write " + name(path) + ": " + message.str(0));
    }
    write_file(path, memory, size);
}

Image read_exr(const std::filesystem::path& path) {
    float* rgba = nullptr;
    int width = 0;
    int height = 0;
    ExrMessage message;
    const std::string file = path.string();
    const int result = LoadEXR(&rgba, &width, &height, file.c_str(), &message.text);
    const std::unique_ptr<float, FreeDeleter> owner(rgba);
    if (result != TINYEXR_SUCCESS) {
        throw ImageError("cannot read " + name(path) + " as OpenEXR: " + message.str(result));
    }
    if (width <= 0 || height <= 0 || rgba == nullptr) {
        throw ImageError("cannot read " + name(path) + " as OpenEXR: the image is empty");
    }
    Image image(static_cast<std::uint32_t>(width), static_cast<std::uint32_t>(height));
    for (std::size_t i = 0; i < image.pixels.size(); ++i) {
        image.pixels[i] = glm::vec3(rgba[4 * i + 0], rgba[4 * i + 1], rgba[4 * i + 2]);
    }
    return image;
}

// ---- PFM ----

std::uint32_t byte_swap(std::uint32_t v) {
    return (v >> 24) | ((v >> 8) & 0x0000ff00u) | ((v << 8) & 0x00ff0000u) | (v << 24);
}

// Little-endian bytes of `value`.
void put_little_endian(float value, char* out) {
    std::uint32_t bits = std::bit_cast<std::uint32_t>(value);
    if constexpr (std::endian::native == std::endian::big) {
        bits = byte_swap(bits);
    }
    std::memcpy(out, &bits, sizeof bits);
}

float get_float(const char* in, bool little_endian) {
    std::uint32_t bits = 0;
    std::memcpy(&bits, in, sizeof bits);
    if ((std::endian::native == std::endian::little) != little_endian) {
        bits = byte_swap(bits);
    }
    return std::bit_cast<float>(bits);
}

void write_pfm(const std::filesystem::path& path, const Image& image) {
    const std::string header =
        "PF\n" + std::to_string(image.width) + " " + std::to_string(image.height) + "\n-1.0\n";
    const std::size_t offset = header.size();
    std::vector<char> data(offset + image.pixels.size() * 3 * sizeof(float));
    std::memcpy(data.data(), header.data(), offset);
    char* out = data.data() + offset;
    for (std::uint32_t row = image.height; row-- > 0;) {
        for (std::uint32_t x = 0; x < image.width; ++x) {
            const glm::vec3& p = image.at(x, row);
            for (int c = 0; c < 3; ++c) {
                put_little_endian(p[c], out);
                out += sizeof(float);
            }
        }
    }
    write_file(path, data.data(), data.size());
}

std::vector<char> read_file(const std::filesystem::path& path) {
    errno = 0;
    File file(std::fopen(path.string().c_str(), "rb"));
    if (!file) {
        throw ImageError("cannot read " + name(path) + ": " + errno_message(errno));
    }
    std::vector<char> data;
    char buffer[1 << 16];
    std::size_t got = 0;
    while ((got = std::fread(buffer, 1, sizeof buffer, file.get())) > 0) {
        data.insert(data.end(), buffer, buffer + got);
    }
    if (std::ferror(file.get()) != 0) {
        throw ImageError("cannot read " + name(path) + ": " + errno_message(errno));
    }
    return data;
}

bool is_space(char c) { return c == ' ' || c == '\n' || c == '\r' || c == '\t'; }

// A header token as shown in a message: printable and short.
std::string shown(std::string_view token) {
    std::string text;
    for (char c : token.substr(0, 32)) {
        text += std::isprint(static_cast<unsigned char>(c)) != 0 ? c : '?';
    }
    return token.size() > 32 ? text + "..." : text;
}

// The header tokens of a PFM file: magic, width, height, scale.
class PfmHeader {
public:
    PfmHeader(const std::vector<char>& data, const std::filesystem::path& path)
        : data_(data), path_(path) {}

    std::string_view token(const char* what) {
        while (at_ < data_.size() && is_space(data_[at_])) {
            ++at_;
        }
        const std::size_t begin = at_;
        while (at_ < data_.size() && !is_space(data_[at_])) {
            ++at_;
        }
        if (begin == at_) {
            fail(std::string("the header ends before the ") + what);
        }
        return {data_.data() + begin, at_ - begin};
    }

    std::uint32_t dimension(const char* what) {
        const std::string_view text = token(what);
        std::uint32_t value = 0;
        const auto [end, error] = std::from_chars(text.data(), text.data() + text.size(), value);
        if (error != std::errc() || end != text.data() + text.size() || value == 0) {
            fail(std::string("bad ") + what + " '" + shown(text) + "'");
        }
        return value;
    }

    float scale() {
        const std::string_view text = token("scale");
        float value = 0.0f;
        const auto [end, error] = std::from_chars(text.data(), text.data() + text.size(), value);
        if (error != std::errc() || end != text.data() + text.size() || value == 0.0f ||
            !std::isfinite(value)) {
            fail("bad scale '" + shown(text) + "'");
        }
        // Exactly one whitespace character separates the header from the pixels.
        if (at_ >= data_.size()) {
            fail("no pixel data");
        }
        ++at_;
        return value;
    }

    std::size_t offset() const { return at_; }

    [[noreturn]] void fail(const std::string& why) const {
        throw ImageError("cannot read " + name(path_) + " as PFM: " + why);
    }

private:
    const std::vector<char>& data_;
    const std::filesystem::path& path_;
    std::size_t at_ = 0;
};

Image read_pfm(const std::filesystem::path& path) {
    const std::vector<char> data = read_file(path);
    PfmHeader header(data, path);
    const std::string_view magic = header.token("magic");
    if (magic != "PF" && magic != "Pf") {
        header.fail("it does not start with PF or Pf");
    }
    const std::size_t channels = magic == "PF" ? 3 : 1;
    const std::uint32_t width = header.dimension("width");
    const std::uint32_t height = header.dimension("height");
    const float scale = header.scale();
    const bool little_endian = scale < 0.0f;
    const float factor = std::abs(scale);

    const std::uint64_t needed = std::uint64_t{width} * height * channels * sizeof(float);
    const std::uint64_t available = data.size() - header.offset();
    if (available < needed) {
        header.fail("the pixel data is cut short (" + std::to_string(available) + " of " +
                    std::to_string(needed) + " bytes)");
    }

    Image image(width, height);
    const char* in = data.data() + header.offset();
    for (std::uint32_t row = height; row-- > 0;) {
        for (std::uint32_t x = 0; x < width; ++x) {
            glm::vec3& p = image.at(x, row);
            if (channels == 3) {
                for (int c = 0; c < 3; ++c) {
                    p[c] = get_float(in, little_endian);
                    in += sizeof(float);
                }
            } else {
                p = glm::vec3(get_float(in, little_endian));
                in += sizeof(float);
            }
            if (factor != 1.0f) {
                p *= factor;
            }
        }
    }
    return image;
}

// ---- PNG ----

std::uint8_t to_srgb8(float linear, float scale) {
    float v = linear * scale;
    v = v > 0.0f ? std::min(v, 1.0f) : 0.0f; // Also maps NaN to 0.
    const float encoded = v <= 0.0031308f ? 12.92f * v : 1.055f * std::pow(v, 1.0f / 2.4f) - 0.055f;
    return static_cast<std::uint8_t>(std::lround(std::clamp(encoded, 0.0f, 1.0f) * 255.0f));
}

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
        write_exr(path, image);
        break;
    case Format::pfm:
        write_pfm(path, image);
        break;
    case Format::png:
        write_png(path, image, exposure);
        break;
    }
}

Image read_image(const std::filesystem::path& path) {
    const Format format = format_of(path, ".exr or .pfm");
    if (format == Format::png) {
        throw ImageError("cannot read " + name(path) +
                         ": PNG is not a linear format, use .exr or .pfm");
    }
    std::error_code error;
    const auto status = std::filesystem::status(path, error);
    if (!std::filesystem::exists(status)) {
        throw ImageError("cannot read " + name(path) + ": no such file");
    }
    if (std::filesystem::is_directory(status)) {
        throw ImageError("cannot read " + name(path) + ": it is a directory");
    }
    return format == Format::exr ? read_exr(path) : read_pfm(path);
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
