// BVH traversal: near child first, far child on a fixed stack whose size the builder's depth bound
// guarantees (VKRT_BVH_MAX_DEPTH). One walk serves closest-hit, any-hit and shadow-transmittance queries;
// callers pass the mode as a constant, so each inlined copy keeps only its own branch.
// Requires `params` (SceneParams), scene_arrays.glsl, intersect.glsl and device_materials.glsl in scope.
#ifndef VKRT_TRAVERSE_GLSL
#define VKRT_TRAVERSE_GLSL

#define VKRT_TRACE_CLOSEST 0  // the nearest hit
#define VKRT_TRACE_ANY 1      // stop at the first hit
#define VKRT_TRACE_SHADOW 2   // multiply the transmission of every surface crossed; stop when opaque

#include "sphere_geometry.h"
#include "ties.h"
#include "solids.glsl"

// Walks that go on past a hit (the holes of alpha: trace.comp's traceVisible and, for paths' shadow rays through
// volumes' holes, device_shadowThroughHoles) take hits in the closest-hit rule's order (ties.h's WalkPast): they
// need the walk's nearest hit, where a new tie group starts, and, for a solid's crossing, where its own tie group
// ends (shape_geometry.h's csgCrossing): coincident faces of its shapes are crossed together, and a search from
// the crossing's own distance met the other shape's face just beyond it as a second crossing.
#if defined(VKRT_HAS_ALPHA) || defined(VKRT_HAS_VOLUME_HOLES)
#define VKRT_WALKS_PAST_HITS
#if defined(VKRT_HAS_SHAPES)
#define VKRT_HIT_GROUP_END
#endif
#endif

struct Hit {
    float t;
    float u, v;  // barycentric weights of v1 and v2; solids: the scene's shape and face * 2 + flip
    uint primitive;
    uint sceneIndex;  // the primitive's index in the scene, which breaks ties (kept to spare a reload)
#ifdef VKRT_HIT_GROUP_END
    float groupEnd;  // a solid's crossing: the end of its tie group; else t
#endif
#ifdef VKRT_WALKS_PAST_HITS
    float nearest;  // closest-hit walks: the nearest hit's distance (ranked: ties.h's rankedDistance)
#endif
};

Hit hitOf(float t, float u, float v, uint primitive, uint sceneIndex, float groupEnd) {
    Hit hit;
    hit.t = t;
    hit.u = u;
    hit.v = v;
    hit.primitive = primitive;
    hit.sceneIndex = sceneIndex;
#ifdef VKRT_HIT_GROUP_END
    hit.groupEnd = groupEnd;
#endif
#ifdef VKRT_WALKS_PAST_HITS
    hit.nearest = t;
#endif
    return hit;
}

// The walk past `hit` (ties.h's walkPast), along a ray from `origin`.
#ifdef VKRT_WALKS_PAST_HITS
WalkPast walkPastHit(WalkPast past, Hit hit, vec3 origin) {
#ifdef VKRT_HIT_GROUP_END
    const float groupEnd = hit.groupEnd;
#else
    const float groupEnd = hit.t;
#endif
    return walkPast(past, hit.t, hit.sceneIndex, groupEnd, hit.nearest, maxAbs(origin));
}
#endif

// Slab test. The far distance is widened by 1 + 2 gamma(3) so rounding never misses a box the ray
// touches (Ize, "Robust BVH Ray Traversal", JCGT 2(2), 2013).
bool intersectBox(vec3 boundsMin, vec3 boundsMax, ShearedRay r, float tMin, float tMax, out float tEntry) {
    const vec3 t0 = (boundsMin - r.lowerFaceOrigin) * r.inverseDirection;
    const vec3 t1 = (boundsMax - r.upperFaceOrigin) * r.inverseDirection;
    const vec3 near = min(t0, t1), far = max(t0, t1);
    tEntry = max(max(near.x, near.y), max(near.z, tMin));
    const float tExit = min(min(far.x, far.y), min(far.z, tMax)) * 1.0000003576;
    return tEntry <= tExit;
}

