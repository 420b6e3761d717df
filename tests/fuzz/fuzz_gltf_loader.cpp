// libFuzzer target for the glTF loader (-DVKRT_FUZZ=ON, clang): each input is loaded as the file it is (JSON,
// or binary glTF when it starts with the GLB magic), then as the JSON chunk of a GLB container. Loading must end
// in a Scene, a SceneError or a MemoryError; anything else (a crash, a sanitizer report, another exception, a hang) is a
// finding. tools/fuzz_loader.sh seeds and runs it; what it finds is kept in tests/fuzz/regressions/, which the
// test suite loads on every build.
#include <cstdint>
#include <cstdlib>
#include <filesystem>
#include <fstream>
#include <string>

#include "common/memory_need.h"
#include "scene/gltf_loader.h"
#include "scene/scene_error.h"

namespace {

const std::filesystem::path& folder() {
    static const std::filesystem::path path = [] {
        std::string pattern = (std::filesystem::temp_directory_path() / "vkrt-fuzz-XXXXXX").string();
        if (!mkdtemp(pattern.data())) std::abort();
        return std::filesystem::path(pattern);
    }();
    return path;
}

void load(const std::string& name, const std::string& bytes) {
    const std::filesystem::path file = folder() / name;
    std::ofstream(file, std::ios::binary | std::ios::trunc).write(bytes.data(), static_cast<std::streamsize>(bytes.size()));
    // What the scene would hold is counted against a gigabyte, as the command counts it against the memory
    // available: beyond it, the loader refuses the file (a clean end, as bad input is).
    vkrt::LoadOptions options;
    options.maxSceneBytes = uint64_t{1} << 30;
    options.memorySource = "the fuzzer's limit";
    try {
        vkrt::loadGltf(file.string(), options);
    } catch (const vkrt::SceneError&) {
        // Bad input, reported: what the loader should do.
    } catch (const vkrt::MemoryError&) {
        // More than the limit, refused before it was taken.
    }
}

std::string littleEndian(uint32_t v) {
    std::string bytes(4, '\0');
    for (int i = 0; i < 4; ++i) bytes[i] = static_cast<char>((v >> (8 * i)) & 0xffu);
    return bytes;
}

}  // namespace

extern "C" int LLVMFuzzerTestOneInput(const uint8_t* data, size_t size) {
    const std::string bytes(reinterpret_cast<const char*>(data), size);
    load("input.gltf", bytes);
    // The same bytes as a GLB's JSON chunk, padded to 4 bytes as GLB requires.
    const std::string json = bytes + std::string((4 - size % 4) % 4, ' ');
    load("input.glb", "glTF" + littleEndian(2) + littleEndian(static_cast<uint32_t>(20 + json.size())) +
                          littleEndian(static_cast<uint32_t>(json.size())) + "JSON" + json);
    return 0;
}
