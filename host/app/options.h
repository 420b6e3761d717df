// The vkrt command line: parsing and help text.
#pragma once

#include <array>
#include <cstdint>
#include <optional>
#include <stdexcept>
#include <string>

#include "common/render_settings.h"

namespace vkrt {

class UsageError : public std::runtime_error {
  public:
    using std::runtime_error::runtime_error;
};

enum class DeviceKind { Gpu, Cpu };

struct Options {
    std::string scenePath;
    std::string outputPath = "out.png";
    std::string statsPath;  // empty: no stats file
    DeviceKind device = DeviceKind::Gpu;
    int deviceIndex = -1;  // -1: choose (discrete GPU first)
    bool listDevices = false;
    bool validate = false;  // Khronos validation layer
    double timeLimitSeconds = 0.0;
    std::optional<double> aperture;                // thin-lens radius; overrides the camera's
    std::optional<double> focusDistance;           // overrides the camera's
    std::optional<std::array<double, 2>> shutter;  // motion blur: open and close times; overrides the scene's
    std::string referencePath;                     // --reference: image to measure the error against
    std::string reportPath;                        // --report: convergence report (.json or .csv)
    double reportEveryMs = 0.0;                    // --report-every-ms: checkpoints by time too
    int camera = 0;
    bool widthGiven = false, heightGiven = false;
    std::optional<glm::dvec3> ambient;  // unset: 0.05, or 1 for a scene without lights
    double exposure = 0.0;
    bool quiet = false;
    bool help = false;
    RenderSettings render;
};

// Throws UsageError with a one-line message for anything malformed.
Options parseOptions(int argc, const char* const argv[]);

const char* helpText();

}  // namespace vkrt
