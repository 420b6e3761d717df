#include "cpu/reference_renderer.h"

#include <algorithm>
#include <atomic>
#include <chrono>
#include <cmath>
#include <limits>
#include <mutex>

#include "camera.h"
#include "common/checkpoint_schedule.h"
#include "common/parallel_for.h"
#include "cpu/closest_hit.h"
#include "random.h"

namespace vkrt {
ReferenceRenderer::ReferenceRenderer(const Scene& scene, const FlatBvh& bvh, const Camera& camera,
                                     const RenderSettings& settings)
    : scene_(scene),
      bvh_(bvh),
      settings_(settings),
      shadingScene_(scene, bvh),
      camera_(cameraFrame(camera, scene.bounds, settings.width, settings.height)) {
    shadingScene_.volumesBlockShadows = settings.integrator == Integrator::Path;
}

double ReferenceRenderer::shutterTime(uint32_t pixel, uint32_t sample) const {
    return scene_.moving() ? vkrtStratified(settings_.seed, pixel, sample, VKRT_DIM_TIME, 0) : 0.0;
}

Ray ReferenceRenderer::cameraRay(double filmX, double filmY, double lensU, double lensV) const {
    const shading::CameraRay ray = shading::cameraRay(camera_, filmX, filmY, lensU, lensV);
    return {ray.origin, ray.direction};
}

shading::ShadingContext ReferenceRenderer::shadingContext(uint32_t pixel, uint32_t sample) const {
    shading::ShadingContext context;
    context.ambient = settings_.ambient;
    context.background = settings_.background;
    context.paths = settings_.integrator == Integrator::Path;
    context.environmentBackdrop = !scene_.environment.neutral;
    context.minThroughput = settings_.minThroughput;
    context.maxDepth = settings_.maxDepth;
    context.lightSamples = static_cast<uint32_t>(settings_.lightSamples);
    context.multipleImportanceSampling = settings_.multipleImportanceSampling;
    context.energyCompensation = settings_.energyCompensation;
    context.stream = vkrtPixelStream(settings_.seed, pixel);
    context.pairRoot = vkrtPairRoot(context.stream);
    context.sampleIndex = sample;
    return context;
}

bool ReferenceRenderer::visibleHit(const CpuShadingDevice& device, const shading::ShadingContext& context,
                                   shading::RayState& ray, double time, SurfaceHit& hit,
                                   shading::HitPoint& point, glm::dvec3& absorbed) const {
    // The holes of alpha-tested and blended surfaces are passed, in the closest-hit rule's order (ties.h's
    // WalkPast); a hole in a volume's surface moves the ray into or out of its medium.
    const Ray line{ray.origin, ray.direction};
    const double originScale = shading::maxAbs(line.origin);
    shading::WalkPast past = shading::walkPastFrom(0.0);
    double travelled = 0.0, nearest;
    absorbed = glm::dvec3(1.0);
    for (uint32_t layer = 0; closestHitPast(scene_, bvh_, line, past, std::numeric_limits<double>::infinity(),
                                            ray.exclude, hit, nearest, time);
         ++layer) {
        point = device.hitPointOf(line, hit);
        absorbed *= shading::absorptionAlong(device, ray.media, std::max(hit.t - travelled, 0.0));
        travelled = std::max(travelled, hit.t);
        if (!shading::passesThrough(device, context, ray, layer, point)) return true;
        ray.media = shading::mediaBeyondHole(device, ray.media, point, ray.direction);
        past = shading::walkPast(past, hit.t, hit.primitive, hit.groupEnd, nearest, originScale);
    }
    absorbed *= shading::absorptionAlong(device, ray.media, std::numeric_limits<double>::infinity());
    return false;
}

glm::dvec3 ReferenceRenderer::radiance(shading::RayState ray, const shading::ShadingContext& context,
                                       double time, RayCounters& counters) const {
    const CpuShadingDevice device(shadingScene_, time, counters);
    SurfaceHit hit;
    shading::HitPoint point;
    glm::dvec3 absorbed;
    const bool found = visibleHit(device, context, ray, time, hit, point, absorbed);
    if (!found) return absorbed * shading::escapedRadiance(device, context, ray);

    // The shared shading step; its continuation rays are traced by recursion.
    const shading::ShadedHit shaded = shading::shadeHit(device, context, ray, point, ray.throughput * absorbed);
    glm::dvec3 result = shaded.radiance;
    if (shaded.reflects) {
        ++counters.secondary;
        result += shaded.reflectionWeight * radiance(shaded.reflection, context, time, counters);
    }
    if (shaded.transmits) {
        ++counters.secondary;
        result += shaded.transmissionWeight * radiance(shaded.transmission, context, time, counters);
    }
    return absorbed * result;
}

glm::dvec3 ReferenceRenderer::pathRadiance(shading::RayState ray, const shading::ShadingContext& context,
                                           double time, RayCounters& counters) const {
    const CpuShadingDevice device(shadingScene_, time, counters);
    glm::dvec3 sum(0.0);
    for (;;) {
        SurfaceHit hit;
        shading::HitPoint point;
        glm::dvec3 absorbed;
        const bool found = visibleHit(device, context, ray, time, hit, point, absorbed);
        const glm::dvec3 weight = ray.throughput * absorbed;
        if (!found) return sum + weight * shading::escapedRadiance(device, context, ray);
        const shading::ShadedHit shaded = shading::shadeHit(device, context, ray, point, weight);
        sum += weight * shaded.radiance;
        shading::RayState next;
        if (!shading::continuePath(context, ray, shaded, next)) return sum;
        ray = next;
        ++counters.secondary;
    }
}

glm::dvec3 ReferenceRenderer::radiance(const Ray& ray, uint32_t pixel, uint32_t sample,
                                       RayCounters& counters) const {
    // A camera ray, with the camera's ray cone (texture levels of detail).
    const glm::dvec2 cone = shading::cameraCone(camera_);
    const shading::RayState state = shading::withCone(
        shading::rayState(ray.origin, ray.direction, glm::dvec3(1.0), 0, 0, kNoPrimitive, 0.0, shading::emptyMedia()),
        cone.x, cone.y);
    const shading::ShadingContext context = shadingContext(pixel, sample);
    const double time = shutterTime(pixel, sample);
    return context.paths ? pathRadiance(state, context, time, counters) : radiance(state, context, time, counters);
}

glm::dvec4 ReferenceRenderer::renderPixel(int x, int y, uint32_t firstSample, uint32_t endSample,
                                          RayCounters& counters) const {
    const uint32_t pixel = static_cast<uint32_t>(y) * settings_.width + x;
    const uint32_t stream = vkrtPixelStream(settings_.seed, pixel);
    glm::dvec3 sum(0.0);
    uint64_t finite = 0;
    for (uint32_t sample = firstSample; sample < endSample; ++sample) {
        // Scrambled (0,2)-sequence positions: stratified at every power-of-two sample count.
        const glm::dvec2 offset =
            shading::filterOffset(static_cast<uint32_t>(settings_.pixelFilter),
                                  vkrtPixelJitterX(stream, sample), vkrtPixelJitterY(stream, sample));
        ++counters.primary;
        const Ray ray = cameraRay(x + 0.5 + offset.x, y + 0.5 + offset.y,
                                  vkrtStratified(settings_.seed, pixel, sample, VKRT_DIM_LENS_U, 0),
                                  vkrtStratified(settings_.seed, pixel, sample, VKRT_DIM_LENS_U, 1));
        const glm::dvec3 value = radiance(ray, pixel, sample, counters);
        // The image holds floats, and a sample beyond their range made its pixel infinite (written so, with
        // exit 0): it is left out and counted as the GPU leaves out what its floats cannot hold. A pixel's
        // average of the samples kept is then within range too.
        if (shading::allFinite(value) && shading::maxAbs(value) <= std::numeric_limits<float>::max()) {
            sum += value;
            ++finite;
        } else {
            ++counters.nonFiniteSamples;
        }
    }
    return glm::dvec4(sum, static_cast<double>(finite));
}

namespace {

constexpr uint32_t kMaxSamplesPerPass = 64;

}  // namespace

RenderResult ReferenceRenderer::render(const ProgressCallback& progress, const CheckpointCallback& checkpoint,
                                       double checkpointEveryMs, StopCondition stop) const {
    // The time limit counts from the first sample: the sums of a large image take a while to allocate (a
    // 4096 x 4096 image's 512 MiB took 1.7 s here, and a 1 s limit left one pixel traced).
    std::vector<glm::dvec4> sums(static_cast<size_t>(settings_.width) * settings_.height, glm::dvec4(0.0));
    stop.start();
    RenderResult result = renderRange(0, static_cast<uint32_t>(settings_.samplesPerPixel), sums, progress,
                                      checkpoint, checkpointEveryMs, stop);
    resolveSums(result, sums, settings_.width, settings_.height);
    return result;
}

RenderResult ReferenceRenderer::renderSamples(uint32_t firstSample, uint32_t endSample,
                                              std::vector<glm::dvec4>& sums,
                                              const StopCondition& stop) const {
    sums.resize(static_cast<size_t>(settings_.width) * settings_.height, glm::dvec4(0.0));
    return renderRange(firstSample, endSample, sums, {}, {}, 0.0, stop);
}

RenderResult ReferenceRenderer::renderRange(uint32_t firstSample, uint32_t endSample,
                                            std::vector<glm::dvec4>& sums, const ProgressCallback& progress,
                                            const CheckpointCallback& checkpoint, double checkpointEveryMs,
                                            const StopCondition& stop) const {
    RenderResult result;
    const uint32_t first = firstSample;
    const uint32_t samples = endSample - firstSample;
    const unsigned threads = threadCount(settings_.threads);
    CheckpointSchedule schedule(endSample, static_cast<bool>(checkpoint), checkpointEveryMs);

    // Passes of samples over all rows, ending where the schedule says. Per pixel the samples are summed in
    // the same order either way, so the image does not depend on the passes.
    uint32_t done = first;
    uint32_t most = first;
    uint32_t checkpointed = first;  // the samples of the last checkpoint's image
    while (done < endSample && result.stopped == StopReason::None) {
        // Passes double from one sample up to kMaxSamplesPerPass: the first image comes soon, and a pixel's
        // share of a pass stays short enough that stopping waits for little.
        const uint32_t end =
            std::min(schedule.passEnd(done), done + std::clamp(done - first, 1u, kMaxSamplesPerPass));
        std::atomic<StopReason> stopped{StopReason::None};
        std::atomic<uint64_t> pixelsDone{0};
        std::atomic<uint64_t> rowsDone{0};
        std::mutex progressLock;
        // One cache line per thread's counters: they change with every ray, and sharing a line between cores
        // would make the threads wait on each other.
        struct alignas(64) WorkerCounters {
            RayCounters rays;
        };
        std::vector<WorkerCounters> counters(threads);
        parallelFor(static_cast<size_t>(settings_.height), threads, [&](size_t row, unsigned worker) {
            const int y = static_cast<int>(row);
            for (int x = 0; x < settings_.width; ++x) {
                if (stopped.load(std::memory_order_relaxed) != StopReason::None) return;
                // Every render gets at least one pixel's samples, however soon it is asked to stop.
                if (const StopReason reason = stop.reason();
                    reason != StopReason::None && (done > first || pixelsDone > 0)) {
                    stopped = reason;
                    return;
                }
                sums[static_cast<size_t>(y) * settings_.width + x] +=
                    renderPixel(x, y, done, end, counters[worker].rays);
                pixelsDone.fetch_add(1, std::memory_order_relaxed);
            }
            const uint64_t rows = ++rowsDone;
            if (progress) {
                std::lock_guard<std::mutex> lock(progressLock);
                progress(static_cast<uint64_t>(done - first) * settings_.height + rows * (end - done),
                         static_cast<uint64_t>(samples) * settings_.height);
            }
        });
        for (const WorkerCounters& c : counters) result.rays += c.rays;
        // A pass cut short leaves some pixels with `end` samples and the rest with `done`.
        result.stopped = stopped;
        if (pixelsDone > 0) most = end;
        if (result.stopped != StopReason::None) break;
        done = end;

        const double renderMs = schedule.renderMs();
        if (schedule.due(done, renderMs)) {
            schedule.take(renderMs, [&] {
                checkpoint(done, renderMs, kNoGpuTime, averageOf(sums, settings_.width, settings_.height));
            });
            checkpointed = done;
        }
    }
    // A render stopped between checkpoints (time limit, interrupt) ends its report with the image it writes,
    // counted by the samples every pixel has.
    if (checkpoint && result.stopped != StopReason::None && (done != checkpointed || most > done)) {
        const double renderMs = schedule.renderMs();
        schedule.take(renderMs, [&] {
            checkpoint(done, renderMs, kNoGpuTime, averageOf(sums, settings_.width, settings_.height));
        });
    }
    result.fewestSamples = done - first;
    result.mostSamples = std::max(done, most) - first;
    return result;
}

}  // namespace vkrt
