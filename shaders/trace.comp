#version 460
// vkrt's tracing kernel: per pixel, stratified samples, each a path (VKRT_PATHS: one ray state carried
// through a loop of bounces) or a Whitted ray tree (walked with an explicit stack of pending rays); the BVH walk
// uses its own fixed stack; Whitted's loop runs over the rays of all of an invocation's samples. The
// shading step at every hit is the one the CPU reference runs (shade_hit.h), drawing the same random numbers;
// this file holds the GPU's own loops and its single-precision hit points.
//
// Features the scene lacks are compiled out: each VKRT_HAS_... define is one of host/gpu/scene_features.cpp's
// (its kFeatures table lists them all), defined only when the scene needs it.
#extension GL_GOOGLE_include_directive : require
#extension GL_EXT_buffer_reference : require
#if defined(VKRT_SUBGROUP_COUNTERS) || defined(VKRT_COUNT_LOOP_PASSES)
#extension GL_KHR_shader_subgroup_arithmetic : require
#endif
#ifdef VKRT_CHAINS_ESCAPES
#extension GL_KHR_shader_subgroup_vote : require
#endif
#include "ieee_floats.glsl"

#include "shared.h"
#include "random.h"
#include "shading_language.h"
#include "spread_workgroups.h"

layout(local_size_x = VKRT_WORKGROUP_WIDTH, local_size_y = VKRT_WORKGROUP_HEIGHT) in;

layout(std430, binding = VKRT_BINDING_PARAMS) readonly buffer Params { SceneParams params; };
layout(push_constant) uniform Pass { PassConstants pass; };

#include "scene_arrays.glsl"
#include "ray.glsl"
#include "intersect.glsl"
#include "device_materials.glsl"
#include "traverse.glsl"
#include "device_lights.glsl"
#include "camera.h"
#include "shade_hit.h"

#ifndef VKRT_PIXEL_FILTER
#define VKRT_PIXEL_FILTER VKRT_FILTER_BOX
#endif

#ifndef VKRT_PATHS
// One pending branch of the ray tree (a RayState). Every member costs a scatter and a gather per push and pop
// on lavapipe, so the volume stack exists only in shaders for scenes with volumes.
struct RayTask {
    vec3 origin;
    uint node;
    vec3 direction;
    int depth;  // with transmission and an environment: the depth times 2, plus 1 where it sees the backdrop
    vec3 throughput;
    uint exclude;
    float arrivalPdf;
#ifdef VKRT_HAS_VOLUMES
    uvec2 media;
#endif
#ifdef VKRT_HAS_MIPMAPS
    float coneWidth;
    float coneSpread;
#endif
};

RayTask taskOf(RayState ray) {
    RayTask task;
    task.origin = ray.origin;
    task.node = ray.node;
    task.direction = ray.direction;
#if defined(VKRT_HAS_TRANSMISSION) && defined(VKRT_HAS_ENVIRONMENT)
    task.depth = 2 * ray.depth + (ray.backdrop ? 1 : 0);
#else
    task.depth = ray.depth;  // the backdrop matters only to an environment, and only transmission keeps it
#endif
    task.throughput = ray.throughput;
    task.exclude = ray.exclude;
    task.arrivalPdf = ray.arrivalPdf;
#ifdef VKRT_HAS_VOLUMES
    task.media = ray.media;
#endif
#ifdef VKRT_HAS_MIPMAPS
    task.coneWidth = ray.coneWidth;
    task.coneSpread = ray.coneSpread;
#endif
    return task;
}

RayState stateOf(RayTask task) {
#ifdef VKRT_HAS_VOLUMES
    const uvec2 media = task.media;
#else
    const uvec2 media = emptyMedia();
#endif
#if defined(VKRT_HAS_TRANSMISSION) && defined(VKRT_HAS_ENVIRONMENT)
    RayState ray = rayState(task.origin, task.direction, task.throughput, task.node, task.depth >> 1, task.exclude,
                            task.arrivalPdf, media);
    ray.backdrop = (task.depth & 1) != 0;
#else
    const RayState ray = rayState(task.origin, task.direction, task.throughput, task.node, task.depth, task.exclude,
                                  task.arrivalPdf, media);
#endif
#ifdef VKRT_HAS_MIPMAPS
    return withCone(ray, task.coneWidth, task.coneSpread);
#else
    return ray;
#endif
}
#endif  // !VKRT_PATHS

