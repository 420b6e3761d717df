// BVH traversal: near child first, far child on a fixed stack whose size the builder's depth bound
// guarantees (VKRT_BVH_MAX_DEPTH). Requires `params` (SceneParams) in scope.
#ifndef VKRT_TRAVERSE_GLSL
#define VKRT_TRAVERSE_GLSL

struct Hit {
    float t;
    float u, v;  // barycentric weights of v1 and v2
    uint triangle;
};

// Slab test. The far distance is widened by 1 + 2 gamma(3) so rounding never misses a box the ray
// touches (Ize, "Robust BVH Ray Traversal", JCGT 2(2), 2013).
bool intersectBox(BvhNode node, ShearedRay r, float tMax, out float tEntry) {
    vec3 t0 = (node.boundsMin - r.origin) * r.inverseDirection;
    vec3 t1 = (node.boundsMax - r.origin) * r.inverseDirection;
    vec3 near = min(t0, t1), far = max(t0, t1);
    tEntry = max(max(near.x, near.y), max(near.z, 0.0));
    const float tExit = min(min(far.x, far.y), min(far.z, tMax)) * 1.0000003576;
    return tEntry <= tExit;
}

// The closest triangle along the ray before tMax, other than `exclude`.
bool traceClosest(ShearedRay r, uint exclude, float tMax, out Hit hit) {
    hit.t = tMax;
    hit.u = 0.0;
    hit.v = 0.0;
    hit.triangle = VKRT_NO_TRIANGLE;
    if (params.counts.z == 0u) return false;
    float entry;
    if (!intersectBox(params.nodes.nodes[0], r, hit.t, entry)) return false;
    uint stack[VKRT_BVH_MAX_DEPTH];
    int size = 0;
    uint current = 0u;
    while (true) {
        const BvhNode node = params.nodes.nodes[current];
        if (node.primCount > 0u) {
            for (uint i = 0u; i < node.primCount; ++i) {
                const uint triangle = node.leftOrFirst + i;
                float t, u, v;
                if (triangle != exclude &&
                    intersectTriangle(r, params.triangles.triangles[triangle], 0.0, hit.t, t, u, v)) {
                    hit = Hit(t, u, v, triangle);
                }
            }
        } else {
            // Enter the nearer child now; put the farther one on the stack.
            uint near = node.leftOrFirst, far = node.leftOrFirst + 1u;
            float tNear, tFar;
            const bool hitNear = intersectBox(params.nodes.nodes[near], r, hit.t, tNear);
            const bool hitFar = intersectBox(params.nodes.nodes[far], r, hit.t, tFar);
            if (hitNear && hitFar) {
                if (tFar < tNear) {
                    const uint swap = near;
                    near = far;
                    far = swap;
                }
                stack[size++] = far;
                current = near;
                continue;
            }
            if (hitNear || hitFar) {
                current = hitNear ? near : far;
                continue;
            }
        }
        // Pop until a node that is still in front of the closest hit so far.
        bool found = false;
        while (size > 0) {
            current = stack[--size];
            if (intersectBox(params.nodes.nodes[current], r, hit.t, entry)) {
                found = true;
                break;
            }
        }
        if (!found) break;
    }
    return hit.triangle != VKRT_NO_TRIANGLE;
}

#endif
