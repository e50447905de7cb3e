// Image files are untrusted input: what the readers decode exactly, and what they refuse (a
// one-line ImageError, no crash, no allocation beyond the limits) for hand-made hostile files.
#include "image_io.hpp"

#include "scratch_dir.hpp"

#include <gtest/gtest.h>

#include <OpenEXR/ImfChannelList.h>
#include <OpenEXR/ImfFrameBuffer.h>
#include <OpenEXR/ImfHeader.h>
#include <OpenEXR/ImfOutputFile.h>
#include <OpenEXR/ImfTileDescription.h>
#include <OpenEXR/ImfTileDescriptionAttribute.h>
#include <OpenEXR/ImfTiledOutputFile.h>

#include <sys/resource.h>

#include <cstdint>
#include <cstring>
#include <filesystem>
#include <fstream>
#include <iterator>
#include <limits>
#include <string>
#include <vector>

namespace {

namespace fs = std::filesystem;

using pt_test::scratch_dir;

pt::Image test_image(std::uint32_t width, std::uint32_t height) {
    pt::Image image(width, height);
    for (std::uint32_t y = 0; y < height; ++y)
        for (std::uint32_t x = 0; x < width; ++x)
            image.at(x, y) = glm::vec3(0.25f * static_cast<float>(x), static_cast<float>(y),
                                       1.0f / static_cast<float>(1 + x + y));
    return image;
}

// ---- OpenEXR files byte by byte (the layout of the OpenEXR file format) ----

std::string le32(std::uint32_t v) {
    std::string s(4, '\0');
    for (int i = 0; i < 4; ++i)
        s[static_cast<std::size_t>(i)] = static_cast<char>((v >> (8 * i)) & 0xffu);
    return s;
}
std::string le32(std::int32_t v) { return le32(static_cast<std::uint32_t>(v)); }
std::string le64(std::uint64_t v) { return le32(std::uint32_t(v)) + le32(std::uint32_t(v >> 32)); }
std::string f32(float v) {
    std::uint32_t bits = 0;
    std::memcpy(&bits, &v, sizeof bits);
    return le32(bits);
}

std::string attribute(const std::string& name, const std::string& type, const std::string& value) {
    return name + '\0' + type + '\0' + le32(static_cast<std::uint32_t>(value.size())) + value;
}
std::string box(std::int32_t x0, std::int32_t y0, std::int32_t x1, std::int32_t y1) {
    return le32(x0) + le32(y0) + le32(x1) + le32(y1);
}
// A channel list of FLOAT channels.
std::string channels(const std::vector<std::string>& names) {
    std::string list;
    for (const std::string& n : names)
        list += n + '\0' + le32(std::uint32_t{2}) + std::string(4, '\0') + le32(std::uint32_t{1}) +
                le32(std::uint32_t{1});
    return attribute("channels", "chlist", list + '\0');
}

const std::string magic = std::string("\x76\x2f\x31\x01", 4);

// A scanline file's header with the given data window and channels, uncompressed.
std::string scanline_header(std::int32_t x0, std::int32_t y0, std::int32_t x1, std::int32_t y1,
                            const std::vector<std::string>& names = {"B", "G", "R"}) {
    return magic + le32(std::uint32_t{2}) + channels(names) +
           attribute("compression", "compression", std::string(1, '\0')) +
           attribute("dataWindow", "box2i", box(x0, y0, x1, y1)) +
           attribute("displayWindow", "box2i", box(x0, y0, x1, y1)) +
           attribute("lineOrder", "lineOrder", std::string(1, '\0')) +
           attribute("pixelAspectRatio", "float", f32(1.0f)) +
           attribute("screenWindowCenter", "v2f", f32(0.0f) + f32(0.0f)) +
           attribute("screenWindowWidth", "float", f32(1.0f)) + '\0';
}

// A complete uncompressed 2x2 file of channels B, G, R, each pixel (x, y) = (x, y, 7).
std::string small_exr() {
    std::string header = scanline_header(0, 0, 1, 1);
    const std::size_t table = header.size();
    std::string chunks;
    std::vector<std::uint64_t> offsets;
    for (std::int32_t y = 0; y < 2; ++y) {
        offsets.push_back(table + 16 + chunks.size());
        std::string pixels;
        for (float b : {7.0f, 7.0f})
            pixels += f32(b);
        for (int x = 0; x < 2; ++x)
            pixels += f32(static_cast<float>(y));
        for (int x = 0; x < 2; ++x)
            pixels += f32(static_cast<float>(x));
        chunks += le32(y) + le32(static_cast<std::uint32_t>(pixels.size())) + pixels;
    }
    return header + le64(offsets[0]) + le64(offsets[1]) + chunks;
}

pt::Image decode(const std::string& bytes, const char* name = "hostile.exr",
                 const pt::ReadLimits& limits = {}) {
    return pt::decode_image(std::span<const char>(bytes.data(), bytes.size()), name, limits);
}

// Decoding throws ImageError with a one-line message that contains `needle`.
void expect_refused(const std::string& bytes, const std::string& needle,
                    const char* name = "hostile.exr", const pt::ReadLimits& limits = {}) {
    try {
        decode(bytes, name, limits);
        ADD_FAILURE() << "accepted: " << needle;
    } catch (const pt::ImageError& e) {
        const std::string what = e.what();
        EXPECT_EQ(what.find('\n'), std::string::npos) << what;
        EXPECT_NE(what.find(needle), std::string::npos) << what;
        EXPECT_NE(what.find(name), std::string::npos) << what;
    }
}

TEST(ImageIo, ExrAndPfmRoundTripExactly) {
    const pt::Image image = test_image(13, 7);
    for (const char* file : {"image.exr", "image.pfm"}) {
        const fs::path path = scratch_dir() / file;
        pt::write_image(path, image);
        const pt::Image back = pt::read_image(path);
        ASSERT_EQ(back.width, image.width) << file;
        ASSERT_EQ(back.height, image.height) << file;
        for (std::size_t i = 0; i < image.pixels.size(); ++i)
            ASSERT_EQ(back.pixels[i], image.pixels[i]) << file << " pixel " << i;
    }
}

TEST(ImageIo, HandMadeExrDecodes) {
    const pt::Image image = decode(small_exr());
    ASSERT_EQ(image.width, 2u);
    ASSERT_EQ(image.height, 2u);
    EXPECT_EQ(image.at(1, 0), glm::vec3(1.0f, 0.0f, 7.0f));
    EXPECT_EQ(image.at(0, 1), glm::vec3(0.0f, 1.0f, 7.0f));
}

// Other writers' files: half floats, tiles, a data window off the origin, luminance only.
TEST(ImageIo, ReadsTiledHalfAndLuminanceExr) {
    const fs::path dir = scratch_dir();
    const int width = 9;
    const int height = 5;
    const Imath::Box2i window({3, -2}, {3 + width - 1, -2 + height - 1});
    std::vector<half> values(static_cast<std::size_t>(width * height));
    for (std::size_t i = 0; i < values.size(); ++i)
        values[i] = half(0.5f * static_cast<float>(i));
    const auto slice = [&] {
        return Imf::Slice::Make(Imf::HALF, values.data(), window, sizeof(half),
                                sizeof(half) * static_cast<std::size_t>(width));
    };
    {
        Imf::Header header(window, window);
        header.channels().insert("Y", Imf::Channel(Imf::HALF));
        header.setTileDescription(Imf::TileDescription(4, 4, Imf::ONE_LEVEL));
        Imf::FrameBuffer frame;
        frame.insert("Y", slice());
        Imf::TiledOutputFile file((dir / "luminance.exr").string().c_str(), header);
        file.setFrameBuffer(frame);
        file.writeTiles(0, file.numXTiles() - 1, 0, file.numYTiles() - 1);
    }
    const pt::Image image = pt::read_image(dir / "luminance.exr");
    ASSERT_EQ(image.width, static_cast<std::uint32_t>(width));
    ASSERT_EQ(image.height, static_cast<std::uint32_t>(height));
    for (std::size_t i = 0; i < values.size(); ++i)
        ASSERT_EQ(image.pixels[i], glm::vec3(static_cast<float>(values[i]))) << i;
}

TEST(ImageIo, ExrWithoutColourChannelsIsNamed) {
    std::string bytes = small_exr();
    // Rename the channels B, G, R to b, g, r.
    for (const char* from : {"B", "G", "R"}) {
        const std::size_t at = bytes.find(std::string(from) + '\0' + le32(std::uint32_t{2}));
        ASSERT_NE(at, std::string::npos);
        bytes[at] = static_cast<char>(bytes[at] - 'A' + 'a');
    }
    expect_refused(bytes, "no R, G, B or Y channel (it has b, g, r)");
}

// The inputs of the security review, and their neighbours: each is a one-line error.
TEST(ImageIo, HostileExrHeadersAreOneLineErrors) {
    // A 26-byte file whose "type" is a 1-byte string (an assertion in the former reader).
    expect_refused(magic + le32(std::uint32_t{2}) + attribute("type", "string", "x") + '\0',
                   "OpenEXR");
    // A malformed tiles attribute: one byte where nine are due (a heap overflow before).
    expect_refused(magic + le32(std::uint32_t{0x202}) + attribute("tiles", "tiledesc", "x") + '\0',
                   "OpenEXR");
    // Truncated everywhere: each prefix of a good file.
    const std::string good = small_exr();
    for (std::size_t n = 0; n < good.size(); n += 7)
        expect_refused(good.substr(0, n), "OpenEXR");
    // Not an OpenEXR file at all.
    expect_refused("P6\n1 1\n255\n\xff\xff\xff", "OpenEXR");
    // A data window at INT_MIN (std::bad_alloc before), and an inverted one.
    const std::int32_t lowest = std::numeric_limits<std::int32_t>::min();
    expect_refused(scanline_header(lowest, lowest, 10, 10) + std::string(64, '\0'), "OpenEXR");
    expect_refused(scanline_header(5, 5, 0, 0) + std::string(64, '\0'), "OpenEXR");
    // A small file that claims 8331008 x 3 pixels (decoded into 673 MB before): wider than
    // any reader allows; and one too short for its chunk table.
    expect_refused(scanline_header(0, 0, 8331007, 2) + std::string(400, '\0'), "too large");
    expect_refused(scanline_header(0, 0, 99, 999) + std::string(400, '\0'), "1000 chunks");
    // A claim of more pixels than allowed.
    expect_refused(scanline_header(0, 0, 1 << 14, 1 << 14) + std::string(64, '\0'),
                   "pixels allowed");
    expect_refused(good, "pixels allowed", "hostile.exr", pt::ReadLimits{3});
    // Many wide channels: chunks far larger than any image needs.
    std::vector<std::string> many;
    for (int i = 0; i < 400; ++i)
        many.push_back(std::string(1, 'c').append(std::to_string(i)));
    expect_refused(scanline_header(0, 0, 65535, 0, many) + std::string(64, '\0'), "chunks");
    // Multi-part and deep files are not read.
    std::string multipart = small_exr();
    multipart[5] = static_cast<char>(0x10); // the multi-part bit
    expect_refused(multipart, "OpenEXR");
    std::string deep = small_exr();
    deep[5] = static_cast<char>(0x08); // the non-image (deep) bit
    expect_refused(deep, "OpenEXR");
    // Chunk offsets that point outside the file.
    std::string wild = good;
    const std::size_t table = scanline_header(0, 0, 1, 1).size();
    wild.replace(table, 8, le64(std::uint64_t{1} << 40));
    expect_refused(wild, "OpenEXR");
}

TEST(ImageIo, HostilePfmHeadersAreOneLineErrors) {
    // The size check's product used to wrap for 2147483648^2.
    expect_refused("PF\n2147483648 2147483648\n-1\n" + std::string(64, '\0'), "pixels allowed",
                   "hostile.pfm");
    expect_refused("PF\n4 4\n-1\n" + std::string(12, '\0'), "cut short", "hostile.pfm");
    expect_refused("PF\n0 4\n-1\n", "width", "hostile.pfm");
    expect_refused("PF\n4 4\nnan\n", "scale", "hostile.pfm");
    expect_refused("P6\n4 4\n255\n", "PF", "hostile.pfm");
    expect_refused("", "magic", "hostile.pfm");
}

// No hostile image makes the process grow past 1 GB (a 578-byte file reached 15 GB before).
// Each test runs in its own process, so the peak resident size is this test's own.
TEST(ImageIo, HostileImagesStayFarBelowOneGigabyte) {
    const std::int32_t big = (1 << 13) - 1;
    for (const std::string& bytes :
         {scanline_header(0, 0, big, big) + std::string(600, '\0'),
          scanline_header(0, 0, (1 << 20) - 1, 31) + std::string(600, '\0'),
          scanline_header(0, 0, 8331007, 2) + std::string(400, '\0')})
        EXPECT_THROW(decode(bytes), pt::ImageError);
    EXPECT_THROW(decode("PF\n65536 65536\n-1\n" + std::string(64, '\0'), "big.pfm"),
                 pt::ImageError);
    rusage usage{};
    getrusage(RUSAGE_SELF, &usage);
    EXPECT_LT(usage.ru_maxrss, 1L << 20) << "peak resident size in KiB";
}

TEST(ImageIo, FilesLargerThanAnyAllowedImageAreNotRead) {
    const fs::path path = scratch_dir() / "padded.pfm";
    std::ofstream(path, std::ios::binary) << "PF\n1 1\n-1\n" << std::string(2000, '\0');
    EXPECT_NO_THROW(pt::read_image(path));
    try {
        pt::read_image(path, pt::ReadLimits{1});
        // 1 pixel allows 32 bytes and a megabyte of tables: 2000 bytes still pass.
    } catch (const pt::ImageError& e) {
        ADD_FAILURE() << e.what();
    }
    const fs::path huge = scratch_dir() / "huge.pfm";
    {
        std::ofstream out(huge, std::ios::binary);
        out << "PF\n1 1\n-1\n";
        out << std::string((1u << 20) + 100, '\0');
    }
    try {
        pt::read_image(huge, pt::ReadLimits{1});
        ADD_FAILURE() << "accepted a file larger than the limit allows";
    } catch (const pt::ImageError& e) {
        EXPECT_NE(std::string(e.what()).find("larger than"), std::string::npos) << e.what();
    }
}

} // namespace
