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

// Compiles `mainFile` (a key of embeddedShaders()) with `#define NAME` for each entry of `defines`
// (entries may be "NAME VALUE"). Throws ShaderError with glslang's log on failure.
CompiledShader compileShader(const std::string& mainFile, const std::vector<std::string>& defines,
                             const std::string& cacheDir,
                             SpirvOptimization optimization = SpirvOptimization::Performance);

// The same for a main file given as text (tests' own kernels); #include still reads embedded files.
CompiledShader compileShaderSource(const std::string& name, const std::string& source,
                                   const std::vector<std::string>& defines, const std::string& cacheDir,
                                   SpirvOptimization optimization = SpirvOptimization::Performance);

}  // namespace vkrt
