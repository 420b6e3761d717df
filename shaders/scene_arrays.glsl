// Where the kernels read the scene's arrays, three ways (host/gpu/gpu_scene.h SceneAccess):
// - VKRT_TEXEL_SCENE: the arrays a walk or a hit reads (nodes, primitives, materials, lights, vertex
//   normals, textures, the environment map, the solids and their shapes, the other per-primitive attributes,
//   the poses under motion blur, the energy compensation tables) bound as uniform texel buffers of 4 x 32-bit
//   words (a texture's RGBA8 texels, the environment's row table and the energy compensation tables as 32-bit
//   words). lavapipe reads a storage buffer one
//   component at a time, lane by lane, in a loop that tests each lane; it fetches a texel for all eight lanes
//   at once with vector loads. Selected for CPU devices (issue 13: docs/performance-log.md).
// - VKRT_BOUND_GEOMETRY: nodes and primitives bound as storage buffers, which lavapipe read about a quarter
//   faster than through 64-bit device addresses; selected for GPUs where they fit the storage-buffer range.
// - neither: through the device addresses in SceneParams, which have no size limit.
// Each array has one accessor (VKRT_NODE, VKRT_PRIMITIVE, gpuMaterialAt, ...), the same in every way.
// Requires `params` in scope.
#ifndef VKRT_SCENE_ARRAYS_GLSL
#define VKRT_SCENE_ARRAYS_GLSL

#if defined(VKRT_TEXEL_SCENE)
layout(binding = VKRT_BINDING_NODES) uniform usamplerBuffer nodeTexels;            // 4 texels a node
layout(binding = VKRT_BINDING_PRIMITIVES) uniform usamplerBuffer primitiveTexels;  // 3 texels a primitive

// The 56 bytes of a 64-byte wide node that the walk reads (shared.h WideBvhNode).
WideBvhNode texelNodeAt(uint i) {
    const int t = int(4u * i);
    const uvec4 a = texelFetch(nodeTexels, t), b = texelFetch(nodeTexels, t + 1);
    const uvec4 c = texelFetch(nodeTexels, t + 2);
    const uvec2 d = texelFetch(nodeTexels, t + 3).xy;
    return WideBvhNode(uintBitsToFloat(a.x), uintBitsToFloat(a.y), uintBitsToFloat(a.z), a.w, b.x, b.y, b.z, b.w,
                       c.x, c.y, c.z, c.w, d.x, d.y, 0u, 0u);
}

GpuPrimitive texelPrimitiveAt(uint i) {
    const int t = int(3u * i);
    const uvec4 a = texelFetch(primitiveTexels, t), b = texelFetch(primitiveTexels, t + 1);
    const uvec4 c = texelFetch(primitiveTexels, t + 2);
    return GpuPrimitive(uintBitsToFloat(a.xyz), a.w, uintBitsToFloat(b.xyz), b.w, uintBitsToFloat(c.xyz), c.w);
}
#define VKRT_NODE(i) texelNodeAt(i)
#define VKRT_PRIMITIVE(i) texelPrimitiveAt(i)

layout(binding = VKRT_BINDING_MATERIALS) uniform usamplerBuffer materialTexels;  // 12 texels a material

