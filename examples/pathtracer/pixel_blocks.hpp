// The pixel-block scheduler: the image in blocks of 8 x 8 pixels, the blocks spread over the
// renderer's threads. A block's pixels share one light tile (initial candidates), nearby
// reservoirs (reuse) and coherent rays, which are traced together as Embree packets.
#pragma once

#include <tbb/blocked_range.h>
#include <tbb/blocked_range2d.h>
#include <tbb/parallel_for.h>
#include <tbb/task_arena.h>

#include <algorithm>
#include <cstdint>
#include <vector>

namespace pt {

/// Pixels along each side of a pixel block.
inline constexpr std::uint32_t pixel_block_side = 8;
/// Pixels of a whole pixel block.
inline constexpr std::uint32_t pixels_per_block = pixel_block_side * pixel_block_side;

/// The pixels [x0, x1) x [y0, y1): 8 x 8, fewer at the image's right and bottom edges.
struct PixelBlock {
    std::uint32_t x0, y0, x1, y1;
};

/// The image's pixel blocks, numbered in rows, and the loops over them on a task arena.
class PixelBlocks {
public:
    PixelBlocks(std::uint32_t width, std::uint32_t height, tbb::task_arena& arena)
        : width_(width), height_(height), arena_(&arena) {}

    std::uint32_t columns() const { return (width_ + pixel_block_side - 1u) / pixel_block_side; }
    std::uint32_t rows() const { return (height_ + pixel_block_side - 1u) / pixel_block_side; }
    std::uint32_t count() const { return columns() * rows(); }
    /// The index of the block that holds pixel (x, y).
    std::uint32_t block_of(std::uint32_t x, std::uint32_t y) const {
        return x / pixel_block_side + (y / pixel_block_side) * columns();
    }
    /// Block `b`'s pixels.
    PixelBlock block_at(std::uint32_t b) const {
        const std::uint32_t x0 = b % columns() * pixel_block_side;
        const std::uint32_t y0 = b / columns() * pixel_block_side;
        return {x0, y0, std::min(width_, x0 + pixel_block_side),
                std::min(height_, y0 + pixel_block_side)};
    }

    /// body(x, y, i) for each pixel of `block` in rows, i = x + y * width.
    template <class Body>
    void for_each_pixel_of(const PixelBlock& block, Body&& body) const {
        for (std::uint32_t y = block.y0; y < block.y1; ++y)
            for (std::uint32_t x = block.x0; x < block.x1; ++x)
                body(x, y, x + y * width_);
    }

    /// body(block) for every block, in squares of up to 8 x 8 blocks (64 x 64 pixels) per task:
    /// reuse reads neighbours up to 30 pixels away, and a square's pixels with that apron stay
    /// in cache, where rows of blocks would stream many megabytes of reservoirs per row.
    template <class BlockBody>
    void for_each_block(BlockBody&& body) const {
        const std::uint32_t column_count = columns();
        const std::uint32_t row_count = rows();
        arena_->execute([&] {
            tbb::parallel_for(
                tbb::blocked_range2d<std::uint32_t>(0u, row_count, 8u, 0u, column_count, 8u),
                [&](const tbb::blocked_range2d<std::uint32_t>& range) {
                    for (std::uint32_t by = range.rows().begin(); by < range.rows().end(); ++by)
                        for (std::uint32_t bx = range.cols().begin(); bx < range.cols().end(); ++bx)
                            body(block_at(bx + by * column_count));
                },
                tbb::simple_partitioner{});
        });
    }

    /// body(block) for every block, grouped by the light tile `tile_of(b)` (< tile_count) that
    /// block b draws its candidates from, the tiles spread over the threads: each tile is read
    /// from memory once and then serves all its blocks from cache.
    template <class TileOf, class BlockBody>
    void for_each_block_by_tile(std::uint32_t tile_count, TileOf&& tile_of,
                                BlockBody&& body) const {
        const std::uint32_t blocks = count();
        std::vector<std::uint32_t> tile_starts(tile_count + 1u, 0u);
        for (std::uint32_t b = 0; b < blocks; ++b)
            ++tile_starts[tile_of(b) + 1u];
        for (std::uint32_t t = 0; t < tile_count; ++t)
            tile_starts[t + 1u] += tile_starts[t];
        std::vector<std::uint32_t> blocks_by_tile(blocks);
        std::vector<std::uint32_t> next(tile_starts.begin(), tile_starts.end() - 1);
        for (std::uint32_t b = 0; b < blocks; ++b)
            blocks_by_tile[next[tile_of(b)]++] = b;
        arena_->execute([&] {
            tbb::parallel_for(tbb::blocked_range<std::uint32_t>(0u, tile_count, 1u),
                              [&](const tbb::blocked_range<std::uint32_t>& range) {
                                  for (std::uint32_t k = tile_starts[range.begin()];
                                       k < tile_starts[range.end()]; ++k)
                                      body(block_at(blocks_by_tile[k]));
                              });
        });
    }

    /// The arena that the loops run on (also for the renderer's other parallel work).
    tbb::task_arena& arena() const { return *arena_; }

private:
    std::uint32_t width_, height_;
    tbb::task_arena* arena_;
};

} // namespace pt
