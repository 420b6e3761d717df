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

#endif
