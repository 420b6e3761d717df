// Large scratch arrays for the BVH build: uninitialised, and on Linux backed by transparent huge pages
// where the kernel allows it (madvise), so that first touching 32 MB costs 16 page faults instead of 8192.
// Page faults are a large part of building a BVH over millions of primitives, on virtual machines most.
#pragma once

#include <algorithm>
#include <cstddef>
#include <cstdint>
#include <cstdlib>
#include <memory>
#include <new>
#include <type_traits>

#if defined(__linux__)
#include <sys/mman.h>
#endif

namespace vkrt {

inline constexpr size_t kHugePageBytes = size_t{2} << 20;

// Asks for huge pages over the 2 MiB-aligned part of [data, data + bytes), before it is first touched.
inline void adviseHugePages([[maybe_unused]] void* data, [[maybe_unused]] size_t bytes) {
#if defined(__linux__) && defined(MADV_HUGEPAGE)
    const uintptr_t begin = (reinterpret_cast<uintptr_t>(data) + kHugePageBytes - 1) & ~(kHugePageBytes - 1);
    const uintptr_t end = (reinterpret_cast<uintptr_t>(data) + bytes) & ~(kHugePageBytes - 1);
    if (end > begin) madvise(reinterpret_cast<void*>(begin), end - begin, MADV_HUGEPAGE);  // a hint only
#endif
}

// `count` uninitialised elements of a trivially copyable type, aligned to huge pages when large.
template <typename T>
class LargeBuffer {
    static_assert(std::is_trivially_copyable_v<T> && std::is_trivially_destructible_v<T>);

  public:
    LargeBuffer() = default;
    explicit LargeBuffer(size_t count) {
        const size_t bytes = std::max<size_t>(count * sizeof(T), 1);
        // aligned_alloc wants a multiple of the alignment; 64 bytes keep elements off shared cache lines.
        const size_t alignment = bytes >= kHugePageBytes ? kHugePageBytes : std::max<size_t>(alignof(T), 64);
        const size_t rounded = (bytes + alignment - 1) & ~(alignment - 1);
        data_.reset(static_cast<T*>(std::aligned_alloc(alignment, rounded)));
        if (!data_) throw std::bad_alloc();
        if (alignment == kHugePageBytes) adviseHugePages(data_.get(), rounded);
    }
    T* get() const { return data_.get(); }
    T& operator[](size_t i) const { return data_.get()[i]; }

  private:
    struct Free {
        void operator()(T* p) const { std::free(p); }
    };
    std::unique_ptr<T, Free> data_;
};

}  // namespace vkrt