// A wide node's grid (shared.h): its origin and per-axis spacing 2^(exponent - 127).
struct WideGrid {
    vec3 origin;
    vec3 spacing;
};

WideGrid wideGrid(WideBvhNode node) {
    const uvec3 exponents = uvec3(node.exponents, node.exponents >> 8, node.exponents >> 16) & 0xffu;
    return WideGrid(vec3(node.originX, node.originY, node.originZ), uintBitsToFloat(exponents << 23));
}

// Tests child slot `slot` of a wide node: its box decoded from the grid (origin + q * spacing, the product
// exact, so the box is the one the host checked to contain the child's), then the slab test. Gives the
// entry distance as the sort key and the link, or +infinity and VKRT_WIDE_EMPTY on a miss.
void testChild(WideBvhNode node, WideGrid grid, uint slot, uint link, ShearedRay r, float tMin, float limit,
               out float key, out uint hitLink) {
    const uint shift = 8u * slot;
    const uvec3 lower = (uvec3(node.lowerX, node.lowerY, node.lowerZ) >> shift) & 0xffu;
    const uvec3 upper = (uvec3(node.upperX, node.upperY, node.upperZ) >> shift) & 0xffu;
    float entry;
    const bool hit = link != VKRT_WIDE_EMPTY &&
                     intersectBox(grid.origin + vec3(lower) * grid.spacing, grid.origin + vec3(upper) * grid.spacing,
                                  r, tMin, limit, entry);
    key = hit ? min(entry, 3.0e38) : uintBitsToFloat(0x7f800000u);
    hitLink = hit ? link : VKRT_WIDE_EMPTY;
}

// One comparator of the sorting network: the nearer of two children first.
void orderChildren(inout float keyA, inout uint linkA, inout float keyB, inout uint linkB) {
    const bool swap = keyB < keyA;
    const float key = keyA;
    const uint link = linkA;
    keyA = swap ? keyB : keyA;
    linkA = swap ? linkB : linkA;
    keyB = swap ? key : keyB;
    linkB = swap ? link : linkB;
}

// With VKRT_COUNT_ITERATIONS (ray_benchmark --count-iterations), every pass of every loop of the walk is
// counted, as llvmpipe counts them against its budget of 65535 per invocation. With VKRT_COUNT_LOOP_PASSES
// (the render kernel on lavapipe), the passes of the walk's, the kernel's and the light loop's
// (device_lights.glsl's device_loopPass), each lane its own. (The
// SIMD group's own count, one lane of those taking part counting each pass, made the Whitted scene's kernel
// 8% slower.)
#ifdef VKRT_COUNT_ITERATIONS
uint vkrtLoopIterations = 0u;
#define VKRT_COUNT_ITERATION() ++vkrtLoopIterations
#elif defined(VKRT_COUNT_LOOP_PASSES)
uint vkrtLoopPasses = 0u;
#define VKRT_COUNT_ITERATION() ++vkrtLoopPasses
#else
#define VKRT_COUNT_ITERATION()
#endif

// How far hits still matter: the nearest hit so far (tMax before the first; any-hit walks keep it there), plus
// a tie's width for closest-hit walks (a tie just beyond the nearest hit can still win), and, for walks past
// hits, the rest of the current tie group.
float searchLimit(float nearest, float tMax, float originScale, const int mode, WalkPast past) {
    if (mode != VKRT_TRACE_CLOSEST || nearest >= tMax) return nearest;
#ifdef VKRT_WALKS_PAST_HITS
    return min(tMax, max(nearest + tieWidth(nearest, originScale), past.end));
#else
    return min(tMax, nearest + tieWidth(nearest, originScale));
#endif
}

// The path integrator's shadow rays stop at a volume's boundary (surface_response.h's shadowTint).
#ifdef VKRT_PATHS
const bool vkrtVolumesBlockShadows = true;
#else
const bool vkrtVolumesBlockShadows = false;
#endif