CameraFrame cameraFrame() {
    const GpuCamera c = params.camera;
    CameraFrame camera;
    camera.projection = c.projection;
    camera.position = c.position;
    camera.forward = c.forward;
    camera.right = c.right;
    camera.up = c.up;
    camera.tanHalfFov = c.tanHalfFov;
    camera.xmag = c.xmag;
    camera.ymag = c.ymag;
    camera.lensRadius = c.lensRadius;
    camera.focusDistance = c.focusDistance;
    camera.sceneRadius = c.sceneRadius;
    camera.width = float(params.width);
    camera.height = float(params.height);
    return camera;
}

// Where `ray` met primitive `hit`, in single precision: the point whichever way rounds less (ray.glsl), the
// front side's normals at the sample's shutter time.
HitPoint hitPointOf(RayState ray, Hit hit) {
    const GpuPrimitive primitive = primitiveAt(hit.primitive);
    HitPoint p;
    p.primitive = hit.primitive;
    p.material = primitive.material;
    p.sphere = false;
#ifdef VKRT_HAS_SPHERES
    p.sphere = primitive.kind == VKRT_PRIMITIVE_SPHERE;
#endif
    p.shape = VKRT_NO_PRIMITIVE;
    p.face = 0u;
    p.uv = vec2(hit.u, hit.v);
    p.tangent = vec4(0.0);
    SurfacePoint surface;
#ifdef VKRT_HAS_SHAPES
    if (isSolid(primitive)) {
        // The crossed shape and face (traverse.glsl's visitSolid), the point projected onto the face when that
        // rounds less than the point along the ray (whose error grows with the shape's distance from the origin).
        p.shape = uint(hit.u);
        const uint code = uint(hit.v);
        p.face = code >> 1u;
        AffineRows toObject, toWorld;
        shapeMaps(p.shape, toObject, toWorld);
        const ShapePoint s = shapePoint(shapeTypeAt(p.shape), code >> 1u, (code & 1u) != 0u, toObject, ray.origin,
                                        ray.direction, hit.t);
        p.material = gpuShapeAt(p.shape).material;
        p.geometricNormal = p.normal = s.normal;
        p.uv = s.uv;
#ifdef VKRT_HAS_NORMAL_MAPS
        vec2 row0, row1;
        tangentFrameTurn(p.material, row0, row1);
        p.tangent = shapeTangent(shapeTypeAt(p.shape), code >> 1u, s.local, toWorld, s.normal, row0, row1);
#endif
        const float rayScale = maxAbs(ray.origin) + hit.t + maxAbs(vec3(toWorld.row0.w, toWorld.row1.w, toWorld.row2.w));
        const float scale = shapeScale(toWorld);
        surface = rayScale < scale ? SurfacePoint(ray.origin + hit.t * ray.direction, rayScale)
                                   : SurfacePoint(affinePoint(toWorld, s.local), scale);
    } else
#endif
#ifdef VKRT_HAS_SPHERES
    if (p.sphere) {
        surface = sphereHitPoint(ray.origin, ray.direction, hit.t, primitive.v0, primitive.v1.x, p.geometricNormal);
        p.normal = p.geometricNormal;
        p.uv = sphereUv(p.geometricNormal);
#ifdef VKRT_HAS_NORMAL_MAPS
        vec2 row0, row1;
        tangentFrameTurn(p.material, row0, row1);
        p.tangent = sphereTangent(p.geometricNormal, row0, row1);
#endif
    } else
#endif
    {
        surface = hitPoint(ray.origin, ray.direction, hit.t, primitive.v0, primitive.v1, primitive.v2, hit.u, hit.v);
        p.geometricNormal = planeNormal(primitive.v0, primitive.v1, primitive.v2);
#ifdef VKRT_HAS_MOTION
        // A moving triangle turns its vertex normals and tangents (given at the shutter's opening) with its face.
        const GpuPrimitive opened = VKRT_PRIMITIVE(hit.primitive);
        const vec3 openedEdge = opened.v1 - opened.v0, openedNormal = planeNormal(opened.v0, opened.v1, opened.v2);
        const vec3 edgeNow = primitive.v1 - primitive.v0;
#endif
#ifdef VKRT_HAS_SMOOTH_NORMALS
        const GpuShading shading = gpuShadingAt(hit.primitive);
        p.normal = normalize(barycentric(shading.normalU0.xyz, shading.normalU1.xyz, shading.normalU2.xyz, vec2(hit.u, hit.v)));
#ifdef VKRT_HAS_MOTION
        p.normal = turnWithFace(p.normal, openedEdge, openedNormal, edgeNow, p.geometricNormal, 1e-6);
#endif
#else
        p.normal = p.geometricNormal;
#endif
#ifdef VKRT_HAS_NORMAL_MAPS
        const GpuTangents tangents = gpuTangentsAt(hit.primitive);
        p.tangent = barycentric(tangents.corner0, tangents.corner1, tangents.corner2, vec2(hit.u, hit.v));
#ifdef VKRT_HAS_MOTION
        p.tangent.xyz = turnWithFace(p.tangent.xyz, openedEdge, openedNormal, edgeNow, p.geometricNormal, 1e-6);
#endif
#endif
    }
    p.position = surface.position;
    p.errorScale = surface.errorScale;
    return p;
}