// Material `i` (shared.h GpuMaterial, whose members fall in 16-byte groups).
GpuMaterial gpuMaterialAt(uint i) {
    const int t = int(12u * i);
    // Twelve fetches written out: lavapipe does not unroll loops, and a loop would index an array.
    const uvec4 w[12] = uvec4[12](texelFetch(materialTexels, t), texelFetch(materialTexels, t + 1),
                                  texelFetch(materialTexels, t + 2), texelFetch(materialTexels, t + 3),
                                  texelFetch(materialTexels, t + 4), texelFetch(materialTexels, t + 5),
                                  texelFetch(materialTexels, t + 6), texelFetch(materialTexels, t + 7),
                                  texelFetch(materialTexels, t + 8), texelFetch(materialTexels, t + 9),
                                  texelFetch(materialTexels, t + 10), texelFetch(materialTexels, t + 11));
    return GpuMaterial(uintBitsToFloat(w[0].xyz), uintBitsToFloat(w[0].w), uintBitsToFloat(w[1].xyz),
                       uintBitsToFloat(w[1].w), uintBitsToFloat(w[2].xyz), uintBitsToFloat(w[2].w),
                       uintBitsToFloat(w[3].x), uintBitsToFloat(w[3].y), uintBitsToFloat(w[3].z), w[3].w,
                       ivec4(w[4]).x, ivec4(w[4]).y, ivec4(w[4]).z, ivec4(w[4]).w,
                       uintBitsToFloat(w[5].x), int(w[5].y), int(w[5].z), w[5].w,
                       uintBitsToFloat(w[6].xyz), uintBitsToFloat(w[6].w),
                       int(w[7].x), uintBitsToFloat(w[7].y), uintBitsToFloat(w[7].z), uintBitsToFloat(w[7].w),
                       int(w[8].x), w[8].y, uintBitsToFloat(w[8].z), uintBitsToFloat(w[8].w),
                       int(w[9].x), int(w[9].y), int(w[9].z), uintBitsToFloat(w[9].w),
                       uintBitsToFloat(w[10].xyz), uintBitsToFloat(w[10].w),
                       int(w[11].x), int(w[11].y), w[11].z, w[11].w);
}

layout(binding = VKRT_BINDING_LIGHTS) uniform usamplerBuffer lightTexels;          // 4 texels a light
layout(binding = VKRT_BINDING_AREA_LIGHTS) uniform usamplerBuffer areaLightTexels;  // 2 texels an area light
layout(binding = VKRT_BINDING_SHADING) uniform usamplerBuffer shadingTexels;       // 4 texels a primitive

GpuPunctualLight gpuLightAt(uint i) {
    const int t = int(4u * i);
    const uvec4 a = texelFetch(lightTexels, t), b = texelFetch(lightTexels, t + 1);
    const uvec4 c = texelFetch(lightTexels, t + 2), d = texelFetch(lightTexels, t + 3);
    return GpuPunctualLight(uintBitsToFloat(a.xyz), a.w, uintBitsToFloat(b.xyz), uintBitsToFloat(b.w),
                            uintBitsToFloat(c.xyz), uintBitsToFloat(c.w), uintBitsToFloat(d.x), d.y, d.z,
                            uintBitsToFloat(d.w));
}

// The cumulative steps of punctual light `i` (GpuPunctualLight's cdfHigh and cdfLow): the table's binary search
// reads only those.
uvec2 gpuLightSteps(uint i) { return texelFetch(lightTexels, int(4u * i + 3u)).yz; }

GpuAreaLight gpuAreaLightAt(uint i) {
    const uvec4 a = texelFetch(areaLightTexels, int(2u * i)), b = texelFetch(areaLightTexels, int(2u * i + 1u));
    return GpuAreaLight(a.x, a.y, a.z, uintBitsToFloat(a.w), uintBitsToFloat(b.x), b.y, b.z, b.w);
}

// The cumulative steps of area light `i` (GpuAreaLight's cdfHigh and cdfLow): the light table's binary search
// reads only those.
uvec2 gpuAreaLightSteps(uint i) { return texelFetch(areaLightTexels, int(2u * i)).yz; }

GpuShading gpuShadingAt(uint i) {
    const int t = int(4u * i);
    return GpuShading(uintBitsToFloat(texelFetch(shadingTexels, t)),
                      uintBitsToFloat(texelFetch(shadingTexels, t + 1)),
                      uintBitsToFloat(texelFetch(shadingTexels, t + 2)),
                      uintBitsToFloat(texelFetch(shadingTexels, t + 3)));
}

// Textures (1 texel each), texture bindings (2 texels each), the textures' own texels (one 32-bit RGBA8 word
// each), the environment map (1 texel a map texel) and its row table (1 word a row).
layout(binding = VKRT_BINDING_TEXTURES) uniform usamplerBuffer textureTexels;
layout(binding = VKRT_BINDING_TEXTURE_BINDINGS) uniform usamplerBuffer textureBindingTexels;
layout(binding = VKRT_BINDING_TEXELS) uniform usamplerBuffer imageWords;
layout(binding = VKRT_BINDING_ENVIRONMENT) uniform usamplerBuffer environmentTexels;
layout(binding = VKRT_BINDING_ENVIRONMENT_ROWS) uniform usamplerBuffer environmentRowWords;

