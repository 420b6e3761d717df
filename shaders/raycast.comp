#version 460
// Traces a batch of rays through the scene's BVH and writes, per ray, the closest hit (distance, primitive,
// barycentrics) or, compiled with VKRT_RAYCAST_ANY_HIT, whether anything lies between tMin and tMax. Used by the
// ray-level conformance tests and the ray benchmarks; the traversal is the renderer's own (traverse.glsl). One
// kernel per mode: lavapipe runs both sides of a branch, masked, so a kernel choosing its walk at run time paid
// for one iteration of every loop of the other walk (any-hit rays 18% slower, closest-hit 4 to 11%).
#extension GL_GOOGLE_include_directive : require
#extension GL_EXT_buffer_reference : require
#include "ieee_floats.glsl"

#include "shared.h"
#include "shading_language.h"
#include "spread_workgroups.h"

layout(local_size_x = VKRT_RAYCAST_WORKGROUP) in;

layout(std430, binding = VKRT_BINDING_PARAMS) readonly buffer Params { SceneParams params; };
layout(push_constant) uniform Constants { RaycastConstants constants; };

#include "scene_arrays.glsl"
#include "ray.glsl"
#include "intersect.glsl"
#include "device_materials.glsl"
#include "traverse.glsl"

void main() {
    // This workgroup's block of rays: columns of blocks, one for each of lavapipe's threads (spread_workgroups.h).
    const uint block = spreadItem(gl_WorkGroupID.x, gl_WorkGroupID.y, gl_NumWorkGroups.y);
    const uint index = block * VKRT_RAYCAST_WORKGROUP + gl_LocalInvocationID.x;
    if (index >= constants.count) return;
#ifdef VKRT_RECORD_WORKGROUPS
    // In place of the hit, the launch index of the workgroup that took the ray (tests of the order).
    constants.hits.hits[index] =
        GpuHit(float(gl_WorkGroupID.x + gl_NumWorkGroups.x * gl_WorkGroupID.y), VKRT_NO_HIT, 0.0, 0.0);
    return;
#endif
    const GpuRay ray = constants.rays.rays[index];
    Hit hit;
    bool complete = true;
#ifdef VKRT_RAYCAST_ANY_HIT
    const bool found = traceAny(shearRay(Ray(ray.origin, ray.direction)), ray.tMin, ray.tMax, hit, complete);
#else
    const bool found =
        traceClosest(shearRay(Ray(ray.origin, ray.direction)), VKRT_NO_PRIMITIVE, ray.tMin, ray.tMax, hit, complete);
#endif
    // A walk the driver cut short is reported as a miss at NaN distance (see traverse.glsl).
    if (!complete) {
        constants.hits.hits[index] = GpuHit(uintBitsToFloat(0x7fc00000u), VKRT_NO_HIT, 0.0, 0.0);
        return;
    }
#ifdef VKRT_COUNT_ITERATIONS
    // The walk's loop iterations in place of the barycentrics (ray_benchmark --count-iterations).
    constants.hits.hits[index] = GpuHit(hit.t, found ? hit.sceneIndex : VKRT_NO_HIT, float(vkrtLoopIterations), 0.0);
    return;
#endif
    // Hits name the primitive by its index in the scene, not its place in the BVH's leaf order.
    constants.hits.hits[index] = found ? GpuHit(hit.t, hit.sceneIndex, hit.u, hit.v) : GpuHit(ray.tMax, VKRT_NO_HIT, 0.0, 0.0);
}
