// PFM images (portable float map): little-endian on write, either byte order and one or three
// channels on read.
#include "image_formats.hpp"

#include <bit>
#include <charconv>
#include <cmath>
#include <cstdint>
#include <cstring>
#include <span>
#include <string>
#include <string_view>
#include <system_error>
#include <vector>

namespace pt::image_formats {
namespace {

bool is_space(char c) { return c == ' ' || c == '\n' || c == '\r' || c == '\t'; }

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

} // namespace

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

} // namespace pt::image_formats
