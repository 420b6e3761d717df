// Every struct, binding index and size that the host and the shaders share. Included by C++ (which maps
// the GLSL types onto GLM) and by GLSL, so each layout has exactly one definition. All structs follow
// std430 and are built from 16-byte rows (a vec3 and a scalar, or four scalars), so C++ and GLSL agree
// without padding rules.
#ifndef VKRT_SHARED_H
#define VKRT_SHARED_H

#ifdef __cplusplus
#include <cstddef>
#include <cstdint>

#include <glm/glm.hpp>
namespace vkrt::gpu {
using vec2 = glm::vec2;
using vec3 = glm::vec3;
using vec4 = glm::vec4;
using uvec2 = glm::uvec2;
using uvec4 = glm::uvec4;
using ivec4 = glm::ivec4;
using uint = uint32_t;
// A buffer device address: a plain 64-bit integer on the host, a typed buffer reference in GLSL.
#define VKRT_ADDRESS(Type, name) uint64_t name
#else
#define VKRT_ADDRESS(Type, name) Type name
#endif

// The deepest BVH the builder emits (levels, root included). The GPU traversal stack holds one entry per
// level below the root, so this bounds its size; the builder switches to median splits near the limit to
// guarantee it, whatever the input.
#define VKRT_BVH_MAX_DEPTH 64

// Hits closer together than this times |origin| + t (the largest origin coordinate plus the distance: the
// magnitude of the numbers a hit's distance is computed from, which its rounding is relative to) are ties:
// coplanar faces, or surfaces closer than single precision resolves there. The primitive with the smaller
// scene index wins, on the GPU and the CPU alike, so coplanar faces do not z-fight by rounding, and rays that
// start near a surface judge ties as precisely as the surface's coordinates allow (a window relative to t
// alone shrank to nothing there, and the devices parted by rounding).
#define VKRT_TIE_EPSILON 9.5367431640625e-7

// New rays start this times the magnitude of their hit point's numbers (the larger of its error scale and its
// largest coordinate) off the surface they leave, on both renderers: 2^-18, about 32 times the float rounding
// of that magnitude, so a GPU ray cannot start behind the surface, and 4 times a tie's width, so a ray leaving
// the winner of a tie clears the coincident surface it won over (a CPU offset of 1e-9 started the ray below
// that surface, which then shadowed all of it). Relative, so tiny and huge scenes behave alike.
#define VKRT_RAY_OFFSET_EPSILON 3.814697265625e-6

// Shadow rays to a point on a light stop this fraction of the distance short of it, above float rounding, so
// that a surface the light lies on does not shadow it; on both renderers, so that a surface that near the
// light is passed by both alike.
#define VKRT_SHADOW_RAY_SHORTENING 1e-5

// The deepest ray tree (--max-depth); the GPU's stack of pending rays holds one more entry than this.
#define VKRT_MAX_RAY_DEPTH 24

// Compute workgroups are 8 x 8 pixels.
#define VKRT_WORKGROUP_WIDTH 8
#define VKRT_WORKGROUP_HEIGHT 8

// The descriptors: a storage buffer holding SceneParams. Everything else is reached through the buffer
// device addresses inside it, so no buffer is bound (or created) for a feature the scene lacks.
#define VKRT_BINDING_PARAMS 0
// With VKRT_BOUND_GEOMETRY or VKRT_TEXEL_SCENE (see scene_arrays.glsl), nodes and primitives are bound here
// as well, and with VKRT_TEXEL_SCENE the other arrays a hit reads (host/gpu/gpu_scene.cpp kTexelArrays).
#define VKRT_BINDING_NODES 1
#define VKRT_BINDING_PRIMITIVES 2
#define VKRT_BINDING_MATERIALS 3
#define VKRT_BINDING_LIGHTS 4
#define VKRT_BINDING_AREA_LIGHTS 5
#define VKRT_BINDING_SHADING 6
#define VKRT_BINDING_TEXTURES 7
#define VKRT_BINDING_TEXTURE_BINDINGS 8
#define VKRT_BINDING_TEXELS 9
#define VKRT_BINDING_ENVIRONMENT 10
#define VKRT_BINDING_ENVIRONMENT_ROWS 11
#define VKRT_BINDING_SHAPES 12
#define VKRT_BINDING_SOLIDS 13
#define VKRT_BINDING_TANGENTS 14
#define VKRT_BINDING_VERTEX_COLORS 15
#define VKRT_BINDING_TEXCOORDS1 16
#define VKRT_BINDING_MOTION 17
#define VKRT_BINDING_SHAPE_POSES 18
#define VKRT_BINDING_GGX_ALBEDO 19
#define VKRT_BINDING_GGX_DIELECTRIC_ALBEDO 20
#define VKRT_BINDING_SHEEN_TABLE 21
#define VKRT_TEXEL_BINDINGS 21  // bindings 1 to 21

// Ray counters, indices into the counter buffer.
#define VKRT_COUNTER_PRIMARY 0
#define VKRT_COUNTER_SHADOW 1
#define VKRT_COUNTER_SECONDARY 2
#define VKRT_COUNTER_NONFINITE 3
#define VKRT_COUNTER_LOOP_PASSES 4  // not a sum: the most loop passes a lane took a sample (lavapipe)
#define VKRT_COUNTER_COUNT 5
// llvmpipe (lavapipe) ends all loops of a SIMD group after this many passes in total, per dispatch.
#define VKRT_LLVMPIPE_LOOP_BUDGET 65535

// A flattened BVH node, 32 bytes (std430 packs a vec3 and a uint into 16 bytes).
// Interior node: primCount == 0, the children are nodes leftOrFirst and leftOrFirst + 1.
// Leaf: primCount > 0 primitives starting at leftOrFirst (primitives are stored in leaf order).
struct BvhNode {
    vec3 boundsMin;
    uint leftOrFirst;
    vec3 boundsMax;
    uint primCount;
};

// A 4-wide BVH node, 64 bytes, the layout the GPU walks (flat_bvh.h collapses the binary tree into it).
// Child boxes are quantized to 8 bits per bound on a per-axis grid of spacing 2^(exponent - 127) counted
// from `origin` (Ylitie, Karras and Laine, "Efficient Incoherent Ray Traversal on GPUs Through Compressed
// Wide BVHs", HPG 2017): child k spans origin + lower_k * spacing to origin + upper_k * spacing, where
// lower_k and upper_k are byte k of the lower* and upper* words. The host rounds outwards and checks that
// the decoded box, as the GPU computes it in float (the product is exact, a power of two times a byte),
// contains the child's own, so the slab test stays conservative. Links: VKRT_WIDE_EMPTY for an unused
// slot, a node index for an interior child, (count << VKRT_WIDE_COUNT_SHIFT) | first for a leaf of `count`
// primitives from `first`. Scalars only, padded to 64 bytes: four texels of a texel buffer on CPU devices
// (scene_arrays.glsl).
#define VKRT_WIDE_EMPTY 0xffffffffu
#define VKRT_WIDE_COUNT_SHIFT 28
#define VKRT_WIDE_INDEX_MASK 0x0fffffffu
struct WideBvhNode {
    float originX;
    float originY;
    float originZ;
    uint exponents;  // bits 0-7, 8-15, 16-23: the x, y and z grid spacing's biased float exponents
    uint lowerX;
    uint lowerY;
    uint lowerZ;
    uint upperX;
    uint upperY;
    uint upperZ;
    uint child0;
    uint child1;
    uint child2;
    uint child3;
    uint unused0;
    uint unused1;
};

// A primitive, 48 bytes (each vec3 shares its 16 bytes with a uint): a triangle's corners and material,
// or (kind VKRT_PRIMITIVE_SPHERE, in shaders built with VKRT_HAS_SPHERES) a sphere with its centre in v0
// and its radius in v1.x. Indices stay integers: integer bits kept in float slots do not survive
// lavapipe's denormal flushing.
// Kind VKRT_PRIMITIVE_SOLID (with VKRT_HAS_SHAPES) is a solid (GpuSolid): its index sits in the kind's upper
// bits, kind = VKRT_PRIMITIVE_SOLID | (solid << 2), and v1.x holds its texture density (shape_geometry.h).
#define VKRT_PRIMITIVE_TRIANGLE 0u
#define VKRT_PRIMITIVE_SPHERE 1u
#define VKRT_PRIMITIVE_SOLID 2u
#define VKRT_PRIMITIVE_KIND_MASK 3u
#define VKRT_PRIMITIVE_INDEX_SHIFT 2u
struct GpuPrimitive {
    vec3 v0;
    uint material;
    vec3 v1;
    uint sceneIndex;  // the primitive's index in the scene, which breaks ties between coincident hits
    vec3 v2;
    uint kind;  // VKRT_PRIMITIVE_*
};

// A shape of a solid (VKRT_shape, shaders/shape_geometry.h), 112 bytes: its world-to-object and
// object-to-world maps as three rows each (at the shutter's opening), its VKRT_SHAPE_* type and material, and
// its probability of being picked as a light (0: it does not emit).
struct GpuShape {
    vec4 toObject0;
    vec4 toObject1;
    vec4 toObject2;
    vec4 toWorld0;
    vec4 toWorld1;
    vec4 toWorld2;
    uint type;
    uint material;
    float lightPick;
    uint unused0;
};

// A solid, 48 bytes: its shapes (firstShape onwards) and the truth table of its CSG expression over their
// inside bits (bit s of the 256: tableLow's words 0-3, then tableHigh's).
struct GpuSolid {
    uint firstShape;
    uint shapeCount;
    uint unused0;
    uint unused1;
    uvec4 tableLow;
    uvec4 tableHigh;
};

// A shape's object-to-world map at one pose (motion blur), three rows.
struct GpuShapePose {
    vec4 row0;
    vec4 row1;
    vec4 row2;
};

// A triangle's COLOR_0 at its three corners (RGBA), 48 bytes.
struct GpuVertexColors {
    vec4 corner0;
    vec4 corner1;
    vec4 corner2;
};

// A triangle's second texture coordinate set (TEXCOORD_1) at its corners, 32 bytes (the last pair unused).
struct GpuTexCoords1 {
    vec4 corners01;  // corner 0 in xy, corner 1 in zw
    vec4 corner2;    // corner 2 in xy
};

// A normal-mapped triangle's tangent frames at its corners, 48 bytes: the unit tangent in xyz, the bitangent's
// sign in w (bitangent = w * cross(normal, tangent)); zero where there is none.
struct GpuTangents {
    vec4 corner0;
    vec4 corner1;
    vec4 corner2;
};

// Per-vertex normals and texture coordinates, 64 bytes: normal.xyz with u in .w, and the three v's.
struct GpuShading {
    vec4 normalU0;
    vec4 normalU1;
    vec4 normalU2;
    vec4 v012;
};

// A material, 192 bytes. See docs/materials.md for what each value means.
struct GpuMaterial {
    vec3 baseColor;
    float metallic;
    vec3 emission;  // emissiveFactor * strength
    float roughness;
    vec3 attenuationColor;
    float attenuationDistance;  // infinity: no absorption
    float transmission;
    float ior;
    float thickness;  // 0: thin-walled
    uint doubleSided;
    int baseColorTexture;          // texture binding (GpuTextureBinding), -1: none
    int emissiveTexture;           // likewise
    int metallicRoughnessTexture;  // likewise
    int occlusionTexture;          // likewise
    float occlusionStrength;       // occlusion = 1 + strength (red - 1)
    int specularTexture;           // likewise (KHR_materials_specular)
    int specularColorTexture;      // likewise
    uint alphaMode;                // VKRT_ALPHA_* (surface_response.h)
    vec3 specularColor;            // KHR_materials_specular
    float specularFactor;
    int normalTexture;   // texture binding, -1: none
    float normalScale;   // scales the tangent-space normal's x and y
    float alpha;         // the base colour factor's alpha
    float alphaCutoff;   // VKRT_ALPHA_MASK: alpha below it is a hole
    int transmissionTexture;  // texture binding, -1: none
    uint unlit;               // 1: KHR_materials_unlit
    float clearcoat;          // KHR_materials_clearcoat
    float clearcoatRoughness;
    int clearcoatTexture;            // texture bindings, -1: none
    int clearcoatRoughnessTexture;
    int clearcoatNormalTexture;
    float clearcoatNormalScale;
    vec3 sheenColor;  // KHR_materials_sheen
    float sheenRoughness;
    int sheenColorTexture;      // texture bindings, -1: none
    int sheenRoughnessTexture;
    uint textureSlots;  // bit k: texture slot k (surface_response.h's VKRT_SLOT_*) has a binding
    uint unused1;
};

// A material's use of a texture, 32 bytes: KHR_texture_transform as the two rows of a 2x3 matrix
// (uv' = (dot(row0.xy, uv) + row0.z, dot(row1.xy, uv) + row1.z)), the texture (GpuTexture), and flags
// (VKRT_BINDING_SRGB in texture_sampling.h: colours are sRGB-encoded, data such as metallic-roughness linear).
struct GpuTextureBinding {
    vec3 row0;
    int texture;
    vec3 row1;
    uint flags;
};

// A texture's place in the texel buffer (RGBA8, one uint per texel, rows top to bottom).
struct GpuTexture {
    uint firstTexel;
    uint width;
    uint height;
    uint flags;  // wrap modes and filtering (VKRT_WRAP_*, VKRT_TEXTURE_NEAREST in texture_sampling.h)
};

// A KHR_lights_punctual light, 64 bytes.
struct GpuPunctualLight {
    vec3 position;
    uint type;  // VKRT_LIGHT_* (punctual_light.h)
    vec3 direction;  // the direction the light shines
    float range;     // 0: unlimited
    vec3 intensity;  // colour * intensity
    float cosOuter;  // cos(outer cone angle)
    float coneScale;  // 1 / max(0.001, cos(inner) - cos(outer))
    // Beyond VKRT_EVERY_PUNCTUAL_LIGHT_UP_TO lights (punctual_light.h), the cumulative steps of 2^-48 up to and
    // including this light in two 24-bit halves (host/scene/light_table.h) and its pick probability; else 0.
    uint cdfHigh;
    uint cdfLow;
    float pick;
};

// One emissive primitive: its index, the cumulative steps of 2^-48 up to and including it in two 24-bit halves
// (host/scene/light_table.h; the last entry's are 2^24 and 0), its area pdf (pick probability / area; triangles
// are sampled by area), its pick probability (spheres are sampled by solid angle) and, for a solid's shape, the
// shape (shapes are sampled part by part; else VKRT_NO_HIT). The search reads the first 16 bytes alone.
struct GpuAreaLight {
    uint primitive;
    uint cdfHigh;
    uint cdfLow;
    float pdfArea;
    float pick;
    uint shape;
    uint unused0;
    uint unused1;
};

struct GpuCamera {
    vec3 position;
    uint projection;  // VKRT_PROJECTION_* (camera.h)
    vec3 forward;
    float tanHalfFov;  // perspective: tan(yfov / 2)
    vec3 right;
    float xmag;  // orthographic: half the view's width
    vec3 up;
    float ymag;           // orthographic: half the view's height
    float lensRadius;     // thin lens; 0: a pinhole
    float focusDistance;  // along forward
    float sceneRadius;    // thin lens: a radius about `position` that holds the whole scene (camera.h)
    uint unused1;
};

// A texel of the environment map (shaders/environment.h), 16 bytes: its radiance (strength included) and
// the cumulative probability of the texels of its row up to and including it (the row's conditional table).
struct GpuEnvironmentTexel {
    vec3 radiance;
    float columnCdf;
};

// A ray for the ray-casting kernel (shaders/raycast.comp), 32 bytes.
struct GpuRay {
    vec3 origin;
    float tMin;
    vec3 direction;
    float tMax;
};

// Its result, 16 bytes: distance (tMax on a miss), primitive (VKRT_NO_HIT on a miss) and barycentrics.
struct GpuHit {
    float t;
    uint primitive;
    float u;
    float v;
};

#define VKRT_NO_HIT 0xffffffffu
#define VKRT_RAYCAST_WORKGROUP 64

#ifndef __cplusplus
layout(buffer_reference, std430, buffer_reference_align = 16) readonly buffer NodeBuffer {
    WideBvhNode nodes[];
};
layout(buffer_reference, std430, buffer_reference_align = 16) readonly buffer PrimitiveBuffer {
    GpuPrimitive primitives[];
};
layout(buffer_reference, std430, buffer_reference_align = 16) readonly buffer ShadingBuffer {
    GpuShading shading[];
};
layout(buffer_reference, std430, buffer_reference_align = 16) readonly buffer MaterialBuffer {
    GpuMaterial materials[];
};
layout(buffer_reference, std430, buffer_reference_align = 16) readonly buffer TextureBuffer {
    GpuTexture textures[];
};
layout(buffer_reference, std430, buffer_reference_align = 16) readonly buffer TextureBindingBuffer {
    GpuTextureBinding bindings[];
};
layout(buffer_reference, std430, buffer_reference_align = 16) readonly buffer VertexColorBuffer {
    GpuVertexColors colors[];
};
layout(buffer_reference, std430, buffer_reference_align = 16) readonly buffer TexCoord1Buffer {
    GpuTexCoords1 texCoords[];
};
layout(buffer_reference, std430, buffer_reference_align = 16) readonly buffer TangentBuffer {
    GpuTangents tangents[];
};
layout(buffer_reference, std430, buffer_reference_align = 16) readonly buffer FloatBuffer {
    float values[];
};
layout(buffer_reference, std430, buffer_reference_align = 16) readonly buffer TexelBuffer {
    uint texels[];
};
layout(buffer_reference, std430, buffer_reference_align = 16) readonly buffer LightBuffer {
    GpuPunctualLight lights[];
};
layout(buffer_reference, std430, buffer_reference_align = 16) readonly buffer AreaLightBuffer {
    GpuAreaLight areaLights[];
};
layout(buffer_reference, std430, buffer_reference_align = 16) readonly buffer ShapeBuffer {
    GpuShape shapes[];
};
layout(buffer_reference, std430, buffer_reference_align = 16) readonly buffer SolidBuffer {
    GpuSolid solids[];
};
layout(buffer_reference, std430, buffer_reference_align = 16) readonly buffer ShapePoseBuffer {
    GpuShapePose poses[];
};
layout(buffer_reference, std430, buffer_reference_align = 16) readonly buffer EnvironmentTexelBuffer {
    GpuEnvironmentTexel texels[];
};
layout(buffer_reference, std430, buffer_reference_align = 16) readonly buffer EnvironmentRowBuffer {
    float rowCdf[];
};
layout(buffer_reference, std430, buffer_reference_align = 16) buffer AccumulationBuffer {
    vec4 pixels[];
};
layout(buffer_reference, std430, buffer_reference_align = 16) buffer CounterBuffer {
    uint counters[];
};
layout(buffer_reference, std430, buffer_reference_align = 16) readonly buffer RayBuffer {
    GpuRay rays[];
};
layout(buffer_reference, std430, buffer_reference_align = 16) writeonly buffer HitBuffer {
    GpuHit hits[];
};
#endif

// Everything a render needs that stays fixed for the whole render.
struct SceneParams {
    GpuCamera camera;
    vec3 ambient;         // Whitted's ambient radiance
    float minThroughput;  // branches of the ray tree weighted less than this are cut
    vec3 background;      // radiance of rays that leave the scene
    uint lightSamples;    // area-light samples per shading point
    uint width;
    uint height;
    uint maxDepth;
    uint seed;
    uint punctualLightCount;
    uint areaLightCount;
    uint primitiveCount;
    uint samplesPerPixel;   // of the whole render (for reference)
    float areaLightPower;   // the area lights' total power (luminance x area)
    uint multipleImportanceSampling;  // 1: on, 0: off
    uint motionSegments;  // motion blur: equal segments of the shutter (0: nothing moves)
    uint environmentBackdrop;  // 1: camera rays that leave the scene see the environment; 0: the background
    VKRT_ADDRESS(NodeBuffer, nodes);
    VKRT_ADDRESS(PrimitiveBuffer, primitives);
    VKRT_ADDRESS(ShadingBuffer, shading);
    VKRT_ADDRESS(MaterialBuffer, materials);
    VKRT_ADDRESS(TextureBuffer, textures);
    VKRT_ADDRESS(TexelBuffer, texels);
    VKRT_ADDRESS(LightBuffer, lights);
    VKRT_ADDRESS(AreaLightBuffer, areaLights);
    VKRT_ADDRESS(AccumulationBuffer, accumulation);
    VKRT_ADDRESS(CounterBuffer, counters);
    VKRT_ADDRESS(PrimitiveBuffer, motion);  // motion blur: poses 1..motionSegments of every primitive, leaf order
    VKRT_ADDRESS(TextureBindingBuffer, textureBindings);
    VKRT_ADDRESS(VertexColorBuffer, vertexColors);  // with VKRT_HAS_VERTEX_COLORS, leaf order
    VKRT_ADDRESS(TexCoord1Buffer, texCoords1);      // with VKRT_HAS_TEXCOORD1, leaf order
    VKRT_ADDRESS(TangentBuffer, tangents);          // with VKRT_HAS_NORMAL_MAPS, leaf order
    VKRT_ADDRESS(EnvironmentTexelBuffer, environmentTexels);  // with VKRT_HAS_ENVIRONMENT: width x height
    VKRT_ADDRESS(EnvironmentRowBuffer, environmentRows);      // the marginal table over rows (height)
    uint environmentWidth;  // 0: no environment (rays that leave the scene see `background`)
    uint environmentHeight;
    float environmentCosRotation;  // the map's rotation about +Y
    float environmentSinRotation;
    VKRT_ADDRESS(FloatBuffer, sheenTable);          // with VKRT_HAS_SHEEN: sheen.h's albedo table
    // With VKRT_HAS_ROUGH_SPECULAR: energy_compensation.h's tables, the dielectric's only where a rough lobe
    // refracts.
    VKRT_ADDRESS(FloatBuffer, ggxAlbedoTable);
    VKRT_ADDRESS(FloatBuffer, ggxDielectricAlbedoTable);
    uint energyCompensation;  // 1: the GGX lobes make up for single scattering's loss; 0: they do not
    uint solidAngleTriangles;  // 1: triangle lights that look large are sampled by solid angle (light_table.h)
    VKRT_ADDRESS(ShapeBuffer, shapes);  // with VKRT_HAS_SHAPES: the solids' shapes
    VKRT_ADDRESS(SolidBuffer, solids);
    VKRT_ADDRESS(ShapePoseBuffer, shapePoses);  // motion blur: poses 1..motionSegments of every shape
    uint volumeHoles;  // 1: a volume's surface has holes (Scene::volumesHaveHoles; shade_hit.h's lightSampleShadow)
};

// Per dispatch: which samples of which rows.
struct PassConstants {
    uint sampleStart;
    uint sampleCount;
    uint rowStart;
    uint rowCount;
    uint tileRowStart;  // the first image row the accumulation buffer holds (it holds one tile of rows)
};

// Push constants of the ray-casting kernel.
struct RaycastConstants {
    VKRT_ADDRESS(RayBuffer, rays);
    VKRT_ADDRESS(HitBuffer, hits);
    uint count;  // rays (the mode is the kernel's: raycast.comp)
};

#ifdef __cplusplus
static_assert(sizeof(GpuRay) == 32 && offsetof(GpuRay, direction) == 16);
static_assert(sizeof(GpuHit) == 16);
static_assert(sizeof(RaycastConstants) == 24);  // 20 bytes in GLSL, padded to the addresses' alignment
static_assert(sizeof(BvhNode) == 32, "BvhNode must stay 32 bytes");
static_assert(offsetof(BvhNode, leftOrFirst) == 12, "std430: uint packs after vec3");
static_assert(offsetof(BvhNode, boundsMax) == 16, "std430: vec3 aligns to 16 bytes");
static_assert(offsetof(BvhNode, primCount) == 28, "std430: uint packs after vec3");
static_assert(sizeof(WideBvhNode) == 64 && offsetof(WideBvhNode, exponents) == 12, "two 32-byte rows");
static_assert(offsetof(WideBvhNode, lowerX) == 16 && offsetof(WideBvhNode, child0) == 40);
static_assert(sizeof(GpuPrimitive) == 48);
static_assert(offsetof(GpuPrimitive, material) == 12 && offsetof(GpuPrimitive, v1) == 16);
static_assert(sizeof(GpuShading) == 64);
static_assert(sizeof(GpuMaterial) == 192 && offsetof(GpuMaterial, sheenColor) == 160 && offsetof(GpuMaterial, clearcoatTexture) == 144 && offsetof(GpuMaterial, transmissionTexture) == 128 && offsetof(GpuMaterial, occlusionStrength) == 80 &&
              offsetof(GpuMaterial, specularColor) == 96 && offsetof(GpuMaterial, specularFactor) == 108);
static_assert(offsetof(GpuMaterial, normalTexture) == 112 && offsetof(GpuMaterial, alphaCutoff) == 124);
static_assert(sizeof(GpuTangents) == 48);
static_assert(offsetof(GpuMaterial, transmission) == 48 && offsetof(GpuMaterial, baseColorTexture) == 64);
static_assert(sizeof(GpuTexture) == 16);
static_assert(sizeof(GpuTextureBinding) == 32 && offsetof(GpuTextureBinding, row1) == 16);
static_assert(sizeof(GpuPunctualLight) == 64 && offsetof(GpuPunctualLight, coneScale) == 48);
static_assert(sizeof(GpuAreaLight) == 32);
static_assert(sizeof(GpuShape) == 112 && offsetof(GpuShape, type) == 96);
static_assert(sizeof(GpuSolid) == 48 && offsetof(GpuSolid, tableLow) == 16 && sizeof(GpuShapePose) == 48);
static_assert(sizeof(GpuCamera) == 80 && offsetof(GpuCamera, lensRadius) == 64);
static_assert(offsetof(SceneParams, ambient) == 80 && offsetof(SceneParams, lightSamples) == 108);
static_assert(offsetof(SceneParams, width) == 112 && offsetof(SceneParams, punctualLightCount) == 128);
static_assert(offsetof(SceneParams, areaLightPower) == 144);
static_assert(offsetof(SceneParams, nodes) == 160, "addresses start on an 8-byte boundary");
static_assert(offsetof(SceneParams, counters) == 160 + 9 * 8);
static_assert(offsetof(SceneParams, motion) == 160 + 10 * 8);
static_assert(offsetof(SceneParams, textureBindings) == 160 + 11 * 8);
static_assert(offsetof(SceneParams, vertexColors) == 160 + 12 * 8);
static_assert(offsetof(SceneParams, tangents) == 160 + 14 * 8);
static_assert(offsetof(SceneParams, environmentTexels) == 160 + 15 * 8);
static_assert(offsetof(SceneParams, environmentWidth) == 160 + 17 * 8);
static_assert(offsetof(SceneParams, sheenTable) == 312);
static_assert(offsetof(SceneParams, ggxDielectricAlbedoTable) == 328);
static_assert(offsetof(SceneParams, energyCompensation) == 336);
static_assert(offsetof(SceneParams, shapes) == 344 && offsetof(SceneParams, shapePoses) == 360);
static_assert(offsetof(SceneParams, volumeHoles) == 368);
static_assert(sizeof(SceneParams) == 376);  // the last uint and 4 bytes of padding to the 8-byte alignment
static_assert(sizeof(GpuEnvironmentTexel) == 16 && offsetof(GpuEnvironmentTexel, columnCdf) == 12);
static_assert(sizeof(GpuVertexColors) == 48 && sizeof(GpuTexCoords1) == 32);
static_assert(sizeof(PassConstants) == 20);
}  // namespace vkrt::gpu
#endif

#endif  // VKRT_SHARED_H
