#include "gpu/gpu_scene.h"

#include <algorithm>
#include <cmath>
#include <cstring>

#include "cpu/area_lights.h"

namespace vkrt {
namespace {

uint32_t wrapBits(WrapMode mode) {
    switch (mode) {
        case WrapMode::ClampToEdge:
            return 1;
        case WrapMode::MirroredRepeat:
            return 2;
        default:
            return 0;
    }
}

}  // namespace

GpuSceneData packScene(const Scene& scene, const FlatBvh& bvh, const SceneFeatures* features) {
    GpuSceneData data;
    data.features = features ? *features : detectFeatures(scene);
    data.nodes = bvh.nodes;

    // Primitives in leaf order, so leaves index them directly. A sphere shares the triangle layout
    // (shared.h).
    std::vector<uint32_t> gpuIndexOf(scene.primitiveCount());
    const bool needShading = data.features.smoothNormals || data.features.textures;
    data.triangles.reserve(bvh.primIndices.size());
    for (uint32_t i = 0; i < bvh.primIndices.size(); ++i) {
        const uint32_t index = bvh.primIndices[i];
        gpuIndexOf[index] = i;
        // A static scene given the motion path (SceneFeatures::all) gets one segment that stays put.
        for (int pose = 1; data.features.motion && pose <= std::max(1, scene.motionSegments); ++pose) {
            const int at = scene.moving() ? pose : 0;
            if (scene.isSphere(index)) {
                const Sphere s = scene.spherePose(index, at);
                data.motion.push_back({s.center, s.material, glm::vec3(s.radius, 0.0f, 0.0f), index,
                                       glm::vec3(0.0f), VKRT_PRIMITIVE_SPHERE});
            } else {
                const Triangle t = scene.trianglePose(index, at);
                data.motion.push_back({t.v0, t.material, t.v1, index, t.v2, VKRT_PRIMITIVE_TRIANGLE});
            }
        }
        if (scene.isSphere(index)) {
            const Sphere& sphere = scene.sphereOf(index);
            data.triangles.push_back({sphere.center, sphere.material, glm::vec3(sphere.radius, 0.0f, 0.0f),
                                      index, glm::vec3(0.0f), VKRT_PRIMITIVE_SPHERE});
            if (needShading) data.shading.push_back({});  // spheres compute theirs
            continue;
        }
        const Triangle& t = scene.triangles[index];
        data.triangles.push_back({t.v0, t.material, t.v1, index, t.v2, VKRT_PRIMITIVE_TRIANGLE});
        if (needShading) {
            const TriangleShading& s = scene.shading[index];
            data.shading.push_back({glm::vec4(s.normal[0], s.uv[0].x), glm::vec4(s.normal[1], s.uv[1].x),
                                    glm::vec4(s.normal[2], s.uv[2].x),
                                    glm::vec4(s.uv[0].y, s.uv[1].y, s.uv[2].y, 0.0f)});
        }
    }

    for (const Material& m : scene.materials) {
        gpu::GpuMaterial g;
        g.baseColorMetallic = glm::vec4(glm::vec3(m.baseColor), m.metallic);
        g.emissionRoughness = glm::vec4(m.emission, m.roughness);
        g.attenuation = glm::vec4(m.attenuationColor, m.attenuationDistance);
        g.transmission = glm::vec4(m.transmission, m.ior, m.thickness, m.doubleSided ? 1.0f : 0.0f);
        g.textures = glm::ivec4(data.features.textures ? m.baseColorTexture : -1,
                                data.features.textures ? m.emissiveTexture : -1, -1, -1);
        data.materials.push_back(g);
    }

    if (data.features.textures) {
        for (const Texture& t : scene.textures) {
            gpu::GpuTexture g{static_cast<uint32_t>(data.texels.size()), static_cast<uint32_t>(t.width),
                              static_cast<uint32_t>(t.height),
                              wrapBits(t.wrapS) | (wrapBits(t.wrapT) << 2) | (t.nearest ? 16u : 0u)};
            data.textures.push_back(g);
            for (size_t p = 0; p * 4 < t.rgba.size(); ++p) {
                // unpackUnorm4x8 reads red from the lowest byte.
                data.texels.push_back(t.rgba[4 * p] | (t.rgba[4 * p + 1] << 8) | (t.rgba[4 * p + 2] << 16) |
                                      (static_cast<uint32_t>(t.rgba[4 * p + 3]) << 24));
            }
        }
    }

    for (const PunctualLight& light : scene.lights) {
        gpu::GpuPunctualLight g;
        const float type = light.type == LightType::Point  ? VKRT_LIGHT_POINT
                           : light.type == LightType::Spot ? VKRT_LIGHT_SPOT
                                                           : VKRT_LIGHT_DIRECTIONAL;
        g.positionType = glm::vec4(glm::vec3(light.position), type);
        g.directionRange = glm::vec4(glm::vec3(light.direction), light.range);
        g.radiantColor = glm::vec4(light.color * light.intensity, 0.0f);
        const double cosOuter = std::cos(static_cast<double>(light.outerConeAngle));
        const double cosInner = std::cos(static_cast<double>(light.innerConeAngle));
        g.cone = glm::vec4(static_cast<float>(cosOuter),
                           static_cast<float>(1.0 / std::max(0.001, cosInner - cosOuter)), 0.0f, 0.0f);
        data.lights.push_back(g);
    }

    const AreaLights areaLights(scene);
    for (size_t i = 0; i < areaLights.primitives().size(); ++i) {
        data.areaLights.push_back(
            {gpuIndexOf[areaLights.primitives()[i]], static_cast<float>(areaLights.cdf()[i]),
             static_cast<float>(areaLights.pdfArea()[i]), static_cast<float>(areaLights.pick()[i])});
    }
    data.areaLightPower = areaLights.totalPower();
    data.motionSegments = data.features.motion ? std::max(1, scene.motionSegments) : 0;
    if (!features) data.features.areaLights = !data.areaLights.empty();
    return data;
}

GpuSceneBuffers::GpuSceneBuffers(const VulkanContext& context, const GpuSceneData& data) {
    buffers_.reserve(8);
    auto upload = [&](const auto& values) -> uint64_t {
        if (values.empty()) return 0;
        buffers_.emplace_back(context, values);
        return buffers_.back().address();
    };
    addresses_.nodes = upload(data.nodes);
    nodeBuffer_ = data.nodes.empty() ? -1 : static_cast<int>(buffers_.size()) - 1;
    addresses_.triangles = upload(data.triangles);
    triangleBuffer_ = data.triangles.empty() ? -1 : static_cast<int>(buffers_.size()) - 1;
    addresses_.shading = upload(data.shading);
    addresses_.materials = upload(data.materials);
    addresses_.textures = upload(data.textures);
    addresses_.texels = upload(data.texels);
    addresses_.lights = upload(data.lights);
    addresses_.areaLights = upload(data.areaLights);
    addresses_.motion = upload(data.motion);
}

void GpuSceneBuffers::fillAddresses(gpu::SceneParams& params) const {
    params.nodes = addresses_.nodes;
    params.triangles = addresses_.triangles;
    params.shading = addresses_.shading;
    params.materials = addresses_.materials;
    params.textures = addresses_.textures;
    params.texels = addresses_.texels;
    params.lights = addresses_.lights;
    params.areaLights = addresses_.areaLights;
    params.motion = addresses_.motion;
}

bool GpuSceneBuffers::geometryFitsDescriptors(const VulkanContext& context) const {
    if (nodeBuffer_ < 0 || triangleBuffer_ < 0) return false;
    const VkDeviceSize range = context.properties().limits.maxStorageBufferRange;
    return buffers_[nodeBuffer_].size() <= range && buffers_[triangleBuffer_].size() <= range;
}

std::vector<const GpuBuffer*> GpuSceneBuffers::bindings(const GpuBuffer& params, bool boundGeometry) const {
    if (!boundGeometry) return {&params};
    return {&params, &buffers_[nodeBuffer_], &buffers_[triangleBuffer_]};
}

gpu::SceneParams makeSceneParams(const GpuSceneData& data, const Camera& camera,
                                 const RenderSettings& settings) {
    gpu::SceneParams p{};
    const float projection = camera.projection == Projection::Orthographic ? VKRT_PROJECTION_ORTHOGRAPHIC
                                                                           : VKRT_PROJECTION_PERSPECTIVE;
    p.camera.positionProjection = glm::vec4(glm::vec3(camera.position), projection);
    p.camera.forwardTanHalfFov =
        glm::vec4(glm::vec3(camera.forward), static_cast<float>(std::tan(0.5 * camera.yfov)));
    p.camera.rightXmag = glm::vec4(glm::vec3(camera.right), static_cast<float>(camera.xmag));
    p.camera.upYmag = glm::vec4(glm::vec3(camera.up), static_cast<float>(camera.ymag));
    p.camera.lens =
        glm::vec4(static_cast<float>(camera.aperture), static_cast<float>(camera.focusDistance), 0.0f, 0.0f);
    p.ambientMinThroughput =
        glm::vec4(glm::vec3(settings.ambient), static_cast<float>(settings.minThroughput));
    p.background = glm::vec4(glm::vec3(settings.background), static_cast<float>(settings.lightSamples));
    p.imageDepthSeed = glm::uvec4(settings.width, settings.height, settings.maxDepth, settings.seed);
    p.counts = glm::uvec4(data.lights.size(), data.areaLights.size(), data.triangles.size(),
                          settings.samplesPerPixel);
    p.lighting =
        glm::vec4(static_cast<float>(data.areaLightPower), settings.multipleImportanceSampling ? 1.0f : 0.0f,
                  static_cast<float>(data.motionSegments), 0.0f);
    return p;
}

}  // namespace vkrt
