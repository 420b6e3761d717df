// BVH traversal: near child first, far child on a fixed stack whose size the builder's depth bound
// guarantees (VKRT_BVH_MAX_DEPTH). One walk serves closest-hit, any-hit and shadow-transmittance queries;
// callers pass the mode as a constant, so each inlined copy keeps only its own branch.
// Requires `params` (SceneParams), geometry.glsl, intersect.glsl and device_materials.glsl in scope.
#ifndef VKRT_TRAVERSE_GLSL
#define VKRT_TRAVERSE_GLSL

#define VKRT_TRACE_CLOSEST 0  // the nearest hit
#define VKRT_TRACE_ANY 1      // stop at the first hit
#define VKRT_TRACE_SHADOW 2   // multiply the transmission of every surface crossed; stop when opaque

#include "sphere_geometry.h"

struct Hit {
    float t;
    float u, v;  // barycentric weights of v1 and v2
    uint primitive;
    uint sceneIndex;  // the primitive's index in the scene, which breaks ties (kept to spare a reload)
};

// Slab test. The far distance is widened by 1 + 2 gamma(3) so rounding never misses a box the ray
// touches (Ize, "Robust BVH Ray Traversal", JCGT 2(2), 2013).
bool intersectBox(BvhNode node, ShearedRay r, float tMin, float tMax, out float tEntry) {
    const vec3 t0 = (node.boundsMin - r.origin) * r.inverseDirection;
    const vec3 t1 = (node.boundsMax - r.origin) * r.inverseDirection;
    const vec3 near = min(t0, t1), far = max(t0, t1);
    tEntry = max(max(near.x, near.y), max(near.z, tMin));
    const float tExit = min(min(far.x, far.y), min(far.z, tMax)) * 1.0000003576;
    return tEntry <= tExit;
}

// How far hits still matter: the best hit so far, plus a tie's width for closest-hit walks (ties are won by
// the smaller scene index, so a tie just beyond the best hit can still win).
float searchLimit(Hit hit, float tMax, const int mode) {
    if (mode != VKRT_TRACE_CLOSEST || hit.primitive == VKRT_NO_PRIMITIVE) return hit.t;
    return min(tMax, hit.t * (1.0 + float(VKRT_TIE_EPSILON)));
}

// The path integrator's shadow rays stop at transmissive surfaces (surface_response.h's shadowTint).
#ifdef VKRT_PATHS
const bool vkrtTransmissionBlocksShadows = true;
#else
const bool vkrtTransmissionBlocksShadows = false;
#endif

// Multiplies `transmittance` by the transmission of a surface crossed at barycentrics / texture
// coordinates (u, v); true when it is now opaque.
bool crossSurface(uint primitive, float u, float v, inout vec3 transmittance) {
#if defined(VKRT_HAS_TRANSMISSION) || defined(VKRT_HAS_ALPHA)
    const SurfaceMaterial material = device_material(device_materialOf(primitive));
    transmittance *= shadowTint(sampleMaterial(material, primitive, vec2(u, v), 0.0), vkrtTransmissionBlocksShadows);
    if (maxComponent(transmittance) > 0.0) return false;
#endif
    transmittance = vec3(0.0);  // opaque
    return true;
}

// Tests one primitive of a leaf; returns true when the walk can stop (any hit, or an opaque shadow).
bool visitPrimitive(ShearedRay r, uint index, uint excludeA, uint excludeB, float tMin, float tMax,
                   const int mode, inout Hit hit, inout vec3 transmittance) {
    if (index == excludeA || index == excludeB) return false;
    const GpuPrimitive primitive = primitiveAt(index);
    float t, u = 0.0, v = 0.0;
#ifdef VKRT_HAS_SPHERES
    if (primitive.kind == VKRT_PRIMITIVE_SPHERE) {
        if (mode == VKRT_TRACE_SHADOW) {
            // A shadow ray crosses a sphere up to twice; each crossing filters the light.
            float roots[2];
            if (!sphereRoots(primitive.v0, primitive.v1.x, r.origin, r.direction, roots[0], roots[1])) return false;
            for (int k = 0; k < 2; ++k) {
                if (!(roots[k] > tMin && roots[k] < tMax)) continue;
                const vec2 uv = sphereUv(normalize(r.origin + roots[k] * r.direction - primitive.v0));
                if (crossSurface(index, uv.x, uv.y, transmittance)) return true;
            }
            return false;
        }
        if (!intersectSphere(primitive.v0, primitive.v1.x, r.origin, r.direction, tMin, searchLimit(hit, tMax, mode), t)) {
            return false;
        }
    } else
#endif
    if (!intersectTriangle(r, primitive, tMin, searchLimit(hit, tMax, mode), t, u, v)) {
        return false;
    }
    if (mode == VKRT_TRACE_ANY) {
        hit = Hit(t, u, v, index, primitive.sceneIndex);
        return true;
    }
    if (mode == VKRT_TRACE_CLOSEST) {
        // Nearer by more than the tie tolerance, or a tie won by the smaller scene index (shared.h).
        const float tolerance = float(VKRT_TIE_EPSILON) * hit.t;
        const bool first = hit.primitive == VKRT_NO_PRIMITIVE;
        if (first || t < hit.t - tolerance || primitive.sceneIndex < hit.sceneIndex) {
            hit = Hit(t, u, v, index, primitive.sceneIndex);
        }
        return false;
    }
    return crossSurface(index, u, v, transmittance);
}

