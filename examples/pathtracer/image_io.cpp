#include "image_io.hpp"

#include "messages.hpp"

#include <OpenEXR/ImfChannelList.h>
#include <OpenEXR/ImfFrameBuffer.h>
#include <OpenEXR/ImfHeader.h>
#include <OpenEXR/ImfIO.h>
#include <OpenEXR/ImfInputFile.h>
#include <OpenEXR/ImfOutputFile.h>
#include <OpenEXR/openexr.h>

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
#include <array>
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
#include <span>
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

std::string errno_message(int error) { return std::generic_category().message(error); }

bool is_space(char c) { return c == ' ' || c == '\n' || c == '\r' || c == '\t'; }

// A header token as shown in a message: printable and short.
std::string shown(std::string_view token) {
    std::string text;
    for (char c : token.substr(0, 32)) {
        text += std::isprint(static_cast<unsigned char>(c)) != 0 ? c : '?';
    }
    return token.size() > 32 ? text + "..." : text;
}

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

// Bytes held in memory, as OpenEXR's C++ API reads a file.
class MemoryStream final : public Imf::IStream {
public:
    MemoryStream(std::span<const char> bytes, const std::string& file_name)
        : Imf::IStream(file_name.c_str()), bytes_(bytes) {}

    bool read(char c[], int n) override {
        if (n < 0 || static_cast<std::uint64_t>(n) > bytes_.size() - at_)
            throw Iex::InputExc("unexpected end of file");
        std::memcpy(c, bytes_.data() + at_, static_cast<std::size_t>(n));
        at_ += static_cast<std::uint64_t>(n);
        return at_ < bytes_.size();
    }
    std::uint64_t tellg() override { return at_; }
    void seekg(std::uint64_t position) override {
        if (position > bytes_.size())
            throw Iex::InputExc("seek past the end of file");
        at_ = position;
    }

private:
    std::span<const char> bytes_;
    std::uint64_t at_ = 0;
};

// The header facts checked before OpenEXR's C++ reader allocates anything, read with its core
// library (built to validate untrusted headers): one flat part, its data window, its chunks.
struct ExrLayout {
    std::uint64_t width = 0;
    std::uint64_t height = 0;
};

struct ExrBytes {
    std::span<const char> bytes;
    std::string message; // the core library's last error message
};

std::int64_t exr_read(exr_const_context_t context, void* user, void* buffer, std::uint64_t size,
                      std::uint64_t offset, exr_stream_error_func_ptr_t) {
    (void)context;
    const std::span<const char> bytes = static_cast<ExrBytes*>(user)->bytes;
    if (offset >= bytes.size())
        return 0;
    const std::uint64_t count = std::min<std::uint64_t>(size, bytes.size() - offset);
    std::memcpy(buffer, bytes.data() + offset, static_cast<std::size_t>(count));
    return static_cast<std::int64_t>(count);
}

std::int64_t exr_size(exr_const_context_t, void* user) {
    return static_cast<std::int64_t>(static_cast<ExrBytes*>(user)->bytes.size());
}

void exr_error(exr_const_context_t context, exr_result_t, const char* message) {
    void* user = nullptr;
    if (exr_get_user_data(context, &user) == EXR_ERR_SUCCESS && user != nullptr && message)
        static_cast<ExrBytes*>(user)->message = message;
}

// Largest width or height either OpenEXR reader accepts; the pixel count is limited separately.
constexpr int exr_max_side = 1 << 20;
// Largest decoded chunk (a block of scanlines or a tile, all channels) read.
constexpr std::uint64_t max_exr_chunk_bytes = std::uint64_t{64} << 20;

[[noreturn]] void fail_exr(const std::string& file, const std::string& why) {
    throw ImageError("cannot read " + file + " as OpenEXR: " + why);
}

// Throws for a failed call of OpenEXR's core library, with its last message.
struct ExrCheck {
    const ExrBytes& source;
    const std::string& file;

    void operator()(exr_result_t result) const {
        if (result != EXR_ERR_SUCCESS)
            fail_exr(file, one_line(source.message.empty() ? exr_get_default_error_message(result)
                                                           : source.message));
    }
};

