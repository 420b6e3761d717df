// The GPU's side of the shared shading code for lights, shadow rays and ray offsets (VKRT_DEVICE in
// shading_language.h). Requires `params`, scene_arrays.glsl, ray.glsl and traverse.glsl in scope.
#ifndef VKRT_DEVICE_LIGHTS_GLSL
#define VKRT_DEVICE_LIGHTS_GLSL

#include "area_light.h"
#include "punctual_light.h"

#ifdef VKRT_HAS_SHAPES
// Shapes, for shape_light.h: their type, material and maps at the sample's shutter time (solids.glsl).
uint device_shapeType(uint shape) { return shapeTypeAt(shape); }
uint device_shapeMaterial(uint shape) { return gpuShapeAt(shape).material; }
void device_shapeMaps(uint shape, out AffineRows toObject, out AffineRows toWorld) {
    shapeMaps(shape, toObject, toWorld);
}
#endif
#include "shape_light.h"

// Whether triangle lights that look large are sampled by solid angle (params.solidAngleTriangles): compiled in
// only for scenes with a large lamp, as the sampler's code costs every other scene's kernel.
bool device_solidAngleTriangles() {
#ifdef VKRT_HAS_SOLID_ANGLE_TRIANGLES
    return params.solidAngleTriangles != 0u;
#else
    return false;
#endif
}

// Per invocation: shadow rays traced, and whether every BVH walk ran to its end (see traverse.glsl).
uint vkrtShadowRays = 0u;
bool vkrtWalksComplete = true;

// A pass of a loop of the shading code, counted as the walk's are (traverse.glsl's VKRT_COUNT_ITERATION).
void device_loopPass() { VKRT_COUNT_ITERATION(); }

vec3 device_offsetOrigin(vec3 position, float errorScale, vec3 normal) {
    return offsetRayOrigin(position, errorScale, normal);
}

// Shadow rays to a point on a light stop short of it (shared.h's VKRT_SHADOW_RAY_SHORTENING).
float device_shadowRayLength(float distance) { return distance * (1.0 - float(VKRT_SHADOW_RAY_SHORTENING)); }

vec4 device_shadowTransmittance(vec3 origin, vec3 direction, float tMin, float tMax, uint excludeA, uint excludeB) {
    ++vkrtShadowRays;
    return shadowTransmittance(Ray(origin, direction), tMin, tMax, excludeA, excludeB, vkrtWalksComplete);
}

#ifdef VKRT_HAS_VOLUME_HOLES
// Some volume's surface has holes (Scene::volumesHaveHoles, also where every feature is compiled in): the path
// kernel's shadow rays meet surfaces in order (shade_hit.h's lightSampleShadow), walked by trace.comp, which
// finds the hit points.
bool device_hasVolumeHoles() { return vkrtVolumesBlockShadows && params.volumeHoles != 0u; }
bool device_shadowThroughHoles(vec3 origin, vec3 direction, float tMax, uint exclude, uint light, inout uvec2 media,
                               inout vec4 passage, inout vec3 absorbed, inout float tMin);
#endif

// Light tables (host/scene/light_table.h): the cumulative steps of entry `i` of the punctual lights' table or of
// the area lights', and the first entry of `count` whose steps exceed the 48-bit number that (pick, pickFine),
// 24 bits each, make (by binary search). The table is a constant at each call, so each inlined search reads one.
uvec2 lightTableSteps(bool punctual, uint i) {
#ifdef VKRT_HAS_PUNCTUAL_LIGHT_TABLE
    if (punctual) return gpuLightSteps(i);
#endif
    return gpuAreaLightSteps(i);
}

uint findInLightTable(bool punctual, uint count, float pick, float pickFine) {
    const uvec2 drawn = lightPickSteps(pick, pickFine);
    uint lo = 0u, hi = count - 1u;
    while (lo < hi) {
        const uint mid = (lo + hi) / 2u;
        const uvec2 steps = lightTableSteps(punctual, mid);
        if (steps.x > drawn.x || (steps.x == drawn.x && steps.y > drawn.y)) hi = mid;
        else lo = mid + 1u;
    }
    return lo;
}

#ifdef VKRT_HAS_PUNCTUAL_LIGHTS
uint device_punctualLightCount() { return params.punctualLightCount; }

PunctualLightParams device_punctualLight(uint i) {
    const GpuPunctualLight light = gpuLightAt(i);
    PunctualLightParams p;
    p.type = light.type;
    p.position = light.position;
    p.direction = light.direction;
    p.intensity = light.intensity;
    p.range = light.range;
    p.cosOuter = light.cosOuter;
    p.coneScale = light.coneScale;
    return p;
}

