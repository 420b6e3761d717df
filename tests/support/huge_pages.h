// What the tests read of the kernel's transparent huge pages.
#pragma once

#include <cstdint>
#include <cstdio>
#include <fstream>
#include <string>

#include <sys/mman.h>

namespace vkrt::test {

// The kernel's transparent huge pages are given where a program asks for them (madvise), and only there: then
// a test can tell asking from not asking.
inline bool hugePagesOnRequest() {
    std::ifstream mode("/sys/kernel/mm/transparent_hugepage/enabled");
    std::string modes;
    std::getline(mode, modes);
    return modes.find("[madvise]") != std::string::npos;
}

// The huge pages of [begin, end) now: AnonHugePages of every mapping in /proc/self/smaps that overlaps it.
inline uint64_t hugePageBytesIn(uintptr_t begin, uintptr_t end) {
    std::ifstream smaps("/proc/self/smaps");
    uint64_t bytes = 0;
    bool overlaps = false;
    for (std::string line; std::getline(smaps, line);) {
        unsigned long from = 0, to = 0, kib = 0;
        // A mapping's first line starts "from-to perms"; its fields ("Name: value") follow.
        if (line.find(':') > line.find(' ') && std::sscanf(line.c_str(), "%lx-%lx ", &from, &to) == 2) {
            overlaps = from < end && to > begin;
        } else if (overlaps && std::sscanf(line.c_str(), "AnonHugePages: %lu kB", &kib) == 1) {
            bytes += uint64_t{kib} * 1024;
        }
    }
    return bytes;
}

// Whether the kernel gives huge pages to memory that asks for them now: a fresh 16 MiB mapping advised for
// them, written, holds at least 12 MiB of them. When its free memory is fragmented (just after a build, say)
// it gives 4 KiB pages, as it may, and a test of vkrt's asking cannot tell anything.
inline bool hugePagesGivenNow() {
    constexpr size_t kBytes = size_t{16} << 20, kAlign = size_t{2} << 20;
    void* mapping =
        mmap(nullptr, kBytes + kAlign, PROT_READ | PROT_WRITE, MAP_PRIVATE | MAP_ANONYMOUS, -1, 0);
    if (mapping == MAP_FAILED) return false;
    const uintptr_t begin = (reinterpret_cast<uintptr_t>(mapping) + kAlign - 1) & ~(kAlign - 1);
    bool given = false;
    if (madvise(reinterpret_cast<void*>(begin), kBytes, MADV_HUGEPAGE) == 0) {
        for (size_t i = 0; i < kBytes; i += 4096) reinterpret_cast<volatile char*>(begin)[i] = 1;
        given = hugePageBytesIn(begin, begin + kBytes) >= kBytes - (size_t{4} << 20);
    }
    munmap(mapping, kBytes + kAlign);
    return given;
}

// Whether the mapping holding `address` is anonymous memory (no file behind it: inode 0 in /proc/self/maps).
// Memory from a file or a memfd (shared memory) takes huge pages by other rules, and smaps does not count
// them as AnonHugePages.
inline bool anonymousMemoryAt(uintptr_t address) {
    std::ifstream maps("/proc/self/maps");
    for (std::string line; std::getline(maps, line);) {
        unsigned long from = 0, to = 0, inode = 0;
        char perms[8] = {}, offset[20] = {}, device[16] = {};
        if (std::sscanf(line.c_str(), "%lx-%lx %7s %19s %15s %lu", &from, &to, perms, offset, device,
                        &inode) == 6 &&
            from <= address && address < to) {
            return inode == 0;
        }
    }
    return false;
}

}  // namespace vkrt::test
