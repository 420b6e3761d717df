// The CPU reference's side of the shared shading code (shaders/shade_hit.h): what VKRT_DEVICE reaches on
// the CPU. Materials, lights and textures come from the scene in double precision; shadow rays walk the BVH
// with the reference's double-precision tests; ray offsets suit double precision.
#pragma once

#include <algorithm>
#include <cstdint>
#include <vector>

#include "bvh/flat_bvh.h"
#include "common/render_settings.h"
#include "cpu/closest_hit.h"
#include "scene/environment_map.h"
#include "scene/ggx_albedo_tables.h"
#include "scene/light_table.h"
#include "scene/scene.h"
#include "scene/shading_inputs.h"
#include "scene/sheen_table.h"
#include "shade_hit.h"

namespace vkrt {

// What the device reads, made once per render.
struct CpuShadingScene {
    CpuShadingScene(const Scene& scene, const FlatBvh& bvh);

    const Scene& scene;
    const FlatBvh& bvh;
    std::vector<shading::SurfaceMaterial> materials;
    std::vector<gpu::GpuTextureBinding> bindings;  // the materials' texture slots
    std::vector<shading::PunctualLightParams> punctualLights;
    PunctualLightTable punctualTable;  // with more than VKRT_EVERY_PUNCTUAL_LIGHT_UP_TO
    PackedTextures textures;
    LightTable lights;
    std::vector<double> shapePick;  // each shape's probability of being picked as a light (0: not a light)
    EnvironmentTables environment;
    const std::vector<float>* sheenTable = nullptr;  // with a sheen material (sheen.h)
    const std::vector<float>* ggxAlbedoTable = nullptr;  // with a rough GGX lobe (energy_compensation.h)
    const std::vector<float>* ggxDielectricAlbedoTable = nullptr;  // with a rough refracting one
    bool volumesBlockShadows = false;  // the path integrator's shadow rays (shadowTint)
    bool volumeHoles = false;          // Scene::volumesHaveHoles: paths' shadow rays meet surfaces in order
    bool smoothNormals = false;  // Scene::smoothNormals: else every triangle is shaded with its face's normal
};

// The device for the rays of one sample: the scene at the sample's shutter time, counting shadow rays.
class CpuShadingDevice {
  public:
    CpuShadingDevice(const CpuShadingScene& data, double time, RayCounters& counters)
        : data_(data), time_(time), counters_(counters) {}

    const shading::SurfaceMaterial& material(uint32_t index) const { return data_.materials[index]; }
    uint32_t materialOf(uint32_t primitive) const { return data_.scene.materialOf(primitive); }

    gpu::GpuTexture textureInfo(int index) const { return data_.textures.textures[index]; }
    const gpu::GpuTextureBinding& textureBinding(int index) const { return data_.bindings[index]; }
    uint32_t texel(uint32_t index) const { return data_.textures.texels[index]; }
    glm::dvec2 textureCoordinates(uint32_t primitive, glm::dvec2 hitUv, uint32_t set) const;
    glm::dvec4 vertexColor(uint32_t primitive, glm::dvec2 hitUv) const;
    double textureDensity(uint32_t primitive, glm::dvec2 hitUv, uint32_t set) const;
    double sheenTable(uint32_t entry) const { return (*data_.sheenTable)[entry]; }
    double ggxAlbedoTable(uint32_t entry) const { return (*data_.ggxAlbedoTable)[entry]; }
    double ggxDielectricAlbedoTable(uint32_t entry) const { return (*data_.ggxDielectricAlbedoTable)[entry]; }

    uint32_t punctualLightCount() const { return static_cast<uint32_t>(data_.punctualLights.size()); }
    shading::PunctualLightParams punctualLight(uint32_t i) const { return data_.punctualLights[i]; }
    // The punctual light that (pick, pickFine) picks from the table, and its pick probability.
    uint32_t pickPunctualLight(double pick, double pickFine, double& probability) const;