// Multiplies `transmittance` by the passage of a surface of material `materialIndex` crossed at barycentrics /
// texture coordinates (u, v) (surface_response.h's shadowPassage); true when it is now opaque. The path
// integrator's shadow rays pass only the holes of alpha-tested and blended surfaces, and, from punctual lights,
// thin-walled transmissive surfaces; without either every surface stops them, and the material is not read.
#if defined(VKRT_HAS_ALPHA) || (defined(VKRT_HAS_TRANSMISSION) && !defined(VKRT_PATHS)) || \
    (defined(VKRT_PATHS) && defined(VKRT_HAS_THIN_TRANSMISSION) && defined(VKRT_HAS_PUNCTUAL_LIGHTS))
#define VKRT_CROSSING_READS_MATERIALS
#endif
bool crossSurface(uint primitive, uint materialIndex, float u, float v, inout vec4 transmittance) {
#ifdef VKRT_CROSSING_READS_MATERIALS
    const SurfaceMaterial material = device_material(materialIndex);
    transmittance *= shadowPassageAt(material, primitive, vec2(u, v), vkrtVolumesBlockShadows && material.volume);
    if (maxComponent(transmittance.xyz) > 0.0) return false;
#endif
    transmittance = vec4(0.0);  // opaque
    return true;
}

#ifdef VKRT_HAS_SHAPES
// A solid's crossing in (tMin, limit), as a hit's t, u (the scene's shape) and v (face * 2 + flip).
bool visitSolid(ShearedRay r, GpuSolid solid, float tMin, float limit, out float t, out float u, out float v,
                out float groupEnd) {
    float tIn[VKRT_SOLID_SHAPES], tOut[VKRT_SOLID_SHAPES];
    uint faceIn[VKRT_SOLID_SHAPES], faceOut[VKRT_SOLID_SHAPES];
    solidIntervals(solid, r.origin, r.direction, tIn, tOut, faceIn, faceOut);
    CsgCrossing crossing;
    t = u = v = groupEnd = 0.0;
    if (!csgCrossing(tIn, tOut, faceIn, faceOut, shapeCountOf(solid), solid.tableLow, solid.tableHigh, tMin, limit,
                     maxAbs(r.origin), crossing)) {
        return false;
    }
    t = crossing.t;
    groupEnd = crossing.groupEnd;
    u = float(solid.firstShape + crossing.shape);
    v = float(crossing.face * 2u + (crossing.flip ? 1u : 0u));
    return true;
}
#endif

// A primitive that a shadow ray may cross in (tMin, tMax), found by the walk's leaf loop, and crossed by
// crossCandidate in the walk's outer loop: a triangle's crossing (t0, u, v) or a sphere's one or two (t0, t1);
// a solid's crossings are found where it is crossed.
struct ShadowCandidate {
    uint index;
    float t0, t1, u, v;
    uint crossings;
};

// Whether a shadow ray may cross primitive `index` in (tMin, tMax), skipping excludeA and excludeB (solids are
// never skipped: shade_hit.h's ShadingFrame). Triangles and spheres are intersected here, solids where they
// are crossed.
bool findsCandidate(ShearedRay r, uint index, uint excludeA, uint excludeB, float tMin, float tMax,
                    out ShadowCandidate candidate) {
    candidate.index = index;
    candidate.t0 = candidate.t1 = candidate.u = candidate.v = 0.0;
    candidate.crossings = 0u;
    const GpuPrimitive primitive = primitiveAt(index);
#ifdef VKRT_HAS_SHAPES
    if (isSolid(primitive)) return true;
#endif
    if (index == excludeA || index == excludeB) return false;
#ifdef VKRT_HAS_SPHERES
    if (primitive.kind == VKRT_PRIMITIVE_SPHERE) {
        float near, far;
        if (sphereRoots(primitive.v0, primitive.v1.x, r.origin, r.direction, near, far)) {
            const bool nearIn = near > tMin && near < tMax, farIn = far > tMin && far < tMax;
            candidate.t0 = nearIn ? near : far;
            candidate.t1 = far;
            candidate.crossings = (nearIn ? 1u : 0u) + (farIn ? 1u : 0u);
        }
        return candidate.crossings > 0u;
    }
#endif
    if (!intersectTriangle(r, primitive, tMin, tMax, candidate.t0, candidate.u, candidate.v)) return false;
    candidate.crossings = 1u;
    return true;
}

