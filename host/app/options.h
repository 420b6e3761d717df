// The vkrt command line: parsing and help text.
#pragma once

#include <array>
#include <cstdint>
#include <optional>
#include <stdexcept>
#include <string>
#include <vector>

#include "app/render_policy.h"
#include "image/tone_map.h"

namespace vkrt {

class UsageError : public std::runtime_error {
  public:
    using std::runtime_error::runtime_error;
};

enum class DeviceKind { Gpu, Cpu };

struct Options {
    std::vector<std::string> warnings;  // options that do nothing in this run, one line each
    std::string scenePath;
    std::string outputPath = "out.png";
    std::string statsPath;  // empty: no stats file
    DeviceKind device = DeviceKind::Gpu;
    int deviceIndex = -1;  // -1: choose (discrete GPU first)
    bool listDevices = false;
    bool validate = false;           // Khronos validation layer
    bool allShaderFeatures = false;  // --shader-features all: compile every feature, not only the scene's
    std::string sceneAccess = "auto";  // --scene-access: how GPU kernels read the scene (auto, texels, ...)
    double timeLimitSeconds = 0.0;
    uint64_t maxHostMemoryBytes = 0;               // --max-memory; 0: what the system has available
    uint64_t maxDeviceMemoryBytes = 0;             // --max-device-memory; 0: what the device offers
    std::optional<std::array<double, 2>> shutter;  // motion blur: open and close times; overrides the scene's
    std::string animation;  // the animation that plays: index or name; empty: the first
    std::string referencePath;                     // --reference: image to measure the error against
    std::string reportPath;                        // --report: convergence report (.json or .csv)
    double reportEveryMs = 0.0;                    // --report-every-ms: checkpoints by time too
    double exposure = 0.0;
    ToneMap toneMap = kDefaultToneMap;  // PNG only
    bool quiet = false;
    bool help = false;
    std::string environmentPath;       // --environment: equirectangular .hdr or .exr; empty: none
    double environmentRotation = 0.0;  // degrees about +Y
    double environmentStrength = 1.0;
    RenderRequest request;  // settings, camera and lens as asked; resolveRender() fills in the rest
};

// Throws UsageError with a one-line message for anything malformed.
Options parseOptions(int argc, const char* const argv[]);

// Every option with its default.
std::string helpText();

}  // namespace vkrt
