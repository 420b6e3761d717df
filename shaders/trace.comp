#version 460
// vkrt's tracing kernel: per pixel, jittered stratified samples, each a Whitted ray tree walked with an
// explicit stack of pending rays; the BVH walk uses its own fixed stack. Shading follows the CPU
// reference (host/cpu/reference_renderer.cpp) step for step and draws the same random numbers.
//
// Features the scene lacks are compiled out: VKRT_HAS_SMOOTH_NORMALS, VKRT_HAS_TEXTURES,
// VKRT_HAS_TRANSMISSION, VKRT_HAS_VOLUMES, VKRT_HAS_PUNCTUAL_LIGHTS, VKRT_HAS_AREA_LIGHTS, VKRT_HAS_SPHERES,
// VKRT_HAS_DEPTH_OF_FIELD.
#extension GL_GOOGLE_include_directive : require
#extension GL_EXT_buffer_reference : require

#include "shared.h"
#include "random.h"

layout(local_size_x = VKRT_WORKGROUP_WIDTH, local_size_y = VKRT_WORKGROUP_HEIGHT) in;

layout(std430, binding = VKRT_BINDING_PARAMS) readonly buffer Params { SceneParams params; };
layout(push_constant) uniform Pass { PassConstants pass; };

#include "geometry.glsl"
#include "ray.glsl"
#include "intersect.glsl"
#include "sphere.glsl"
#include "materials.glsl"
#include "traverse.glsl"
#include "lights.glsl"
#include "media.glsl"

// One pending branch of the ray tree. Every member costs a scatter and a gather per push and pop on
// lavapipe, so the volume stack exists only in shaders for scenes with volumes.
struct RayTask {
    vec3 origin;
    uint node;  // ray-tree node number: children of k are 2k + 1 (reflection) and 2k + 2 (transmission)
    vec3 direction;
    int depth;
    vec3 throughput;
    uint exclude;      // the primitive the ray leaves
    float arrivalPdf;  // the density with which a glossy lobe chose the ray (0: camera, mirror, refraction)
#ifdef VKRT_HAS_VOLUMES
    uvec2 media;  // the volumes the ray is inside (media.glsl)
#endif
};

RayTask makeTask(vec3 origin, uint node, vec3 direction, int depth, vec3 throughput, uvec2 media, uint exclude,
                 float arrivalPdf) {
    RayTask task;
    task.origin = origin;
    task.node = node;
    task.direction = direction;
    task.depth = depth;
    task.throughput = throughput;
    task.exclude = exclude;
    task.arrivalPdf = arrivalPdf;
#ifdef VKRT_HAS_VOLUMES
    task.media = media;
#endif
    return task;
}

uvec2 mediaOf(RayTask task) {
#ifdef VKRT_HAS_VOLUMES
    return task.media;
#else
    return VKRT_EMPTY_MEDIA;
#endif
}

struct Counters {
    uint primary;
    uint shadow;
    uint secondary;
};

#ifdef VKRT_HAS_DEPTH_OF_FIELD
// Shirley and Chiu's concentric map from the unit square to the unit disk.
vec2 concentricDisk(float u, float v) {
    const float a = 2.0 * u - 1.0, b = 2.0 * v - 1.0;
    if (a == 0.0 && b == 0.0) return vec2(0.0);
    if (abs(a) > abs(b)) {
        const float phi = 0.25 * PI * (b / a);
        return a * vec2(cos(phi), sin(phi));
    }
    const float phi = 0.5 * PI - 0.25 * PI * (a / b);
    return b * vec2(cos(phi), sin(phi));
}
#endif

// The camera ray through film position (filmX, filmY) in pixels; with a lens, through lens point (u, v).
Ray cameraRay(float filmX, float filmY, float lensU, float lensV) {
    const GpuCamera camera = params.camera;
    const float width = float(params.imageDepthSeed.x), height = float(params.imageDepthSeed.y);
    const float sx = 2.0 * filmX / width - 1.0;
    const float sy = 1.0 - 2.0 * filmY / height;
    if (uint(camera.positionProjection.w) == VKRT_PROJECTION_ORTHOGRAPHIC) {
        const vec3 origin = camera.positionProjection.xyz + sx * camera.rightXmag.w * camera.rightXmag.xyz +
                            sy * camera.upYmag.w * camera.upYmag.xyz;
        return Ray(origin, camera.forwardTanHalfFov.xyz);
    }
    const float tanHalf = camera.forwardTanHalfFov.w;
    const vec3 direction = normalize(camera.forwardTanHalfFov.xyz +
                                     sx * tanHalf * (width / height) * camera.rightXmag.xyz +
                                     sy * tanHalf * camera.upYmag.xyz);
#ifdef VKRT_HAS_DEPTH_OF_FIELD
    // Thin lens: rays from every point of the lens meet where the pinhole ray crosses the focal plane.
    if (!(camera.lens.x > 0.0)) return Ray(camera.positionProjection.xyz, direction);
    const vec3 focus = camera.positionProjection.xyz +
                       direction * (camera.lens.y / dot(direction, camera.forwardTanHalfFov.xyz));
    const vec2 disk = camera.lens.x * concentricDisk(lensU, lensV);
    const vec3 origin = camera.positionProjection.xyz + disk.x * camera.rightXmag.xyz + disk.y * camera.upYmag.xyz;
    return Ray(origin, normalize(focus - origin));
#else
    return Ray(camera.positionProjection.xyz, direction);
#endif
}