// Where crossing a surface is costly (a solid's intervals, the textures of a surface whose material crossSurface
// reads), a shadow walk crosses its candidates in its outer loop, once a leaf's candidate is found, not in the
// leaf loop: on lavapipe a loop's body runs whole, masked, at every pass any lane needs, and crossing at every
// primitive a leaf holds took half of surfaces.gltf's render time (issue 13). Elsewhere the leaf loop crosses
// them: the outer loop's pass that each candidate then costs made the Whitted scene's Whitted render, whose
// shadow rays cross glass, 5% slower.
#if defined(VKRT_HAS_SHAPES) || (defined(VKRT_HAS_TEXTURES) && defined(VKRT_CROSSING_READS_MATERIALS))
#define VKRT_DEFERS_CROSSINGS
#endif

// A shadow ray's crossings of a candidate in (tMin, tMax), nearest first (a triangle is crossed once, a sphere
// up to twice, a solid at each crossing csgCrossing finds): each filters `transmittance`; true once it is
// opaque. One call of crossSurface serves every kind, in a loop of one pass a crossing.
bool crossCandidate(ShearedRay r, ShadowCandidate candidate, float tMin, float tMax, inout vec4 transmittance) {
    const GpuPrimitive primitive = primitiveAt(candidate.index);
    uint crossings = candidate.crossings;
#ifdef VKRT_HAS_SHAPES
    const bool solid = isSolid(primitive);
    GpuSolid operands;
    float tIn[VKRT_SOLID_SHAPES], tOut[VKRT_SOLID_SHAPES];
    uint faceIn[VKRT_SOLID_SHAPES], faceOut[VKRT_SOLID_SHAPES];
    float after = tMin;  // a solid's crossings are found one by one, each beyond the last one's tie group
    if (solid) {
        operands = solidOf(primitive);
        solidIntervals(operands, r.origin, r.direction, tIn, tOut, faceIn, faceOut);
        crossings = 2u * VKRT_SOLID_SHAPES;  // at most; the loop ends at the last
    }
#endif
    uint k = 0u;
    do {
        VKRT_COUNT_ITERATION();
        vec2 uv = vec2(candidate.u, candidate.v);
        uint material = primitive.material;
#ifdef VKRT_HAS_SHAPES
        if (solid) {
            CsgCrossing crossing;
            if (!csgCrossing(tIn, tOut, faceIn, faceOut, shapeCountOf(operands), operands.tableLow, operands.tableHigh,
                             after, tMax, maxAbs(r.origin), crossing)) {
                return false;
            }
            const uint shape = operands.firstShape + crossing.shape;
            AffineRows toObject, toWorld;
            shapeMaps(shape, toObject, toWorld);
            uv = shapePoint(shapeTypeAt(shape), crossing.face, crossing.flip, toObject, r.origin, r.direction,
                            crossing.t).uv;
            material = gpuShapeAt(shape).material;
            after = crossing.groupEnd;
        }
#endif
#ifdef VKRT_HAS_SPHERES
        if (primitive.kind == VKRT_PRIMITIVE_SPHERE) {
            uv = sphereUv(normalize(r.origin + (k == 0u ? candidate.t0 : candidate.t1) * r.direction - primitive.v0));
        }
#endif
        if (crossSurface(candidate.index, material, uv.x, uv.y, transmittance)) return true;
    } while (++k < crossings);
    return false;
}