#ifdef VKRT_HAS_PUNCTUAL_LIGHT_TABLE
// The punctual light that (pick, pickFine) picks from the table, and its pick probability.
uint device_pickPunctualLight(float pick, float pickFine, out float probability) {
    const uint light = findInLightTable(true, params.punctualLightCount, pick, pickFine);
    probability = gpuLightAt(light).pick;
    return light;
}
#endif
#endif

#ifdef VKRT_HAS_AREA_LIGHTS
bool device_hasAreaLights() { return params.areaLightCount > 0u; }

// The light that (pick, pickFine) picks from the table, and a point on it.
LightPoint device_sampleAreaLight(float pick, float pickFine, float u, float v, vec3 from) {
    const GpuAreaLight light = gpuAreaLightAt(findInLightTable(false, params.areaLightCount, pick, pickFine));
    const GpuPrimitive emitter = primitiveAt(light.primitive);
#ifdef VKRT_HAS_SHAPES
    if (light.shape != VKRT_NO_PRIMITIVE) {
        const GpuSolid solid = solidOf(emitter);
        return sampleShapeLight(light.primitive, SolidOperands(solid.firstShape, shapeCountOf(solid), solid.tableLow,
                                                               solid.tableHigh),
                                light.shape, light.pick, u, v);
    }
#endif
    LightPoint p;
#ifdef VKRT_HAS_SPHERES
    if (emitter.kind == VKRT_PRIMITIVE_SPHERE) {
        p = sampleSphereLight(light.primitive, emitter.v0, emitter.v1.x, light.pick, from,
                              sphereSeenThrough(device_material(emitter.material)), u, v);
        p.material = emitter.material;
        return p;
    }
#endif
#ifdef VKRT_HAS_MOTION
    const float pdfArea = light.pick / triangleArea(emitter.v0, emitter.v1, emitter.v2);  // the area now
#else
    const float pdfArea = light.pdfArea;
#endif
    p = sampleTriangleLight(light.primitive, emitter.v0, emitter.v1, emitter.v2, light.pick, pdfArea, from,
                            device_solidAngleTriangles(), u, v);
    p.material = emitter.material;
    return p;
}

// The density per solid angle with which device_sampleAreaLight, seen from `from`, picks `point` on emissive
// `primitive` (on `shape`, for a solid). The pick probability is the primitive's share of the power at the
// shutter's opening.
float device_lightSolidAnglePdf(uint primitive, uint shape, vec3 from, vec3 point, float cosLight) {
#ifdef VKRT_HAS_SHAPES
    if (shape != VKRT_NO_PRIMITIVE) {
        return shapeLightSolidAnglePdf(shape, gpuShapeAt(shape).lightPick, from, point, cosLight);
    }
#endif
    const GpuPrimitive opened = VKRT_PRIMITIVE(primitive);
    const GpuPrimitive now = primitiveAt(primitive);
    const vec3 emission = gpuMaterialAt(opened.material).emission;
    const vec3 offset = point - from;
#ifdef VKRT_HAS_SPHERES
    if (opened.kind == VKRT_PRIMITIVE_SPHERE) {
        const float pick = lightPickProbability(lightPower(emission, 4.0 * VKRT_PI * opened.v1.x * opened.v1.x),
                                                params.areaLightPower, params.areaLightCount);
        return sphereLightSolidAnglePdf(now.v0, now.v1.x, pick, from,
                                        sphereSeenThrough(device_material(opened.material)), dot(offset, offset),
                                        cosLight);
    }
#endif
    const float openArea = triangleArea(opened.v0, opened.v1, opened.v2);
    const float pick = lightPickProbability(lightPower(emission, openArea), params.areaLightPower,
                                            params.areaLightCount);
#ifdef VKRT_HAS_MOTION
    const float area = triangleArea(now.v0, now.v1, now.v2);
#else
    const float area = openArea;
#endif
    return triangleLightSolidAnglePdf(now.v0, now.v1, now.v2, pick, pick / area, from, device_solidAngleTriangles(),
                                      dot(offset, offset), cosLight);
}
#endif

#ifdef VKRT_HAS_ENVIRONMENT
// The environment map's tables (shaders/environment.h).
bool device_hasEnvironment() { return params.environmentWidth > 0u; }

uvec2 device_environmentSize() { return uvec2(params.environmentWidth, params.environmentHeight); }

vec2 device_environmentRotation() { return vec2(params.environmentCosRotation, params.environmentSinRotation); }

vec3 device_environmentTexel(uint i) { return gpuEnvironmentTexelAt(i).radiance; }

float device_environmentRowCdf(uint y) { return gpuEnvironmentRowCdf(y); }

float device_environmentColumnCdf(uint i) { return gpuEnvironmentTexelAt(i).columnCdf; }

#include "environment.h"
#endif

#endif