// Filter importance sampling (host/cpu/pixel_filter.h): a sample's offset from its pixel's centre.
#ifndef VKRT_PIXEL_FILTER
#define VKRT_PIXEL_FILTER 0  // 0 box, 1 tent (radius 1), 2 Gaussian (standard deviation 0.5)
#endif
float tentInverse(float u) { return u < 0.5 ? sqrt(2.0 * u) - 1.0 : 1.0 - sqrt(2.0 - 2.0 * u); }

vec2 filterOffset(float u, float v) {
#if VKRT_PIXEL_FILTER == 1
    return vec2(tentInverse(u), tentInverse(v));
#elif VKRT_PIXEL_FILTER == 2
    const float radius = 0.5 * sqrt(-2.0 * log(1.0 - u));
    return radius * vec2(cos(2.0 * PI * v), sin(2.0 * PI * v));
#else
    return vec2(u - 0.5, v - 0.5);
#endif
}

// Radiance arriving along one camera ray: the ray tree, depth first.
// `complete` turns false when a BVH walk was cut short (see traverse.glsl); the sample is then discarded.
vec3 traceRayTree(Ray primary, uint pixel, uint sampleIndex, inout Counters counters, inout bool complete) {
    const uint maxDepth = params.imageDepthSeed.z;
    const float minThroughput = params.ambientMinThroughput.w;
    RayTask stack[VKRT_MAX_RAY_DEPTH + 1];
    int size = 0;
    stack[size++] = makeTask(primary.origin, 0u, primary.direction, 0, vec3(1.0), VKRT_EMPTY_MEDIA, VKRT_NO_TRIANGLE, 0.0);
    vec3 radiance = vec3(0.0);
    while (size > 0) {
        const RayTask task = stack[--size];
        Hit hit;
        const bool found = traceClosest(shearRay(Ray(task.origin, task.direction)), task.exclude, 0.0, VKRT_INFINITY, hit,
                                        complete);
        vec3 weight = task.throughput;
#ifdef VKRT_HAS_VOLUMES
        const int medium = innermostMedium(mediaOf(task));
        if (medium >= 0) weight *= beerLambert(params.materials.materials[medium], found ? hit.t : VKRT_INFINITY);
#endif
        if (!found) {
            radiance += weight * params.background.rgb;
            continue;
        }

        const GpuTriangle triangle = primitiveAt(hit.triangle);
        const uint materialIndex = triangle.material;
        const GpuMaterial material = params.materials.materials[materialIndex];
        const vec3 toViewer = -task.direction;
        SurfacePoint surfacePoint;
        vec3 geometricNormal, normal;  // facing the front (outside) until oriented below
        bool sphere = false;
#ifdef VKRT_HAS_SPHERES
        sphere = triangle.kind == VKRT_PRIMITIVE_SPHERE;
        if (sphere) {
            surfacePoint = sphereHitPoint(task.origin, task.direction, hit.t, triangle.v0, triangle.v1.x, geometricNormal);
            normal = geometricNormal;
            const vec2 uv = sphereUv(geometricNormal);
            hit.u = uv.x;
            hit.v = uv.y;
        } else
#endif
        {
            surfacePoint = hitPoint(task.origin, task.direction, hit.t, triangle.v0, triangle.v1, triangle.v2, hit.u, hit.v);
            geometricNormal = normalize(cross(triangle.v1 - triangle.v0, triangle.v2 - triangle.v0));
#ifdef VKRT_HAS_SMOOTH_NORMALS
            const GpuShading shading = params.shading.shading[hit.triangle];
            normal = normalize((1.0 - hit.u - hit.v) * shading.normalU0.xyz + hit.u * shading.normalU1.xyz +
                               hit.v * shading.normalU2.xyz);
#ifdef VKRT_HAS_MOTION
            // A moving triangle turns its vertex normals (given at the shutter's opening) with its face.
            const GpuTriangle opened = VKRT_TRIANGLE(hit.triangle);
            normal = rotateLike(normal, normalize(cross(opened.v1 - opened.v0, opened.v2 - opened.v0)), geometricNormal);
#endif
#else
            normal = geometricNormal;
#endif
        }

        // Orient both normals towards the viewer; remember which side was hit.
        const bool frontFace = dot(geometricNormal, toViewer) > 0.0;
        if (!frontFace) {
            geometricNormal = -geometricNormal;
            normal = -normal;
        }
        if (!(dot(normal, toViewer) > 0.0)) normal = geometricNormal;
        // New rays skip the primitive they leave, except rays that go into a sphere (they must find its far
        // side); a ray leaving a sphere's outside cannot meet the sphere again.
        const uint excludeOnViewerSide = sphere && !frontFace ? VKRT_NO_TRIANGLE : hit.triangle;
        const uint excludeBeyond = sphere && frontFace ? VKRT_NO_TRIANGLE : hit.triangle;

        vec3 local = vec3(0.0);
        if (frontFace || material.transmission.w != 0.0) {
            float emissionWeight = 1.0;
#ifdef VKRT_HAS_AREA_LIGHTS
            if (task.arrivalPdf > 0.0 && params.counts.y > 0u) {
                // A traced lobe ray found a light that light sampling also reaches (multiple importance sampling).
                const float lightPdf = lightSolidAnglePdf(hit.triangle, task.origin, surfacePoint.position,
                                                          abs(dot(geometricNormal, task.direction)));
                emissionWeight = params.lighting.y != 0.0 ? powerHeuristic(1.0, task.arrivalPdf, params.background.w * lightPdf)
                                                          : 0.0;  // without MIS, light samples alone light the lobe
            }
#endif
            local += emissionWeight * emissionAt(material, hit.triangle, hit.u, hit.v);
        }
        const SurfaceResponse surface = surfaceResponse(material, albedoAt(material, hit.triangle, hit.u, hit.v));
        // Ambient light reaches the diffuse part, and the specular part where it is not traced.
        local += params.ambientMinThroughput.rgb * (surface.diffuse + (surface.traced ? vec3(0.0) : surface.specular));
        const bool lobeSampled = surface.traced && !surface.mirror && uint(task.depth) < maxDepth;
        local += directLight(surfacePoint, normal, geometricNormal, toViewer, surface, hit.triangle, excludeOnViewerSide,
                             lobeSampled, pixel, sampleIndex, task.node, counters.shadow, complete);
        radiance += weight * local;

        if (uint(task.depth) < maxDepth && surface.traced) {
#ifdef VKRT_HAS_VOLUMES
            const bool volume = material.transmission.z > 0.0 && surface.transmission > 0.0;
#else
            const bool volume = false;
#endif
            // A volume is entered through its front face and left through its back face, from the medium the
            // ray is in into the one beyond (nested dielectrics); thin-walled and opaque surfaces look the
            // same from both sides.
            uvec2 beyond = mediaOf(task);
            float eta = surface.ior;
#ifdef VKRT_HAS_VOLUMES
            if (volume) {
                beyond = frontFace ? mediaEntered(mediaOf(task), materialIndex) : mediaExited(mediaOf(task), materialIndex);
                eta = mediaIor(beyond) / mediaIor(mediaOf(task));
            }
#endif
            // The microfacet normal both branches share: the shading normal for a mirror, else a visible normal.
            const float cosOut = dot(normal, toViewer);
            vec3 microNormal = normal;
            if (!surface.mirror) {
                vec3 tangent, bitangent;
                orthonormalBasis(normal, tangent, bitangent);
                const vec3 m = sampleGgxVisibleNormal(vec3(dot(toViewer, tangent), dot(toViewer, bitangent), cosOut),
                                                      surface.alpha,
                                                      vkrtStratified(params.imageDepthSeed.w, pixel, sampleIndex, vkrtNodeDimension(task.node, VKRT_DIM_LOBE_U), 0u),
                                                      vkrtStratified(params.imageDepthSeed.w, pixel, sampleIndex, vkrtNodeDimension(task.node, VKRT_DIM_LOBE_U), 1u));
                microNormal = normalize(m.x * tangent + m.y * bitangent + m.z * normal);
            }
            const float cosMicro = max(0.0, dot(microNormal, toViewer));
            const float dielectric = fresnelDielectric(cosMicro, eta);
            // Reflection: Fresnel, times G2 / G1 for a sampled visible normal (Heitz 2018, eq. 19).
            const vec3 reflected = reflectAbout(toViewer, microNormal);
            vec3 reflectWeight = fresnelAt(surface, cosMicro, eta);
            float reflectPdf = 0.0;  // 0: a delta lobe, whose rays see lights at full weight
            if (!surface.mirror) {
                const float cosIn = dot(normal, reflected);
                const bool above = cosIn > 0.0 && dot(geometricNormal, reflected) > 0.0;
                reflectWeight *= above ? ggxG2(cosOut, cosIn, surface.alpha) / ggxG1(cosOut, surface.alpha) : 0.0;
                reflectPdf = ggxReflectionPdf(cosOut, dot(normal, microNormal), surface.alpha);
            }
#ifdef VKRT_HAS_TRANSMISSION
            // Transmission through the same microfacet; thin-walled surfaces pass rays straight through. Pushed
            // first so that the reflection, pushed last, is traced first, as on the CPU.
            vec3 transmitWeight = surface.transmission * (1.0 - dielectric) * surface.albedo;
            vec3 direction = task.direction;
            bool passes = maxComponent(transmitWeight) > 0.0;
            if (passes && volume) passes = refractThrough(toViewer, microNormal, eta, direction);
            if (passes && volume && !surface.mirror) {
                const float cosIn = dot(normal, direction);
                passes = cosIn < 0.0 && dot(geometricNormal, direction) < 0.0;
                if (passes) transmitWeight *= ggxG2(cosOut, -cosIn, surface.alpha) / ggxG1(cosOut, surface.alpha);
            }
            if (passes && maxComponent(weight * transmitWeight) >= minThroughput) {
                ++counters.secondary;
                stack[size++] = makeTask(offsetRayOrigin(surfacePoint, -geometricNormal), 2u * task.node + 2u, direction,
                                        task.depth + 1, weight * transmitWeight, beyond, excludeBeyond, 0.0);
            }
#endif
            if (maxComponent(weight * reflectWeight) >= minThroughput) {
                ++counters.secondary;
                stack[size++] = makeTask(offsetRayOrigin(surfacePoint, geometricNormal), 2u * task.node + 1u, reflected,
                                        task.depth + 1, weight * reflectWeight, mediaOf(task), excludeOnViewerSide,
                                        reflectPdf);
            }
        }
    }
    return radiance;
}