// Tests one primitive of a leaf for a closest-hit or any-hit walk (shadow walks: findsCandidate); returns true
// when the walk can stop (any hit). `solid`: the primitive is a solid, which is never excluded (shade_hit.h's
// ShadingFrame); the walk's leaf loop visits triangles and spheres, its outer loop solids, so that each
// inlined copy holds one kind's code.
bool visitPrimitive(ShearedRay r, uint index, uint excludeA, uint excludeB, WalkPast past, float tMax,
                   float originScale, const int mode, inout Hit hit, inout float nearest, inout bool lost,
                   const bool solid) {
    if (!solid && (index == excludeA || index == excludeB)) return false;
    const GpuPrimitive primitive = primitiveAt(index);
#ifdef VKRT_WALKS_PAST_HITS
    const float tMin = mode == VKRT_TRACE_CLOSEST ? searchFloor(past, primitive.sceneIndex) : past.floor;
#else
    const float tMin = past.floor;
#endif
    float t, u = 0.0, v = 0.0, groupEnd = 0.0;  // a solid's crossing sets its tie group's end, at least t
#ifdef VKRT_HAS_SHAPES
    if (solid) {
        if (!visitSolid(r, solidOf(primitive), tMin, searchLimit(nearest, tMax, originScale, mode, past), t, u, v,
                        groupEnd)) {
            return false;
        }
    } else
#endif
#ifdef VKRT_HAS_SPHERES
    if (primitive.kind == VKRT_PRIMITIVE_SPHERE) {
        if (!intersectSphere(primitive.v0, primitive.v1.x, r.origin, r.direction, tMin, searchLimit(nearest, tMax, originScale, mode, past), t)) {
            return false;
        }
    } else
#endif
    if (!intersectTriangle(r, primitive, tMin, searchLimit(nearest, tMax, originScale, mode, past), t, u, v)) {
        return false;
    }
    if (mode == VKRT_TRACE_ANY) {
        hit = hitOf(t, u, v, index, primitive.sceneIndex, t);
        return true;
    }
    if (mode == VKRT_TRACE_CLOSEST) {
        // ties.h's rule; a walk that lost a candidate runs again (`lost`).
#ifdef VKRT_WALKS_PAST_HITS
        const float ranked = rankedDistance(past, t), bestRanked = rankedDistance(past, hit.t);
#else
        const float ranked = t, bestRanked = hit.t;
#endif
        if (takesClosestHit(ranked, primitive.sceneIndex, hit.primitive != VKRT_NO_PRIMITIVE, bestRanked,
                            hit.sceneIndex, originScale, nearest, lost)) {
            hit = hitOf(t, u, v, index, primitive.sceneIndex, max(groupEnd, t));
        }
        return false;
    }
    return false;
}

