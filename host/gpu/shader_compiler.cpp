#include "gpu/shader_compiler.h"

#include <algorithm>
#include <chrono>
#include <cstdlib>
#include <cstring>
#include <filesystem>
#include <fstream>
#include <mutex>
#include <sstream>
#include <string_view>

#include <glslang/Public/ResourceLimits.h>
#include <glslang/Public/ShaderLang.h>
#include <glslang/SPIRV/GlslangToSpv.h>
#include <glslang/build_info.h>
#include <spirv-tools/optimizer.hpp>

#include "common/atomic_file.h"

namespace vkrt {
namespace {

// Resolves #include "name" against the embedded shader sources.
class EmbeddedIncluder : public glslang::TShader::Includer {
  public:
    IncludeResult* includeLocal(const char* headerName, const char*, size_t) override {
        return find(headerName);
    }
    IncludeResult* includeSystem(const char* headerName, const char*, size_t) override {
        return find(headerName);
    }
    void releaseInclude(IncludeResult* result) override { delete result; }

  private:
    IncludeResult* find(const char* name) {
        const auto& sources = embeddedShaders();
        auto it = sources.find(name);
        if (it == sources.end()) return nullptr;
        return new IncludeResult(it->first, it->second.data(), it->second.size(), nullptr);
    }
};

// FNV-1a, 64 bits: a stable key for the cache (not a security boundary).
uint64_t fnv1a(std::string_view text, uint64_t hash = 1469598103934665603ull) {
    for (unsigned char c : text) {
        hash ^= c;
        hash *= 1099511628211ull;
    }
    return hash;
}

std::string cacheKeyFor(const std::string& mainFile, const std::string& mainText, const std::string& preamble,
                        SpirvOptimization optimization) {
    // SPIR-V run through spirv-opt (optimizeSpirv) has keys of its own, so caches from before are not reused.
    const char* optimizer = optimization == SpirvOptimization::Performance ? " spirv-opt -O"
                            : optimization == SpirvOptimization::KeepLocals
                                ? " spirv-opt inline, scalar replacement, simplification"
                                : "";
    uint64_t hash =
        fnv1a(std::to_string(GLSLANG_VERSION_MAJOR) + "." + std::to_string(GLSLANG_VERSION_MINOR) + "." +
              std::to_string(GLSLANG_VERSION_PATCH) + optimizer);
    hash = fnv1a(mainFile, hash);
    hash = fnv1a(mainText, hash);
    hash = fnv1a(preamble, hash);
    for (const auto& [name, text] : embeddedShaders()) hash = fnv1a(text, fnv1a(name, hash));
    std::ostringstream key;
    key << std::hex << hash;
    return key.str();
}

// A cache entry (KEY.spvc) is the SPIR-V module followed by two words, the FNV-1a hash of the module's bytes
// (fnv1a): an entry cut short or changed on disk is compiled again rather than handed to the driver (lavapipe
// failed every later render of the scene with VK_ERROR_UNKNOWN, naming no cache).
uint64_t moduleChecksum(const std::vector<uint32_t>& spirv, size_t words) {
    return fnv1a(std::string_view(reinterpret_cast<const char*>(spirv.data()), words * 4));
}

bool readCache(const std::filesystem::path& file, std::vector<uint32_t>& spirv) {
    std::ifstream in(file, std::ios::binary | std::ios::ate);
    if (!in) return false;
    const std::streamsize bytes = in.tellg();
    if (bytes < 28 || bytes % 4 != 0) return false;  // a header of five words and the checksum at least
    std::vector<uint32_t> words(static_cast<size_t>(bytes) / 4);
    in.seekg(0);
    in.read(reinterpret_cast<char*>(words.data()), bytes);
    const size_t moduleWords = words.size() - 2;
    uint64_t stored = 0;
    std::memcpy(&stored, words.data() + moduleWords, sizeof(stored));
    if (!in || words[0] != 0x07230203u || stored != moduleChecksum(words, moduleWords)) return false;
    words.resize(moduleWords);
    spirv = std::move(words);
    return true;
}

// spirv-opt's performance passes (spirv-opt -O): functions inlined, loads and stores of locals forwarded,
// dead code removed. glslang runs them only for HLSL or with optimizeSize. On lavapipe the module is about
// half the size and pipeline creation (spirv_to_nir and NIR's passes, the bulk of a render's fixed cost)
// takes a quarter to a third of the time (docs/performance-log.md). The path kernel runs slower with them,
// because of one of them: the SSA rewrite of locals stored more than once (eliminate-local-multi-store) alone
// made it 1.8 times as slow (gpu_ms 1420 against 790 on the Whitted scene), its loop-carried state turned
// into phis. KeepLocals runs the passes before that one: every function inlined into main, locals stored once
// forwarded, and local structs split into their members (scalar replacement) and forwarded again. Pipeline
// creation then takes a quarter of the unoptimised module's time (100 against 370 ms on the Cornell box,
// before the scalar replacement, which cut it by another 12 to 40 ms: the Whitted scene's path kernel 137
// against 103 ms, medians of 4) and the kernel runs as fast, the image the same bit for bit. Then the
// performance passes that leave locals in memory (constant propagation, redundancy elimination,
// simplification, dead branches, block merging): the Whitted scene's path kernel 123 KiB instead of 220, its
// pipeline made in 60 ms instead of 76 (Cornell box 28 against 39, scenes/textures.gltf 99 against 115),
// the GPU time and the image the same (medians of 5 alternate rounds). The passes leave NoContraction (GLSL
// `precise`) arithmetic as written.
// Returns the input unchanged if the optimizer fails.
std::vector<uint32_t> optimizeSpirv(const std::vector<uint32_t>& spirv, SpirvOptimization optimization) {
    spvtools::Optimizer optimizer(SPV_ENV_VULKAN_1_2);
    if (optimization == SpirvOptimization::Performance) {
        optimizer.RegisterPerformancePasses();
    } else {
        optimizer.RegisterPass(spvtools::CreateWrapOpKillPass())
            .RegisterPass(spvtools::CreateDeadBranchElimPass())
            .RegisterPass(spvtools::CreateMergeReturnPass())
            .RegisterPass(spvtools::CreateInlineExhaustivePass())
            .RegisterPass(spvtools::CreateEliminateDeadFunctionsPass())
            .RegisterPass(spvtools::CreateAggressiveDCEPass())
            .RegisterPass(spvtools::CreatePrivateToLocalPass())
            .RegisterPass(spvtools::CreateLocalSingleBlockLoadStoreElimPass())
            .RegisterPass(spvtools::CreateLocalSingleStoreElimPass())
            .RegisterPass(spvtools::CreateAggressiveDCEPass())
            .RegisterPass(spvtools::CreateScalarReplacementPass(100))
            .RegisterPass(spvtools::CreateLocalSingleBlockLoadStoreElimPass())
            .RegisterPass(spvtools::CreateLocalSingleStoreElimPass())
            .RegisterPass(spvtools::CreateAggressiveDCEPass())
            // The performance passes that neither rewrite locals into SSA nor need it done: constants
            // propagated, redundant values and dead branches removed, instructions simplified, blocks merged.
            .RegisterPass(spvtools::CreateLocalAccessChainConvertPass())
            .RegisterPass(spvtools::CreateCCPPass())
            .RegisterPass(spvtools::CreateRedundancyEliminationPass())
            .RegisterPass(spvtools::CreateCombineAccessChainsPass())
            .RegisterPass(spvtools::CreateSimplificationPass())
            .RegisterPass(spvtools::CreateVectorDCEPass())
            .RegisterPass(spvtools::CreateDeadInsertElimPass())
            .RegisterPass(spvtools::CreateDeadBranchElimPass())
            .RegisterPass(spvtools::CreateCopyPropagateArraysPass())
            .RegisterPass(spvtools::CreateReduceLoadSizePass())
            .RegisterPass(spvtools::CreateAggressiveDCEPass())
            .RegisterPass(spvtools::CreateBlockMergePass())
            .RegisterPass(spvtools::CreateCFGCleanupPass());
    }
    std::vector<uint32_t> optimized;
    if (!optimizer.Run(spirv.data(), spirv.size(), &optimized) || optimized.empty()) return spirv;
    return optimized;
}

void initializeGlslangOnce() {
    static std::once_flag once;
    std::call_once(once, [] {
        glslang::InitializeProcess();
        std::atexit([] { glslang::FinalizeProcess(); });
    });
}

}  // namespace

std::string defaultShaderCacheDir() {
    if (const char* explicitDir = std::getenv("VKRT_SHADER_CACHE")) return explicitDir;
    if (const char* xdg = std::getenv("XDG_CACHE_HOME"); xdg && *xdg) return std::string(xdg) + "/vkrt";
    if (const char* home = std::getenv("HOME"); home && *home) return std::string(home) + "/.cache/vkrt";
    return "";
}

CompiledShader compileShader(const std::string& mainFile, const std::vector<std::string>& defines,
                             const std::string& cacheDir, SpirvOptimization optimization) {
    const auto& sources = embeddedShaders();
    const auto main = sources.find(mainFile);
    if (main == sources.end()) throw ShaderError("no embedded shader named " + mainFile);
    return compileShaderSource(main->first, main->second, defines, cacheDir, optimization);
}

CompiledShader compileShaderSource(const std::string& mainFile, const std::string& source,
                                   const std::vector<std::string>& defines, const std::string& cacheDir,
                                   SpirvOptimization optimization) {
    const auto start = std::chrono::steady_clock::now();

    std::string preamble;
    for (const std::string& define : defines) {
        std::string line = define;
        const size_t space = line.find(' ');
        if (space == std::string::npos) line += " 1";
        preamble += "#define " + line + "\n";
    }
    CompiledShader result;
    result.cacheKey = cacheKeyFor(mainFile, source, preamble, optimization);
    const std::filesystem::path cacheFile =
        cacheDir.empty() ? std::filesystem::path()
                         : std::filesystem::path(cacheDir) / (result.cacheKey + ".spvc");
    if (!cacheDir.empty() && readCache(cacheFile, result.spirv)) {
        // The entry's time is its last use, for pruneShaderCache (a cache may be read-only).
        std::error_code ignored;
        std::filesystem::last_write_time(cacheFile, std::filesystem::file_time_type::clock::now(), ignored);
        result.fromCache = true;
        result.compileMs =
            std::chrono::duration<double, std::milli>(std::chrono::steady_clock::now() - start).count();
        return result;
    }

    initializeGlslangOnce();
    glslang::TShader shader(EShLangCompute);
    const char* text = source.c_str();
    const char* name = mainFile.c_str();
    shader.setStringsWithLengthsAndNames(&text, nullptr, &name, 1);
    shader.setPreamble(preamble.c_str());
    shader.setEnvInput(glslang::EShSourceGlsl, EShLangCompute, glslang::EShClientVulkan, 100);
    shader.setEnvClient(glslang::EShClientVulkan, glslang::EShTargetVulkan_1_2);
    shader.setEnvTarget(glslang::EShTargetSpv, glslang::EShTargetSpv_1_5);
    EmbeddedIncluder includer;
    const auto messages = static_cast<EShMessages>(EShMsgSpvRules | EShMsgVulkanRules);
    if (!shader.parse(GetDefaultResources(), 460, false, messages, includer)) {
        throw ShaderError(mainFile + ": " + shader.getInfoLog());
    }
    glslang::TProgram program;
    program.addShader(&shader);
    if (!program.link(messages)) throw ShaderError(mainFile + ": link failed: " + program.getInfoLog());
    glslang::SpvOptions options;
    options.disableOptimizer = false;
    options.optimizeSize = false;
    std::vector<uint32_t> unoptimized;
    glslang::GlslangToSpv(*program.getIntermediate(EShLangCompute), unoptimized, &options);
    result.spirv =
        optimization == SpirvOptimization::None ? unoptimized : optimizeSpirv(unoptimized, optimization);
    result.compileMs =
        std::chrono::duration<double, std::milli>(std::chrono::steady_clock::now() - start).count();

    if (!cacheDir.empty()) {
        // A cache that cannot be written is no reason to fail the render.
        try {
            std::filesystem::create_directories(cacheDir);
            writeFileAtomically(cacheFile.string(), [&](const std::string& temporary) {
                std::ofstream out(temporary, std::ios::binary);
                const uint64_t checksum = moduleChecksum(result.spirv, result.spirv.size());
                out.write(reinterpret_cast<const char*>(result.spirv.data()),
                          static_cast<std::streamsize>(result.spirv.size() * 4));
                out.write(reinterpret_cast<const char*>(&checksum), sizeof(checksum));
                if (!out.flush()) throw std::runtime_error("cannot write the shader cache");
            });
            pruneShaderCache(cacheDir, kShaderCacheBytes);
        } catch (const std::exception&) {
        }
    }
    return result;
}

void pruneShaderCache(const std::string& cacheDir, uintmax_t maxBytes) {
    namespace fs = std::filesystem;
    struct Entry {
        fs::file_time_type time;
        uintmax_t bytes;
        fs::path path;
    };
    std::vector<Entry> entries;
    uintmax_t total = 0;
    const fs::file_time_type now = fs::file_time_type::clock::now();
    std::error_code error;
    for (fs::directory_iterator it(cacheDir, error), end; !error && it != end; it.increment(error)) {
        std::error_code ignored;
        const fs::file_time_type time = it->last_write_time(ignored);
        if (ignored || !it->is_regular_file(ignored)) continue;
        const fs::path& path = it->path();
        if (path.filename().string().find(".spvc.tmp-") != std::string::npos) {
            if (now - time >= std::chrono::hours(1)) fs::remove(path, ignored);
        } else if (path.extension() == ".spvc") {
            const uintmax_t bytes = it->file_size(ignored);
            if (ignored) continue;
            entries.push_back({time, bytes, path});
            total += bytes;
        }
    }
    std::sort(entries.begin(), entries.end(), [](const Entry& a, const Entry& b) { return a.time < b.time; });
    for (const Entry& entry : entries) {
        if (total <= maxBytes) break;
        std::error_code ignored;
        fs::remove(entry.path, ignored);
        total -= entry.bytes;
    }
}

}  // namespace vkrt
