#include "app/options.h"

#include <algorithm>
#include <cctype>
#include <charconv>
#include <cmath>
#include <filesystem>
#include <limits>
#include <sstream>
#include <string>
#include <utility>
#include <vector>

#include <CLI/CLI.hpp>
#include <glm/vector_relational.hpp>

#include "common/atomic_file.h"
#include "common/file_names.h"
#include "image/image_io.h"
#include "punctual_light.h"
#include "random.h"
#include "shared.h"

namespace vkrt {
namespace {

// Values from here on round to infinity in single precision, where the renderers keep them: FLT_MAX plus half
// its last place, 2^128 - 2^103.
constexpr double kBeyondFloat = 0x1.ffffffp+127;

// A colour: one value for grey, or three separated by commas (R,G,B). Empty when malformed.
std::optional<glm::dvec3> parseColor(const std::string& text) {
    if (!text.empty() && text.back() == ',') return std::nullopt;  // getline yields no empty last part
    std::vector<double> parts;
    std::stringstream stream(text);
    std::string part;
    while (std::getline(stream, part, ',')) {
        double value = 0.0;
        const char* end = part.data() + part.size();
        auto [ptr, error] = std::from_chars(part.data(), end, value);
        if (error != std::errc() || ptr != end || !std::isfinite(value) || std::abs(value) >= kBeyondFloat) {
            return std::nullopt;
        }
        parts.push_back(value);
    }
    if (parts.size() == 1) return glm::dvec3(parts[0]);
    if (parts.size() == 3) return glm::dvec3(parts[0], parts[1], parts[2]);
    return std::nullopt;
}

// Checks on the text of a value, before CLI11 converts it; each returns the error or an empty string.
template <typename T>
std::optional<T> parseNumber(const std::string& text) {
    T value{};
    const char* end = text.data() + text.size();
    auto [ptr, error] = std::from_chars(text.data(), end, value);
    if (error != std::errc() || ptr != end) return std::nullopt;
    return value;
}
// A whole number in decimal, rewritten without leading zeros or sign: CLI11 then converts with base 0, which
// read "010" as octal 8 (and "08" as out of range). A transform, so that the rewritten text is the one
// converted.
const CLI::Validator kInteger(
    [](std::string& text) {
        const std::optional<long long> value = parseNumber<long long>(text);
        if (!value) return "'" + text + "' is not a whole number";
        text = std::to_string(*value);
        return std::string();
    },
    "");
const CLI::Validator kFinite(
    [](std::string& text) {
        const std::optional<double> value = parseNumber<double>(text);
        if (!value) return "'" + text + "' is not a valid number";
        if (!std::isfinite(*value)) return "'" + text + "' is not finite";
        // The renderers keep such values in single precision, where larger ones would become infinite.
        return std::abs(*value) < kBeyondFloat ? std::string()
                                               : "'" + text + "' is beyond single precision's range (3.4e38)";
    },
    "");
const CLI::Validator kPositive(
    [](std::string& text) { return *parseNumber<double>(text) > 0.0 ? std::string() : "must be positive"; },
    "");
const CLI::Validator kNotNegative(
    [](std::string& text) {
        return *parseNumber<double>(text) >= 0.0 ? std::string() : "must not be negative";
    },
    "");
const CLI::Validator kColor(
    [](std::string& text) {
        const std::optional<glm::dvec3> color = parseColor(text);
        if (!color) {
            return "'" + text +
                   "' is not one finite value or three separated by commas (R,G,B), each within single "
                   "precision's range";
        }
        return glm::all(glm::greaterThanEqual(*color, glm::dvec3(0.0)))
                   ? std::string()
                   : "'" + text + "' is a radiance and must not be negative";
    },
    "");
const CLI::Validator kImagePath(
    [](std::string& text) {
        try {
            imageFormatFromPath(text);
            return std::string();
        } catch (const ImageError& e) {
            return std::string(e.what());
        }
    },
    "");
const CLI::Validator kReportPath(
    [](std::string& text) {
        const std::string extension = lowerExtension(text);
        return extension == ".json" || extension == ".csv" ? std::string() : "must name a .json or .csv file";
    },
    "");

// A size in bytes: a number with an optional unit, binary (K, KiB, M, MiB, G, GiB, T, TiB) or decimal (KB,
// MB, GB, TB). Empty when malformed, not positive, or beyond 2^64.
std::optional<uint64_t> parseByteSize(const std::string& text) {
    size_t digits = 0;
    while (digits < text.size() &&
           (std::isdigit(static_cast<unsigned char>(text[digits])) || text[digits] == '.'))
        ++digits;
    const std::optional<double> number = parseNumber<double>(text.substr(0, digits));
    std::string unit = text.substr(digits);
    unit.erase(0, unit.find_first_not_of(' '));
    static const std::pair<const char*, double> kUnits[] = {
        {"", 1.0},     {"B", 1.0},      {"K", 0x1p10},   {"KiB", 0x1p10}, {"KB", 1e3},
        {"M", 0x1p20}, {"MiB", 0x1p20}, {"MB", 1e6},     {"G", 0x1p30},   {"GiB", 0x1p30},
        {"GB", 1e9},   {"T", 0x1p40},   {"TiB", 0x1p40}, {"TB", 1e12}};
    for (const auto& [name, scale] : kUnits) {
        if (!number || unit != name) continue;
        const double bytes = *number * scale;
        if (!(bytes >= 1.0) || bytes >= 0x1p64) return std::nullopt;
        return static_cast<uint64_t>(bytes);
    }
    return std::nullopt;
}
const CLI::Validator kByteSize(
    [](std::string& text) {
        return parseByteSize(text) ? std::string()
                                   : "'" + text + "' is not a size such as 512MiB, 4GiB or 4000000000";
    },
    "");

// The parser, bound to the Options it fills, plus the raw text of values converted after parsing.
struct CommandLine {
    CLI::App app{"vkrt: a Vulkan compute ray tracer for glTF 2.0 scenes", "vkrt"};
    Options options;
    std::string device = "gpu", filter = "box", toneMap = toneMapName(kDefaultToneMap),
                shaderFeatures = "scene";
    std::vector<double> shutter;
    std::string ambient, background, integrator, maxMemory, maxDeviceMemory;
    int height = 0;  // --height, when given
    int maxDepth = 0;
    bool noMis = false;

