// OpenEXR images: written with OpenEXR's C++ library; read with it after its core library has
// checked the untrusted header (one flat part, its data window, its chunks).
#include "image_formats.hpp"
#include "messages.hpp"

#include <OpenEXR/ImfChannelList.h>
#include <OpenEXR/ImfFrameBuffer.h>
#include <OpenEXR/ImfHeader.h>
#include <OpenEXR/ImfIO.h>
#include <OpenEXR/ImfInputFile.h>
#include <OpenEXR/ImfOutputFile.h>
#include <OpenEXR/openexr.h>

#include <algorithm>
#include <array>
#include <cstdint>
#include <cstring>
#include <exception>
#include <span>
#include <string>

namespace pt::image_formats {
namespace {

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

} // namespace

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

} // namespace pt::image_formats