// A strict reader of `source`'s bytes, within the size limits of either reader.
exr_context_initializer_t exr_initializer(ExrBytes& source) {
    exr_context_initializer_t init = EXR_DEFAULT_CONTEXT_INITIALIZER;
    init.error_handler_fn = exr_error;
    init.user_data = &source;
    init.read_fn = exr_read;
    init.size_fn = exr_size;
    init.max_image_width = exr_max_side;
    init.max_image_height = exr_max_side;
    init.max_tile_width = exr_max_side;
    init.max_tile_height = exr_max_side;
    init.flags = EXR_CONTEXT_FLAG_STRICT_HEADER | EXR_CONTEXT_FLAG_DISABLE_CHUNK_RECONSTRUCTION;
    return init;
}

// The size of the data window, within the pixel limit.
ExrLayout exr_layout(exr_const_context_t context, const ReadLimits& limits, const ExrCheck& check) {
    exr_attr_box2i_t window{};
    check(exr_get_data_window(context, 0, &window));
    ExrLayout layout;
    if (window.max.x >= window.min.x && window.max.y >= window.min.y) {
        layout.width = static_cast<std::uint64_t>(std::int64_t{window.max.x} - window.min.x + 1);
        layout.height = static_cast<std::uint64_t>(std::int64_t{window.max.y} - window.min.y + 1);
    }
    if (layout.width == 0 || layout.height == 0)
        fail_exr(check.file, "the data window is empty");
    if (layout.width * layout.height > limits.max_pixels)
        fail_exr(check.file, "it is " + std::to_string(layout.width) + "x" +
                                 std::to_string(layout.height) + ", more than the " +
                                 std::to_string(limits.max_pixels) + " pixels allowed");
    return layout;
}

// The reader holds one chunk decoded (and one compressed) beside the image: a file whose
// chunks are larger than any sensible image needs (many channels, very wide lines) is refused
// before they are allocated. Every chunk needs an 8-byte offset and a chunk header of at least
// 8 bytes: a file too short for its chunk table is cut short, whatever its compression.
void check_exr_chunks(exr_const_context_t context, std::size_t file_bytes, const ExrCheck& check) {
    std::uint64_t chunk_bytes = 0;
    check(exr_get_chunk_unpacked_size(context, 0, &chunk_bytes));
    if (chunk_bytes > max_exr_chunk_bytes)
        fail_exr(check.file, "its chunks decode to " + std::to_string(chunk_bytes) +
                                 " bytes, more than the " + std::to_string(max_exr_chunk_bytes) +
                                 " allowed");
    std::int32_t chunks = 0;
    check(exr_get_chunk_count(context, 0, &chunks));
    if (chunks <= 0 || std::uint64_t(chunks) * 16u > file_bytes)
        fail_exr(check.file, "the file is too short for its " + std::to_string(chunks) + " chunks");
}

ExrLayout check_exr_header(std::span<const char> bytes, const ReadLimits& limits,
                           const std::string& file) {
    ExrBytes source{bytes, {}};
    const ExrCheck check{source, file};
    const exr_context_initializer_t init = exr_initializer(source);
    exr_context_t context = nullptr;
    const exr_result_t opened = exr_start_read(&context, file.c_str(), &init);
    struct Finish {
        exr_context_t* context;
        ~Finish() {
            if (*context != nullptr)
                exr_finish(context);
        }
    } finish{&context};
    check(opened);

    int parts = 0;
    check(exr_get_count(context, &parts));
    if (parts != 1)
        fail_exr(file,
                 "it has " + std::to_string(parts) + " parts; only single-part files are read");
    exr_storage_t storage = EXR_STORAGE_LAST_TYPE;
    check(exr_get_storage(context, 0, &storage));
    if (storage != EXR_STORAGE_SCANLINE && storage != EXR_STORAGE_TILED)
        fail_exr(file, "deep images are not read");
    const ExrLayout layout = exr_layout(context, limits, check);
    check_exr_chunks(context, bytes.size(), check);
    return layout;
}

// The channels read, in the order R, G, B; a luminance-only image reads Y into all three.
std::array<const char*, 3> exr_channels(const Imf::ChannelList& channels, const std::string& file) {
    if (channels.findChannel("R") && channels.findChannel("G") && channels.findChannel("B"))
        return {"R", "G", "B"};
    if (channels.findChannel("Y"))
        return {"Y", "Y", "Y"};
    std::string names;
    for (auto c = channels.begin(); c != channels.end(); ++c)
        names += (names.empty() ? "" : ", ") + shown(c.name());
    throw ImageError("cannot read " + file + " as OpenEXR: no R, G, B or Y channel (it has " +
                     (names.empty() ? std::string("none") : names) + ")");
}

