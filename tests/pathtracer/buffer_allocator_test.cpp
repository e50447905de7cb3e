// The renderer's per-pixel storage (examples/pathtracer/buffer_allocator.hpp): every buffer on
// 64-byte boundaries, one of 2 MiB or more on a 2 MiB boundary (where huge pages can back it),
// and a plain vector otherwise.
#include "buffer_allocator.hpp"
#include "reservoir.hpp"

#include <gtest/gtest.h>

#include <cstddef>
#include <cstdint>
#include <numeric>

namespace {

std::uintptr_t address(const void* p) { return reinterpret_cast<std::uintptr_t>(p); }

TEST(BufferAllocator, SmallBuffersStartOnCacheLinesAndLargeOnesOnHugePages) {
    constexpr std::size_t huge_page = pt::BufferAllocator<char>::huge_page;
    for (std::size_t pixels : {std::size_t{1}, std::size_t{1000}, huge_page / 64u - 1u,
                               huge_page / 64u, std::size_t{1280} * 720u}) {
        const pt::ReservoirBuffer reservoirs(pixels);
        EXPECT_EQ(address(reservoirs.data()) % 64u, 0u) << pixels << " reservoirs";
        if (pixels * sizeof(pt::Reservoir) >= huge_page) {
            EXPECT_EQ(address(reservoirs.data()) % huge_page, 0u) << pixels << " reservoirs";
        }
        const pt::PixelBuffer<pt::GSurface> surfaces(pixels);
        EXPECT_EQ(address(surfaces.data()) % 64u, 0u) << pixels << " surfaces";
    }
}

TEST(BufferAllocator, BuffersBehaveAsVectors) {
    // Grown across the 2 MiB threshold, copied and swapped: the values survive every move
    // between the two kinds of storage (and in the sanitizer build ASan reports a buffer freed
    // with another alignment than it was allocated with: new-delete-type-mismatch).
    pt::PixelBuffer<std::uint32_t> values(1000u);
    std::iota(values.begin(), values.end(), 0u);
    values.resize(std::size_t{1} << 20u, 7u);
    ASSERT_EQ(values.size(), std::size_t{1} << 20u);
    EXPECT_EQ(values[999], 999u);
    EXPECT_EQ(values.back(), 7u);
    pt::PixelBuffer<std::uint32_t> copy = values;
    copy.resize(10u);
    copy.shrink_to_fit();
    std::swap(copy, values);
    EXPECT_EQ(values.size(), 10u);
    EXPECT_EQ(values[9], 9u);
    EXPECT_EQ(copy.size(), std::size_t{1} << 20u);
}

} // namespace