GpuTexture gpuTextureAt(int i) {
    const uvec4 a = texelFetch(textureTexels, i);
    return GpuTexture(a.x, a.y, a.z, a.w);
}

GpuTextureBinding gpuTextureBindingAt(int i) {
    const uvec4 a = texelFetch(textureBindingTexels, 2 * i), b = texelFetch(textureBindingTexels, 2 * i + 1);
    return GpuTextureBinding(uintBitsToFloat(a.xyz), int(a.w), uintBitsToFloat(b.xyz), b.w);
}

uint gpuImageTexel(uint i) { return texelFetch(imageWords, int(i)).x; }

GpuEnvironmentTexel gpuEnvironmentTexelAt(uint i) {
    const uvec4 a = texelFetch(environmentTexels, int(i));
    return GpuEnvironmentTexel(uintBitsToFloat(a.xyz), uintBitsToFloat(a.w));
}

float gpuEnvironmentRowCdf(uint y) { return uintBitsToFloat(texelFetch(environmentRowWords, int(y)).x); }

// The solids' shapes (7 texels each) and the solids (3 texels each).
layout(binding = VKRT_BINDING_SHAPES) uniform usamplerBuffer shapeTexels;
layout(binding = VKRT_BINDING_SOLIDS) uniform usamplerBuffer solidTexels;

GpuShape gpuShapeAt(uint i) {
    const int t = int(7u * i);
    const uvec4 g = texelFetch(shapeTexels, t + 6);
    return GpuShape(uintBitsToFloat(texelFetch(shapeTexels, t)), uintBitsToFloat(texelFetch(shapeTexels, t + 1)),
                    uintBitsToFloat(texelFetch(shapeTexels, t + 2)), uintBitsToFloat(texelFetch(shapeTexels, t + 3)),
                    uintBitsToFloat(texelFetch(shapeTexels, t + 4)), uintBitsToFloat(texelFetch(shapeTexels, t + 5)),
                    g.x, g.y, uintBitsToFloat(g.z), g.w);
}

GpuSolid gpuSolidAt(uint i) {
    const int t = int(3u * i);
    const uvec4 a = texelFetch(solidTexels, t);
    return GpuSolid(a.x, a.y, a.z, a.w, texelFetch(solidTexels, t + 1), texelFetch(solidTexels, t + 2));
}

// Per-primitive vertex attributes (leaf order): tangents and vertex colours 3 texels each, the second texture
// coordinates 2; the primitives' and shapes' poses under motion blur (3 texels each); and the energy
// compensation tables (one word an entry).
layout(binding = VKRT_BINDING_TANGENTS) uniform usamplerBuffer tangentTexels;
layout(binding = VKRT_BINDING_VERTEX_COLORS) uniform usamplerBuffer vertexColorTexels;
layout(binding = VKRT_BINDING_TEXCOORDS1) uniform usamplerBuffer texCoord1Texels;
layout(binding = VKRT_BINDING_MOTION) uniform usamplerBuffer motionTexels;
layout(binding = VKRT_BINDING_SHAPE_POSES) uniform usamplerBuffer shapePoseTexels;
layout(binding = VKRT_BINDING_GGX_ALBEDO) uniform usamplerBuffer ggxAlbedoWords;
layout(binding = VKRT_BINDING_GGX_DIELECTRIC_ALBEDO) uniform usamplerBuffer ggxDielectricAlbedoWords;
layout(binding = VKRT_BINDING_SHEEN_TABLE) uniform usamplerBuffer sheenWords;

vec4 texel4(usamplerBuffer texels, uint i) { return uintBitsToFloat(texelFetch(texels, int(i))); }

GpuTangents gpuTangentsAt(uint i) {
    return GpuTangents(texel4(tangentTexels, 3u * i), texel4(tangentTexels, 3u * i + 1u),
                       texel4(tangentTexels, 3u * i + 2u));
}

GpuVertexColors gpuVertexColorsAt(uint i) {
    return GpuVertexColors(texel4(vertexColorTexels, 3u * i), texel4(vertexColorTexels, 3u * i + 1u),
                           texel4(vertexColorTexels, 3u * i + 2u));
}

