#include "embree_tracer.h"

#include <algorithm>
#include <chrono>
#include <stdexcept>

#include <embree3/rtcore.h>

#include "common/parallel_for.h"

namespace vkrt {

EmbreeTracer::EmbreeTracer(const std::vector<Triangle>& triangles) {
    device_ = rtcNewDevice(nullptr);
    if (!device_) throw std::runtime_error("Embree: rtcNewDevice failed");
    const auto start = std::chrono::steady_clock::now();
    scene_ = rtcNewScene(device_);
    RTCGeometry geometry = rtcNewGeometry(device_, RTC_GEOMETRY_TYPE_TRIANGLE);
    auto* vertices = static_cast<float*>(rtcSetNewGeometryBuffer(
        geometry, RTC_BUFFER_TYPE_VERTEX, 0, RTC_FORMAT_FLOAT3, 3 * sizeof(float), triangles.size() * 3));
    auto* indices = static_cast<unsigned*>(rtcSetNewGeometryBuffer(
        geometry, RTC_BUFFER_TYPE_INDEX, 0, RTC_FORMAT_UINT3, 3 * sizeof(unsigned), triangles.size()));
    for (size_t i = 0; i < triangles.size(); ++i) {
        const glm::vec3 corners[3] = {triangles[i].v0, triangles[i].v1, triangles[i].v2};
        for (int k = 0; k < 3; ++k) {
            for (int c = 0; c < 3; ++c) vertices[9 * i + 3 * k + c] = corners[k][c];
            indices[3 * i + k] = static_cast<unsigned>(3 * i + k);
        }
    }
    rtcCommitGeometry(geometry);
    rtcAttachGeometry(scene_, geometry);
    rtcReleaseGeometry(geometry);
    rtcCommitScene(scene_);
    buildMs_ = std::chrono::duration<double, std::milli>(std::chrono::steady_clock::now() - start).count();
}

const char* EmbreeTracer::version() {
    return RTC_VERSION_STRING;
}

EmbreeTracer::~EmbreeTracer() {
    if (scene_) rtcReleaseScene(scene_);
    if (device_) rtcReleaseDevice(device_);
}

double EmbreeTracer::trace(const std::vector<gpu::GpuRay>& rays, bool anyHit, int threads,
                           std::vector<uint32_t>& hits) const {
    hits.assign(rays.size(), VKRT_NO_HIT);
    // Blocks of rays, handed out in order to the threads.
    constexpr size_t kBlock = 1024;
    auto work = [&](size_t block, unsigned /*worker*/) {
        const size_t begin = block * kBlock, end = std::min(rays.size(), begin + kBlock);
        RTCIntersectContext context;
        rtcInitIntersectContext(&context);
        for (size_t i = begin; i < end; ++i) {
            const gpu::GpuRay& r = rays[i];
            RTCRayHit rayHit{};
            rayHit.ray.org_x = r.origin.x;
            rayHit.ray.org_y = r.origin.y;
            rayHit.ray.org_z = r.origin.z;
            rayHit.ray.dir_x = r.direction.x;
            rayHit.ray.dir_y = r.direction.y;
            rayHit.ray.dir_z = r.direction.z;
            rayHit.ray.tnear = r.tMin;
            rayHit.ray.tfar = r.tMax;
            rayHit.ray.mask = 0xffffffffu;
            rayHit.hit.geomID = RTC_INVALID_GEOMETRY_ID;
            if (anyHit) {
                rtcOccluded1(scene_, &context, &rayHit.ray);
                if (rayHit.ray.tfar < 0.0f) hits[i] = 0;  // Embree marks occlusion with tfar = -inf
            } else {
                rtcIntersect1(scene_, &context, &rayHit);
                if (rayHit.hit.geomID != RTC_INVALID_GEOMETRY_ID) hits[i] = rayHit.hit.primID;
            }
        }
    };
    const auto start = std::chrono::steady_clock::now();
    parallelFor((rays.size() + kBlock - 1) / kBlock, threadCount(threads), work);
    return std::chrono::duration<double, std::milli>(std::chrono::steady_clock::now() - start).count();
}

}  // namespace vkrt
