/// @file reuse/image_view.hpp
/// Non-owning views of per-pixel buffers (reservoirs, G-buffer surfaces) that the reuse
/// passes read. The caller owns the memory, in host or device space.
#pragma once

#include "restir/config.hpp"

#include <cstdint>
#include <type_traits>

namespace restir {

/// Integer pixel coordinates; may lie outside an image (then they name no pixel).
struct PixelCoord {
    std::int32_t x = 0;
    std::int32_t y = 0;
};

/// A row-major width x height image of `T` at `data` (element (x, y) at x + y * width).
/// Trivially copyable, so it can be passed to a GPU kernel by value.
template <class T>
struct ImageView {
    T* data = nullptr;
    std::uint32_t width = 0u;
    std::uint32_t height = 0u;

    /// True when `p` names a pixel of this image.
    RESTIR_HOST_DEVICE constexpr bool contains(PixelCoord p) const noexcept {
        return p.x >= 0 && p.y >= 0 && static_cast<std::uint32_t>(p.x) < width &&
               static_cast<std::uint32_t>(p.y) < height;
    }

    /// The element at `p`, which must be inside the image.
    RESTIR_HOST_DEVICE constexpr T& operator[](PixelCoord p) const noexcept {
        RESTIR_ASSERT(contains(p));
        return data[static_cast<std::uint32_t>(p.x) + static_cast<std::uint32_t>(p.y) * width];
    }

    /// The same image, read-only: `ImageView<T>` converts to `ImageView<const T>`, so a
    /// buffer written by one pass is passed as it is to the next pass, which reads it.
    /// (A template, so that views of const elements declare no conversion to themselves.)
    template <class U = T>
    requires(std::is_same_v<U, T> && !std::is_const_v<U>) RESTIR_HOST_DEVICE constexpr
    operator ImageView<const U>() const noexcept {
        return {data, width, height};
    }

    /// The linear index of `p` (for seeding per-pixel random numbers).
    RESTIR_HOST_DEVICE constexpr std::uint32_t index_of(PixelCoord p) const noexcept {
        return static_cast<std::uint32_t>(p.x) + static_cast<std::uint32_t>(p.y) * width;
    }
};

} // namespace restir
