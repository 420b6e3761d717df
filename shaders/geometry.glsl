// Where the kernels read BVH nodes and triangles. When both arrays fit the device's storage-buffer range
// (VKRT_BOUND_GEOMETRY), they are bound as storage buffers, which lavapipe reads about a quarter faster
// than through 64-bit buffer device addresses; larger scenes read them through the addresses in
// SceneParams, which have no such limit. Requires `params` in scope.
#ifndef VKRT_GEOMETRY_GLSL
#define VKRT_GEOMETRY_GLSL

#ifdef VKRT_BOUND_GEOMETRY
layout(std430, binding = VKRT_BINDING_NODES) readonly buffer BoundNodes { BvhNode boundNodes[]; };
layout(std430, binding = VKRT_BINDING_TRIANGLES) readonly buffer BoundTriangles { GpuTriangle boundTriangles[]; };
#define VKRT_NODE(i) boundNodes[i]
#define VKRT_TRIANGLE(i) boundTriangles[i]
#else
#define VKRT_NODE(i) params.nodes.nodes[i]
#define VKRT_TRIANGLE(i) params.triangles.triangles[i]
#endif

// Motion blur (VKRT_HAS_MOTION): every ray of a sample sees the scene at one shutter time in [0, 1]. The
// shutter is cut into equal segments, and each primitive moves linearly between its poses at their ends
// (pose 0 is the primitive itself, poses 1..segments follow in params.motion), as Scene::triangleAt.
float vkrtShutterTime = 0.0;

GpuTriangle primitiveAt(uint i) {
    GpuTriangle p = VKRT_TRIANGLE(i);
#ifdef VKRT_HAS_MOTION
    const uint segments = uint(params.lighting.z);
    const float x = vkrtShutterTime * float(segments);
    const uint segment = min(uint(x), segments - 1u);
    const float s = x - float(segment);
    // Member by member: glslang miscompiles whole-struct copies that mix buffer and local structs here.
    vec3 a0 = p.v0, a1 = p.v1, a2 = p.v2;
    if (segment > 0u) {
        const uint start = i * segments + segment - 1u;
        a0 = params.motion.triangles[start].v0;
        a1 = params.motion.triangles[start].v1;
        a2 = params.motion.triangles[start].v2;
    }
    const uint end = i * segments + segment;
    p.v0 = a0 + s * (params.motion.triangles[end].v0 - a0);
    p.v1 = a1 + s * (params.motion.triangles[end].v1 - a1);
    p.v2 = a2 + s * (params.motion.triangles[end].v2 - a2);
#endif
    return p;
}

#endif
