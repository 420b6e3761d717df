#include "gpu/gpu_renderer.h"

#include <algorithm>
#include <chrono>
#include <cmath>
#include <future>

#include "common/checkpoint_schedule.h"
#include "common/elapsed_time.h"
#include "gpu/vulkan_check.h"

namespace vkrt {
namespace {

uint32_t groupsFor(uint32_t count, uint32_t size) {
    return (count + size - 1) / size;
}

// At most this many samples per pixel in one dispatch. On lavapipe, fewer: llvmpipe cuts off an invocation's
// loops after VKRT_LLVMPIPE_LOOP_BUDGET passes in total, and a sample cut short is dropped (and counted);
// dropping long paths or ray trees more often than short ones would bias the image, so the planner keeps a
// batch's samples within the budget by the loop passes the kernel reports a sample takes.
constexpr uint32_t kMaxSamplesPerDispatch = 16;

const SceneFeatures kAllFeatures = SceneFeatures::all();

// The dispatch planner for this device, with the options' limits or else the device's:
// - the time a dispatch should take. A GPU's dispatches are short enough that no watchdog fires and a stop
//   request is seen soon. On lavapipe, which has no watchdog, longer dispatches hold more samples a pixel:
//   the Whitted scene's GPU time with dispatches of 50, 100 and 150 ms (medians of 6 and 5 alternate rounds)
//   was 362, 341 and 388 ms with Whitted, 368, 352 and 323 with paths.
// - the invocations a dispatch keeps when it takes several samples a pixel. lavapipe runs one SIMD group per
//   thread at a time and gives each thread one contiguous run of a dispatch's workgroups: with 4,096
//   invocations (64 workgroups) the csg scene's paths took 10 to 12% longer, a few costly workgroups leaving
//   a thread waiting at each dispatch's end (measured before the workgroups' tiles were spread,
//   workgroup_order.h). A GPU holds tens of thousands at once (an H200's 132 multiprocessors 2,048 each).
// - llvmpipe's loop budget, on lavapipe only.
DispatchPlanner plannerFor(const GpuRenderOptions& options, const VulkanContext& context,
                           const RenderSettings& settings) {
    const bool cpuDevice = context.properties().deviceType == VK_PHYSICAL_DEVICE_TYPE_CPU;
    double targetMs = cpuDevice ? 100.0 : 50.0;
    if (options.targetDispatchMs > 0.0) targetMs = options.targetDispatchMs;
    uint32_t invocations = cpuDevice ? 16384u : 1u << 18;
    if (options.minDispatchInvocations > 0) invocations = options.minDispatchInvocations;
    const uint32_t width = static_cast<uint32_t>(settings.width);
    return DispatchPlanner(static_cast<uint32_t>(settings.height), targetMs,
                           (invocations + width - 1) / width, cpuDevice ? VKRT_LLVMPIPE_LOOP_BUDGET : 0u);
}

// The scene packed for the GPU, once it and the camera are within the GPU's reach (a camera far away also
// made every triangle test overflow).
GpuSceneData packWithinReach(const Scene& scene, const FlatBvh& bvh, const Camera& camera,
                             const SceneFeatures* features) {
    checkGpuReach(scene, &camera.position);
    return packScene(scene, bvh, features);
}

}  // namespace

GpuRenderer::GpuRenderer(const VulkanContext& context, const Scene& scene, const FlatBvh& bvh,
                         const Camera& camera, const RenderSettings& settings,
                         const GpuRenderOptions& options)
    : context_(context),
      settings_(settings),
      options_(options),
      data_(packWithinReach(scene, bvh, camera, options.allFeatures ? &kAllFeatures : nullptr)),
      planner_(plannerFor(options, context, settings)) {
    report_.packMs = millisecondsSince(constructed_);
    report_.targetDispatchMs = planner_.targetMs();
    report_.workgroupOrder = workgroupOrderFor(options.workgroupOrder, context);
    tiles_ = spreadGrid(groupsFor(static_cast<uint32_t>(settings.width), VKRT_WORKGROUP_WIDTH),
                        spreadThreads(report_.workgroupOrder));
    if (settings.integrator == Integrator::Whitted && settings.maxDepth > VKRT_MAX_RAY_DEPTH) {
        throw GpuError("--max-depth " + std::to_string(settings.maxDepth) + " exceeds the GPU's limit for " +
                       "Whitted ray trees of " + std::to_string(VKRT_MAX_RAY_DEPTH));
    }
    // What the render will hold on the device, planned before anything is allocated (MemoryError when it
    // does not fit). Then the shader variant, and the arrays the scene uses (absent features keep a zero
    // address and no buffer).
    const uint32_t width = static_cast<uint32_t>(settings.width),
                   height = static_cast<uint32_t>(settings.height);
    report_.memory =
        planDeviceMemory(context, sceneBufferNeed(data_), width, height, options.maxDeviceMemoryBytes);
    // The shader variant: the scene's features, the camera's lens, and how it reads geometry.
    if (camera.projection == Projection::Perspective && camera.aperture > 0.0)
        data_.features.depthOfField = true;
    defines_ = data_.features.defines();
    report_.sceneAccess = chooseSceneAccess(context, data_, options.sceneAccess);
    for (const std::string& define : GpuSceneBuffers::accessDefines(report_.sceneAccess))
        defines_.push_back(define);
    if (options.subgroupCounters && context.hasSubgroupArithmetic())
        defines_.push_back("VKRT_SUBGROUP_COUNTERS");
    // llvmpipe's loop budget covers all of an invocation's samples in a dispatch: the kernel reports the loop
    // passes a sample takes, and the planner keeps batches within the budget.
    if (planner_.loopBudget() > 0 && context.hasSubgroupArithmetic())
        defines_.push_back("VKRT_COUNT_LOOP_PASSES");
    // On lavapipe, where a pass of the ray-tree or bounce loop costs all of its code whether or not a lane
    // shades a hit, a SIMD group whose rays all escape starts its next samples within the pass
    // (shaders/trace.comp). A real GPU branches around what no lane runs, and is left as it was.
    if (planner_.loopBudget() > 0 && context.hasSubgroupVote()) defines_.push_back("VKRT_CHAINS_ESCAPES");
    // Double precision where a large primitive needs it (scene_features.cpp); it is not free on lavapipe,
    // whose SIMD registers hold half as many doubles (the Whitted scene's sphere roots in double: GPU time
    // 1.07 times that in float with Whitted's ray trees, 1.10 with paths; docs/performance-log.md).
    if (data_.features.largeSpheres && context.hasShaderFloat64()) defines_.push_back("VKRT_SPHERE_FLOAT64");
    if (data_.features.largeTriangles && context.hasShaderFloat64())
        defines_.push_back("VKRT_TRIANGLE_FLOAT64");
    if (context.keepsIeeeFloats()) defines_.push_back("VKRT_IEEE_FLOATS");
    if (settings.integrator == Integrator::Path) defines_.push_back("VKRT_PATHS");
    if (settings.pixelFilter != PixelFilter::Box) {
        defines_.push_back("VKRT_PIXEL_FILTER " + std::to_string(static_cast<int>(settings.pixelFilter)) + "u");
    }

    // The scene's buffers are written on another thread while this one makes the pipeline: the two are
    // independent, and each takes a large part of a textured asset's start (DamagedHelmet on lavapipe: 112 MB
    // of texels, and about 100 ms of the driver's NIR passes; its render took 584 ms with the two in turn and
    // 533 so, medians of 5). The pipeline is made on the thread that made the device (made elsewhere,
    // lavapipe took longer to create it). `data_` is only read until the writer is done. If the shader or the
    // pipeline fails, the future's destructor waits for the writer, and that error is the one reported (a
    // writer's own, such as a lack of device memory, is then dropped).
    double sceneWriteMs = 0.0;
    std::future<std::unique_ptr<GpuSceneBuffers>> written = std::async(std::launch::async, [&] {
        const auto start = std::chrono::steady_clock::now();
        auto buffers = std::make_unique<GpuSceneBuffers>(context, data_, scene);
        sceneWriteMs = millisecondsSince(start);
        return buffers;
    });

    // spirv-opt's performance passes pay for Whitted's kernel (faster to create and to run); the path kernel
    // they make slower to run on lavapipe, so it gets all but their SSA rewrite of locals
    // (shader_compiler.cpp; docs/performance-log.md).
    const SpirvOptimization optimization = settings.integrator == Integrator::Path
                                               ? SpirvOptimization::KeepLocals
                                               : SpirvOptimization::Performance;
    const CompiledShader shader = compileShader("trace.comp", defines_, options.shaderCacheDir, optimization);
    spirv_ = shader.spirv;
    report_.compileMs = shader.compileMs;
    report_.shaderFromCache = shader.fromCache;
    report_.shaderKey = shader.cacheKey;
    pipeline_ =
        std::make_unique<ComputePipeline>(context, spirv_, GpuSceneBuffers::bindingKinds(report_.sceneAccess),
                                          static_cast<uint32_t>(sizeof(gpu::PassConstants)));
    report_.pipelineMs = pipeline_->createMs();

    sceneBuffers_ = written.get();
    report_.sceneWriteMs = sceneWriteMs;
    gpu::SceneParams params = makeSceneParams(data_, camera, scene.bounds, settings);
    sceneBuffers_->fillAddresses(params);
    accumulation_ = GpuBuffer(context, report_.memory.tileRows * width * kAccumulationBytesPerPixel);
    accumulation_.fillZero();
    counters_ = GpuBuffer(context, VKRT_COUNTER_COUNT * sizeof(uint32_t));
    counters_.fillZero();
    params.accumulation = accumulation_.address();
    params.counters = counters_.address();
    params_ = GpuBuffer(context, &params, sizeof(params));
    pipeline_->bind(sceneBuffers_->bindings(params_, report_.sceneAccess));

    // The device has the scene now: the host's packed copy goes (all but the features).
    const SceneFeatures features = data_.features;
    data_ = GpuSceneData{};
    data_.features = features;

    timer_ = std::make_unique<GpuTimer>(context);
    report_.setupMs = millisecondsSince(constructed_);
}

GpuRenderer::~GpuRenderer() = default;

double GpuRenderer::runDispatch(uint32_t sampleStart, uint32_t sampleCount, uint32_t rowStart,
                                uint32_t rowCount) {
    if (report_.dispatches + 1 == options_.simulateDeviceLossAtDispatch) {
        throw DeviceLostError("the device was lost (simulated at dispatch " +
                              std::to_string(options_.simulateDeviceLossAtDispatch) + ")");
    }
    const gpu::PassConstants pass{sampleStart, sampleCount, rowStart, rowCount, tileRowStart_};
    const auto start = std::chrono::steady_clock::now();
    context_.submitAndWait([&](VkCommandBuffer commands) {
        // Earlier dispatches' and transfers' writes must land before this one reads and adds to them.
        VkMemoryBarrier before{VK_STRUCTURE_TYPE_MEMORY_BARRIER};
        before.srcAccessMask = VK_ACCESS_SHADER_WRITE_BIT | VK_ACCESS_TRANSFER_WRITE_BIT;
        before.dstAccessMask = VK_ACCESS_SHADER_READ_BIT | VK_ACCESS_SHADER_WRITE_BIT;
        vkCmdPipelineBarrier(commands, VK_PIPELINE_STAGE_COMPUTE_SHADER_BIT | VK_PIPELINE_STAGE_TRANSFER_BIT,
                             VK_PIPELINE_STAGE_COMPUTE_SHADER_BIT, 0, 1, &before, 0, nullptr, 0, nullptr);
        timer_->begin(commands);
        pipeline_->dispatch(commands, &pass, sizeof(pass), tiles_.perColumn,
                            groupsFor(rowCount, VKRT_WORKGROUP_HEIGHT), tiles_.columns);
        timer_->end(commands);
        makeShaderWritesVisibleToHost(commands);
    });
    const double wallMs = millisecondsSince(start);
    report_.gpuMs += timer_->elapsedMs();
    ++report_.dispatches;
    report_.longestDispatchMs = std::max(report_.longestDispatchMs, wallMs);
    report_.dispatchWallMs += wallMs;
    report_.mostSamplesInDispatch = std::max(report_.mostSamplesInDispatch, sampleCount);
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
    // A maximum over the render, not a sum (VKRT_COUNT_LOOP_PASSES).
    report_.loopPassesPerSample = now[VKRT_COUNTER_LOOP_PASSES];
    if (now[VKRT_COUNTER_LOOP_PASSES] > 0) planner_.loopPassesPerSample(now[VKRT_COUNTER_LOOP_PASSES]);
}

void GpuRenderer::copyToHost() {
    if (dirtyEnd_ <= dirtyBegin_) return;
    const auto start = std::chrono::steady_clock::now();
    // The rows dispatched since the last copy, whole rows at a time, a few MiB each: no host copy of the
    // whole buffer, and a copy cut short by a lost device leaves every row either added or not.
    const uint32_t width = static_cast<uint32_t>(settings_.width);
    const size_t rowBytes = static_cast<size_t>(width) * kAccumulationBytesPerPixel;
    // Read where the host sees them (a CPU device's own memory, else a staging buffer's): a host buffer to
    // copy them into took 0.5 ms, or 7 when its 2 MiB were first touched on 4 KiB pages (256 x 256 on
    // lavapipe).
    const uint32_t rowsPerChunk = std::max<uint32_t>(1, static_cast<uint32_t>((8u << 20) / rowBytes));
    for (uint32_t first = dirtyBegin_; first < dirtyEnd_; first += rowsPerChunk) {
        const uint32_t count = std::min(rowsPerChunk, dirtyEnd_ - first);
        const size_t pixels = static_cast<size_t>(count) * width;
        accumulation_.readWith(count * rowBytes, (first - tileRowStart_) * rowBytes, [&](const void* mapped) {
            // The compensated sum is (sum - lost), evaluated in double.
            const glm::vec4* chunk = static_cast<const glm::vec4*>(mapped);
            glm::dvec4* sums = sums_ + static_cast<size_t>(first) * width;
            for (size_t i = 0; i < pixels; ++i)
                sums[i] += glm::dvec4(chunk[2 * i]) - glm::dvec4(chunk[2 * i + 1]);
        });
        for (uint32_t row = first; row < first + count; ++row) rowSamplesCopied_[row] = rowSamples_[row];
    }
    accumulation_.fillZero((dirtyBegin_ - tileRowStart_) * rowBytes, (dirtyEnd_ - dirtyBegin_) * rowBytes);
    dirtyBegin_ = UINT32_MAX;
    dirtyEnd_ = 0;
    ++report_.hostCopies;
    lastCopy_ = std::chrono::steady_clock::now();
    lastCopyMs_ = millisecondsSince(start);
    report_.hostCopyMs += lastCopyMs_;
}

bool GpuRenderer::copyDue() const {
    if (options_.hostCopyEveryMs <= 0.0) return true;
    const double sinceCopy = millisecondsSince(lastCopy_);
    return sinceCopy >= options_.hostCopyEveryMs && sinceCopy >= 20.0 * lastCopyMs_;
}

StopReason GpuRenderer::renderTile(uint32_t tile, uint32_t tileEnd, uint32_t first, uint32_t end,
                                   uint64_t totalUnits, const StopCondition& stop,
                                   const ProgressCallback& progress, RayCounters& rays) {
    // Batches of samples over bands of rows, sized by the planner (dispatch_planner.h).
    for (uint32_t s = first; s < end;) {
        const uint32_t samples =
            planner_.batchSamples(s, std::min(end - s, kMaxSamplesPerDispatch), tile, tileEnd);
        for (uint32_t row = tile; row < tileEnd;) {
            const uint32_t rows = planner_.rows(row, tileEnd, samples);
            const double ms = runDispatch(s, samples, row, rows);
            planner_.record(row, rows, samples, ms);
            dirtyBegin_ = std::min(dirtyBegin_, row);
            dirtyEnd_ = std::max(dirtyEnd_, row + rows);
            for (uint32_t r = row; r < row + rows; ++r) rowSamples_[r] += samples;
            unitsDone_ += static_cast<uint64_t>(rows) * samples;
            const uint64_t lost = rays.nonFiniteSamples;
            readCounters(rays);
            if (rays.nonFiniteSamples > lost) planner_.samplesLost();
            row += rows;
            if (progress) progress(unitsDone_, totalUnits);
            // Stopping here leaves some rows with more samples than others; pixels are averaged over their
            // own sample counts.
            if (const StopReason reason = stop.reason(); reason != StopReason::None) return reason;
            if (copyDue()) copyToHost();
        }
        s += samples;
    }
    return StopReason::None;
}

RenderResult GpuRenderer::render(const ProgressCallback& progress, const CheckpointCallback& checkpoint,
                                 double checkpointEveryMs, StopCondition stop) {
    // The time limit counts from the first sample: the sums of a large image take a while to allocate (a
    // 4096 x 4096 image's 512 MiB took 1.7 s here, and a 1 s limit left one pixel traced).
    std::vector<glm::dvec4> sums(static_cast<size_t>(settings_.width) * settings_.height, glm::dvec4(0.0));
    stop.start();
    RenderResult result = renderRange(0, static_cast<uint32_t>(settings_.samplesPerPixel), sums, progress,
                                      checkpoint, checkpointEveryMs, stop);
    resolveSums(result, sums, settings_.width, settings_.height);
    return result;
}

RenderResult GpuRenderer::renderSamples(uint32_t firstSample, uint32_t endSample,
                                        std::vector<glm::dvec4>& sums, const StopCondition& stop) {
    sums.resize(static_cast<size_t>(settings_.width) * settings_.height, glm::dvec4(0.0));
    RenderResult result = renderRange(firstSample, endSample, sums, {}, {}, 0.0, stop);
    if (result.stopped == StopReason::DeviceLost) throw DeviceLostError(report_.deviceLost);
    return result;
}

RenderResult GpuRenderer::renderRange(uint32_t first, uint32_t end, std::vector<glm::dvec4>& sums,
                                      const ProgressCallback& progress, const CheckpointCallback& checkpoint,
                                      double checkpointEveryMs, const StopCondition& stop) {
    RenderResult result;
    const uint32_t height = static_cast<uint32_t>(settings_.height);
    const uint64_t totalUnits = static_cast<uint64_t>(end - first) * height;
    CheckpointSchedule schedule(end, static_cast<bool>(checkpoint), checkpointEveryMs);
    sums_ = sums.data();
    rowSamples_.assign(height, 0);
    rowSamplesCopied_.assign(height, 0);
    // The device's sums are added into the host's at tile changes, checkpoints, the end, and by time
    // (copyDue). Dispatches are sized from the times measured so far (planner_); a renderer's first is
    // one row, and later ranges start from the speed measured before.
    lastCopy_ = std::chrono::steady_clock::now();
    lastCopyMs_ = 0.0;
    unitsDone_ = 0;
    uint32_t done = first;  // samples every pixel has
    uint32_t checkpointed = first;  // the samples of the last checkpoint's image
    try {
        // Passes end where the schedule says (every power of two, with checkpoints); within a pass, tile by
        // tile. A tiled image's passes double its samples even without checkpoints, so that a time limit or
        // an interrupt leaves every tile with some (a pass of all the samples left most tiles black).
        const bool tiled = report_.memory.tileRows < height;
        while (done < end && result.stopped == StopReason::None) {
            uint32_t passEnd = schedule.passEnd(done);
            if (tiled) passEnd = std::min(passEnd, done + std::max(1u, done - first));
            for (uint32_t tile = 0; tile < height && result.stopped == StopReason::None;
                 tile += report_.memory.tileRows) {
                if (tile != tileRowStart_) {
                    copyToHost();
                    tileRowStart_ = tile;
                }
                const uint32_t tileEnd = std::min(height, tile + report_.memory.tileRows);
                result.stopped =
                    renderTile(tile, tileEnd, done, passEnd, totalUnits, stop, progress, result.rays);
            }
            if (result.stopped != StopReason::None) break;
            done = passEnd;
            const double renderMs = schedule.renderMs();
            if (checkpoint && schedule.due(done, renderMs)) {
                schedule.take(renderMs, [&] {
                    copyToHost();
                    checkpoint(done, renderMs, report_.gpuMs,
                               averageOf(sums, settings_.width, settings_.height));
                });
                checkpointed = done;
            }
        }
        copyToHost();
        // A render stopped between checkpoints (time limit, interrupt) ends its report with the image it
        // writes, counted by the samples every pixel has.
        // (Rows count their samples from `first`.)
        const auto [fewest, most] = std::minmax_element(rowSamplesCopied_.begin(), rowSamplesCopied_.end());
        const uint32_t every = first + *fewest;
        if (checkpoint && result.stopped != StopReason::None && (every != checkpointed || *most > *fewest)) {
            const double renderMs = schedule.renderMs();
            schedule.take(renderMs, [&] {
                checkpoint(every, renderMs, report_.gpuMs,
                           averageOf(sums, settings_.width, settings_.height));
            });
        }
    } catch (const DeviceLostError& e) {
        // What the host holds is all there is: every row as of its last copy.
        report_.deviceLost = e.what();
        result.stopped = StopReason::DeviceLost;
    }
    sums_ = nullptr;
    result.fewestSamples = *std::min_element(rowSamplesCopied_.begin(), rowSamplesCopied_.end());
    result.mostSamples = *std::max_element(rowSamplesCopied_.begin(), rowSamplesCopied_.end());
    if (progress) progress(totalUnits, totalUnits);
    report_.deviceMemoryBytes = context_.peakAllocatedBytes();
    return result;
}

}  // namespace vkrt
