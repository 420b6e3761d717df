// The host memory a render will take on top of the loaded scene, estimated before it is spent, and what the
// machine has: a render that does not fit is refused at once, with the figures (exit code 2).
#pragma once

#include <cstdint>
#include <string>

#include "common/memory_need.h"

namespace vkrt {

struct Options;

struct HostMemoryInputs {
    uint64_t triangles = 0;
    uint64_t textureBytes = 0;  // the scene's packed texels (packedTextureBytes)
    uint64_t environmentTexels = 0;  // the environment map's (its sampling tables and its GPU copy)
    int width = 0;
    int height = 0;
    bool gpu = false;                 // rendered by the GPU tracer
    bool deviceInHostMemory = false;  // the Vulkan device is the CPU (lavapipe): its memory is the host's
    uint64_t deviceBudgetBytes = UINT64_MAX;  // the most that device will hold (it tiles the image beyond)
    bool report = false;     // --report or --reference: a reference image and checkpoint images too
    bool shared = false;     // a rank of an MPI job: its sums are copied to be reduced (at checkpoints too)
    std::string outputPath;  // its extension decides the encoder's buffers
};

// The larger of two phases, part by part. Rendering: the BVH build, the scene packed for the GPU, on a CPU
// Vulkan device the device's buffers, the image's sums and its average. Writing: the BVH, the image and the
// encoder's buffers. Both: the reference and checkpoint images of a convergence report. A rank of an MPI job
// also holds the copy of its sums that it reduces, and at checkpoints a second one.
MemoryNeed estimateHostMemory(const HostMemoryInputs& inputs);

struct HostMemory {
    uint64_t bytes = 0;
    std::string source;  // "MemAvailable in /proc/meminfo", "the cgroup's memory.max", "--max-memory"
};

// What the machine can give now: MemAvailable, or less when a cgroup (a container) limits the process.
HostMemory availableHostMemory();

// What the machine has for the render, or --max-memory when that is less.
HostMemory hostMemoryFor(const Options& options);

// Throws MemoryError naming the need and what is available, when `need` is more than `available`.
void checkHostMemory(const MemoryNeed& need, const HostMemory& available);

}  // namespace vkrt