GpuTexCoords1 gpuTexCoords1At(uint i) {
    return GpuTexCoords1(texel4(texCoord1Texels, 2u * i), texel4(texCoord1Texels, 2u * i + 1u));
}

// A primitive's corners at a pose (GpuPrimitive's v0, v1 and v2).
void gpuMotionCornersAt(uint i, out vec3 v0, out vec3 v1, out vec3 v2) {
    v0 = texel4(motionTexels, 3u * i).xyz;
    v1 = texel4(motionTexels, 3u * i + 1u).xyz;
    v2 = texel4(motionTexels, 3u * i + 2u).xyz;
}

GpuShapePose gpuShapePoseAt(uint i) {
    return GpuShapePose(texel4(shapePoseTexels, 3u * i), texel4(shapePoseTexels, 3u * i + 1u),
                        texel4(shapePoseTexels, 3u * i + 2u));
}

float gpuGgxAlbedo(uint entry) { return uintBitsToFloat(texelFetch(ggxAlbedoWords, int(entry)).x); }
float gpuGgxDielectricAlbedo(uint entry) {
    return uintBitsToFloat(texelFetch(ggxDielectricAlbedoWords, int(entry)).x);
}
float gpuSheenAlbedo(uint entry) { return uintBitsToFloat(texelFetch(sheenWords, int(entry)).x); }
#elif defined(VKRT_BOUND_GEOMETRY)
layout(std430, binding = VKRT_BINDING_NODES) readonly buffer BoundNodes { WideBvhNode boundNodes[]; };
layout(std430, binding = VKRT_BINDING_PRIMITIVES) readonly buffer BoundPrimitives { GpuPrimitive boundPrimitives[]; };
#define VKRT_NODE(i) boundNodes[i]
#define VKRT_PRIMITIVE(i) boundPrimitives[i]
#else
#define VKRT_NODE(i) params.nodes.nodes[i]
#define VKRT_PRIMITIVE(i) params.primitives.primitives[i]
#endif
#ifndef VKRT_TEXEL_SCENE
#define gpuMaterialAt(i) params.materials.materials[i]
#define gpuLightAt(i) params.lights.lights[i]
#define gpuLightSteps(i) uvec2(params.lights.lights[i].cdfHigh, params.lights.lights[i].cdfLow)
#define gpuAreaLightAt(i) params.areaLights.areaLights[i]
#define gpuAreaLightSteps(i) uvec2(params.areaLights.areaLights[i].cdfHigh, params.areaLights.areaLights[i].cdfLow)
#define gpuShadingAt(i) params.shading.shading[i]
#define gpuTextureAt(i) params.textures.textures[i]
#define gpuTextureBindingAt(i) params.textureBindings.bindings[i]
#define gpuImageTexel(i) params.texels.texels[i]
#define gpuEnvironmentTexelAt(i) params.environmentTexels.texels[i]
#define gpuEnvironmentRowCdf(y) params.environmentRows.rowCdf[y]
#define gpuShapeAt(i) params.shapes.shapes[i]
#define gpuSolidAt(i) params.solids.solids[i]
#define gpuTangentsAt(i) params.tangents.tangents[i]
#define gpuVertexColorsAt(i) params.vertexColors.colors[i]
#define gpuTexCoords1At(i) params.texCoords1.texCoords[i]
#define gpuShapePoseAt(i) params.shapePoses.poses[i]
#define gpuGgxAlbedo(entry) params.ggxAlbedoTable.values[entry]
#define gpuGgxDielectricAlbedo(entry) params.ggxDielectricAlbedoTable.values[entry]
#define gpuSheenAlbedo(entry) params.sheenTable.values[entry]
void gpuMotionCornersAt(uint i, out vec3 v0, out vec3 v1, out vec3 v2) {
    v0 = params.motion.primitives[i].v0;
    v1 = params.motion.primitives[i].v1;
    v2 = params.motion.primitives[i].v2;
}
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
    if (segment > 0u) gpuMotionCornersAt(i * segments + segment - 1u, a0, a1, a2);
    vec3 b0, b1, b2;
    gpuMotionCornersAt(i * segments + segment, b0, b1, b2);
    p.v0 = a0 + s * (b0 - a0);
    p.v1 = a1 + s * (b1 - a1);
    p.v2 = a2 + s * (b2 - a2);
#endif
    return p;
}

#endif
