#include "app/options.h"

#include <charconv>
#include <cmath>
#include <filesystem>
#include <sstream>
#include <vector>

#include "image/image_io.h"
#include "random.h"

namespace vkrt {
namespace {

template <typename T>
T parseNumber(const std::string& flag, const std::string& text) {
    T value{};
    const char* end = text.data() + text.size();
    auto [ptr, error] = std::from_chars(text.data(), end, value);
    if (error != std::errc() || ptr != end) throw UsageError(flag + ": '" + text + "' is not a valid number");
    if constexpr (std::is_floating_point_v<T>) {
        if (!std::isfinite(value)) throw UsageError(flag + ": '" + text + "' is not finite");
    }
    return value;
}

int parseInt(const std::string& flag, const std::string& text, int min, int max) {
    const long long value = parseNumber<long long>(flag, text);
    if (value < min || value > max) {
        throw UsageError(flag + " must be between " + std::to_string(min) + " and " + std::to_string(max));
    }
    return static_cast<int>(value);
}

glm::dvec3 parseColor(const std::string& flag, const std::string& text) {
    std::vector<double> parts;
    std::stringstream stream(text);
    std::string part;
    while (std::getline(stream, part, ',')) parts.push_back(parseNumber<double>(flag, part));
    if (parts.size() == 1) return glm::dvec3(parts[0]);
    if (parts.size() == 3) return glm::dvec3(parts[0], parts[1], parts[2]);
    throw UsageError(flag + " takes one value or three separated by commas (R,G,B)");
}

}  // namespace

const char* helpText() {
    return R"(vkrt: a Vulkan compute ray tracer for glTF 2.0 scenes

Usage: vkrt --scene FILE [options]

  --scene FILE          glTF 2.0 scene (.gltf or .glb) to render (required)
  --out FILE            output image: .png (tonemapped sRGB), .exr or .pfm (linear)  [out.png]
  --width W             image width in pixels                                         [512]
  --height H            image height in pixels  [width / the camera's aspect ratio, else 512]
  --spp N               samples per pixel (jittered, stratified)                      [16]
  --max-depth D         reflection/refraction bounces after the first hit (0-24)     [8]
  --light-samples N     area-light samples per shading point (1-16)                   [1]
  --no-mis              light glossy surfaces by light samples alone (no multiple importance sampling)
  --filter box|tent|gaussian   pixel filter (tent: radius 1 px; Gaussian: sigma 0.5 px) [box]
  --device gpu|cpu      GPU tracer (Vulkan compute) or the CPU reference renderer   [gpu]
  --device-index N      which Vulkan device (see --list-devices)    [discrete GPU first]
  --list-devices        print the Vulkan devices and exit
  --validate            enable the Khronos validation layer
  --time-limit SECONDS  GPU: stop after the pass that crosses this time
  --shutter OPEN CLOSE  motion blur: shutter interval in the file's animation time (seconds)
                        [the scene's extras.shutter, else 0 0]
  --aperture R          thin-lens radius in scene units (depth of field)   [the camera's, else 0]
  --focus-distance D    distance of the plane in focus  [the camera's, else the scene's centre]
  --reference FILE      linear image (.exr/.pfm) to measure the error against
  --report FILE         error against run time at every doubling of samples (.json or .csv);
                        without --reference, a render with 16x the samples and seed+1 is the reference
  --report-every-ms N   also record a checkpoint after any pass that crosses N ms
  --seed S              seed of the counter-based random numbers                      [0]
  --camera N            which camera of the file to use (node order)                  [0]
  --ambient R[,G,B]     ambient radiance       [0.05; 1 when the scene has no lights]
  --background R[,G,B]  radiance of rays that leave the scene                         [0]
  --exposure EV         PNG exposure in stops                                         [0]
  --threads N           CPU threads (0 = all)                                         [0]
  --stats FILE.json     write render statistics as JSON
  --quiet               no progress bar or warnings
  --help                this text

Exit codes: 0 success, 1 runtime failure, 2 bad usage or bad input.
)";
}

Options parseOptions(int argc, const char* const argv[]) {
    Options options;
    for (int i = 1; i < argc; ++i) {
        const std::string flag = argv[i];
        auto value = [&]() -> std::string {
            if (i + 1 >= argc) throw UsageError(flag + " needs a value");
            return argv[++i];
        };
        if (flag == "--help" || flag == "-h") {
            options.help = true;
        } else if (flag == "--scene") {
            options.scenePath = value();
        } else if (flag == "--out") {
            options.outputPath = value();
            try {
                imageFormatFromPath(options.outputPath);
            } catch (const ImageError& e) {
                throw UsageError(std::string("--out: ") + e.what());
            }
        } else if (flag == "--width") {
            options.render.width = parseInt(flag, value(), 1, 16384);
            options.widthGiven = true;
        } else if (flag == "--height") {
            options.render.height = parseInt(flag, value(), 1, 16384);
            options.heightGiven = true;
        } else if (flag == "--spp") {
            options.render.samplesPerPixel = parseInt(flag, value(), 1, 1 << 24);
        } else if (flag == "--max-depth") {
            options.render.maxDepth = parseInt(flag, value(), 0, 24);
        } else if (flag == "--filter") {
            const std::string filter = value();
            if (filter == "box")
                options.render.pixelFilter = PixelFilter::Box;
            else if (filter == "tent")
                options.render.pixelFilter = PixelFilter::Tent;
            else if (filter == "gaussian")
                options.render.pixelFilter = PixelFilter::Gaussian;
            else
                throw UsageError("--filter must be box, tent or gaussian");
        } else if (flag == "--light-samples") {
            options.render.lightSamples = parseInt(flag, value(), 1, VKRT_MAX_LIGHT_SAMPLES);
        } else if (flag == "--no-mis") {
            options.render.multipleImportanceSampling = false;
        } else if (flag == "--device") {
            const std::string device = value();
            if (device == "gpu")
                options.device = DeviceKind::Gpu;
            else if (device == "cpu")
                options.device = DeviceKind::Cpu;
            else
                throw UsageError("--device must be gpu or cpu");
        } else if (flag == "--device-index") {
            options.deviceIndex = parseInt(flag, value(), 0, 255);
        } else if (flag == "--list-devices") {
            options.listDevices = true;
        } else if (flag == "--validate") {
            options.validate = true;
        } else if (flag == "--time-limit") {
            options.timeLimitSeconds = parseNumber<double>(flag, value());
            if (options.timeLimitSeconds <= 0.0) throw UsageError("--time-limit must be positive");
        } else if (flag == "--shutter") {
            const double open = parseNumber<double>(flag, value());
            const double close = parseNumber<double>(flag, value());
            if (!(close >= open)) throw UsageError("--shutter: CLOSE must not come before OPEN");
            options.shutter = std::array<double, 2>{open, close};
        } else if (flag == "--aperture") {
            options.aperture = parseNumber<double>(flag, value());
            if (*options.aperture < 0.0) throw UsageError("--aperture must not be negative");
        } else if (flag == "--focus-distance") {
            options.focusDistance = parseNumber<double>(flag, value());
            if (*options.focusDistance <= 0.0) throw UsageError("--focus-distance must be positive");
        } else if (flag == "--reference") {
            options.referencePath = value();
        } else if (flag == "--report") {
            options.reportPath = value();
            const std::string extension = std::filesystem::path(options.reportPath).extension().string();
            if (extension != ".json" && extension != ".csv")
                throw UsageError("--report must name a .json or .csv file");
        } else if (flag == "--report-every-ms") {
            options.reportEveryMs = parseNumber<double>(flag, value());
            if (options.reportEveryMs <= 0.0) throw UsageError("--report-every-ms must be positive");
        } else if (flag == "--seed") {
            options.render.seed = static_cast<uint32_t>(parseInt(flag, value(), 0, 2147483647));
        } else if (flag == "--camera") {
            options.camera = parseInt(flag, value(), 0, 1 << 20);
        } else if (flag == "--ambient") {
            options.ambient = parseColor(flag, value());
        } else if (flag == "--background") {
            options.render.background = parseColor(flag, value());
        } else if (flag == "--exposure") {
            options.exposure = parseNumber<double>(flag, value());
        } else if (flag == "--threads") {
            options.render.threads = parseInt(flag, value(), 0, 1024);
        } else if (flag == "--stats") {
            options.statsPath = value();
        } else if (flag == "--quiet") {
            options.quiet = true;
        } else {
            throw UsageError("unknown option '" + flag + "' (see --help)");
        }
    }
    if (!options.help && !options.listDevices && options.scenePath.empty()) {
        throw UsageError("--scene FILE is required (see --help)");
    }
    return options;
}

}  // namespace vkrt