// Walks the BVH for hits in (tMin, tMax), skipping primitives excludeA and excludeB. CLOSEST and ANY fill
// `hit` and return whether there was one; SHADOW multiplies `transmittance` and returns true once it is 0.
//
// One iteration of the outer loop visits one node: a leaf's primitives are tested by an inner loop, one per
// iteration, and the next node comes from an inner loop that pops until an entry still in front of the
// closest hit. The walk carries a node's link (its first child or primitive, and its primitive count), read
// with its box when its parent was visited, so a pop loads nothing. On lavapipe every branch of a loop body
// runs (masked) whether or not a lane takes it, so separate loops for the separate kinds of work cost less
// than one body doing all of them (issue 13: 1.75x on 2CylinderEngine's camera rays).
//
// llvmpipe (lavapipe) ends all loops of an invocation after 65535 iterations in total (each pass of any
// loop counts, an inner loop at least once per outer iteration). A walk that runs out is reported, not
// silently cut short: `complete` turns false and the caller counts the sample as non-finite.
bool traverseBvh(ShearedRay r, uint excludeA, uint excludeB, float tMin, float tMax, const int mode, out Hit hit,
                 inout vec3 transmittance, out bool complete) {
    hit = Hit(tMax, 0.0, 0.0, VKRT_NO_PRIMITIVE, VKRT_NO_PRIMITIVE);
    complete = true;
    if (params.primitiveCount == 0u) return false;
    const BvhNode root = VKRT_NODE(0u);
    float entry;
    if (!intersectBox(root, r, tMin, hit.t, entry)) return false;
    // Pending far children: their links and the distances at which the ray enters them.
    uint stackFirst[VKRT_BVH_MAX_DEPTH];
    uint stackCount[VKRT_BVH_MAX_DEPTH];
    float stackEntry[VKRT_BVH_MAX_DEPTH];
    int size = 0;
    uint first = root.leftOrFirst, count = root.primCount;
    complete = false;
    for (;;) {
        // Descend through interior nodes, one per iteration: test both children, enter the nearer, stack the
        // farther. Ends at a leaf, or where the ray misses both children.
        if (count == 0u) do {
            const BvhNode left = VKRT_NODE(first);
            const BvhNode right = VKRT_NODE(first + 1u);
            float tLeft, tRight;
            const float limit = searchLimit(hit, tMax, mode);
            const bool hitLeft = intersectBox(left, r, tMin, limit, tLeft);
            const bool hitRight = intersectBox(right, r, tMin, limit, tRight);
            if (!hitLeft && !hitRight) break;
            const bool leftFirst = hitLeft && (!hitRight || tLeft <= tRight);
            if (hitLeft && hitRight) {
                stackFirst[size] = leftFirst ? right.leftOrFirst : left.leftOrFirst;
                stackCount[size] = leftFirst ? right.primCount : left.primCount;
                stackEntry[size] = leftFirst ? tRight : tLeft;
                ++size;
            }
            first = leftFirst ? left.leftOrFirst : right.leftOrFirst;
            count = leftFirst ? left.primCount : right.primCount;
        } while (count == 0u);
        // A leaf: test its primitives, one per iteration.
        if (count > 0u) {
            uint index = first;
            do {
                if (visitPrimitive(r, index, excludeA, excludeB, tMin, tMax, mode, hit, transmittance)) {
                    complete = true;
                    return true;
                }
            } while (++index < first + count);
        }
        // Pop until an entry the ray enters in front of the closest hit (the others are dropped).
        for (;;) {
            if (size == 0) {
                complete = true;
                return mode == VKRT_TRACE_CLOSEST && hit.primitive != VKRT_NO_PRIMITIVE;
            }
            --size;
            if (mode != VKRT_TRACE_CLOSEST || stackEntry[size] <= searchLimit(hit, tMax, mode)) break;
        }
        first = stackFirst[size];
        count = stackCount[size];
    }
    return false;
}

bool traceClosest(ShearedRay r, uint exclude, float tMin, float tMax, out Hit hit, inout bool complete) {
    vec3 unused = vec3(1.0);
    bool walked;
    const bool found = traverseBvh(r, exclude, VKRT_NO_PRIMITIVE, tMin, tMax, VKRT_TRACE_CLOSEST, hit, unused, walked);
    complete = complete && walked;
    return found;
}

bool traceAny(ShearedRay r, float tMin, float tMax, out Hit hit, inout bool complete) {
    vec3 unused = vec3(1.0);
    bool walked;
    const bool found = traverseBvh(r, VKRT_NO_PRIMITIVE, VKRT_NO_PRIMITIVE, tMin, tMax, VKRT_TRACE_ANY, hit, unused, walked);
    complete = complete && walked;
    return found;
}

// Fraction of light passing from the ray's origin to tMax: 0 behind an opaque surface, the product of the
// transmission tints of transmissive ones (shadow rays do not refract).
vec3 shadowTransmittance(Ray ray, float tMax, uint excludeA, uint excludeB, inout bool complete) {
    vec3 transmittance = vec3(1.0);
    Hit unused;
    bool walked;
    traverseBvh(shearRay(ray), excludeA, excludeB, 0.0, tMax, VKRT_TRACE_SHADOW, unused, transmittance, walked);
    complete = complete && walked;
    return transmittance;
}

#endif
