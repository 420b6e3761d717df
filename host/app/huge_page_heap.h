// The malloc heap of vkrt's main thread on transparent huge pages (Linux with glibc; elsewhere nothing).
#pragma once

#include <cstdint>

namespace vkrt {

// Makes the main arena's heap grow 256 MiB at a time and never shrink, with allocations below 32 MiB taken
// from it rather than from mappings of their own, and every thread's allocations from it (no arenas of the
// threads' own, which would be on 4 KiB pages), and advises the next 256 MiB MADV_HUGEPAGE before any of
// it is touched. Call it early in main, while the heap is small: what the heap holds beyond that first step
// is on 4 KiB pages, as before, but for the large buffers of a CPU device, which ask for huge pages
// themselves (gpu/gpu_buffer.cpp). Where the kernel gives no huge pages, or another allocator stands in front
// of glibc's (the sanitizers'), nothing changes.
//
// First-touch page faults on 4 KiB pages, each costly on a virtual machine, were a large part of the host's
// time (issue 13): lavapipe's pipeline creation, whose NIR passes allocate and zero their memory on this
// thread, took 75 ms of the Whitted scene's render and takes 45 on huge pages; decoding DamagedHelmet's
// textures took 830 ms and takes 195. The cost is resident memory where a block is touched in part (a huge
// page is resident whole): with this alone the helmet's peak grew from 309 to 371 MB on the CPU reference
// (459 to 543 with the GPU); with its textures packed in place too it is 306 (369). One arena: the scene
// loads, and the GPU's scene buffers are written, on threads of their own (prepared_render.cpp,
// gpu_renderer.cpp), whose arenas would be on 4 KiB pages (a Vulkan context made on such a thread cost 1,600
// more page faults); the CPU reference's render and the BVH build took as long with one arena as without. The
// one lock is no bottleneck on machines with many more cores either: a 1M-triangle BVH build makes about
// 1,500 allocations, and the CPU reference's render none per sample (counted with a uprobe on malloc).
// glibc's own tunable (glibc.malloc.hugetlb=1) does the like for every arena, but is read from the
// environment at start only.
void useHugePageHeap();

// The process's anonymous memory on transparent huge pages now (AnonHugePages in /proc/self/smaps_rollup), in
// bytes; 0 where the kernel does not say.
uint64_t hugePageBytes();

}  // namespace vkrt
