#include "gpu/gpu_scene.h"

#include <algorithm>
#include <cmath>
#include <cstdio>
#include <cstring>
#include <limits>
#include <type_traits>

#include "camera.h"
#include "scene/ggx_albedo_tables.h"
#include "scene/light_table.h"
#include "scene/scene_error.h"
#include "scene/shading_inputs.h"
#include "scene/sheen_table.h"
#include "shape_geometry.h"

namespace vkrt {

namespace {

// A material as the shader specialised to `features` reads it: what the shader leaves out is switched off
// (textures, normal maps, holes, coats and sheen), so the texture slots it loops over are the ones it has.
void specialise(shading::SurfaceMaterial& s, const SceneFeatures& features) {
    if (!features.textures) {
        s.baseColorTexture = s.emissiveTexture = s.metallicRoughnessTexture = s.occlusionTexture = -1;
        s.specularTexture = s.specularColorTexture = s.transmissionTexture = -1;
        s.clearcoatTexture = s.clearcoatRoughnessTexture = s.sheenColorTexture = s.sheenRoughnessTexture = -1;
    }
    if (!features.textures || !features.normalMaps) s.normalTexture = s.clearcoatNormalTexture = -1;
    if (!features.alpha) s.alphaMode = VKRT_ALPHA_OPAQUE;  // no holes anywhere: every surface is opaque
    if (!features.clearcoat) s.clearcoat = 0.0;
    if (!features.sheen) s.sheenColor = glm::dvec3(0.0);
    s.textureSlots = shading::materialTextureSlots(s);
}

gpu::GpuMaterial gpuMaterial(const shading::SurfaceMaterial& s, float thickness) {
    gpu::GpuMaterial g{};
    g.baseColor = glm::vec3(s.baseColor);
    g.metallic = static_cast<float>(s.metallic);
    g.emission = glm::vec3(s.emission);
    g.roughness = static_cast<float>(s.roughness);
    g.attenuationColor = glm::vec3(s.attenuationColor);
    g.attenuationDistance = static_cast<float>(s.attenuationDistance);
    g.transmission = static_cast<float>(s.transmission);
    g.ior = static_cast<float>(s.ior);
    g.thickness = thickness;
    g.doubleSided = s.doubleSided ? 1u : 0u;
    g.baseColorTexture = s.baseColorTexture;
    g.emissiveTexture = s.emissiveTexture;
    g.metallicRoughnessTexture = s.metallicRoughnessTexture;
    g.occlusionTexture = s.occlusionTexture;
    g.occlusionStrength = static_cast<float>(s.occlusionStrength);
    g.specularTexture = s.specularTexture;
    g.specularColorTexture = s.specularColorTexture;
    g.specularColor = glm::vec3(s.specularColor);
    g.specularFactor = static_cast<float>(s.specularFactor);
    g.normalTexture = s.normalTexture;
    g.normalScale = static_cast<float>(s.normalScale);
    g.alphaMode = s.alphaMode;
    g.alpha = static_cast<float>(s.alpha);
    g.alphaCutoff = static_cast<float>(s.alphaCutoff);
    g.transmissionTexture = s.transmissionTexture;
    g.unlit = s.unlit ? 1u : 0u;
    g.clearcoat = static_cast<float>(s.clearcoat);
    g.clearcoatRoughness = static_cast<float>(s.clearcoatRoughness);
    g.clearcoatTexture = s.clearcoatTexture;
    g.clearcoatRoughnessTexture = s.clearcoatRoughnessTexture;
    g.clearcoatNormalTexture = s.clearcoatNormalTexture;
    g.clearcoatNormalScale = static_cast<float>(s.clearcoatNormalScale);
    g.sheenColor = glm::vec3(s.sheenColor);
    g.sheenRoughness = static_cast<float>(s.sheenRoughness);
    g.sheenColorTexture = s.sheenColorTexture;
    g.sheenRoughnessTexture = s.sheenRoughnessTexture;
    g.textureSlots = s.textureSlots;
    return g;
}

// Solid `primitive` as a GpuPrimitive: its index in the kind's upper bits.
gpu::GpuPrimitive solidPrimitive(const Scene& scene, uint32_t primitive) {
    const uint32_t solid = primitive - scene.firstSolid();
    const Shape& first = scene.shapes[scene.solidOf(primitive).firstShape];
    return {glm::vec3(0.0f), first.material,  glm::vec3(0.0f),
            primitive,       glm::vec3(0.0f), VKRT_PRIMITIVE_SOLID | (solid << VKRT_PRIMITIVE_INDEX_SHIFT)};
}

// An affine map's three rows, in float.
void affineRowsOf(const glm::dmat4& m, glm::vec4& row0, glm::vec4& row1, glm::vec4& row2) {
    const shading::AffineRows rows = shading::affineRows(m);
    row0 = glm::vec4(rows.row0);
    row1 = glm::vec4(rows.row1);
    row2 = glm::vec4(rows.row2);
}

// The solids, their shapes and the shapes' poses, as the shader reads them.
void packSolids(const Scene& scene, const LightTable& lights, GpuSceneData& data) {
    for (const Solid& solid : scene.solids) {
        data.solids.push_back(
            {solid.firstShape, solid.shapeCount, 0u, 0u, solid.tableLow(), solid.tableHigh()});
    }
    for (const Shape& shape : scene.shapes) {
        gpu::GpuShape g{};
        affineRowsOf(shape.toObject, g.toObject0, g.toObject1, g.toObject2);
        affineRowsOf(glm::dmat4(shape.toWorld), g.toWorld0, g.toWorld1, g.toWorld2);
        g.type = shape.type;
        g.material = shape.material;
        data.shapes.push_back(g);
    }
    for (size_t i = 0; i < lights.shapes.size(); ++i) {
        if (lights.shapes[i] != VKRT_NO_PRIMITIVE)
            data.shapes[lights.shapes[i]].lightPick = static_cast<float>(lights.pick[i]);
    }
    // A static scene given the motion path (SceneFeatures::all) gets one segment that stays put.
    for (uint32_t shape = 0; data.features.motion && shape < scene.shapes.size(); ++shape) {
        for (int pose = 1; pose <= std::max(1, scene.motionSegments); ++pose) {
            gpu::GpuShapePose g{};
            affineRowsOf(glm::dmat4(scene.shapePose(shape, scene.moving() ? pose : 0)), g.row0, g.row1,
                         g.row2);
            data.shapePoses.push_back(g);
        }
    }
}

}  // namespace

void checkGpuReach(const Scene& scene, const glm::dvec3* eye) {
    // The GPU's watertight triangle test multiplies three coordinates relative to the ray's origin in single
    // precision (its distance's numerator): beyond about 7e12 the products overflow and every test fails,
    // silently (a triangle 1e13 across, or seen from 1e13 away, vanished; one at 1e12 rendered as on the
    // CPU). The CPU reference, in double precision, renders such scenes.
    double reach = 0.0;
    if (!scene.bounds.empty()) {
        for (int axis = 0; axis < 3; ++axis) {
            reach = std::max({reach, std::abs(static_cast<double>(scene.bounds.min[axis])),
                              std::abs(static_cast<double>(scene.bounds.max[axis]))});
        }
    }
    const char* what = "the scene reaches";
    if (eye && glm::length(*eye) > reach) {
        reach = glm::length(*eye);
        what = "the camera is";
    }
    char extent[32];
    std::snprintf(extent, sizeof extent, "%.3g", reach);
    if (!(reach <= kGpuReach)) {
        throw SceneError(scene.sourcePath + ": " + what + " " + extent +
                         " units from the scene's middle; the GPU's single-precision tests hold to 1e12 "
                         "(--device cpu renders it)");
    }
    // Those products are about the cube of the scene's size, and below about 1e-13 they underflow: a quad
    // 1e-18 across, seen from as near, came out black where the CPU saw it (spheres hold down to 1e-20).
    if (!scene.triangles.empty() && reach < kGpuSmallestReach) {
        throw SceneError(scene.sourcePath + ": the scene and its camera lie within " + extent +
                         " units of its middle; the GPU's single-precision triangle test holds from 1e-12 "
                         "(--device cpu renders it)");
    }
    // A shape's intersection squares the ray's direction and origin in its object space, which its map's
    // inverse scales: beyond about 1.8e19 the squares overflow in float (a sphere 1e-20 across vanished, a
    // cone filled its bounding square). Origins lie within the scene's reach or at the camera, twice that
    // from the shape at most.
    for (size_t i = 0; i < scene.shapes.size(); ++i) {
        double largest = 0.0;
        for (int pose = 0; pose <= (scene.shapePoses.empty() ? 0 : scene.motionSegments); ++pose) {
            const glm::dmat3 inverse =
                glm::inverse(glm::dmat3(glm::dmat4(scene.shapePose(static_cast<uint32_t>(i), pose))));
            for (int c = 0; c < 3; ++c)
                largest = std::max(
                    {largest, std::abs(inverse[c].x), std::abs(inverse[c].y), std::abs(inverse[c].z)});
        }
        // A ray's origin is at most twice the reach from the shape: reach / (1 / largest) times its size.
        if (!(largest <= kGpuShapeInverseScale && 2.0 * reach * largest <= kGpuShapeInverseScale)) {
            char size[32], ratio[32];
            std::snprintf(size, sizeof size, "%.3g", 2.0 / largest);
            std::snprintf(ratio, sizeof ratio, "%.3g", reach * largest);
            throw SceneError(
                scene.sourcePath + ": shape " + std::to_string(i) + " is about " + size +
                " across, and rays reach it from " + ratio +
                " times its size; the GPU's single-precision shape tests hold for shapes down to "
                "1e-18 across, seen from up to 5e17 times their size (--device cpu renders it)");
        }
    }
}

GpuSceneData packScene(const Scene& scene, const FlatBvh& bvh, const SceneFeatures* features) {
    checkGpuReach(scene, nullptr);
    GpuSceneData data;
    data.features = features ? *features : detectFeatures(scene);
    // How a large primitive is tested (double or float) follows the scene's geometry in a shader with every
    // feature too: it is how the scene's own hits are found, not a path compiled in or left out.
    if (features) findLargePrimitives(scene, data.features);
    data.nodes = collapseToWide(bvh);

    // Primitives in leaf order, so leaves index them directly. A sphere shares the triangle layout
    // (shared.h).
    std::vector<uint32_t> gpuIndexOf(scene.primitiveCount());
    const bool needShading = data.features.smoothNormals || data.features.textures;
    // A scene without smooth normals is shaded with its faces' normals, also by a shader that reads vertex
    // normals (a superset of the scene's features): they are packed as its faces' own.
    const bool smoothNormals = features ? scene.smoothNormals() : data.features.smoothNormals;
    data.primitives.reserve(bvh.primIndices.size());
    for (uint32_t i = 0; i < bvh.primIndices.size(); ++i) {
        const uint32_t index = bvh.primIndices[i];
        gpuIndexOf[index] = i;
        // A static scene given the motion path (SceneFeatures::all) gets one segment that stays put.
        for (int pose = 1; data.features.motion && pose <= std::max(1, scene.motionSegments); ++pose) {
            const int at = scene.moving() ? pose : 0;
            if (scene.isSolid(index)) {
                data.motion.push_back(solidPrimitive(scene, index));
            } else if (scene.isSphere(index)) {
                const Sphere s = scene.spherePose(index, at);
                data.motion.push_back({s.center, s.material, glm::vec3(s.radius, 0.0f, 0.0f), index,
                                       glm::vec3(0.0f), VKRT_PRIMITIVE_SPHERE});
            } else {
                const Triangle t = scene.trianglePose(index, at);
                data.motion.push_back({t.v0, t.material, t.v1, index, t.v2, VKRT_PRIMITIVE_TRIANGLE});
            }
        }
        if (!scene.isTriangle(index)) {
            if (scene.isSolid(index)) {
                data.primitives.push_back(solidPrimitive(scene, index));
            } else {
                const Sphere& sphere = scene.sphereOf(index);
                data.primitives.push_back({sphere.center, sphere.material,
                                           glm::vec3(sphere.radius, 0.0f, 0.0f), index, glm::vec3(0.0f),
                                           VKRT_PRIMITIVE_SPHERE});
            }
            if (needShading) data.shading.push_back({});  // spheres and solids compute theirs
            if (data.features.vertexColors)
                data.vertexColors.push_back({glm::vec4(1.0f), glm::vec4(1.0f), glm::vec4(1.0f)});
            if (data.features.texCoords1) data.texCoords1.push_back({});
            if (data.features.normalMaps) data.tangents.push_back({});
            continue;
        }
        const Triangle& t = scene.triangles[index];
        data.primitives.push_back({t.v0, t.material, t.v1, index, t.v2, VKRT_PRIMITIVE_TRIANGLE});
        if (data.features.vertexColors) {
            const std::array<glm::vec4, 3>& c =
                scene.vertexColors.empty() ? kVertexColorWhite : scene.vertexColors[index];
            data.vertexColors.push_back({c[0], c[1], c[2]});
        }
        if (data.features.texCoords1) {
            const std::array<glm::vec2, 3> t =
                scene.uv1.empty() ? std::array<glm::vec2, 3>{} : scene.uv1[index];
            data.texCoords1.push_back({glm::vec4(t[0], t[1]), glm::vec4(t[2], 0.0f, 0.0f)});
        }
        if (data.features.normalMaps) {
            const std::array<glm::vec4, 3> t =
                scene.tangents.empty() ? std::array<glm::vec4, 3>{} : scene.tangents[index];
            data.tangents.push_back({t[0], t[1], t[2]});
        }
        if (needShading) {
            const TriangleShading& s = scene.shading[index];
            const glm::vec3 face(faceNormal(t));
            const auto normal = [&](int k) { return smoothNormals ? s.normal[k] : face; };
            data.shading.push_back({glm::vec4(normal(0), s.uv[0].x), glm::vec4(normal(1), s.uv[1].x),
                                    glm::vec4(normal(2), s.uv[2].x),
                                    glm::vec4(s.uv[0].y, s.uv[1].y, s.uv[2].y, 0.0f)});
        }
    }

    for (const Material& m : scene.materials) {
        shading::SurfaceMaterial s = surfaceMaterial(m, scene.textures, data.textureBindings);
        specialise(s, data.features);
        data.materials.push_back(gpuMaterial(s, m.thickness));
    }

    if (data.features.textures) {
        data.textures = describeTextures(scene);
        data.texels.count = packedTextureBytes(scene) / 4;
    } else {
        data.textureBindings.clear();  // no material reads one
    }

    const PunctualLightTable punctualTable = buildPunctualLightTable(scene);
    for (const PunctualLight& light : scene.lights) {
        const shading::PunctualLightParams p = punctualLightParams(light);
        gpu::GpuPunctualLight g{};
        g.position = glm::vec3(p.position);
        g.type = p.type;
        g.direction = glm::vec3(p.direction);
        g.range = static_cast<float>(p.range);
        g.intensity = glm::vec3(p.intensity);
        g.cosOuter = static_cast<float>(p.cosOuter);
        g.coneScale = static_cast<float>(p.coneScale);
        if (!punctualTable.empty()) {  // the cumulative steps of 2^-48 as two 24-bit halves
            const size_t i = data.lights.size();
            g.cdfHigh = static_cast<uint32_t>(punctualTable.steps[i] >> 24);
            g.cdfLow = static_cast<uint32_t>(punctualTable.steps[i] & 0xffffffu);
            g.pick = static_cast<float>(punctualTable.pick[i]);
        }
        data.lights.push_back(g);
    }

    const LightTable lights = buildLightTable(scene);
    for (size_t i = 0; i < lights.primitives.size(); ++i) {
        // The cumulative steps of 2^-48 as two 24-bit halves, each exact in a uint (and the last, 2^48, as
        // 2^24 and 0).
        const uint64_t steps = lights.steps[i];
        data.areaLights.push_back({gpuIndexOf[lights.primitives[i]], static_cast<uint32_t>(steps >> 24),
                                   static_cast<uint32_t>(steps & 0xffffffu),
                                   static_cast<float>(lights.pdfArea[i]), static_cast<float>(lights.pick[i]),
                                   lights.shapes[i], 0u, 0u});
    }
    if (data.features.shapes) packSolids(scene, lights, data);
    data.areaLightPower = lights.totalPower;
    data.solidAngleTriangles = lights.solidAngleTriangles;
    // The scene's own answer, also where `features` is a superset (its walk of the primitives done once).
    data.volumeHoles = features ? scene.volumesHaveHoles() : data.features.volumeHoles;
    if (data.features.environment && scene.environment.present()) {
        const EnvironmentDistribution distribution = EnvironmentDistribution::build(scene.environment);
        for (size_t i = 0; i < scene.environment.radiance.size(); ++i) {
            data.environmentTexels.push_back(
                {scene.environment.radiance[i], static_cast<float>(distribution.columnCdf[i])});
        }
        for (double cdf : distribution.rowCdf) data.environmentRows.push_back(static_cast<float>(cdf));
        data.environment = environmentMapInfo(scene.environment);
    }
    if (data.features.sheen) data.sheenTable = sheenAlbedoTable();
    if (data.features.roughSpecular) {
        data.ggxAlbedoTable = ggxAlbedoTable();
        // The shader reads the dielectric's table only for a rough volume.
        if (data.features.roughRefraction) data.ggxDielectricAlbedoTable = ggxDielectricAlbedoTable();
    }
    data.motionSegments = data.features.motion ? std::max(1, scene.motionSegments) : 0;
    data.environmentBackdrop = !scene.environment.neutral;
    if (!features) data.features.areaLights = !data.areaLights.empty();
    return data;
}

namespace {

// Every array of the packed scene with its name and the SceneParams address it fills, in upload order.
template <typename Visit>
void visitArrays(const GpuSceneData& d, Visit&& visit) {
    using P = gpu::SceneParams;
    visit("BVH nodes", d.nodes, &P::nodes);
    visit("primitives", d.primitives, &P::primitives);
    visit("shading normals and texture coordinates", d.shading, &P::shading);
    visit("materials", d.materials, &P::materials);
    visit("textures", d.textures, &P::textures);
    visit("texels", d.texels, &P::texels);
    visit("lights", d.lights, &P::lights);
    visit("area lights", d.areaLights, &P::areaLights);
    visit("motion poses", d.motion, &P::motion);
    visit("texture bindings", d.textureBindings, &P::textureBindings);
    visit("vertex colours", d.vertexColors, &P::vertexColors);
    visit("second texture coordinates", d.texCoords1, &P::texCoords1);
    visit("tangents", d.tangents, &P::tangents);
    visit("environment map", d.environmentTexels, &P::environmentTexels);
    visit("environment rows", d.environmentRows, &P::environmentRows);
    visit("sheen table", d.sheenTable, &P::sheenTable);
    visit("GGX albedo table", d.ggxAlbedoTable, &P::ggxAlbedoTable);
    visit("GGX dielectric albedo table", d.ggxDielectricAlbedoTable, &P::ggxDielectricAlbedoTable);
    visit("shapes", d.shapes, &P::shapes);
    visit("solids", d.solids, &P::solids);
    visit("shape poses", d.shapePoses, &P::shapePoses);
}

template <typename Values>
uint64_t bytesOf(const Values& values) {
    return static_cast<uint64_t>(values.size()) * sizeof(typename Values::value_type);
}

}  // namespace

MemoryNeed sceneBufferNeed(const GpuSceneData& data) {
    MemoryNeed need;
    visitArrays(data, [&](const char* name, const auto& values, auto) { need.add(name, bytesOf(values)); });
    return need;
}

GpuSceneBuffers::GpuSceneBuffers(const VulkanContext& context, const GpuSceneData& data, const Scene& scene) {
    buffers_.reserve(sceneBufferNeed(data).parts().size());
    visitArrays(data, [&](const char*, const auto& values, auto address) {
        if (values.empty()) return;
        if constexpr (std::is_same_v<std::decay_t<decltype(values)>, TexelCount>) {
            buffers_.emplace_back(context, bytesOf(values), [&](void* mapped) {
                writeTexels(scene, data.textures, static_cast<uint32_t*>(mapped));
            });
        } else {
            buffers_.emplace_back(context, values);
        }
        addresses_.*address = buffers_.back().address();
        bufferIndex_.emplace_back(address, buffers_.size() - 1);
    });
}

void GpuSceneBuffers::fillAddresses(gpu::SceneParams& params) const {
    // Only the scene's arrays: accumulation and counters belong to the renderer.
    const GpuSceneData none;
    visitArrays(none, [&](const char*, const auto&, auto address) { params.*address = addresses_.*address; });
}

const char* sceneAccessName(SceneAccess access) {
    switch (access) {
        case SceneAccess::Texels:
            return "texel buffers";
        case SceneAccess::Storage:
            return "storage buffers";
        case SceneAccess::Addresses:
            return "device addresses";
        case SceneAccess::Auto:
            break;
    }
    return "auto";
}

const GpuBuffer* GpuSceneBuffers::bufferOf(uint64_t gpu::SceneParams::*address) const {
    for (const auto& [array, index] : bufferIndex_)
        if (array == address) return &buffers_[index];
    return nullptr;
}

namespace {

// The arrays bound with SceneAccess::Texels, in binding order from VKRT_BINDING_NODES on (shaders/shared.h),
// and how each is read: texels of four words, or single words (a texture's RGBA8 texels, a float table).
using P = gpu::SceneParams;
struct TexelArray {
    uint64_t P::*address;
    BindingKind kind;
};
constexpr TexelArray kTexelArrays[] = {
    {&P::nodes, BindingKind::Texels},          {&P::primitives, BindingKind::Texels},
    {&P::materials, BindingKind::Texels},      {&P::lights, BindingKind::Texels},
    {&P::areaLights, BindingKind::Texels},     {&P::shading, BindingKind::Texels},
    {&P::textures, BindingKind::Texels},       {&P::textureBindings, BindingKind::Texels},
    {&P::texels, BindingKind::Words},          {&P::environmentTexels, BindingKind::Texels},
    {&P::environmentRows, BindingKind::Words}, {&P::shapes, BindingKind::Texels},
    {&P::solids, BindingKind::Texels},         {&P::tangents, BindingKind::Texels},
    {&P::vertexColors, BindingKind::Texels},   {&P::texCoords1, BindingKind::Texels},
    {&P::motion, BindingKind::Texels},         {&P::shapePoses, BindingKind::Texels},
    {&P::ggxAlbedoTable, BindingKind::Words},  {&P::ggxDielectricAlbedoTable, BindingKind::Words},
    {&P::sheenTable, BindingKind::Words}};
static_assert(std::size(kTexelArrays) == VKRT_TEXEL_BINDINGS);
static_assert(VKRT_BINDING_PRIMITIVES == VKRT_BINDING_NODES + 1 &&
              VKRT_BINDING_SHADING == VKRT_BINDING_NODES + 5 &&
              VKRT_BINDING_ENVIRONMENT_ROWS == VKRT_BINDING_NODES + 10 &&
              VKRT_BINDING_SOLIDS == VKRT_BINDING_NODES + 12 &&
              VKRT_BINDING_MOTION == VKRT_BINDING_NODES + 16 &&
              VKRT_BINDING_SHEEN_TABLE == VKRT_BINDING_NODES + 20);

// The float nearest `value` from above (infinity beyond float's range).
float roundedUp(double value) {
    const float rounded = static_cast<float>(value);
    return static_cast<double>(rounded) < value
               ? std::nextafter(rounded, std::numeric_limits<float>::infinity())
               : rounded;
}

}  // namespace

SceneAccess chooseSceneAccess(const VulkanContext& context, const GpuSceneData& data, SceneAccess wanted) {
    const auto bytesAt = [&](uint64_t P::*address) {
        uint64_t bytes = 0;
        visitArrays(data, [&](const char*, const auto& values, auto array) {
            if (array == address) bytes = bytesOf(values);
        });
        return bytes;
    };
    const uint64_t nodes = bytesAt(&P::nodes), primitives = bytesAt(&P::primitives);
    if (nodes == 0 || primitives == 0) return SceneAccess::Addresses;
    const VkPhysicalDeviceLimits& limits = context.properties().limits;
    if (wanted == SceneAccess::Auto) wanted = SceneAccess::Texels;
    if (wanted == SceneAccess::Texels) {
        bool fits = true;
        for (const TexelArray& array : kTexelArrays) {
            const uint64_t texelBytes = array.kind == BindingKind::Words ? 4 : 16;
            fits = fits && bytesAt(array.address) / texelBytes <= limits.maxTexelBufferElements;
        }
        if (fits) return wanted;
    }
    if (wanted != SceneAccess::Addresses && std::max(nodes, primitives) <= limits.maxStorageBufferRange)
        return SceneAccess::Storage;
    return SceneAccess::Addresses;
}

std::vector<std::string> GpuSceneBuffers::accessDefines(SceneAccess access) {
    if (access == SceneAccess::Texels) return {"VKRT_TEXEL_SCENE"};
    if (access == SceneAccess::Storage) return {"VKRT_BOUND_GEOMETRY"};
    return {};
}

std::vector<const GpuBuffer*> GpuSceneBuffers::bindings(const GpuBuffer& params, SceneAccess access) const {
    std::vector<const GpuBuffer*> buffers{&params};
    if (access == SceneAccess::Storage) {
        buffers.push_back(bufferOf(&P::nodes));
        buffers.push_back(bufferOf(&P::primitives));
    } else if (access == SceneAccess::Texels) {
        // An array the scene lacks is never read; any buffer fills its binding.
        for (const TexelArray& array : kTexelArrays) {
            const GpuBuffer* buffer = bufferOf(array.address);
            buffers.push_back(buffer ? buffer : &params);
        }
    }
    return buffers;
}

std::vector<BindingKind> GpuSceneBuffers::bindingKinds(SceneAccess access) {
    if (access == SceneAccess::Storage)
        return {BindingKind::Storage, BindingKind::Storage, BindingKind::Storage};
    std::vector<BindingKind> kinds{BindingKind::Storage};
    if (access == SceneAccess::Texels)
        for (const TexelArray& array : kTexelArrays) kinds.push_back(array.kind);
    return kinds;
}

gpu::SceneParams makeSceneParams(const GpuSceneData& data, const Camera& camera, const Aabb& sceneBounds,
                                 const RenderSettings& settings) {
    gpu::SceneParams p{};
    const shading::CameraFrame frame = cameraFrame(camera, sceneBounds, settings.width, settings.height);
    p.camera.position = glm::vec3(frame.position);
    p.camera.projection = frame.projection;
    p.camera.forward = glm::vec3(frame.forward);
    p.camera.tanHalfFov = static_cast<float>(frame.tanHalfFov);
    p.camera.right = glm::vec3(frame.right);
    p.camera.xmag = static_cast<float>(frame.xmag);
    p.camera.up = glm::vec3(frame.up);
    p.camera.ymag = static_cast<float>(frame.ymag);
    p.camera.lensRadius = static_cast<float>(frame.lensRadius);
    p.camera.focusDistance = static_cast<float>(frame.focusDistance);
    p.camera.sceneRadius = roundedUp(frame.sceneRadius);
    p.ambient = glm::vec3(settings.ambient);
    p.minThroughput = static_cast<float>(settings.minThroughput);
    p.background = glm::vec3(settings.background);
    p.lightSamples = static_cast<uint32_t>(settings.lightSamples);
    p.width = static_cast<uint32_t>(settings.width);
    p.height = static_cast<uint32_t>(settings.height);
    p.maxDepth = static_cast<uint32_t>(settings.maxDepth);
    p.seed = settings.seed;
    p.punctualLightCount = static_cast<uint32_t>(data.lights.size());
    p.areaLightCount = static_cast<uint32_t>(data.areaLights.size());
    p.primitiveCount = static_cast<uint32_t>(data.primitives.size());
    p.samplesPerPixel = static_cast<uint32_t>(settings.samplesPerPixel);
    p.areaLightPower = static_cast<float>(data.areaLightPower);
    p.multipleImportanceSampling = settings.multipleImportanceSampling ? 1u : 0u;
    p.energyCompensation = settings.energyCompensation ? 1u : 0u;
    p.solidAngleTriangles = data.solidAngleTriangles ? 1u : 0u;
    p.volumeHoles = data.volumeHoles ? 1u : 0u;
    p.motionSegments = static_cast<uint32_t>(data.motionSegments);
    p.environmentBackdrop = data.environmentBackdrop ? 1u : 0u;
    p.environmentWidth = data.environment.width;
    p.environmentHeight = data.environment.height;
    p.environmentCosRotation = static_cast<float>(data.environment.cosRotation);
    p.environmentSinRotation = static_cast<float>(data.environment.sinRotation);
    return p;
}

}  // namespace vkrt