// The nearest surface along `ray` that is there at its hit, and in `absorbed` what the volumes on the way absorb
// up to it (or along the whole ray where it meets nothing). The holes of alpha-tested and blended surfaces
// (passesThrough) are passed, in the closest-hit rule's order (ties.h's WalkPast); a hole in a volume's surface
// moves `ray` into or out of its medium (mediaBeyondHole). One traversal call site, so the walk is inlined once.
bool traceVisible(inout RayState ray, ShadingContext context, out Hit hit, out HitPoint point, out vec3 absorbed) {
    const ShearedRay sheared = shearRay(Ray(ray.origin, ray.direction));
#ifdef VKRT_HAS_ALPHA
    WalkPast past = walkPastFrom(0.0);
    float travelled = 0.0;
    absorbed = vec3(1.0);
    for (uint layer = 0u;
         traceClosestPast(sheared, ray.exclude, VKRT_NO_PRIMITIVE, past, VKRT_INFINITY, hit, vkrtWalksComplete);
         ++layer) {
        VKRT_COUNT_ITERATION();
        point = hitPointOf(ray, hit);
        absorbed *= absorptionAlong(ray.media, max(hit.t - travelled, 0.0));
        travelled = max(travelled, hit.t);
        if (!passesThrough(context, ray, layer, point)) return true;
        ray.media = mediaBeyondHole(ray.media, point, ray.direction);
        past = walkPastHit(past, hit, ray.origin);
    }
    absorbed *= absorptionAlong(ray.media, VKRT_INFINITY);
    return false;
#else
    const bool found = traceClosest(sheared, ray.exclude, 0.0, VKRT_INFINITY, hit, vkrtWalksComplete);
    absorbed = absorptionAlong(ray.media, found ? hit.t : VKRT_INFINITY);
    if (found) point = hitPointOf(ray, hit);
    return found;
#endif
}

#ifdef VKRT_HAS_VOLUME_HOLES
// A path's shadow ray from `origin` to tMax where volumes' surfaces have holes (shade_hit.h's lightSampleShadow):
// its first VKRT_MAX_ALPHA_LAYERS surfaces beyond tMin met one by one, in the closest-hit rule's order, as
// traceVisible meets them, each crossed by crossInOrder (what passes into `passage`, what the media before it
// absorb into `absorbed`, and `media` moved into or out of a volume at a hole in its surface). `exclude` and the
// light's primitive are skipped throughout. True where surfaces may lie beyond those (the rest are left to the
// walk in any order, from `tMin`); false where none do or the light is blocked.
bool device_shadowThroughHoles(vec3 origin, vec3 direction, float tMax, uint exclude, uint light, inout uvec2 media,
                               inout vec4 passage, inout vec3 absorbed, inout float tMin) {
    const ShearedRay sheared = shearRay(Ray(origin, direction));
    RayState ray;  // what hitPointOf reads
    ray.origin = origin;
    ray.direction = direction;
    WalkPast past = walkPastFrom(tMin);
    Hit hit;
    for (uint layer = 0u; layer < VKRT_MAX_ALPHA_LAYERS; ++layer) {
        VKRT_COUNT_ITERATION();
        if (!traceClosestPast(sheared, exclude, light, past, tMax, hit, vkrtWalksComplete)) {
            ++vkrtShadowRays;
            return false;
        }
        const HitPoint point = hitPointOf(ray, hit);
        crossInOrder(point, direction, max(hit.t - tMin, 0.0), media, passage, absorbed);
        tMin = max(tMin, hit.t);
        past = walkPastHit(past, hit, origin);
        if (!(maxComponent(passage.xyz) > 0.0)) {
            ++vkrtShadowRays;
            passage = vec4(0.0);
            return false;
        }
    }
    tMin = past.end;
    return true;  // counted by the walk that takes the rest
}
#endif

