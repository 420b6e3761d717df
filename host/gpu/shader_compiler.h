// Run-time GLSL to SPIR-V compilation with the glslang library. The shader sources are embedded in the
// binary at build time; each scene compiles its own variant (a list of defines), and the SPIR-V is cached
// on disk under a key made of the sources and the defines.
#pragma once

#include <cstdint>
#include <map>
#include <stdexcept>
#include <string>
#include <vector>

namespace vkrt {

class ShaderError : public std::runtime_error {
  public:
    using std::runtime_error::runtime_error;
};

// File name (as #included) to text, for every file under shaders/.
const std::map<std::string, std::string>& embeddedShaders();

struct CompiledShader {
    std::vector<uint32_t> spirv;
    bool fromCache = false;
    double compileMs = 0.0;  // time to get the SPIR-V: glslang's GLSL to SPIR-V, or reading it from the cache
    std::string cacheKey;
};

// What runs on the SPIR-V after glslang: spirv-opt's performance passes (the default; see
// shader_compiler.cpp), all but those that rewrite locals stored more than once into SSA form (KeepLocals:
// inlining, scalar replacement, the forwarding of locals stored once, simplification), or nothing (every
// function still there under its name, as the specialisation test reads them).
enum class SpirvOptimization { Performance, KeepLocals, None };

// The folder for cached SPIR-V: $VKRT_SHADER_CACHE, else $XDG_CACHE_HOME/vkrt, else ~/.cache/vkrt.
// An empty string turns the cache off.
std::string defaultShaderCacheDir();

// The most the SPIR-V cache keeps: each variant is 60 to 400 KiB, and every scene's features and every build
// of vkrt make variants of their own, so a cache that only grew would fill a disk over the years.
constexpr uintmax_t kShaderCacheBytes = uintmax_t(64) << 20;

// Removes the entries of the cache in `cacheDir` used longest ago (an entry's time is when it was written or
// last read) until the rest take at most `maxBytes`, and temporary files that a killed writer left an hour or
// more ago. Files that are not the cache's are left alone, and so are errors: another process may be pruning
// too.
void pruneShaderCache(const std::string& cacheDir, uintmax_t maxBytes);

// Compiles `mainFile` (a key of embeddedShaders()) with `#define NAME` for each entry of `defines`
// (entries may be "NAME VALUE"), or reads it from the cache in `cacheDir` (empty: none), which is then kept
// within kShaderCacheBytes. Throws ShaderError with glslang's log on failure.
CompiledShader compileShader(const std::string& mainFile, const std::vector<std::string>& defines,
                             const std::string& cacheDir,
                             SpirvOptimization optimization = SpirvOptimization::Performance);

// The same for a main file given as text (tests' own kernels); #include still reads embedded files.
CompiledShader compileShaderSource(const std::string& name, const std::string& source,
                                   const std::vector<std::string>& defines, const std::string& cacheDir,
                                   SpirvOptimization optimization = SpirvOptimization::Performance);

}  // namespace vkrt