    bool hasAreaLights() const { return !data_.lights.empty(); }
    shading::LightPoint sampleAreaLight(double pick, double pickFine, double u, double v,
                                        const glm::dvec3& from) const;
    double lightSolidAnglePdf(uint32_t primitive, uint32_t shape, const glm::dvec3& from,
                              const glm::dvec3& point, double cosLight) const;

    // Shapes, for shape_light.h: their type, material and maps at the shutter time.
    uint32_t shapeType(uint32_t shape) const { return data_.scene.shapes[shape].type; }
    uint32_t shapeMaterial(uint32_t shape) const { return data_.scene.shapes[shape].material; }
    void shapeMaps(uint32_t shape, shading::AffineRows& toObject, shading::AffineRows& toWorld) const;

    // The environment map (host/scene/environment_map.h).
    bool hasEnvironment() const { return data_.environment.hasEnvironment(); }
    glm::uvec2 environmentSize() const { return data_.environment.environmentSize(); }
    glm::dvec2 environmentRotation() const { return data_.environment.environmentRotation(); }
    glm::dvec3 environmentTexel(uint32_t i) const { return data_.environment.environmentTexel(i); }
    double environmentRowCdf(uint32_t y) const { return data_.environment.environmentRowCdf(y); }
    double environmentColumnCdf(uint32_t i) const { return data_.environment.environmentColumnCdf(i); }

    // The fraction of light passing from distance tMin to tMax along `direction` from `origin`: 0 behind an
    // opaque surface, the product of the tints of transmissive ones (shadow rays do not refract) in xyz, and
    // of their holes in w (surface_response.h's shadowPassage).
    glm::dvec4 shadowTransmittance(const glm::dvec3& origin, const glm::dvec3& direction, double tMin,
                                   double tMax, uint32_t excludeA, uint32_t excludeB) const;

    // The scene has holes in volumes' surfaces: paths' shadow rays meet surfaces in order (shade_hit.h's
    // lightSampleShadow).
    bool hasVolumeHoles() const { return data_.volumeHoles; }
    // A path's shadow ray where volumes' surfaces have holes: its first VKRT_MAX_ALPHA_LAYERS surfaces from
    // tMin met one by one in the closest-hit rule's order (ties.h's WalkPast), each crossed by shade_hit.h's
    // crossInOrder (into `passage`, `absorbed` and `media`); `exclude` and `light` are skipped throughout.
    // True where surfaces may lie beyond those, and `tMin` is then where the rest starts; false where none do
    // or the light is blocked (the GPU's trace.comp walks the same way).
    bool shadowThroughHoles(const glm::dvec3& origin, const glm::dvec3& direction, double tMax,
                            uint32_t exclude, uint32_t light, glm::uvec2& media, glm::dvec4& passage,
                            glm::dvec3& absorbed, double& tMin) const;

    // Where `ray` met `hit`, at the sample's shutter time: the point and its front side's normals, as the
    // GPU's trace.comp's hitPointOf finds them.
    shading::HitPoint hitPointOf(const RayT<double>& ray, const SurfaceHit& hit) const;

    // New rays start off the surface, on the side they leave from, by the GPU's relative offset
    // (shared.h's VKRT_RAY_OFFSET_EPSILON), far above the rounding of a double-precision hit point: so both
    // renderers treat surfaces within a tie's width of the one a ray leaves alike. Excluding the primitive
    // just hit removes the remaining risk of hitting it again. Shadow rays to a point on a light stop as
    // short of it as the GPU's (VKRT_SHADOW_RAY_SHORTENING).
    double shadowRayLength(double distance) const { return distance * (1.0 - VKRT_SHADOW_RAY_SHORTENING); }

    glm::dvec3 offsetOrigin(const glm::dvec3& position, double errorScale, const glm::dvec3& normal) const {
        return position + VKRT_RAY_OFFSET_EPSILON * std::max(shading::maxAbs(position), errorScale) * normal;
    }

    double time() const { return time_; }

    // Loop passes are counted on the GPU alone (llvmpipe's budget: device_lights.glsl).
    void loopPass() const {}

  private:
    const CpuShadingScene& data_;
    double time_;
    RayCounters& counters_;
};

}  // namespace vkrt