// One finished sample into the pixel's Kahan-compensated sum (rgb and the finite-sample count). A sample whose
// BVH walk was cut short (traverse.glsl), of an invocation that has run llvmpipe's loop budget, that is not
// finite, or that would take the single-precision sum beyond its range (radiance near 1e38, where the CPU's
// double sums hold) is discarded and counted.
void addSample(vec3 value, bool complete, inout precise vec4 sum, inout precise vec4 sumLost, inout uint nonFinite) {
#ifdef VKRT_COUNT_LOOP_PASSES
    // An invocation that has itself run 65535 loop passes has spent llvmpipe's budget (its SIMD group's passes
    // are at least its own), and a loop it cut short without a walk's noticing (the light loop) left the
    // sample short.
    complete = complete && vkrtLoopPasses < 65535u;
#endif
    if (complete && allFinite(value)) {
        precise const vec4 corrected = vec4(value, 1.0) - sumLost;
        precise const vec4 next = sum + corrected;
        if (allFinite(next.xyz)) {
            sumLost = (next - sum) - corrected;
            sum = next;
            return;
        }
    }
    ++nonFinite;
}

// The camera ray of sample `s` of the pixel at `xy`; sets the context's sample index (and the shutter time).
RayState cameraRayState(CameraFrame camera, vec2 cone, uvec2 xy, uint s, inout ShadingContext context) {
#ifdef VKRT_HAS_MOTION
    vkrtShutterTime = vkrtStratifiedFrom(context.pairRoot, s, VKRT_DIM_TIME, 0u);
#endif
    context.sampleIndex = s;
    // Scrambled (0,2)-sequence positions: stratified at every power-of-two sample count.
    const vec2 offset = filterOffset(uint(VKRT_PIXEL_FILTER), vkrtPixelJitterX(context.stream, s),
                                     vkrtPixelJitterY(context.stream, s));
    const CameraRay primary = cameraRay(camera, float(xy.x) + 0.5 + offset.x, float(xy.y) + 0.5 + offset.y,
                                        vkrtStratifiedFrom(context.pairRoot, s, VKRT_DIM_LENS_U, 0u),
                                        vkrtStratifiedFrom(context.pairRoot, s, VKRT_DIM_LENS_U, 1u));
    return withCone(rayState(primary.origin, primary.direction, vec3(1.0), 0u, 0, VKRT_NO_PRIMITIVE, 0.0, emptyMedia()),
                    cone.x, cone.y);
}

// The walk of either kernel's next ray: true where `ray` meets a surface; where it escapes, what it brings in is
// added to `radiance`. Where surfaces have no holes only the hit leaves the walk, and its point and the volumes'
// absorption up to it are found after it by completeHit (the kernels' walks sit in inner loops, and a value that
// leaves a loop is blended at each of its passes on lavapipe).
bool walkRay(inout RayState ray, ShadingContext context, out Hit hit, out HitPoint point, out vec3 absorbed,
             inout vec3 radiance) {
#ifdef VKRT_HAS_ALPHA
    const bool found = traceVisible(ray, context, hit, point, absorbed);
    if (!found) radiance += ray.throughput * absorbed * escapedRadiance(context, ray);
#else
    const bool found = traceClosest(shearRay(Ray(ray.origin, ray.direction)), ray.exclude, 0.0, VKRT_INFINITY, hit,
                                    vkrtWalksComplete);
    if (!found) radiance += ray.throughput * absorptionAlong(ray.media, VKRT_INFINITY) * escapedRadiance(context, ray);
#endif
    return found;
}

// walkRay's hit point and the absorption up to it, where the walk left them to be found after it.
void completeHit(RayState ray, Hit hit, inout HitPoint point, inout vec3 absorbed) {
#ifndef VKRT_HAS_ALPHA
    absorbed = absorptionAlong(ray.media, hit.t);
    point = hitPointOf(ray, hit);
#endif
}