void main() {
    const uint width = params.imageDepthSeed.x;
    const uvec2 xy = uvec2(gl_GlobalInvocationID.x, pass.rowStart + gl_GlobalInvocationID.y);
    if (xy.x >= width || gl_GlobalInvocationID.y >= pass.rowCount) return;
    const uint pixel = xy.y * width + xy.x;
    const uint seed = params.imageDepthSeed.w;
    Counters counters = Counters(0u, 0u, 0u);
    uint nonFinite = 0u;
    precise vec4 sum = vec4(0.0);
    precise vec4 sumLost = vec4(0.0);  // Kahan compensation of `sum`
    for (uint s = pass.sampleStart; s < pass.sampleStart + pass.sampleCount; ++s) {
#ifdef VKRT_HAS_MOTION
        vkrtShutterTime = vkrtStratified(seed, pixel, s, VKRT_DIM_TIME, 0u);
#endif
        // Scrambled (0,2)-sequence positions: stratified at every power-of-two sample count.
        const float jx = vkrtPixelJitterX(seed, pixel, s);
        const float jy = vkrtPixelJitterY(seed, pixel, s);
        const vec2 offset = filterOffset(jx, jy);
        ++counters.primary;
        bool complete = true;
        const Ray primary = cameraRay(float(xy.x) + 0.5 + offset.x, float(xy.y) + 0.5 + offset.y, vkrtStratified(seed, pixel, s, VKRT_DIM_LENS_U, 0u),
                                      vkrtStratified(seed, pixel, s, VKRT_DIM_LENS_U, 1u));
        const vec3 value = traceRayTree(primary, pixel, s, counters, complete);
        if (complete && allFinite(value)) {
            precise const vec4 corrected = vec4(value, 1.0) - sumLost;
            precise const vec4 next = sum + corrected;
            sumLost = (next - sum) - corrected;
            sum = next;
        } else {
            ++nonFinite;
        }
    }
    // Kahan-compensated accumulation: pixels[2p] holds the running sum (rgb and the finite-sample count),
    // pixels[2p + 1] the low-order part lost so far, so 1e5 and more samples keep single-precision digits.
    precise vec4 total = params.accumulation.pixels[2u * pixel];
    precise vec4 lost = params.accumulation.pixels[2u * pixel + 1u];
    precise const vec4 corrected = (sum - sumLost) - lost;
    precise const vec4 next = total + corrected;
    lost = (next - total) - corrected;
    params.accumulation.pixels[2u * pixel] = next;
    params.accumulation.pixels[2u * pixel + 1u] = lost;
    atomicAdd(params.counters.counters[VKRT_COUNTER_PRIMARY], counters.primary);
    atomicAdd(params.counters.counters[VKRT_COUNTER_SHADOW], counters.shadow);
    atomicAdd(params.counters.counters[VKRT_COUNTER_SECONDARY], counters.secondary);
    if (nonFinite > 0u) atomicAdd(params.counters.counters[VKRT_COUNTER_NONFINITE], nonFinite);
}
