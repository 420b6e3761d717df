#include "gpu/scene_features.h"

#include <algorithm>
#include <cmath>
#include <limits>
#include <vector>

#include "media.h"
#include "microfacet.h"
#include "punctual_light.h"
#include "scene/ggx_albedo_tables.h"
#include "scene/light_table.h"
#include "shape_geometry.h"

namespace vkrt {
namespace {

struct FeatureName {
    bool SceneFeatures::*flag;
    const char* name;
    const char* define;
};

constexpr FeatureName kFeatures[] = {
    {&SceneFeatures::smoothNormals, "smooth_normals", "VKRT_HAS_SMOOTH_NORMALS"},
    {&SceneFeatures::textures, "textures", "VKRT_HAS_TEXTURES"},
    {&SceneFeatures::transmission, "transmission", "VKRT_HAS_TRANSMISSION"},
    {&SceneFeatures::volumes, "volumes", "VKRT_HAS_VOLUMES"},
    {&SceneFeatures::thinTransmission, "thin_transmission", "VKRT_HAS_THIN_TRANSMISSION"},
    {&SceneFeatures::absorption, "absorption", "VKRT_HAS_ABSORPTION"},
    {&SceneFeatures::punctualLights, "punctual_lights", "VKRT_HAS_PUNCTUAL_LIGHTS"},
    {&SceneFeatures::punctualLightTable, "punctual_light_table", "VKRT_HAS_PUNCTUAL_LIGHT_TABLE"},
    {&SceneFeatures::areaLights, "area_lights", "VKRT_HAS_AREA_LIGHTS"},
    {&SceneFeatures::spheres, "spheres", "VKRT_HAS_SPHERES"},
    {&SceneFeatures::shapes, "shapes", "VKRT_HAS_SHAPES"},
    {&SceneFeatures::shapeSpheres, "shape_spheres", "VKRT_HAS_SHAPE_SPHERES"},
    {&SceneFeatures::shapeBoxes, "shape_boxes", "VKRT_HAS_SHAPE_BOXES"},
    {&SceneFeatures::shapeCylinders, "shape_cylinders", "VKRT_HAS_SHAPE_CYLINDERS"},
    {&SceneFeatures::shapeCones, "shape_cones", "VKRT_HAS_SHAPE_CONES"},
    {&SceneFeatures::csg, "csg", "VKRT_HAS_CSG"},
    {&SceneFeatures::motion, "motion_blur", "VKRT_HAS_MOTION"},
    {&SceneFeatures::depthOfField, "depth_of_field", "VKRT_HAS_DEPTH_OF_FIELD"},
    {&SceneFeatures::vertexColors, "vertex_colors", "VKRT_HAS_VERTEX_COLORS"},
    {&SceneFeatures::texCoords1, "texcoord1", "VKRT_HAS_TEXCOORD1"},
    {&SceneFeatures::normalMaps, "normal_maps", "VKRT_HAS_NORMAL_MAPS"},
    {&SceneFeatures::alpha, "alpha", "VKRT_HAS_ALPHA"},
    {&SceneFeatures::volumeHoles, "volume_holes", "VKRT_HAS_VOLUME_HOLES"},
    {&SceneFeatures::unlit, "unlit", "VKRT_HAS_UNLIT"},
    {&SceneFeatures::mipmaps, "mipmaps", "VKRT_HAS_MIPMAPS"},
    {&SceneFeatures::clearcoat, "clearcoat", "VKRT_HAS_CLEARCOAT"},
    {&SceneFeatures::environment, "environment", "VKRT_HAS_ENVIRONMENT"},
    {&SceneFeatures::sheen, "sheen", "VKRT_HAS_SHEEN"},
    {&SceneFeatures::roughSpecular, "rough_specular", "VKRT_HAS_ROUGH_SPECULAR"},
    {&SceneFeatures::tracedLobes, "traced_lobes", "VKRT_HAS_TRACED_LOBES"},
    {&SceneFeatures::glossyLobes, "glossy_lobes", "VKRT_HAS_GLOSSY_LOBES"},
    {&SceneFeatures::roughRefraction, "rough_refraction", "VKRT_HAS_ROUGH_REFRACTION"},
    {&SceneFeatures::largeTriangles, "large_triangles", "VKRT_HAS_LARGE_TRIANGLES"},
    {&SceneFeatures::largeSpheres, "large_spheres", "VKRT_HAS_LARGE_SPHERES"},
    {&SceneFeatures::solidAngleTriangles, "solid_angle_triangles", "VKRT_HAS_SOLID_ANGLE_TRIANGLES"},
};

// Whether some point of `material` may trace a lobe (surface_response.h's `traced` and `coatTraced`): a
// metal, a transmissive surface, a specular reflection below roughness 1, or a coat. Textures only scale
// the factors, so a factor of 0 stays 0, and a roughness of 1 can fall only under a texture. A matte
// dielectric (glTF's default roughness 1) keeps its faint specular reflection untraced.
bool tracesLobe(const Material& material) {
    const bool smooth = material.roughness < 1.0f || material.metallicRoughnessTexture.used();
    return material.metallic > 0.0f || material.transmission > 0.0f ||
           (material.specularFactor > 0.0f && smooth) || material.clearcoat > 0.0f;
}

// Whether a lobe `material` traces can be rough rather than a mirror (surface_response.h's `mirror` and
// `coatMirror` false where shade_hit.h traces): a traced base at roughness VKRT_MIRROR_ROUGHNESS or more, or
// a coat likewise. A texture only scales a roughness factor down, so a factor below it stays a mirror. (A
// coat over an untraced base counts the base's roughness too: conservative, as the base's lobe is still
// worked out.)
bool tracesGlossyLobe(const Material& material) {
    return (tracesLobe(material) && material.roughness >= VKRT_MIRROR_ROUGHNESS) ||
           (material.clearcoat > 0.0f && material.clearcoatRoughness >= VKRT_MIRROR_ROUGHNESS);
}

// Whether light fades inside `material`'s volume (media.h).
bool absorbs(const Material& material) {
    return shading::attenuates(glm::dvec3(material.attenuationColor), material.attenuationDistance);
}

// A primitive 1024 times as large as the scene's typical one is tested in double where the device has it: the
// float tests' errors grow with a primitive's size, and such a primitive's errors are far larger than the
// rest of the scene's rounding.
constexpr float kLargeFactor = 1024.0f;

}  // namespace

// Whether some triangle, at some pose of its motion, is 1024 times as long as the scene's median triangle or
// as its smallest sphere or shape, whichever is smallest (a ground quad under the objects on it): the
// distance the GPU's float triangle test gives is off by float epsilon times the corners' distance from the
// ray, which such a triangle makes far larger than the rest of the scene's rounding, and ray.glsl's hitPoint
// computes it again in double (VKRT_TRIANGLE_FLOAT64). Whether some sphere, at some pose of its motion, is
// 1024 times as wide as that: a float root is off by float epsilon times the distance from the ray's origin
// to the sphere's centre (shaders/sphere_geometry.h), which a sphere used as the ground makes its radius even
// where rays travel a short way, and the roots are found in double (VKRT_SPHERE_FLOAT64). Smaller spheres'
// roots are off by about what a triangle's distance is at the same distance (ray.glsl's sphereHitPoint
// offsets new rays by it).
void findLargePrimitives(const Scene& scene, SceneFeatures& features) {
    auto longestEdge = [](const Triangle& t) {
        return std::max({glm::length(t.v1 - t.v0), glm::length(t.v2 - t.v1), glm::length(t.v0 - t.v2)});
    };
    // The longest of all, and the median of at most 65536 spread over the scene: a threshold 1024 times it
    // needs no more, and a large scene no copy of all its lengths.
    const size_t stride = std::max<size_t>(1, scene.triangles.size() / 65536);
    float longest = 0.0f;
    std::vector<float> lengths;
    for (size_t i = 0; i < scene.triangles.size(); ++i) {
        const float length = longestEdge(scene.triangles[i]);
        longest = std::max(longest, length);
        if (i % stride == 0) lengths.push_back(length);
    }
    // A moving triangle's later poses (skins and morph targets stretch them): between two poses its corners
    // move linearly, and no edge is longer there than at both ends.
    for (const Triangle& pose : scene.trianglePoses) longest = std::max(longest, longestEdge(pose));
    float typical = std::numeric_limits<float>::infinity();
    if (!lengths.empty()) {
        auto middle = lengths.begin() + static_cast<std::ptrdiff_t>(lengths.size() / 2);
        std::nth_element(lengths.begin(), middle, lengths.end());
        typical = *middle;
    }
    float widest = 0.0f;
    for (const std::vector<Sphere>* poses : {&scene.spheres, &scene.spherePoses}) {
        for (const Sphere& sphere : *poses) {
            typical = std::min(typical, 2.0f * sphere.radius);
            widest = std::max(widest, 2.0f * sphere.radius);
        }
    }
    for (const Shape& shape : scene.shapes) {
        const glm::mat3 linear(shape.toWorld);
        typical = std::min(typical, 2.0f * std::max({glm::length(linear[0]), glm::length(linear[1]),
                                                     glm::length(linear[2])}));
    }
    features.largeTriangles = longest > kLargeFactor * typical;
    features.largeSpheres = widest > kLargeFactor * typical;
}

SceneFeatures SceneFeatures::all() {
    SceneFeatures features;
    for (const FeatureName& f : kFeatures) features.*f.flag = true;
    return features;
}

std::vector<std::string> SceneFeatures::defines() const {
    std::vector<std::string> result;
    for (const FeatureName& f : kFeatures) {
        if (this->*f.flag) result.push_back(f.define);
    }
    for (const std::string& define : solidShapesDefine()) result.push_back(define);
    return result;
}

std::vector<std::string> SceneFeatures::solidShapesDefine() const {
    static_assert(VKRT_CSG_MAX_SHAPES == 8, "SceneFeatures::solidShapes' default");
    if (!csg || solidShapes >= VKRT_CSG_MAX_SHAPES) return {};
    return {"VKRT_SOLID_SHAPES " + std::to_string(solidShapes)};
}

std::vector<std::string> SceneFeatures::names() const {
    std::vector<std::string> result;
    for (const FeatureName& f : kFeatures) {
        if (this->*f.flag) result.push_back(f.name);
    }
    return result;
}

SceneFeatures detectFeatures(const Scene& scene) {
    SceneFeatures features;
    std::vector<bool> used(scene.materials.size(), false);
    std::vector<bool> onAnalytic(scene.materials.size(), false);  // used by a sphere or a shape
    for (const Triangle& triangle : scene.triangles) used[triangle.material] = true;
    features.smoothNormals = scene.smoothNormals();
    for (const Sphere& sphere : scene.spheres) used[sphere.material] = onAnalytic[sphere.material] = true;
    features.spheres = !scene.spheres.empty();
    for (const Shape& shape : scene.shapes) {
        used[shape.material] = onAnalytic[shape.material] = true;
        features.shapeSpheres |= shape.type == VKRT_SHAPE_SPHERE;
        features.shapeBoxes |= shape.type == VKRT_SHAPE_BOX;
        features.shapeCylinders |= shape.type == VKRT_SHAPE_CYLINDER;
        features.shapeCones |= shape.type == VKRT_SHAPE_CONE;
    }
    features.shapes = !scene.solids.empty();
    features.solidShapes = 1;
    for (const Solid& solid : scene.solids)
        features.solidShapes = std::max(features.solidShapes, solid.shapeCount);
    features.csg = features.solidShapes > 1;
    features.vertexColors = !scene.vertexColors.empty();
    features.motion = scene.moving();
    for (size_t m = 0; m < scene.materials.size(); ++m) {
        if (!used[m]) continue;
        const Material& material = scene.materials[m];
        for (const TextureSlot* slot : material.textureSlots()) {
            // An emissive texture matters only on an emissive material.
            if (!slot->used() || (slot == &material.emissiveTexture && !material.emissive())) continue;
            features.textures = true;
            // Ray cones pick levels of detail where a minified texture reads other texels than level 0
            // magnified would: it has mipmaps, or another filter.
            const Texture& texture = scene.textures[slot->texture];
            features.mipmaps |= (texture.width > 1 || texture.height > 1) &&
                                (texture.mipmaps != MipmapMode::None || texture.minNearest != texture.nearest);
            // The second texture coordinate set: read by a slot, and given by some mesh.
            features.texCoords1 |= slot->texCoord == 1 && !scene.uv1.empty();
        }
        features.unlit |= material.unlit;
        features.clearcoat |= material.clearcoat > 0.0f;
        features.sheen |= material.hasSheen();
        features.roughSpecular |= hasRoughSpecular(material);
        features.tracedLobes |= tracesLobe(material);
        features.glossyLobes |= tracesGlossyLobe(material);
        // Meshes carry their tangent frames (none: no mesh has a normal texture); spheres and shapes compute
        // theirs.
        features.normalMaps |= (material.normalTexture.used() || material.clearcoatNormalTexture.used()) &&
                               (!scene.tangents.empty() || onAnalytic[m]);
        const bool transmits = material.transmits(), medium = scene.boundsMedium(material);
        features.transmission |= transmits;
        features.volumes |= medium;
        features.thinTransmission |= transmits && !material.hasVolume();
        features.absorption |= medium && absorbs(material);
        features.roughRefraction |= transmits && refractsRoughly(material);
    }
    features.alpha = scene.surfacesHaveHoles();  // an alpha, or COLOR_0's alpha, below full cover
    features.volumeHoles = scene.volumesHaveHoles();
    features.punctualLights = !scene.lights.empty();
    features.punctualLightTable = scene.lights.size() > VKRT_EVERY_PUNCTUAL_LIGHT_UP_TO;
    features.areaLights =
        !scene.emissiveTriangles.empty() || !scene.emissiveSpheres.empty() || !scene.emissiveShapes.empty();
    features.environment = scene.environment.present();
    findLargePrimitives(scene, features);
    features.solidAngleTriangles = samplesTrianglesBySolidAngle(scene);
    return features;
}

}  // namespace vkrt