#ifdef VKRT_PATHS
// Shades walkRay's hit and continues the path from it into `ray`: false where the path ends there.
bool bouncePath(inout RayState ray, ShadingContext context, Hit hit, HitPoint point, vec3 absorbed,
                inout vec3 radiance, inout uint secondaryRays) {
    completeHit(ray, hit, point, absorbed);
    const vec3 weight = ray.throughput * absorbed;
    const ShadedHit shaded = shadeHit(context, ray, point, weight);
    radiance += weight * shaded.radiance;
    RayState next;
    if (!continuePath(context, ray, shaded, next)) return false;
    ray = next;
    ++secondaryRays;
    return true;
}

// Samples [s, end) of the pixel at `xy`, each one path: one ray per bounce, continued by continuePath, added to
// `sum` as it ends. Counts camera rays in `primaryRays` and bounces in `secondaryRays`.
//
// With VKRT_CHAINS_ESCAPES (lavapipe, where a pass of the bounce loop costs all of its code, shading and light
// sampling included, whether or not a lane hit anything), the SIMD group's lanes begin their samples together:
// a lane whose path has ended waits in the loop, and once every lane's path has ended, the last ones escaping
// at this pass's walk, each lane adds its sample and traces its next camera ray within the walk's inner loop,
// instead of passing through the shading code once more (the Whitted scene, a third sky: GPU time about 0.88
// of that; the Cornell box, whose paths do not escape, about 1.03; docs/performance-log.md). Chaining the lanes
// still walking while others had ended made the Whitted scene's GPU time 1.6 times as long: the lanes' samples
// drifted apart, and the group ran the sum of their paths instead of the longest of each sample's. (Without it,
// starting the next sample in the bounce loop whenever a lane's path ends, as traceRayTrees does, was no faster
// on lavapipe: the camera ray's code then runs, masked, at every bounce, and paths vary less in length than ray
// trees do in size.)
void tracePaths(CameraFrame camera, vec2 cone, uvec2 xy, uint s, uint end, ShadingContext context,
                inout precise vec4 sum, inout precise vec4 sumLost, inout uint primaryRays, inout uint secondaryRays,
                inout uint nonFinite) {
    if (s == end) return;
#ifdef VKRT_CHAINS_ESCAPES
    vkrtWalksComplete = true;
    RayState ray = cameraRayState(camera, cone, xy, s, context);
    ++primaryRays;
    vec3 radiance = vec3(0.0);
    bool ended = false;  // this lane's path, which then waits for the group's
    for (;;) {
        VKRT_COUNT_ITERATION();
        Hit hit;
        HitPoint point;
        vec3 absorbed;
        bool found = false;
        bool allEnded, chained;
        do {
            if (!ended) {
                found = walkRay(ray, context, hit, point, absorbed, radiance);
                ended = !found;
            }
            allEnded = subgroupAll(ended);
            chained = allEnded && s + 1u != end;
            if (chained) {
                VKRT_COUNT_ITERATION();
                addSample(radiance, vkrtWalksComplete, sum, sumLost, nonFinite);
                ++s;
                vkrtWalksComplete = true;
                ray = cameraRayState(camera, cone, xy, s, context);
                ++primaryRays;
                radiance = vec3(0.0);
                ended = false;
            }
        } while (chained);
        if (allEnded) break;  // the last sample's paths
        if (found) ended = !bouncePath(ray, context, hit, point, absorbed, radiance, secondaryRays);
    }
    addSample(radiance, vkrtWalksComplete, sum, sumLost, nonFinite);
#else
    // A do-while: llvmpipe tests a loop's exit at the end of its body, and a `for` that tested it at the top
    // would run the whole body once more, masked, in every dispatch (traceRayTrees).
    do {
        VKRT_COUNT_ITERATION();
        vkrtWalksComplete = true;
        RayState ray = cameraRayState(camera, cone, xy, s, context);
        ++primaryRays;
        vec3 radiance = vec3(0.0);
        for (;;) {
            VKRT_COUNT_ITERATION();
            Hit hit;
            HitPoint point;
            vec3 absorbed;
            if (!walkRay(ray, context, hit, point, absorbed, radiance)) break;
            if (!bouncePath(ray, context, hit, point, absorbed, radiance, secondaryRays)) break;
        }
        addSample(radiance, vkrtWalksComplete, sum, sumLost, nonFinite);
    } while (++s < end);
#endif
}
#else
// Samples [first, end) of the pixel at `xy`, each a ray tree walked depth first (the reflection traced first, as
// on the CPU), added to `sum` as they finish. The ray to trace next is held in registers, and only a transmission
// waiting behind a reflection goes on the stack: each push and pop is a scatter and a gather of every member on
// lavapipe, and keeping the other rays off it made the Whitted scene's GPU time 4% shorter (issue 13).
//
// One loop runs over every ray of every tree: an invocation whose tree ends starts its next sample in the next
// iteration instead of idling until its neighbours' trees end too. SIMD lanes (llvmpipe's eight, a GPU's warp)
// run a loop for as long as any of them needs it, so a group of invocations takes as many iterations as the one
// with the most rays over all its samples, rather than the sum over samples of the largest tree (issue 13).
// Counts camera rays in `primaryRays`, reflection and refraction rays in `secondaryRays`, and samples not
// finished (llvmpipe's loop budget, traverse.glsl, can end the loop early) in `nonFinite`.
void traceRayTrees(CameraFrame camera, vec2 cone, uvec2 xy, uint first, uint end, ShadingContext context,
                   inout precise vec4 sum, inout precise vec4 sumLost, inout uint primaryRays, inout uint secondaryRays,
                   inout uint nonFinite) {
    if (first == end) return;
    RayTask stack[VKRT_MAX_RAY_DEPTH + 1];
    int size = 0;
    uint finished = 0u;
    vec3 radiance = vec3(0.0);
    RayState ray;
    uint s = first;
    bool startsSample = true;  // the pass begins sample s with its camera ray
    // The next ray is chosen at the end of each pass, and the loop ends there: llvmpipe tests a loop's exit at
    // the end of its body, so an exit at the top cost every invocation one more pass of the whole body, masked,
    // in every dispatch (the Whitted scene's GPU time 7% longer; issue 13).
    for (;;) {
        VKRT_COUNT_ITERATION();
        Hit hit;
        HitPoint point;
        vec3 absorbed;
        bool found;
        // The tree's next ray. With VKRT_CHAINS_ESCAPES (lavapipe), where every ray of the SIMD group escapes
        // and no branch waits behind any, each lane adds its sample and traces its next sample's camera ray in
        // an inner loop: a pass of the outer loop costs all of its code whether or not a lane shades a hit, and
        // a group that sees only the background took a whole pass a sample (the Whitted scene, a third sky:
        // GPU time 0.85 to 0.92 of that; scenes that show little background within the machine's noise;
        // docs/performance-log.md). The vote keeps a lane that hit from waiting while its neighbours run
        // through their samples.
        bool chained;
        do {
            VKRT_COUNT_ITERATION();
            if (startsSample) {
                vkrtWalksComplete = true;
                radiance = vec3(0.0);
                ray = cameraRayState(camera, cone, xy, s, context);
                ++primaryRays;
                ++s;
                startsSample = false;
            }
            found = walkRay(ray, context, hit, point, absorbed, radiance);
#ifdef VKRT_CHAINS_ESCAPES
            chained = subgroupAll(!found && size == 0) && s != end;
#else
            chained = false;
#endif
            if (chained) {
                addSample(radiance, vkrtWalksComplete, sum, sumLost, nonFinite);
                ++finished;
                startsSample = true;
            }
        } while (chained);
        bool queued = false;  // `ray` holds the tree's next ray, not yet traced
        if (found) {
            completeHit(ray, hit, point, absorbed);
            const vec3 weight = ray.throughput * absorbed;
            const ShadedHit shaded = shadeHit(context, ray, point, weight);
            radiance += weight * shaded.radiance;
            if (shaded.transmits) {
                ++secondaryRays;
                if (shaded.reflects) {
                    stack[size++] = taskOf(shaded.transmission);
                } else {
                    ray = shaded.transmission;
                    queued = true;
                }
            }
            if (shaded.reflects) {
                ++secondaryRays;
                ray = shaded.reflection;
                queued = true;
            }
        }
        if (!queued) {
            if (size > 0) {
                ray = stateOf(stack[--size]);
            } else {
                // The sample's tree is done: add it, and start the next with its camera ray.
                addSample(radiance, vkrtWalksComplete, sum, sumLost, nonFinite);
                ++finished;
                if (s == end) break;
                startsSample = true;
            }
        }
    }
    nonFinite += (end - first) - finished;
}
#endif

