// Embree 3 as a benchmark anchor: traces the same rays as vkrt's GPU traversal, single rays
// (rtcIntersect1 / rtcOccluded1) spread over host threads. Benchmark-only: the renderer never uses it.
#pragma once

#include <vector>

#include "scene/scene.h"
#include "shared.h"

struct RTCDeviceTy;
struct RTCSceneTy;

namespace vkrt {

class EmbreeTracer {
  public:
    explicit EmbreeTracer(const std::vector<Triangle>& triangles);
    ~EmbreeTracer();
    EmbreeTracer(const EmbreeTracer&) = delete;
    EmbreeTracer& operator=(const EmbreeTracer&) = delete;

    // Traces every ray (closest hit, or any hit when `anyHit`) on `threads` threads; returns the wall time
    // in milliseconds and, per ray, the triangle hit (VKRT_NO_HIT for none; for any-hit, 0 for occluded).
    double trace(const std::vector<gpu::GpuRay>& rays, bool anyHit, int threads,
                 std::vector<uint32_t>& hits) const;

    double buildMs() const { return buildMs_; }
    static const char* version();

  private:
    RTCDeviceTy* device_ = nullptr;
    RTCSceneTy* scene_ = nullptr;
    double buildMs_ = 0.0;
};

}  // namespace vkrt
