// A scene in the GPU's layout (shaders/shared.h), before upload: triangles in BVH leaf order, materials,
// textures, lights and the area-light table. Arrays for features the scene lacks stay empty.
#pragma once

#include <vector>

#include "bvh/flat_bvh.h"
#include "common/render_settings.h"
#include "gpu/scene_features.h"
#include "scene/scene.h"
#include "shared.h"

namespace vkrt {

struct GpuSceneData {
    SceneFeatures features;
    std::vector<gpu::BvhNode> nodes;
    std::vector<gpu::GpuTriangle> triangles;  // triangles[i] is scene triangle sceneTriangle[i]
    std::vector<uint32_t> sceneTriangle;
    std::vector<gpu::GpuShading> shading;     // only with smooth normals or textures
    std::vector<gpu::GpuMaterial> materials;
    std::vector<gpu::GpuTexture> textures;    // only with textures
    std::vector<uint32_t> texels;
    std::vector<gpu::GpuPunctualLight> lights;
    std::vector<gpu::GpuAreaLight> areaLights;
};

GpuSceneData packScene(const Scene& scene, const FlatBvh& bvh);

// The fixed per-render parameters; buffer addresses are filled in by the renderer.
gpu::SceneParams makeSceneParams(const GpuSceneData& data, const Camera& camera, const RenderSettings& settings);

}  // namespace vkrt
