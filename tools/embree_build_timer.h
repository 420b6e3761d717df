// Embree 3's BVH build as a benchmark anchor for vkrt's builder: the same triangles, built at a given
// quality (RTC_BUILD_QUALITY_LOW: Morton; MEDIUM, Embree's default: binned SAH; HIGH: binned SAH with
// spatial splits) on a fixed number of threads. Benchmark-only: the renderer never uses it.
#pragma once

#include <string>
#include <vector>

#include "scene/scene.h"

struct RTCDeviceTy;

namespace vkrt {

enum class EmbreeBuildQuality { Low, Medium, High };

const char* qualityName(EmbreeBuildQuality quality);

// The Embree version compiled against, e.g. "3.13.5".
const char* embreeVersion();

class EmbreeBuildTimer {
  public:
    // An Embree device limited to `threads` threads ("threads=N"; 0: Embree's default, every core),
    // with the triangles in shared buffers, so that a build reads them where they lie.
    EmbreeBuildTimer(const std::vector<Triangle>& triangles, int threads);
    ~EmbreeBuildTimer();
    EmbreeBuildTimer(const EmbreeBuildTimer&) = delete;
    EmbreeBuildTimer& operator=(const EmbreeBuildTimer&) = delete;

    // Builds a fresh scene over the triangles and returns the wall time in milliseconds, from
    // rtcNewScene to the end of rtcCommitScene.
    double build(EmbreeBuildQuality quality) const;

  private:
    RTCDeviceTy* device_ = nullptr;
    std::vector<float> vertices_;    // xyz per corner, padded: Embree may read 16 bytes from the last one
    std::vector<unsigned> indices_;  // three corners per triangle
    size_t triangleCount_ = 0;
};

}  // namespace vkrt
