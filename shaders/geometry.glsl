// Where the kernels read BVH nodes and primitives. When both arrays fit the device's storage-buffer range
// (VKRT_BOUND_GEOMETRY), they are bound as storage buffers, which lavapipe reads about a quarter faster
// than through 64-bit buffer device addresses; larger scenes read them through the addresses in
// SceneParams, which have no such limit. Requires `params` in scope.
#ifndef VKRT_GEOMETRY_GLSL
#define VKRT_GEOMETRY_GLSL

#ifdef VKRT_BOUND_GEOMETRY
layout(std430, binding = VKRT_BINDING_NODES) readonly buffer BoundNodes { BvhNode boundNodes[]; };
layout(std430, binding = VKRT_BINDING_PRIMITIVES) readonly buffer BoundPrimitives { GpuPrimitive boundPrimitives[]; };
#define VKRT_NODE(i) boundNodes[i]
#define VKRT_PRIMITIVE(i) boundPrimitives[i]
#else
#define VKRT_NODE(i) params.nodes.nodes[i]
#define VKRT_PRIMITIVE(i) params.primitives.primitives[i]
#endif

// Motion blur (VKRT_HAS_MOTION): every ray of a sample sees the scene at one shutter time in [0, 1]. The
// shutter is cut into equal segments, and each primitive moves linearly between its poses at their ends
// (pose 0 is the primitive itself, poses 1..segments follow in params.motion), as Scene::triangleAt.
float vkrtShutterTime = 0.0;

GpuPrimitive primitiveAt(uint i) {
    GpuPrimitive p = VKRT_PRIMITIVE(i);
#ifdef VKRT_HAS_MOTION
    const uint segments = params.motionSegments;
    const float x = vkrtShutterTime * float(segments);
    const uint segment = min(uint(x), segments - 1u);
    const float s = x - float(segment);
    // Member by member: glslang miscompiles whole-struct copies that mix buffer and local structs here.
    vec3 a0 = p.v0, a1 = p.v1, a2 = p.v2;
    if (segment > 0u) {
        const uint start = i * segments + segment - 1u;
        a0 = params.motion.primitives[start].v0;
        a1 = params.motion.primitives[start].v1;
        a2 = params.motion.primitives[start].v2;
    }
    const uint end = i * segments + segment;
    p.v0 = a0 + s * (params.motion.primitives[end].v0 - a0);
    p.v1 = a1 + s * (params.motion.primitives[end].v1 - a1);
    p.v2 = a2 + s * (params.motion.primitives[end].v2 - a2);
#endif
    return p;
}

#endif
