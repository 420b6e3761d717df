// Where the kernels read BVH nodes and primitives. When both arrays fit the device's storage-buffer range
// (VKRT_BOUND_GEOMETRY), they are bound as storage buffers, which lavapipe reads about a quarter faster
// than through 64-bit buffer device addresses; larger scenes read them through the addresses in
// SceneParams, which have no such limit. Requires `params` in scope.
#ifndef VKRT_GEOMETRY_GLSL
#define VKRT_GEOMETRY_GLSL


#ifdef VKRT_BOUND_GEOMETRY
layout(std430, binding = VKRT_BINDING_NODES) readonly buffer BoundNodes { WideBvhNode boundNodes[]; };
layout(std430, binding = VKRT_BINDING_PRIMITIVES) readonly buffer BoundPrimitives { GpuPrimitive boundPrimitives[]; };
#define VKRT_PRIMITIVE(i) boundPrimitives[i]
#else
#define VKRT_PRIMITIVE(i) params.primitives.primitives[i]
#endif

#if defined(VKRT_BOUND_GEOMETRY) && defined(VKRT_WIDE_LOADS)
// The traversal's reads as 64-bit words (the same bytes, a second view of the same bindings). llvmpipe
// gathers a load one component at a time, lane by lane, so half the components is nearly half the cost:
// 1.1-1.4x on ray_benchmark (issue 13). Selected for CPU devices with shaderInt64 (gpu_raycaster.cpp).
#extension GL_EXT_shader_explicit_arithmetic_types_int64 : require
layout(std430, binding = VKRT_BINDING_NODES) readonly buffer BoundNodeWords { u64vec4 boundNodeWords[]; };
layout(std430, binding = VKRT_BINDING_PRIMITIVES) readonly buffer BoundPrimitiveWords { u64vec2 boundPrimitiveWords[]; };

// A 64-byte wide node as two loads of four words each (llvmpipe loads a vector in one pass over the lanes).
WideBvhNode vkrtNodeAt(uint i) {
    const u64vec4 w0 = boundNodeWords[2u * i], w1 = boundNodeWords[2u * i + 1u];
    const uvec2 a = unpackUint2x32(w0.x), b = unpackUint2x32(w0.y), c = unpackUint2x32(w0.z), d = unpackUint2x32(w0.w);
    const uvec2 e = unpackUint2x32(w1.x), f = unpackUint2x32(w1.y), g = unpackUint2x32(w1.z);
    return WideBvhNode(uintBitsToFloat(a.x), uintBitsToFloat(a.y), uintBitsToFloat(b.x), b.y, c.x, c.y, d.x, d.y,
                       e.x, e.y, f.x, f.y, g.x, g.y, 0u, 0u);
}

GpuPrimitive vkrtPrimitiveAt(uint i) {
    const u64vec2 w0 = boundPrimitiveWords[3u * i], w1 = boundPrimitiveWords[3u * i + 1u];
    const u64vec2 w2 = boundPrimitiveWords[3u * i + 2u];
    const uvec2 a = unpackUint2x32(w0.x), b = unpackUint2x32(w0.y), c = unpackUint2x32(w1.x);
    const uvec2 d = unpackUint2x32(w1.y), e = unpackUint2x32(w2.x), f = unpackUint2x32(w2.y);
    return GpuPrimitive(uintBitsToFloat(uvec3(a, b.x)), b.y, uintBitsToFloat(uvec3(c, d.x)), d.y,
                        uintBitsToFloat(uvec3(e, f.x)), f.y);
}
#define VKRT_NODE(i) vkrtNodeAt(i)
#elif defined(VKRT_BOUND_GEOMETRY)
#define VKRT_NODE(i) boundNodes[i]
#define vkrtPrimitiveAt(i) boundPrimitives[i]
#else
#define VKRT_NODE(i) params.nodes.nodes[i]
#define vkrtPrimitiveAt(i) params.primitives.primitives[i]
#endif

// Motion blur (VKRT_HAS_MOTION): every ray of a sample sees the scene at one shutter time in [0, 1]. The
// shutter is cut into equal segments, and each primitive moves linearly between its poses at their ends
// (pose 0 is the primitive itself, poses 1..segments follow in params.motion), as Scene::triangleAt.
float vkrtShutterTime = 0.0;

GpuPrimitive primitiveAt(uint i) {
    GpuPrimitive p = vkrtPrimitiveAt(i);
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