    CommandLine() {
        RenderSettings& s = options.request.settings;
        app.set_help_flag();  // --help is an ordinary flag: main() prints the help and exits 0
        app.get_formatter()->column_width(30);
        app.footer(
            "Exit codes: 0 success, 1 runtime failure, 2 bad usage or bad input. SIGINT, SIGTERM or SIGHUP "
            "stops the render and writes the samples done, then ends vkrt by that signal (130, 143 or 129 in "
            "a shell); a second one ends it at once.");
        app.add_flag("-h,--help", options.help, "this text");
        app.add_option("--scene", options.scenePath, "glTF 2.0 scene (.gltf or .glb) to render (required)")
            ->type_name("FILE");
        app.add_option("--out", options.outputPath,
                       "output image: .png (tonemapped sRGB), .exr or .pfm (linear)")
            ->type_name("FILE")
            ->check(kImagePath)
            ->capture_default_str();
        app.add_option("--width", s.width, "image width in pixels")
            ->type_name("W")
            ->transform(kInteger)
            ->check(CLI::Range(1, kMaxImageSide))
            ->capture_default_str();
        app.add_option("--height", height, "image height in pixels")
            ->type_name("H")
            ->transform(kInteger)
            ->check(CLI::Range(1, kMaxImageSide))
            ->default_str("width / the camera's aspect ratio, else the width");
        app.add_option("--spp", s.samplesPerPixel, "samples per pixel (jittered, stratified)")
            ->type_name("N")
            ->transform(kInteger)
            ->check(CLI::Range(1, 1 << 24))
            ->capture_default_str();
        app.add_option("--integrator", integrator,
                       "path: path tracing (every lobe continued, all indirect light, Russian roulette); "
                       "whitted: distributed Whitted ray tracing (mirror, glossy and refracted rays; diffuse "
                       "surfaces lit by the lights and an ambient term)")
            ->type_name("path|whitted")
            ->check(CLI::IsMember({"path", "whitted"}))
            ->default_str("path (glTF's materials are physically based)");
        app.add_option("--max-depth", maxDepth,
                       "bounces after the first hit: paths 0-" + std::to_string(kMaxPathDepth) +
                           ", Whitted 0-" + std::to_string(VKRT_MAX_RAY_DEPTH))
            ->type_name("D")
            ->transform(kInteger)
            ->check(CLI::Range(0, kMaxPathDepth))
            ->default_str(std::to_string(kDefaultPathDepth) + " for paths, " +
                          std::to_string(kDefaultWhittedDepth) + " for Whitted");
        app.add_option("--light-samples", s.lightSamples,
                       "area-light and environment samples per shading point, and punctual lights picked "
                       "where a scene has more than " +
                           std::to_string(VKRT_EVERY_PUNCTUAL_LIGHT_UP_TO) + " (1-" +
                           std::to_string(VKRT_MAX_LIGHT_SAMPLES) + ")")
            ->type_name("N")
            ->transform(kInteger)
            ->check(CLI::Range(1, static_cast<int>(VKRT_MAX_LIGHT_SAMPLES)))
            ->capture_default_str();
        app.add_flag("--no-mis", noMis,
                     "light glossy surfaces by light samples alone (no multiple importance sampling)");
        app.add_option("--filter", filter, "pixel filter: box, tent (radius 1 px) or gaussian (sigma 0.5 px)")
            ->type_name("box|tent|gaussian")
            ->check(CLI::IsMember({"box", "tent", "gaussian"}))
            ->capture_default_str();
        app.add_option("--device", device, "GPU tracer (Vulkan compute) or the CPU reference renderer")
            ->type_name("gpu|cpu")
            ->check(CLI::IsMember({"gpu", "cpu"}))
            ->capture_default_str();
        app.add_option("--device-index", options.deviceIndex, "which Vulkan device (see --list-devices)")
            ->type_name("N")
            ->transform(kInteger)
            ->check(CLI::Range(0, 255))
            ->default_str("discrete GPU first");
        app.add_flag("--list-devices", options.listDevices, "print the Vulkan devices and exit");
        app.add_flag("--validate", options.validate, "enable the Khronos validation layer");
        app.add_option(
               "--shader-features", shaderFeatures,
               "GPU diagnostic: scene compiles the shader with only what the scene uses; all compiles "
               "every feature in (the same image; measures what specialisation gains)")
            ->type_name("scene|all")
            ->check(CLI::IsMember({"scene", "all"}))
            ->capture_default_str();
        app.add_option(
               "--scene-access", options.sceneAccess,
               "GPU diagnostic: how the kernels read the scene's arrays: auto (the device's best), texels "
               "(texel buffers), storage (storage buffers) or addresses (device addresses); the same "
               "image; arrays too large for the way asked take the next one down")
            ->type_name("auto|texels|storage|addresses")
            ->check(CLI::IsMember({"auto", "texels", "storage", "addresses"}))
            ->capture_default_str();
        app.add_option("--time-limit", options.timeLimitSeconds,
                       "stop after this long of tracing (counted from the first sample), once the dispatch "
                       "(GPU) or pixel (CPU) in flight is done; each pixel averages the samples it got")
            ->type_name("SECONDS")
            ->check(kFinite)
            ->check(kPositive);
        app.add_option("--max-memory", maxMemory,
                       "host memory the render may take; refused at once (exit 2) when its estimate is more")
            ->type_name("SIZE")
            ->check(kByteSize)
            ->default_str("what the system has available");
        app.add_option("--max-device-memory", maxDeviceMemory,
                       "GPU memory the render may take; the image is rendered in tiles when only they fit")
            ->type_name("SIZE")
            ->check(kByteSize)
            ->default_str("the device's heap or budget");
        app.add_option("--shutter", shutter,
                       "motion blur: shutter interval in the file's animation time (seconds)")
            ->type_name("SECONDS")
            ->expected(2)
            ->check(kFinite)
            ->default_str("the scene's extras.shutter, else 0 0");
        app.add_option("--animation", options.animation,
                       "the file's animation that poses and moves the scene, by name, else by index (a "
                       "file's animations are separate clips)")
            ->type_name("INDEX|NAME")
            ->default_str("the first");
        app.add_option("--aperture", options.request.aperture,
                       "thin-lens radius in scene units (depth of field)")
            ->type_name("R")
            ->check(kFinite)
            ->check(kNotNegative)
            ->default_str("the camera's, else 0");
        app.add_option("--focus-distance", options.request.focusDistance, "distance of the plane in focus")
            ->type_name("D")
            ->check(kFinite)
            ->check(kPositive)
            ->default_str("the camera's, else the scene's centre");
        app.add_option("--reference", options.referencePath,
                       "linear image (.exr/.pfm) to measure the error against")
            ->type_name("FILE");
        app.add_option("--report", options.reportPath,
                       "error against run time at every doubling of samples (.json or .csv); without "
                       "--reference, a render with 16x the samples and seed+1 is the reference")
            ->type_name("FILE")
            ->check(kReportPath);
        app.add_option("--report-every-ms", options.reportEveryMs,
                       "also record a checkpoint after any pass that crosses N ms")
            ->type_name("N")
            ->check(kFinite)
            ->check(kPositive);
        app.add_option("--seed", s.seed, "seed of the counter-based random numbers")
            ->type_name("S")
            ->transform(kInteger)
            ->check(CLI::Range(0u, kMaxSeed))
            ->capture_default_str();
        app.add_option("--camera", options.request.camera,
                       "which camera of the file to use, counted in the order the scene's nodes are walked "
                       "(depth first from its roots)")
            ->type_name("N")
            ->transform(kInteger)
            ->check(CLI::Range(0, 1 << 20))
            ->capture_default_str();
        app.add_option("--ambient", ambient,
                       "Whitted's ambient radiance (a scene without lights, given neither this nor --environment, "
                       "is lit by a neutral environment of radiance 1 instead); for paths, a uniform environment "
                       "of this radiance")
            ->type_name("R[,G,B]")
            ->check(kColor)
            ->default_str("Whitted: 0.05, 0 under an environment; paths: none");
        app.add_option("--background", background,
                       "radiance of rays that leave the scene (without --environment)")
            ->type_name("R[,G,B]")
            ->check(kColor)
            ->default_str("0");
        app.add_option("--environment", options.environmentPath,
                       "equirectangular radiance map (.hdr or .exr, top row the zenith +Y) around the scene: "
                       "seen by rays that leave it, importance sampled as a light; the ambient default "
                       "becomes 0")
            ->type_name("FILE");
        app.add_option("--environment-rotation", options.environmentRotation,
                       "turn the environment about +Y (right-handed: +Z towards +X)")
            ->type_name("DEGREES")
            ->check(kFinite)
            ->capture_default_str();
        app.add_option("--environment-strength", options.environmentStrength,
                       "multiplies the environment's radiance")
            ->type_name("S")
            ->check(kFinite)
            ->check(kNotNegative)
            ->capture_default_str();
        app.add_option(
               "--tonemap", toneMap,
               "PNG tone mapping: pbr-neutral (Khronos PBR Neutral, the glTF Sample Viewer's default: base "
               "colours as authored, highlights rolled off), aces (Narkowicz's ACES fit) or clamp")
            ->type_name("NAME")
            ->check(CLI::IsMember({"pbr-neutral", "aces", "clamp"}))
            ->capture_default_str();
        app.add_option("--exposure", options.exposure, "PNG exposure in stops")
            ->type_name("EV")
            ->check(kFinite)
            ->capture_default_str();
        app.add_option("--threads", s.threads, "CPU threads (0 = all)")
            ->type_name("N")
            ->transform(kInteger)
            ->check(CLI::Range(0, 1024))
            ->capture_default_str();
        app.add_option("--stats", options.statsPath, "write render statistics as JSON")
            ->type_name("FILE.json");
        app.add_flag("--quiet", options.quiet, "no progress bar or warnings");
    }

