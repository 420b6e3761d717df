#include "support/unit_square.h"

#include "scene/procedural_meshes.h"
#include "scene/scene_builder.h"
#include "support/test_paths.h"

namespace vkrt::test {

Texture textureOf(int width, int height, const std::vector<uint32_t>& texels) {
    Texture texture;
    texture.width = width;
    texture.height = height;
    texture.nearest = true;
    std::vector<uint8_t> rgba;
    for (uint32_t t : texels) {
        for (int c = 0; c < 4; ++c) rgba.push_back(static_cast<uint8_t>(t >> (8 * c)));
    }
    texture.rgba = std::make_shared<const std::vector<uint8_t>>(std::move(rgba));
    return texture;
}

Material lambertian(float albedo) {
    Material m;
    m.baseColor = glm::vec4(glm::vec3(albedo), 1.0f);
    m.metallic = 0.0f;
    m.specularFactor = 0.0f;
    return m;
}

void addUnitSquare(Scene& scene, uint32_t material) {
    addFlatQuad(scene, {0, 0, 0}, {1, 0, 0}, {1, 1, 0}, {0, 1, 0}, material);
    for (size_t i = scene.triangles.size() - 2; i < scene.triangles.size(); ++i) {
        const Triangle& t = scene.triangles[i];
        for (int k = 0; k < 3; ++k) {
            const glm::vec3 v = k == 0 ? t.v0 : k == 1 ? t.v1 : t.v2;
            scene.shading[i].uv[k] = glm::vec2(v.x, 1.0f - v.y);
        }
    }
}

Camera squareCamera() {
    Camera camera;
    camera.projection = Projection::Orthographic;
    camera.position = {0.5, 0.5, 1.0};
    camera.forward = {0.0, 0.0, -1.0};
    camera.right = {1.0, 0.0, 0.0};
    camera.up = {0.0, 1.0, 0.0};
    camera.xmag = camera.ymag = 0.5;
    return camera;
}

Camera sphereCamera() {
    Camera camera;
    camera.projection = Projection::Orthographic;
    camera.position = {0.0, 0.0, 5.0};
    camera.xmag = camera.ymag = 1.0;
    return camera;
}

void addUvSphereMesh(Scene& scene, int rings, int segments, uint32_t material, bool tangents) {
    for (const Triangle& t : makeUvSphere(glm::vec3(0.0f), 1.0f, rings, segments, material)) {
        const glm::vec3 corners[3] = {t.v0, t.v1, t.v2};
        TriangleShading shading{};
        std::array<glm::vec4, 3> frames;
        for (int k = 0; k < 3; ++k) {
            const glm::vec3 n = glm::normalize(corners[k]);
            shading.normal[k] = n;
            const glm::vec3 east = glm::cross(glm::vec3(0.0f, 1.0f, 0.0f), n);
            frames[k] =
                glm::vec4(glm::length(east) > 1e-3f ? glm::normalize(east) : glm::vec3(1, 0, 0), 1.0f);
        }
        scene.triangles.push_back(t);
        scene.shading.push_back(shading);
        if (tangents) scene.tangents.push_back(frames);
    }
}

RenderSettings ambientOnly(int size) {
    RenderSettings settings;
    settings.width = settings.height = size;
    settings.samplesPerPixel = 4;
    settings.ambient = glm::dvec3(1.0);
    settings.background = glm::dvec3(0.25);
    return settings;
}

RenderPair renderUnitSquare(const VulkanContext& context, Scene scene, const Material& material,
                            const RenderSettings& settings) {
    scene.materials.push_back(material);
    addUnitSquare(scene, static_cast<uint32_t>(scene.materials.size()) - 1);
    finalizeScene(scene);
    const FlatBvh bvh = bvhFor(scene);
    return renderGpuAndCpu(context, scene, bvh, squareCamera(), settings, shaderCacheDir());
}

}  // namespace vkrt::test
