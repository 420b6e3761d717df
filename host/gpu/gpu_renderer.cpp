#include "gpu/gpu_renderer.h"

#include <algorithm>
#include <chrono>
#include <cmath>

#include "common/checkpoint_schedule.h"
#include "gpu/vulkan_check.h"

namespace vkrt {
namespace {

double millisecondsSince(std::chrono::steady_clock::time_point start) {
    return std::chrono::duration<double, std::milli>(std::chrono::steady_clock::now() - start).count();
}

uint32_t groupsFor(uint32_t count, uint32_t size) {
    return (count + size - 1) / size;
}

// At most this many samples per pixel in one dispatch: llvmpipe cuts off an invocation's loops after 65535
// iterations in total, so one invocation must not trace too many. A path can bounce up to --max-depth times,
// each bounce a BVH walk and its shadow rays, so a path has an invocation to itself: a long path cut short
// would be dropped (and counted), and dropping long paths more often than short ones would bias the image.
constexpr uint32_t kMaxSamplesPerDispatch = 16;
constexpr uint32_t kMaxPathSamplesPerDispatch = 1;

const SceneFeatures kAllFeatures = SceneFeatures::all();

}  // namespace

GpuRenderer::GpuRenderer(const VulkanContext& context, const Scene& scene, const FlatBvh& bvh,
                         const Camera& camera, const RenderSettings& settings,
                         const GpuRenderOptions& options)
    : context_(context),
      settings_(settings),
      options_(options),
      data_(packScene(scene, bvh, options.allFeatures ? &kAllFeatures : nullptr)) {
    if (settings.integrator == Integrator::Whitted && settings.maxDepth > VKRT_MAX_RAY_DEPTH) {
        throw GpuError("--max-depth " + std::to_string(settings.maxDepth) + " exceeds the GPU's limit for " +
                       "Whitted ray trees of " + std::to_string(VKRT_MAX_RAY_DEPTH));
    }
    // Upload what the scene uses; absent features keep a zero address and no buffer.
    gpu::SceneParams params = makeSceneParams(data_, camera, settings);
    sceneBuffers_ = std::make_unique<GpuSceneBuffers>(context, data_);
    sceneBuffers_->fillAddresses(params);
    const size_t pixels = static_cast<size_t>(settings.width) * settings.height;
    accumulation_ = GpuBuffer(context, 2 * pixels * sizeof(glm::vec4));  // sum and compensation
    accumulation_.fillZero();
    counters_ = GpuBuffer(context, VKRT_COUNTER_COUNT * sizeof(uint32_t));
    counters_.fillZero();
    params.accumulation = accumulation_.address();
    params.counters = counters_.address();
    params_ = GpuBuffer(context, &params, sizeof(params));

    // The shader variant: the scene's features, the camera's lens, and how it reads geometry.
    if (camera.projection == Projection::Perspective && camera.aperture > 0.0)
        data_.features.depthOfField = true;
    defines_ = data_.features.defines();
    report_.boundGeometry = !options.deviceAddressesOnly && sceneBuffers_->geometryFitsDescriptors(context);
    if (report_.boundGeometry) defines_.push_back("VKRT_BOUND_GEOMETRY");
    if (context.wideGeometryLoads()) defines_.push_back("VKRT_WIDE_LOADS");
    if (data_.features.spheres && context.hasShaderFloat64()) defines_.push_back("VKRT_SPHERE_FLOAT64");
    if (settings.integrator == Integrator::Path) defines_.push_back("VKRT_PATHS");
    if (settings.pixelFilter != PixelFilter::Box) {
        defines_.push_back("VKRT_PIXEL_FILTER " + std::to_string(static_cast<int>(settings.pixelFilter)) + "u");
    }
    const CompiledShader shader = compileShader("trace.comp", defines_, options.shaderCacheDir);
    spirv_ = shader.spirv;
    report_.compileMs = shader.compileMs;
    report_.shaderFromCache = shader.fromCache;
    report_.shaderKey = shader.cacheKey;
    const auto bindings = sceneBuffers_->bindings(params_, report_.boundGeometry);
    pipeline_ = std::make_unique<ComputePipeline>(context, spirv_, static_cast<uint32_t>(bindings.size()),
                                                  static_cast<uint32_t>(sizeof(gpu::PassConstants)));
    report_.pipelineMs = pipeline_->createMs();
    pipeline_->bind(bindings);

    timer_ = std::make_unique<GpuTimer>(context);
}

GpuRenderer::~GpuRenderer() = default;

double GpuRenderer::runDispatch(uint32_t sampleStart, uint32_t sampleCount, uint32_t rowStart,
                                uint32_t rowCount) {
    const gpu::PassConstants pass{sampleStart, sampleCount, rowStart, rowCount};
    const auto start = std::chrono::steady_clock::now();
    context_.submitAndWait([&](VkCommandBuffer commands) {
        // Earlier dispatches' and transfers' writes must land before this one reads and adds to them.
        VkMemoryBarrier before{VK_STRUCTURE_TYPE_MEMORY_BARRIER};
        before.srcAccessMask = VK_ACCESS_SHADER_WRITE_BIT | VK_ACCESS_TRANSFER_WRITE_BIT;
        before.dstAccessMask = VK_ACCESS_SHADER_READ_BIT | VK_ACCESS_SHADER_WRITE_BIT;
        vkCmdPipelineBarrier(commands, VK_PIPELINE_STAGE_COMPUTE_SHADER_BIT | VK_PIPELINE_STAGE_TRANSFER_BIT,
                             VK_PIPELINE_STAGE_COMPUTE_SHADER_BIT, 0, 1, &before, 0, nullptr, 0, nullptr);
        timer_->begin(commands);
        pipeline_->dispatch(commands, &pass, sizeof(pass), groupsFor(settings_.width, VKRT_WORKGROUP_WIDTH),
                            groupsFor(rowCount, VKRT_WORKGROUP_HEIGHT));
        timer_->end(commands);
        makeShaderWritesVisibleToHost(commands);
    });
    const double wallMs = millisecondsSince(start);
    report_.gpuMs += timer_->elapsedMs();
    ++report_.dispatches;
    report_.longestDispatchMs = std::max(report_.longestDispatchMs, wallMs);
    return wallMs;
}

void GpuRenderer::readCounters(RayCounters& counters) {
    // The device counters are 32-bit and wrap; per-dispatch differences are added up in 64 bits.
    uint32_t now[VKRT_COUNTER_COUNT];
    counters_.download(now, sizeof(now));
    uint32_t delta[VKRT_COUNTER_COUNT];
    for (int i = 0; i < VKRT_COUNTER_COUNT; ++i) {
        delta[i] = now[i] - lastCounters_[i];
        lastCounters_[i] = now[i];
    }
    counters.primary += delta[VKRT_COUNTER_PRIMARY];
    counters.shadow += delta[VKRT_COUNTER_SHADOW];
    counters.secondary += delta[VKRT_COUNTER_SECONDARY];
    counters.nonFiniteSamples += delta[VKRT_COUNTER_NONFINITE];
}

RenderResult GpuRenderer::render(const ProgressCallback& progress, const CheckpointCallback& checkpoint,
                                 double checkpointEveryMs, StopCondition stop) {
    stop.start();
    RenderResult result;
    const uint32_t height = static_cast<uint32_t>(settings_.height);
    const uint32_t spp = static_cast<uint32_t>(settings_.samplesPerPixel);
    CheckpointSchedule schedule(spp, static_cast<bool>(checkpoint), checkpointEveryMs);

    // Passes of `samples` samples over the whole image, in bands of rows. Each dispatch is sized from the
    // measured speed of the last to take about targetDispatchMs, growing at most twofold per step, since
    // the cost of a band depends on what it sees.
    double unitsPerMs = 0.0;  // rows x samples traced per millisecond, as last measured
    double lastUnits = 1.0;   // rows x samples of the last dispatch; the first is a single row
    auto nextUnits = [&] {
        return unitsPerMs > 0.0 ? std::clamp(unitsPerMs * options_.targetDispatchMs, 1.0, 2.0 * lastUnits)
                                : lastUnits;
    };
    uint32_t samplesDone = 0;
    uint32_t mostSamples = 0;
    while (samplesDone < spp && result.stopped == StopReason::None) {
        // Passes end where the schedule says (every power of two, with checkpoints).
        const uint32_t limit = std::min(schedule.boundary(samplesDone) - samplesDone,
                                        settings_.integrator == Integrator::Path ? kMaxPathSamplesPerDispatch
                                                                                 : kMaxSamplesPerDispatch);
        const uint32_t samples =
            static_cast<uint32_t>(std::clamp(nextUnits() / height, 1.0, static_cast<double>(limit)));
        uint32_t row = 0;
        while (row < height) {
            const uint32_t rows = static_cast<uint32_t>(
                std::clamp(nextUnits() / samples, 1.0, static_cast<double>(height - row)));
            const double ms = runDispatch(samplesDone, samples, row, rows);
            lastUnits = static_cast<double>(rows) * samples;
            unitsPerMs = lastUnits / std::max(ms, 0.01);
            readCounters(result.rays);
            row += rows;
            mostSamples = samplesDone + samples;
            if (progress)
                progress(static_cast<uint64_t>(samplesDone) * height + static_cast<uint64_t>(row) * samples,
                         static_cast<uint64_t>(spp) * height);
            // Stopping here leaves rows [0, row) with one pass more than the rest; pixels are averaged over
            // their own sample counts.
            result.stopped = stop.reason();
            if (result.stopped != StopReason::None) break;
        }
        if (row < height) break;  // stopped part way through the pass
        samplesDone += samples;
        const double renderMs = schedule.renderMs();
        if (checkpoint && (schedule.due(samplesDone, renderMs) || result.stopped != StopReason::None)) {
            schedule.take(renderMs, [&] { checkpoint(samplesDone, renderMs, report_.gpuMs, readImage()); });
        }
    }
    result.fewestSamples = samplesDone;
    result.mostSamples = std::max(samplesDone, mostSamples);
    if (progress) progress(static_cast<uint64_t>(spp) * height, static_cast<uint64_t>(spp) * height);

    result.image = readImage();
    report_.deviceMemoryBytes = context_.peakAllocatedBytes();
    return result;
}

Image GpuRenderer::readImage() const {
    // Average the finite samples of each pixel; the compensated sum is (sum - lost), evaluated in double.
    std::vector<glm::vec4> sums(2 * static_cast<size_t>(settings_.width) * settings_.height);
    accumulation_.download(sums.data(), sums.size() * sizeof(glm::vec4));
    std::vector<glm::dvec4> totals(sums.size() / 2);
    for (size_t i = 0; i < totals.size(); ++i)
        totals[i] = glm::dvec4(sums[2 * i]) - glm::dvec4(sums[2 * i + 1]);
    return averageOf(totals, settings_.width, settings_.height);
}

}  // namespace vkrt