    // The values CLI11 leaves as text or that depend on one another.
    void finish() {
        RenderSettings& s = options.request.settings;
        // Without --height a file camera's aspect ratio sets it (render_policy.cpp), else the image is square.
        if (app.count("--height")) options.request.height = height;
        s.height = s.width;
        if (app.count("--max-depth")) options.request.maxDepth = maxDepth;
        if (!integrator.empty()) {
            options.request.integrator = integrator == "whitted" ? Integrator::Whitted : Integrator::Path;
        }
        s.multipleImportanceSampling = !noMis;
        s.pixelFilter = filter == "tent"       ? PixelFilter::Tent
                        : filter == "gaussian" ? PixelFilter::Gaussian
                                               : PixelFilter::Box;
        options.device = device == "cpu" ? DeviceKind::Cpu : DeviceKind::Gpu;
        options.allShaderFeatures = shaderFeatures == "all";
        options.toneMap = toneMapFromName(toneMap).value_or(kDefaultToneMap);  // CLI11 checked the name
        if (!shutter.empty()) {
            if (!(shutter[1] >= shutter[0])) throw UsageError("--shutter: CLOSE must not come before OPEN");
            options.shutter = std::array<double, 2>{shutter[0], shutter[1]};
        }
        if (!maxMemory.empty()) options.maxHostMemoryBytes = *parseByteSize(maxMemory);
        if (!maxDeviceMemory.empty()) options.maxDeviceMemoryBytes = *parseByteSize(maxDeviceMemory);
        if (!ambient.empty()) options.request.ambient = parseColor(ambient);
        if (!background.empty()) s.background = *parseColor(background);
    }
};

}  // namespace

std::string helpText() {
    CommandLine commandLine;
    return commandLine.app.help();
}

Options parseOptions(int argc, const char* const argv[]) {
    CommandLine commandLine;
    try {
        commandLine.app.parse(argc, argv);
    } catch (const CLI::ParseError& e) {
        std::string message = e.what();
        std::replace(message.begin(), message.end(), '\n', ' ');
        throw UsageError(message + " (see --help)");
    }
    commandLine.finish();
    const Options& options = commandLine.options;
    // A file option given an empty name is a mistake, not the option left out (an empty --reference once
    // rendered its own reference at 16 times the samples instead).
    const std::pair<const char*, const std::string*> files[] = {
        {"--scene", &options.scenePath},         {"--out", &options.outputPath},
        {"--stats", &options.statsPath},         {"--report", &options.reportPath},
        {"--reference", &options.referencePath}, {"--environment", &options.environmentPath}};
    for (const auto& [name, path] : files) {
        if (commandLine.app.count(name) > 0 && path->empty())
            throw UsageError(std::string(name) + " needs a file name");
    }
    if (!options.help && !options.listDevices && options.scenePath.empty()) {
        throw UsageError("--scene FILE is required (see --help)");
    }
    // Options this run makes no use of are said to, once each (they were taken silently).
    Options& said = commandLine.options;
    const auto given = [&](const char* name) { return commandLine.app.count(name) > 0; };
    if (options.device == DeviceKind::Cpu) {
        for (const char* name :
             {"--device-index", "--max-device-memory", "--validate", "--shader-features", "--scene-access"}) {
            if (given(name))
                said.warnings.push_back(std::string(name) + " is for the GPU; --device cpu ignores it");
        }
    }
    if (options.environmentPath.empty()) {
        for (const char* name : {"--environment-rotation", "--environment-strength"}) {
            if (given(name))
                said.warnings.push_back(std::string(name) + " does nothing without --environment");
        }
    } else if (given("--background")) {
        said.warnings.push_back(
            "--background does nothing with --environment: rays that leave the scene see the map");
    }
    if (imageFormatFromPath(options.outputPath) != ImageFormat::Png) {
        for (const char* name : {"--tonemap", "--exposure"}) {
            if (given(name)) {
                said.warnings.push_back(std::string(name) + " is for PNG output; " + options.outputPath +
                                        " keeps the linear radiance");
            }
        }
    }
    // Its checkpoints go to the report: without one, --report-every-ms did nothing, silently (with
    // --reference alone, only the last checkpoint is printed).
    if (options.reportEveryMs > 0.0 && options.reportPath.empty())
        throw UsageError("--report-every-ms needs --report, where its checkpoints are written");
    // The files a run writes are distinct: one would overwrite another.
    const std::pair<const char*, const std::string*> written[] = {
        {"--out", &options.outputPath}, {"--stats", &options.statsPath}, {"--report", &options.reportPath}};
    for (size_t i = 0; i < std::size(written); ++i) {
        for (size_t j = i + 1; j < std::size(written); ++j) {
            const std::string& a = *written[i].second;
            const std::string& b = *written[j].second;
            if (!a.empty() && !b.empty() && sameFile(a, b)) {
                throw UsageError(std::string(written[i].first) + " and " + written[j].first +
                                 " name the same file: " + b);
            }
        }
        // Nor does a run write over what it reads.
        const std::pair<const char*, const std::string*> read[] = {
            {"--scene", &options.scenePath},
            {"--reference", &options.referencePath},
            {"--environment", &options.environmentPath}};
        for (const auto& [name, path] : read) {
            const std::string& output = *written[i].second;
            if (!output.empty() && !path->empty() && sameFile(output, *path)) {
                throw UsageError(std::string(written[i].first) + " would write over " + name + ": " + output);
            }
        }
    }
    return options;
}

}  // namespace vkrt