// Walks the BVH for hits in (past.floor, tMax), skipping primitives excludeA and excludeB; closest-hit walks
// take only hits not yet passed (ties.h's WalkPast). CLOSEST and ANY fill `hit` and return whether there was
// one; SHADOW multiplies `transmittance` and returns true once it is 0.
//
// The tree is 4-wide (shared.h's WideBvhNode). One iteration of the outer loop visits one node: interior
// nodes by an inner loop, one per iteration (test the four children, enter the nearest, stack the others
// farthest first), a leaf's primitives by an inner loop, one per iteration, and the next node comes from an
// inner loop that pops until an entry still in front of the closest hit. Links (shared.h) say where a
// child's node or primitives are, so a pop loads nothing. On lavapipe every branch of a loop body runs
// (masked) whether or not a lane takes it, so separate loops for the separate kinds of work cost less than
// one body doing all of them (issue 13: 1.75x on 2CylinderEngine's camera rays); four children a node
// halve the interior iterations and the node bytes read of the binary tree's pairs. A shadow walk's leaf loop
// finds the primitives it may cross (findsCandidate) and crosses them there, or, where crossing is costly
// (VKRT_DEFERS_CROSSINGS), stops at the first, crosses it in the outer loop, and goes on with the leaf's rest
// in the next outer pass; the other walks' leaf loops likewise stop at a solid, which the outer loop visits
// (a solid's intervals in the leaf loop cost a sixth of surfaces.gltf's render).
//
// llvmpipe (lavapipe) ends all loops of an invocation after 65535 iterations in total (each pass of any
// loop counts, an inner loop at least once per outer iteration). A walk that runs out is reported, not
// silently cut short: `complete` turns false and the caller counts the sample as non-finite.
bool traverseBvh(ShearedRay r, uint excludeA, uint excludeB, WalkPast past, float tMax, const int mode, out Hit hit,
                 inout vec4 transmittance, out bool complete) {
    const float tMin = past.start;  // boxes: no hit not yet passed lies before the current group's start
    hit = hitOf(tMax, 0.0, 0.0, VKRT_NO_PRIMITIVE, VKRT_NO_PRIMITIVE, tMax);
    complete = true;
    if (params.primitiveCount == 0u) return false;
    // Closest-hit walks: the nearest hit's distance, which ties are judged against, and whether a candidate
    // within a tie's width of it was dropped (visitPrimitive); then the walk runs once more with the nearest
    // distance known, and every hit in its window is seen (rare: three surfaces within two ties' widths).
    float nearest = tMax;
    bool lost = false;
    // Pending children: their links and the distances at which the ray enters them. A wide level stacks
    // at most three, and the wide tree is no deeper than the binary one (VKRT_BVH_MAX_DEPTH). (One 64-bit
    // word an entry was 3-5% slower on lavapipe.)
    uint stackLink[3 * VKRT_BVH_MAX_DEPTH];
    float stackEntry[3 * VKRT_BVH_MAX_DEPTH];
#define VKRT_PUSH(link, entry) stackLink[size] = link, stackEntry[size] = entry
#define VKRT_POP(link, entry) link = stackLink[size], entry = stackEntry[size]
    int size = 0;
    uint link = 0u;  // the root, always an interior node
    const float originScale = maxAbs(r.origin);
    complete = false;
    for (;;) {
        VKRT_COUNT_ITERATION();
        // Descend through interior nodes, one per iteration. Ends at a leaf, or where the ray misses every
        // child.
        if ((link >> VKRT_WIDE_COUNT_SHIFT) == 0u) do {
            VKRT_COUNT_ITERATION();
            const WideBvhNode node = VKRT_NODE(link);
            const WideGrid grid = wideGrid(node);
            const float limit = searchLimit(nearest, tMax, originScale, mode, past);
            float key0, key1, key2, key3;
            uint link0, link1, link2, link3;
            testChild(node, grid, 0u, node.child0, r, tMin, limit, key0, link0);
            testChild(node, grid, 1u, node.child1, r, tMin, limit, key1, link1);
            testChild(node, grid, 2u, node.child2, r, tMin, limit, key2, link2);
            testChild(node, grid, 3u, node.child3, r, tMin, limit, key3, link3);
            // Nearest first (a sorting network of five comparators); misses, at +infinity, go last.
            orderChildren(key0, link0, key1, link1);
            orderChildren(key2, link2, key3, link3);
            orderChildren(key0, link0, key2, link2);
            orderChildren(key1, link1, key3, link3);
            orderChildren(key1, link1, key2, link2);
            if (link0 == VKRT_WIDE_EMPTY) break;
            // Stack the other children that were hit, farthest first (a miss's slot is overwritten).
            VKRT_PUSH(link3, key3);
            size += link3 != VKRT_WIDE_EMPTY ? 1 : 0;
            VKRT_PUSH(link2, key2);
            size += link2 != VKRT_WIDE_EMPTY ? 1 : 0;
            VKRT_PUSH(link1, key1);
            size += link1 != VKRT_WIDE_EMPTY ? 1 : 0;
            link = link0;
        } while ((link >> VKRT_WIDE_COUNT_SHIFT) == 0u);
        // A leaf: test its primitives, one per iteration.
        const uint count = link >> VKRT_WIDE_COUNT_SHIFT;
        const uint first = link & VKRT_WIDE_INDEX_MASK;
        uint index = first;
        bool found = false;  // a candidate for the outer loop, `candidate`; the leaf goes on from `index`
        ShadowCandidate candidate;
        if (count > 0u) {
            do {
                VKRT_COUNT_ITERATION();
                if (mode == VKRT_TRACE_SHADOW) {
                    found = findsCandidate(r, index, excludeA, excludeB, past.floor, tMax, candidate);
#ifdef VKRT_DEFERS_CROSSINGS
                    if (found) {
                        ++index;
                        break;
                    }
#else
                    if (found && crossCandidate(r, candidate, past.floor, tMax, transmittance)) {
                        complete = true;
                        return true;
                    }
#endif
                } else {
#ifdef VKRT_HAS_SHAPES
                    if (isSolid(primitiveAt(index))) {  // visited in the outer loop
                        found = true;
                        candidate.index = index++;
                        break;
                    }
#endif
                    if (visitPrimitive(r, index, excludeA, excludeB, past, tMax, originScale, mode, hit, nearest,
                                       lost, false)) {
                        complete = true;
                        return true;
                    }
                }
            } while (++index < first + count);
        }
#ifdef VKRT_DEFERS_CROSSINGS
        if (found) {
#ifdef VKRT_HAS_SHAPES
            const bool stops = mode == VKRT_TRACE_SHADOW
                                   ? crossCandidate(r, candidate, past.floor, tMax, transmittance)
                                   : visitPrimitive(r, candidate.index, excludeA, excludeB, past, tMax, originScale,
                                                    mode, hit, nearest, lost, true);
#else
            const bool stops = crossCandidate(r, candidate, past.floor, tMax, transmittance);  // shadow walks only
#endif
            if (stops) {
                complete = true;
                return true;
            }
            if (index < first + count) {  // the rest of the leaf in the next pass
                link = ((first + count - index) << VKRT_WIDE_COUNT_SHIFT) | index;
                continue;
            }
        }
#endif
        // Pop until an entry the ray enters in front of the closest hit (the others are dropped).
        for (;;) {
            VKRT_COUNT_ITERATION();
            if (size == 0) {
                if (lost) {  // from the root again, the nearest distance kept
                    lost = false;
                    hit.primitive = VKRT_NO_PRIMITIVE;
                    link = 0u;
                    break;
                }
                complete = true;
#ifdef VKRT_WALKS_PAST_HITS
                hit.nearest = nearest;
#endif
                return mode == VKRT_TRACE_CLOSEST && hit.primitive != VKRT_NO_PRIMITIVE;
            }
            --size;
            float entry;
            VKRT_POP(link, entry);
            if (mode != VKRT_TRACE_CLOSEST || entry <= searchLimit(nearest, tMax, originScale, mode, past)) break;
        }
    }
#undef VKRT_PUSH
#undef VKRT_POP
    return false;
}

