// The CPU reference renderer: plain, recursive, distributed Whitted ray tracing in double precision, of
// triangles and analytic spheres. It is the oracle the GPU tracer is tested against. It shares the physics
// with the GPU (shaders/shade_hit.h and the headers it includes, compiled here in double precision) and keeps
// apart what makes it independent: its own BVH walk and triangle test (double Moller-Trumbore), recursion
// instead of a stack, and ray offsets suited to double precision. It favours obvious correctness over speed
// (rows are still shared among all cores).
#pragma once

#include <cstdint>
#include <vector>

#include "bvh/bvh_traversal.h"
#include "bvh/flat_bvh.h"
#include "camera.h"
#include "common/render_settings.h"
#include "cpu/closest_hit.h"
#include "cpu/cpu_shading_device.h"
#include "image/render_result.h"
#include "scene/scene.h"
#include "shade_hit.h"

namespace vkrt {

using Ray = RayT<double>;

class ReferenceRenderer {
  public:
    ReferenceRenderer(const Scene& scene, const FlatBvh& bvh, const Camera& camera,
                      const RenderSettings& settings);

    // Renders every sample, or until `stop` says so (checked before each pixel of a pass). With a checkpoint
    // callback, it is also called with the image so far at every power-of-two sample count, at the end, and
    // after any pass that crosses checkpointEveryMs (> 0).
    RenderResult render(const ProgressCallback& progress = {}, const CheckpointCallback& checkpoint = {},
                        double checkpointEveryMs = 0.0, StopCondition stop = {}) const;

    // Adds samples [firstSample, endSample) of every pixel into `sums` (rgb sums and finite-sample counts,
    // one per pixel, row by row), or stops part way when `stop` says so (its clock is the caller's: not
    // restarted). The result has no image; its sample counts are those of this range. Renders shared among
    // processes are made of such ranges: a sample's value does not depend on who renders it.
    RenderResult renderSamples(uint32_t firstSample, uint32_t endSample, std::vector<glm::dvec4>& sums,
                               const StopCondition& stop = {}) const;

    // The pieces, public for tests.
    // Film coordinates in pixels, (0, 0) top-left; (lensU, lensV) in [0, 1)^2 picks the lens point.
    Ray cameraRay(double filmX, double filmY, double lensU = 0.5, double lensV = 0.5) const;
    // Where in the shutter interval (0: open, 1: close) a sample sees the scene; every ray of the sample's
    // tree shares it.
    double shutterTime(uint32_t pixel, uint32_t sample) const;
    // Radiance arriving along a camera-like ray (the root of a ray tree) for sample `sample` of `pixel`.
    glm::dvec3 radiance(const Ray& ray, uint32_t pixel, uint32_t sample, RayCounters& counters) const;
    // The sum of the finite samples [firstSample, endSample) of a pixel (rgb) and how many there were (w).
    glm::dvec4 renderPixel(int x, int y, uint32_t firstSample, uint32_t endSample,
                           RayCounters& counters) const;

  private:
    RenderResult renderRange(uint32_t firstSample, uint32_t endSample, std::vector<glm::dvec4>& sums,
                             const ProgressCallback& progress, const CheckpointCallback& checkpoint,
                             double checkpointEveryMs, const StopCondition& stop) const;
    shading::ShadingContext shadingContext(uint32_t pixel, uint32_t sample) const;
    // The nearest surface along `ray` that is there (alpha), and what the volumes on the way absorb up to it,
    // as the GPU's traceVisible finds them; the holes passed in volumes' surfaces move `ray` into or out of
    // them.
    bool visibleHit(const CpuShadingDevice& device, const shading::ShadingContext& context,
                    shading::RayState& ray, double time, SurfaceHit& hit, shading::HitPoint& point,
                    glm::dvec3& absorbed) const;
    // The path integrator: radiance arriving along a path's first ray, one ray per bounce, in a loop.
    glm::dvec3 pathRadiance(shading::RayState ray, const shading::ShadingContext& context, double time,
                            RayCounters& counters) const;
    // Whitted: radiance arriving along one ray of the tree, seen at shutter time `time`, by recursion.
    glm::dvec3 radiance(shading::RayState ray, const shading::ShadingContext& context, double time,
                        RayCounters& counters) const;

    const Scene& scene_;
    const FlatBvh& bvh_;
    RenderSettings settings_;
    CpuShadingScene shadingScene_;
    shading::CameraFrame camera_;
};

}  // namespace vkrt
