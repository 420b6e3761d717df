#include "embree_build_timer.h"

#include <chrono>
#include <stdexcept>

#include <embree3/rtcore.h>

namespace vkrt {

const char* qualityName(EmbreeBuildQuality quality) {
    switch (quality) {
        case EmbreeBuildQuality::Low:
            return "low";
        case EmbreeBuildQuality::Medium:
            return "medium";
        case EmbreeBuildQuality::High:
            return "high";
    }
    return "?";
}

const char* embreeVersion() {
    return RTC_VERSION_STRING;
}

EmbreeBuildTimer::EmbreeBuildTimer(const std::vector<Triangle>& triangles, int threads)
    : triangleCount_(triangles.size()) {
    const std::string config = threads > 0 ? "threads=" + std::to_string(threads) : std::string();
    device_ = rtcNewDevice(config.empty() ? nullptr : config.c_str());
    if (!device_) throw std::runtime_error("Embree: rtcNewDevice failed");
    vertices_.resize(9 * triangles.size() + 4);
    indices_.resize(3 * triangles.size());
    for (size_t i = 0; i < triangles.size(); ++i) {
        const glm::vec3 corners[3] = {triangles[i].v0, triangles[i].v1, triangles[i].v2};
        for (int k = 0; k < 3; ++k) {
            for (int c = 0; c < 3; ++c) vertices_[9 * i + 3 * k + c] = corners[k][c];
            indices_[3 * i + k] = static_cast<unsigned>(3 * i + k);
        }
    }
}

EmbreeBuildTimer::~EmbreeBuildTimer() {
    if (device_) rtcReleaseDevice(device_);
}

double EmbreeBuildTimer::build(EmbreeBuildQuality quality) const {
    const RTCBuildQuality rtcQuality = quality == EmbreeBuildQuality::Low    ? RTC_BUILD_QUALITY_LOW
                                       : quality == EmbreeBuildQuality::High ? RTC_BUILD_QUALITY_HIGH
                                                                             : RTC_BUILD_QUALITY_MEDIUM;
    const auto start = std::chrono::steady_clock::now();
    RTCScene scene = rtcNewScene(device_);
    rtcSetSceneBuildQuality(scene, rtcQuality);
    RTCGeometry geometry = rtcNewGeometry(device_, RTC_GEOMETRY_TYPE_TRIANGLE);
    rtcSetGeometryBuildQuality(geometry, rtcQuality);
    rtcSetSharedGeometryBuffer(geometry, RTC_BUFFER_TYPE_VERTEX, 0, RTC_FORMAT_FLOAT3, vertices_.data(), 0,
                               3 * sizeof(float), 3 * triangleCount_);
    rtcSetSharedGeometryBuffer(geometry, RTC_BUFFER_TYPE_INDEX, 0, RTC_FORMAT_UINT3, indices_.data(), 0,
                               3 * sizeof(unsigned), triangleCount_);
    rtcCommitGeometry(geometry);
    rtcAttachGeometry(scene, geometry);
    rtcReleaseGeometry(geometry);
    rtcCommitScene(scene);
    const double ms =
        std::chrono::duration<double, std::milli>(std::chrono::steady_clock::now() - start).count();
    const RTCError error = rtcGetDeviceError(device_);
    rtcReleaseScene(scene);
    if (error != RTC_ERROR_NONE) throw std::runtime_error("Embree: build failed");
    return ms;
}

}  // namespace vkrt