// The closest hit before tMax not yet passed by `past`, skipping primitives excludeA and excludeB.
bool traceClosestPast(ShearedRay r, uint excludeA, uint excludeB, WalkPast past, float tMax, out Hit hit,
                      inout bool complete) {
    vec4 unused = vec4(1.0);
    bool walked;
    const bool found = traverseBvh(r, excludeA, excludeB, past, tMax, VKRT_TRACE_CLOSEST, hit, unused, walked);
    complete = complete && walked;
    return found;
}

bool traceClosest(ShearedRay r, uint exclude, float tMin, float tMax, out Hit hit, inout bool complete) {
    return traceClosestPast(r, exclude, VKRT_NO_PRIMITIVE, walkPastFrom(tMin), tMax, hit, complete);
}

bool traceAny(ShearedRay r, float tMin, float tMax, out Hit hit, inout bool complete) {
    vec4 unused = vec4(1.0);
    bool walked;
    const bool found =
        traverseBvh(r, VKRT_NO_PRIMITIVE, VKRT_NO_PRIMITIVE, walkPastFrom(tMin), tMax, VKRT_TRACE_ANY, hit, unused, walked);
    complete = complete && walked;
    return found;
}

// Fraction of light passing from tMin to tMax along the ray: 0 behind an opaque surface, the product of the
// transmission tints of transmissive ones (shadow rays do not refract) in xyz, and of their holes in w
// (surface_response.h's shadowPassage).
vec4 shadowTransmittance(Ray ray, float tMin, float tMax, uint excludeA, uint excludeB, inout bool complete) {
    vec4 transmittance = vec4(1.0);
    Hit unused;
    bool walked;
    traverseBvh(shearRay(ray), excludeA, excludeB, walkPastFrom(tMin), tMax, VKRT_TRACE_SHADOW, unused, transmittance,
                walked);
    complete = complete && walked;
    return transmittance;
}

#endif
