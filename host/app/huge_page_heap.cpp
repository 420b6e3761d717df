#include "app/huge_page_heap.h"

#include <cstddef>
#include <cstdlib>
#include <fstream>
#include <sstream>
#include <string>

#include "common/large_buffer.h"

#if defined(__linux__) && defined(__GLIBC__)
#include <malloc.h>
#include <unistd.h>
#endif

namespace vkrt {

void useHugePageHeap() {
#if defined(__linux__) && defined(__GLIBC__) && defined(MADV_HUGEPAGE)
    constexpr int kGrowthStep = 256 << 20;
    constexpr int kOwnMappingFrom = 32 << 20;  // glibc's largest mmap threshold
    // mallopt returns 0 where a setting is refused (the sanitizers' allocators refuse all): the heap is then
    // left as it is.
    if (mallopt(M_TOP_PAD, kGrowthStep) == 0 || mallopt(M_TRIM_THRESHOLD, 1 << 30) == 0 ||
        mallopt(M_MMAP_THRESHOLD, kOwnMappingFrom) == 0 || mallopt(M_ARENA_MAX, 1) == 0) {
        return;
    }
    // Grow the heap by one step now, while its new pages are untouched, and advise them. (Through a volatile
    // pointer: the compiler may leave out a malloc whose block is only freed.)
    char* const top = static_cast<char*>(sbrk(0));
    static void* volatile grown;
    grown = std::malloc(kHugePageBytes);
    std::free(grown);
    char* const end = static_cast<char*>(sbrk(0));
    if (top != reinterpret_cast<char*>(-1) && end > top) adviseHugePages(top, static_cast<size_t>(end - top));
#endif
}

uint64_t hugePageBytes() {
    std::ifstream rollup("/proc/self/smaps_rollup");
    for (std::string line; std::getline(rollup, line);) {
        std::istringstream fields(line);
        std::string name;
        uint64_t kib = 0;
        if (fields >> name >> kib && name == "AnonHugePages:") return kib * 1024;
    }
    return 0;
}

}  // namespace vkrt