void write_exr(const std::filesystem::path& path, const Image& image) {
    const int width = static_cast<int>(image.width);
    const int height = static_cast<int>(image.height);
    try {
        Imf::Header header(width, height);
        header.compression() = Imf::ZIP_COMPRESSION;
        for (const char* channel : {"R", "G", "B"})
            header.channels().insert(channel, Imf::Channel(Imf::FLOAT));
        // Slices point straight into the interleaved pixels: no copy.
        auto* base = reinterpret_cast<char*>(const_cast<glm::vec3*>(image.pixels.data()));
        const std::size_t x_stride = sizeof(glm::vec3);
        const std::size_t y_stride = x_stride * image.width;
        Imf::FrameBuffer frame;
        const char* names[3] = {"R", "G", "B"};
        for (std::size_t c = 0; c < 3; ++c)
            frame.insert(names[c],
                         Imf::Slice(Imf::FLOAT, base + c * sizeof(float), x_stride, y_stride));
        Imf::OutputFile file(path.string().c_str(), header, 1);
        file.setFrameBuffer(frame);
        file.writePixels(height);
    } catch (const std::exception& e) {
        throw ImageError("cannot write " + name(path) + ": " + one_line(e.what()));
    }
}

Image read_exr(std::span<const char> bytes, const std::string& file, const ReadLimits& limits) {
    static const bool configured = [] {
        Imf::Header::setMaxImageSize(exr_max_side, exr_max_side);
        Imf::Header::setMaxTileSize(exr_max_side, exr_max_side);
        return true;
    }();
    (void)configured;
    const ExrLayout layout = check_exr_header(bytes, limits, file);
    try {
        MemoryStream stream(bytes, file);
        Imf::InputFile input(stream, 1);
        const Imath::Box2i window = input.header().dataWindow();
        const auto width = static_cast<std::uint64_t>(window.max.x - window.min.x + 1);
        const auto height = static_cast<std::uint64_t>(window.max.y - window.min.y + 1);
        if (width != layout.width || height != layout.height)
            throw ImageError("cannot read " + file + " as OpenEXR: inconsistent data window");
        const std::array<const char*, 3> names = exr_channels(input.header().channels(), file);

        Image image(static_cast<std::uint32_t>(width), static_cast<std::uint32_t>(height));
        auto* base = reinterpret_cast<char*>(image.pixels.data());
        Imf::FrameBuffer frame;
        for (std::size_t c = 0; c < 3; ++c)
            if (c == 0 || names[c] != names[0]) // Y is read once and copied
                frame.insert(names[c],
                             Imf::Slice::Make(Imf::FLOAT, base + c * sizeof(float), window,
                                              sizeof(glm::vec3), sizeof(glm::vec3) * width));
        input.setFrameBuffer(frame);
        input.readPixels(window.min.y, window.max.y);
        if (names[1] == names[0])
            for (glm::vec3& p : image.pixels)
                p = glm::vec3(p.x);
        return image;
    } catch (const ImageError&) {
        throw;
    } catch (const std::exception& e) {
        throw ImageError("cannot read " + file + " as OpenEXR: " + one_line(e.what()));
    }
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

// The header tokens of a PFM file: magic, width, height, scale.
class PfmHeader {
public:
    PfmHeader(std::span<const char> data, const std::string& file) : data_(data), file_(file) {}

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
        throw ImageError("cannot read " + file_ + " as PFM: " + why);
    }

private:
    std::span<const char> data_;
    const std::string& file_;
    std::size_t at_ = 0;
};

Image read_pfm(std::span<const char> data, const std::string& file, const ReadLimits& limits) {
    PfmHeader header(data, file);
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

    const std::uint64_t pixels = std::uint64_t{width} * height; // no wrap: both below 2^32
    if (pixels > limits.max_pixels)
        header.fail("it is " + std::to_string(width) + "x" + std::to_string(height) +
                    ", more than the " + std::to_string(limits.max_pixels) + " pixels allowed");
    const std::uint64_t needed = pixels * channels * sizeof(float);
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

Image decode_image(std::span<const char> bytes, const std::filesystem::path& path,
                   const ReadLimits& limits) {
    const Format format = format_of(path, ".exr or .pfm");
    if (format == Format::png) {
        throw ImageError("cannot read " + name(path) +
                         ": PNG is not a linear format, use .exr or .pfm");
    }
    return format == Format::exr ? read_exr(bytes, name(path), limits)
                                 : read_pfm(bytes, name(path), limits);
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
