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
#include <vector>

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

// The allocator of HugePageVector: arrays of 2 MiB or more are whole huge pages (aligned and rounded up to
// them), so that no part of a large array faults 4 KiB at a time; smaller ones come from std::allocator.
template <typename T>
struct HugePageAllocator {
    using value_type = T;
    HugePageAllocator() = default;
    template <typename U>
    HugePageAllocator(const HugePageAllocator<U>&) {}

    T* allocate(size_t count) {
        const size_t bytes = count * sizeof(T);
        if (bytes < kHugePageBytes) return std::allocator<T>{}.allocate(count);
        const size_t rounded = (bytes + kHugePageBytes - 1) & ~(kHugePageBytes - 1);
        void* data = std::aligned_alloc(kHugePageBytes, rounded);
        if (!data) throw std::bad_alloc();
        adviseHugePages(data, rounded);
        return static_cast<T*>(data);
    }
    void deallocate(T* data, size_t count) {
        if (count * sizeof(T) < kHugePageBytes) {
            std::allocator<T>{}.deallocate(data, count);
        } else {
            std::free(data);
        }
    }
    template <typename U>
    bool operator==(const HugePageAllocator<U>&) const {
        return true;
    }
};

// A std::vector on huge pages: for arrays of millions of elements, such as the BVH's nodes, whose first
// touch on 4 KiB pages costs more than filling them (a virtual machine measured 32 MB in 130 ms on 4 KiB
// pages, 3 ms on huge pages).
template <typename T>
using HugePageVector = std::vector<T, HugePageAllocator<T>>;

}  // namespace vkrt