// Adds this invocation's `count` to ray counter `counter`. Every invocation adding to the same word serialises
// the atomics: on lavapipe a path kernel that does nothing else took 4 times as long with one atomic per
// invocation and counter (307 against 76 ms for 64 samples of 256 x 256). Where the device can sum across a
// subgroup, one invocation adds the subgroup's total.
void addToCounter(uint counter, uint count) {
#ifdef VKRT_SUBGROUP_COUNTERS
    const uint total = subgroupAdd(count);
    if (subgroupElect() && total > 0u) atomicAdd(params.counters.counters[counter], total);
#else
    if (count > 0u) atomicAdd(params.counters.counters[counter], count);
#endif
}

void main() {
    const uint width = params.width;
    // This workgroup's tile: in every band of rows, lavapipe's thread t takes tiles t, t + T, t + 2T, ... of
    // the band's (spread_workgroups.h).
    const uint tile = spreadItem(gl_WorkGroupID.x, gl_WorkGroupID.z, gl_NumWorkGroups.z);
    const uint row = gl_GlobalInvocationID.y;  // from the dispatch's first
    const uvec2 xy = uvec2(tile * VKRT_WORKGROUP_WIDTH + gl_LocalInvocationID.x, pass.rowStart + row);
    if (xy.x >= width || row >= pass.rowCount) return;
    const uint pixel = xy.y * width + xy.x;
    const CameraFrame camera = cameraFrame();
    const vec2 cone = cameraCone(camera);
    ShadingContext context;
    context.ambient = params.ambient;
    context.background = params.background;
#ifdef VKRT_PATHS
    context.paths = true;
#else
    context.paths = false;
#endif
    context.environmentBackdrop = params.environmentBackdrop != 0u;
    context.minThroughput = params.minThroughput;
    context.maxDepth = int(params.maxDepth);
    context.lightSamples = params.lightSamples;
    context.multipleImportanceSampling = params.multipleImportanceSampling != 0u;
    context.energyCompensation = params.energyCompensation != 0u;
    context.stream = vkrtPixelStream(params.seed, pixel);
    context.pairRoot = vkrtPairRoot(context.stream);
    uint primaryRays = 0u, secondaryRays = 0u, nonFinite = 0u;
    precise vec4 sum = vec4(0.0);
    precise vec4 sumLost = vec4(0.0);  // Kahan compensation of `sum`
#ifdef VKRT_PATHS
    tracePaths(camera, cone, xy, pass.sampleStart, pass.sampleStart + pass.sampleCount, context, sum, sumLost,
               primaryRays, secondaryRays, nonFinite);
#else
    traceRayTrees(camera, cone, xy, pass.sampleStart, pass.sampleStart + pass.sampleCount, context, sum, sumLost,
                  primaryRays, secondaryRays, nonFinite);
#endif
    // Kahan-compensated accumulation: pixels[2p] holds the running sum (rgb and the finite-sample count),
    // pixels[2p + 1] the low-order part lost so far, so 1e5 and more samples keep single-precision digits;
    // p counts pixels from the first row of the tile the buffer holds.
    const uint slot = (xy.y - pass.tileRowStart) * width + xy.x;
    precise vec4 total = params.accumulation.pixels[2u * slot];
    precise vec4 lost = params.accumulation.pixels[2u * slot + 1u];
    precise const vec4 corrected = (sum - sumLost) - lost;
    precise const vec4 next = total + corrected;
    if (allFinite(next.xyz)) {
        lost = (next - total) - corrected;
        params.accumulation.pixels[2u * slot] = next;
        params.accumulation.pixels[2u * slot + 1u] = lost;
    } else {
        nonFinite += uint(sum.w);  // this dispatch's samples would take the pixel's sum beyond float's range
    }
    addToCounter(VKRT_COUNTER_PRIMARY, primaryRays);
    addToCounter(VKRT_COUNTER_SHADOW, vkrtShadowRays);
    addToCounter(VKRT_COUNTER_SECONDARY, secondaryRays);
    addToCounter(VKRT_COUNTER_NONFINITE, nonFinite);
#ifdef VKRT_COUNT_LOOP_PASSES
    // The most loop passes a lane of the SIMD group took a sample, for the host's choice of samples a dispatch
    // (dispatch_planner.h).
    const uint passes = subgroupMax(vkrtLoopPasses);
    if (subgroupElect() && pass.sampleCount > 0u) {
        atomicMax(params.counters.counters[VKRT_COUNTER_LOOP_PASSES], (passes + pass.sampleCount - 1u) / pass.sampleCount);
    }
#endif
}
