// Storage for the renderer's per-pixel buffers (reservoirs, G-buffer surfaces).
#pragma once

#include <cstddef>
#include <new>
#include <vector>

#if defined(__linux__)
#include <sys/mman.h>
#endif

namespace pt {

/// Storage on 64-byte boundaries, so that a 64-byte record is one cache line (reuse reads its
/// neighbours' at random, and a record across two lines costs two misses). A buffer of 2 MiB or
/// more starts on a 2 MiB boundary and asks Linux for transparent huge pages (`madvise`; the
/// kernel may decline, and elsewhere nothing is asked): a spatial pass reads reservoirs and
/// surfaces in a window of about 60 rows, several megabytes, which in 4 KiB pages overflows the
/// TLB (docs/performance.md, "Huge pages").
template <class T>
struct BufferAllocator {
    using value_type = T;
    static constexpr std::size_t huge_page = std::size_t{2} << 20u;

    BufferAllocator() = default;
    template <class U>
    BufferAllocator(const BufferAllocator<U>&) noexcept {}

    T* allocate(std::size_t n) {
        const std::size_t bytes = n * sizeof(T);
        if (bytes < huge_page)
            return static_cast<T*>(::operator new (bytes, std::align_val_t{64}));
        // Whole huge pages, so that the last one is not shared with other allocations.
        const std::size_t rounded = (bytes + huge_page - 1u) / huge_page * huge_page;
        void* p = ::operator new (rounded, std::align_val_t{huge_page});
#if defined(__linux__) && defined(MADV_HUGEPAGE)
        ::madvise(p, rounded, MADV_HUGEPAGE); // a hint: failure leaves 4 KiB pages
#endif
        return static_cast<T*>(p);
    }
    void deallocate(T* p, std::size_t n) noexcept {
        const bool huge = n * sizeof(T) >= huge_page;
        ::operator delete (p, std::align_val_t{huge ? huge_page : 64u});
    }
    bool operator==(const BufferAllocator&) const noexcept { return true; }
};

/// A per-pixel buffer in `BufferAllocator` storage.
template <class T>
using PixelBuffer = std::vector<T, BufferAllocator<T>>;

} // namespace pt
