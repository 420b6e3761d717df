// A scene in the GPU's layout (shaders/shared.h), before upload: primitives in BVH leaf order, materials,
// textures, lights and the area-light table. Arrays for features the scene lacks stay empty.
#pragma once

#include <string>
#include <utility>
#include <vector>

#include "bvh/flat_bvh.h"
#include "common/memory_need.h"
#include "common/render_settings.h"
#include "gpu/compute_pipeline.h"
#include "gpu/gpu_buffer.h"
#include "gpu/scene_features.h"
#include "scene/scene.h"
#include "shared.h"

namespace vkrt {

// How many texels the scene's textures take. The texels themselves are not packed with the rest:
// GpuSceneBuffers writes them from the scene straight into the device's buffer (its mapped memory on lavapipe
// and other devices the host sees), so a hundred MB of texture is never first copied in host memory.
struct TexelCount {
    using value_type = uint32_t;
    size_t count = 0;
    size_t size() const { return count; }
    bool empty() const { return count == 0; }
};

struct GpuSceneData {
    SceneFeatures features;
    std::vector<gpu::WideBvhNode> nodes;             // the BVH collapsed to 4-wide nodes (flat_bvh.h)
    std::vector<gpu::GpuPrimitive> primitives;       // in BVH leaf order; each keeps its scene index
    std::vector<gpu::GpuShading> shading;            // only with smooth normals or textures
    std::vector<gpu::GpuVertexColors> vertexColors;  // only with vertex colours, leaf order
    std::vector<gpu::GpuTexCoords1> texCoords1;      // only with TEXCOORD_1, leaf order
    std::vector<gpu::GpuTangents> tangents;          // only with normal maps, leaf order
    std::vector<float> sheenTable;                   // only with sheen (sheen.h)
    std::vector<float> ggxAlbedoTable;               // only with rough GGX lobes (energy_compensation.h)
    std::vector<float> ggxDielectricAlbedoTable;     // only where one of them refracts
    std::vector<gpu::GpuMaterial> materials;
    std::vector<gpu::GpuTexture> textures;                // only with textures
    std::vector<gpu::GpuTextureBinding> textureBindings;  // the materials' texture slots, only with textures
    TexelCount texels;
    std::vector<gpu::GpuPunctualLight> lights;
    std::vector<gpu::GpuAreaLight> areaLights;
    std::vector<gpu::GpuEnvironmentTexel> environmentTexels;  // only with an environment
    std::vector<float> environmentRows;                       // its marginal table over rows
    shading::EnvironmentMapInfo environment{};                // width 0: none
    bool environmentBackdrop = true;  // camera rays see the environment (not the neutral default)
    std::vector<gpu::GpuPrimitive> motion;  // poses 1..motionSegments of every primitive (Scene), leaf order
    std::vector<gpu::GpuShape> shapes;      // only with shapes: the solids' shapes
    std::vector<gpu::GpuSolid> solids;
    std::vector<gpu::GpuShapePose> shapePoses;  // poses 1..motionSegments of every shape
    int motionSegments = 0;
    double areaLightPower = 0.0;  // LightTable::totalPower, for multiple importance sampling
    bool solidAngleTriangles = false;  // LightTable::solidAngleTriangles
    bool volumeHoles = false;  // Scene::volumesHaveHoles, also under a superset of the scene's features
};

// Packs what the scene's features need; `features`, when given, replaces the detected set (a superset
// compiles and packs paths the scene does not need, which tests use to show leaving them out is exact).
GpuSceneData packScene(const Scene& scene, const FlatBvh& bvh, const SceneFeatures* features = nullptr);

// How far from the scene's middle (the re-centred origin) the GPU's single-precision triangle test holds.
inline constexpr double kGpuReach = 1e12;
// The least extent (the scene's and the camera's distance from its middle) the triangle test holds at.
inline constexpr double kGpuSmallestReach = 1e-12;
// The largest entry of a shape's world-to-object map the GPU's float shape tests hold (shapes down to about
// 1e-18 across).
inline constexpr double kGpuShapeInverseScale = 1e18;

// Throws SceneError, naming --device cpu, when the scene, or the camera at `eye` (when given), is farther
// from its middle than kGpuReach, or a scene with triangles lies within kGpuSmallestReach of it, or a shape
// is smaller than kGpuShapeInverseScale allows. packScene checks the scene.
void checkGpuReach(const Scene& scene, const glm::dvec3* eye);

// The device memory each of the scene's buffers will take, by name (empty arrays take none).
MemoryNeed sceneBufferNeed(const GpuSceneData& data);

// The fixed per-render parameters, scene buffer addresses not yet filled in.
gpu::SceneParams makeSceneParams(const GpuSceneData& data, const Camera& camera, const Aabb& sceneBounds,
                                 const RenderSettings& settings);

// How kernels read the scene's arrays (shaders/scene_arrays.glsl), from the most widely possible to the
// fastest on CPU devices:
// - Addresses: everything through the device addresses in SceneParams (no size limit);
// - Storage: nodes and primitives bound as storage buffers (VKRT_BOUND_GEOMETRY), within the device's
//   storage-buffer range;
// - Texels: nodes, primitives and the arrays a hit reads (materials, lights, vertex attributes, textures, the
//   environment map, solids and shapes, poses under motion blur, the energy-compensation tables) bound as
//   texel buffers (VKRT_TEXEL_SCENE; gpu_scene.cpp's kTexelArrays), within the texel-buffer range. lavapipe
//   fetches a texel for all SIMD lanes with vector loads, but reads storage buffers and addresses one lane at
//   a time; an H200 traced 1.03 to 1.22 times as fast in GPU time with texels as with storage buffers, in
//   every render and nearly every ray benchmark measured (docs/performance-log.md).
// Auto: texels on every device, where the arrays fit, else the next way down.
enum class SceneAccess { Auto, Addresses, Storage, Texels };

const char* sceneAccessName(SceneAccess access);

// How kernels on `context` read the scene packed in `data`: `wanted` where the arrays it binds fit the
// device's range (Auto: the device's best), else the next way down (texels, storage buffers, addresses).
// Decided from the arrays' sizes, so the shader can be made while the buffers are written.
SceneAccess chooseSceneAccess(const VulkanContext& context, const GpuSceneData& data,
                              SceneAccess wanted = SceneAccess::Auto);

// The scene's arrays in device buffers. Empty arrays (features the scene lacks) get no buffer and
// address 0.
class GpuSceneBuffers {
  public:
    // `data` packed from `scene` (which gives the texels).
    GpuSceneBuffers(const VulkanContext& context, const GpuSceneData& data, const Scene& scene);
    // Writes the buffer addresses into `params` (all but accumulation and counters).
    void fillAddresses(gpu::SceneParams& params) const;

    // The shader's define for `access` (none for addresses).
    static std::vector<std::string> accessDefines(SceneAccess access);
    // What a kernel binds: SceneParams (a storage buffer), then nodes and primitives (Storage), or the texel
    // arrays from VKRT_BINDING_NODES on (Texels); bindingKinds says how each is read.
    std::vector<const GpuBuffer*> bindings(const GpuBuffer& params, SceneAccess access) const;
    static std::vector<BindingKind> bindingKinds(SceneAccess access);

  private:
    std::vector<GpuBuffer> buffers_;
    // The buffer holding each array, by its address in SceneParams (absent: the array is empty).
    const GpuBuffer* bufferOf(uint64_t gpu::SceneParams::*address) const;

    std::vector<std::pair<uint64_t gpu::SceneParams::*, size_t>> bufferIndex_;  // into buffers_
    gpu::SceneParams addresses_{};
};

}  // namespace vkrt
