#include "app/host_memory.h"

#include <unistd.h>

#include <algorithm>
#include <fstream>
#include <sstream>

#include "app/options.h"
#include "common/file_names.h"

namespace vkrt {
namespace {

// Measured: `/usr/bin/time -f %M build/bvh_benchmark --triangles N --runs 1 --threads 2 --embree none` peaks
// at 233 MB for 1M triangles and 453 MB for 2M, 40 bytes of each triangle being the input's own.
constexpr uint64_t kBvhBuildBytesPerTriangle = 200;
// The GPU's copy of a triangle (shaders/shared.h): a 48-byte primitive, up to 64 bytes of shading data and
// its share of the 64-byte 4-wide nodes.
constexpr uint64_t kGpuBytesPerTriangle = 48 + 64 + 32;
// The GPU's copy of an environment texel (shaders/shared.h's GpuEnvironmentTexel): its radiance and its row's
// cumulative table.
constexpr uint64_t kGpuBytesPerEnvironmentTexel = 16;
// Per pixel: double sums and counts, the averaged float image.
constexpr uint64_t kSumBytesPerPixel = 32;
constexpr uint64_t kImageBytesPerPixel = 12;
constexpr uint64_t kDeviceAccumulationBytesPerPixel = 32;

// What an encoder holds besides the image: stb's PNG (8-bit RGB, filtered rows, the deflated file) or
// tinyexr's EXR (interleaved and planar float copies, the compressed file); PFM writes from the image. The
// extension is read in any case, as the writers read it: "m.EXR" is an EXR, and its encoder was left out.
uint64_t encoderBytesPerPixel(const std::string& path) {
    const std::string extension = lowerExtension(path);
    if (extension == ".png") return 10;
    if (extension == ".exr") return 48;
    return 0;
}

// A number from a file such as memory.max ("max" or missing: none).
uint64_t readNumber(const char* path) {
    std::ifstream file(path);
    uint64_t value = 0;
    return file >> value ? value : 0;
}

}  // namespace

MemoryNeed estimateHostMemory(const HostMemoryInputs& in) {
    const uint64_t pixels = static_cast<uint64_t>(in.width) * static_cast<uint64_t>(in.height);
    const uint64_t bvh = in.triangles * kBvhBuildBytesPerTriangle;
    const uint64_t referenceImages = in.report ? 2 * pixels * kImageBytesPerPixel : 0;
    // Two phases, and the larger is the need: rendering (the renderer's buffers) and writing the image file
    // (the renderer is gone by then; the encoder works from the image).
    MemoryNeed rendering;
    rendering.add("BVH build", bvh);
    // The texels: packed for the CPU reference; written straight into the GPU's buffers, mapped on a CPU
    // device (counted with its buffers below), else through a staging buffer of their size.
    // The environment map's sampling tables (a double per texel), and on the GPU its texels packed with them
    // (GpuEnvironmentTexel) next to the tables they are made from.
    rendering.add("environment sampling tables", in.environmentTexels * sizeof(double));
    if (in.gpu) {
        rendering.add("environment map packed for the GPU",
                      in.environmentTexels * kGpuBytesPerEnvironmentTexel);
        rendering.add("scene packed for the GPU", in.triangles * kGpuBytesPerTriangle);
        if (!in.deviceInHostMemory) rendering.add("texel staging buffer", in.textureBytes);
    } else {
        rendering.add("textures packed for the CPU reference", in.textureBytes);
    }
    if (in.deviceInHostMemory) {
        rendering.add("device buffers in host memory (a CPU device)",
                      std::min(in.deviceBudgetBytes, in.triangles * kGpuBytesPerTriangle + in.textureBytes +
                                                         in.environmentTexels * kGpuBytesPerEnvironmentTexel +
                                                         pixels * kDeviceAccumulationBytesPerPixel));
    }
    rendering.add("image sums", pixels * kSumBytesPerPixel);
    // A rank's sums reduced onto rank 0 (the reduction's buffer), and at a checkpoint the copy reduced then.
    if (in.shared)
        rendering.add("sums reduced across ranks", (in.report ? 2 : 1) * pixels * kSumBytesPerPixel);
    rendering.add("image", pixels * kImageBytesPerPixel);
    rendering.add("reference and checkpoint images", referenceImages);
    MemoryNeed writing;
    writing.add("BVH build", bvh);
    writing.add("image", pixels * kImageBytesPerPixel);
    writing.add("reference and checkpoint images", referenceImages);
    writing.add("image file encoding", pixels * encoderBytesPerPixel(in.outputPath));
    return writing.total() > rendering.total() ? writing : rendering;
}

HostMemory availableHostMemory() {
    HostMemory memory;
    std::ifstream meminfo("/proc/meminfo");
    std::string line;
    while (std::getline(meminfo, line)) {
        std::istringstream fields(line);
        std::string key;
        uint64_t kib = 0;
        if (fields >> key >> kib && key == "MemAvailable:") {
            memory.bytes = kib * 1024;
            memory.source = "MemAvailable in /proc/meminfo";
        }
    }
    if (memory.source.empty()) {
        memory.bytes =
            static_cast<uint64_t>(sysconf(_SC_AVPHYS_PAGES)) * static_cast<uint64_t>(sysconf(_SC_PAGESIZE));
        memory.source = "free physical memory";
    }
    // A container's limit (cgroup v2), less what the group holds already.
    if (const uint64_t limit = readNumber("/sys/fs/cgroup/memory.max"); limit > 0) {
        const uint64_t used = readNumber("/sys/fs/cgroup/memory.current");
        const uint64_t left = limit > used ? limit - used : 0;
        if (left < memory.bytes) {
            memory.bytes = left;
            memory.source = "the cgroup's memory.max less memory.current";
        }
    }
    return memory;
}

HostMemory hostMemoryFor(const Options& options) {
    HostMemory available = availableHostMemory();
    if (options.maxHostMemoryBytes > 0 && options.maxHostMemoryBytes < available.bytes)
        available = HostMemory{options.maxHostMemoryBytes, "--max-memory"};
    return available;
}

void checkHostMemory(const MemoryNeed& need, const HostMemory& available) {
    if (need.total() <= available.bytes) return;
    throw MemoryError("the render needs about " + need.describe() + " of host memory, and " +
                      formatBytes(available.bytes) + " is available (" + available.source + ")");
}

}  // namespace vkrt
