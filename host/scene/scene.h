// Scene: plain data that every renderer reads. No Vulkan, no glTF types.
//
// Geometry is flattened to world space when the glTF node graph is walked, so renderers never see the
// hierarchy. Positions are single precision (what the GPU stores); the CPU reference promotes them to
// double, so both renderers trace exactly the same geometry.
#pragma once

#include <algorithm>
#include <array>
#include <cmath>
#include <cstdint>
#include <limits>
#include <memory>
#include <string>
#include <vector>

#include <glm/glm.hpp>

#include "scene/environment_map.h"

namespace vkrt {

struct Aabb {
    glm::vec3 min{std::numeric_limits<float>::infinity()};
    glm::vec3 max{-std::numeric_limits<float>::infinity()};

    void grow(const glm::vec3& p) {
        min = glm::min(min, p);
        max = glm::max(max, p);
    }
    void grow(const Aabb& b) {
        min = glm::min(min, b.min);
        max = glm::max(max, b.max);
    }
    bool empty() const { return !(min.x <= max.x && min.y <= max.y && min.z <= max.z); }
    glm::vec3 extent() const { return max - min; }
    glm::vec3 center() const { return 0.5f * (min + max); }
    float surfaceArea() const {
        if (empty()) return 0.0f;
        glm::vec3 e = extent();
        return 2.0f * (e.x * e.y + e.y * e.z + e.z * e.x);
    }
    bool contains(const Aabb& b) const {
        return glm::all(glm::lessThanEqual(min, b.min)) && glm::all(glm::greaterThanEqual(max, b.max));
    }
};

// A triangle in world space. Winding is counter-clockwise seen from the front, as in glTF (the loader
// swaps two vertices when a node's transform mirrors the geometry).
struct Triangle {
    glm::vec3 v0, v1, v2;
    uint32_t material;

    Aabb bounds() const {
        Aabb b;
        b.grow(v0);
        b.grow(v1);
        b.grow(v2);
        return b;
    }
};

// The unit normal of `t`'s plane (right-handed winding), in double precision.
inline glm::dvec3 faceNormal(const Triangle& t) {
    return glm::normalize(
        glm::cross(glm::dvec3(t.v1) - glm::dvec3(t.v0), glm::dvec3(t.v2) - glm::dvec3(t.v0)));
}

// An analytic sphere (the VKRT_sphere node extension, docs/vkrt_sphere.md). Spheres share the BVH with
// the triangles: primitive index triangles.size() + i is sphere i.
struct Sphere {
    glm::vec3 center;
    float radius;
    uint32_t material;

    // Padded by a few ulps of the centre's magnitude, so a hit point rounded outwards stays inside.
    Aabb bounds() const {
        const glm::vec3 magnitude = glm::abs(center) + glm::vec3(radius);
        const glm::vec3 extent = glm::vec3(radius) + 4e-7f * magnitude;
        return {center - extent, center + extent};
    }
};

// A canonical convex shape (the VKRT_shape node extension, docs/vkrt_shape.md) placed in the world by an
// affine map: a sphere, box, cylinder or cone (shaders/shape_geometry.h's VKRT_SHAPE_*), alone or as an
// operand of a CSG solid.
struct Shape {
    uint32_t type;  // VKRT_SHAPE_*
    uint32_t material;
    glm::mat4 toWorld;    // object to world, at the shutter's opening (float, as the GPU stores it)
    glm::dmat4 toObject;  // its inverse, in double
};

// A solid: one shape, or a CSG object (VKRT_csg) over up to VKRT_CSG_MAX_SHAPES shapes, as the truth table of
// its boolean expression over the shapes' inside bits. Solids share the BVH with triangles and spheres:
// primitive index triangles.size() + spheres.size() + i is solid i.
struct Solid {
    uint32_t firstShape = 0;  // into Scene::shapes
    uint32_t shapeCount = 0;
    std::array<uint32_t, 8> table{};  // bit s: points inside exactly the shapes of s's set bits are inside
    Aabb bounds;                      // over the whole shutter

    // The table's bits 0 to 127 and 128 to 255, as the shared code reads it (shape_geometry.h's csgTable).
    glm::uvec4 tableLow() const { return {table[0], table[1], table[2], table[3]}; }
    glm::uvec4 tableHigh() const { return {table[4], table[5], table[6], table[7]}; }
};

// Per-vertex attributes of a triangle, kept apart from positions so traversal touches less memory.
struct TriangleShading {
    glm::vec3 normal[3];  // unit length; the geometric normal when the file has none (glTF: flat shading)
    glm::vec2 uv[3];      // TEXCOORD_0, or zero
};

// glTF's alphaMode: how the base colour's alpha covers the surface.
enum class AlphaMode : uint8_t { Opaque, Mask, Blend };

enum class WrapMode : uint8_t { Repeat, ClampToEdge, MirroredRepeat };

// How a minified texture picks among its mipmap levels (glTF's minFilter *_MIPMAP_NEAREST, *_MIPMAP_LINEAR,
// or NEAREST / LINEAR: no mipmaps).
enum class MipmapMode : uint8_t { None, Nearest, Linear };

// An 8-bit RGBA texture as stored in the file (base colour textures are sRGB-encoded).
struct Texture {
    int width = 0;
    int height = 0;
    // Shared by the textures that show one image (glTF pairs an image with a sampler, and any number of
    // textures may show one image): it is decoded once, and packed once for each colour space it is read in.
    std::shared_ptr<const std::vector<uint8_t>> rgba;
    WrapMode wrapS = WrapMode::Repeat;
    WrapMode wrapT = WrapMode::Repeat;
    bool nearest = false;     // magnification filter NEAREST; otherwise bilinear
    bool minNearest = false;  // minification filter NEAREST (within a level); otherwise bilinear
    MipmapMode mipmaps = MipmapMode::Linear;  // glTF leaves the default to the renderer: trilinear
    std::string name;
};

// A material's use of a texture: which one, through which texture coordinates, and the KHR_texture_transform
// applied to them (uv' = translation(offset) * rotation * scale(scale) * uv, as the extension defines it).
struct TextureSlot {
    int texture = -1;  // index into Scene::textures; -1: none
    int texCoord = 0;  // TEXCOORD_n; vkrt reads sets 0 and 1
    glm::vec2 offset{0.0f};
    float rotation = 0.0f;  // radians
    glm::vec2 scale{1.0f};

    bool used() const { return texture >= 0; }
    // The rotation and scale as the rows of a 2 x 2 matrix: uv' = (dot(rows[0], uv), dot(rows[1], uv)) +
    // offset. The extension writes its rotation as mat3(cos, sin, 0, -sin, cos, 0, 0, 0, 1) and means those
    // as rows, (cos, sin) and (-sin, cos), as the Khronos sample viewer applies it: with them, every arrow of
    // the self-checking TextureTransformTest points at its "correct" mark (the transposed rotation points
    // them at "error").
    std::array<glm::vec2, 2> linearRows() const {
        const float c = std::cos(rotation), s = std::sin(rotation);
        return {glm::vec2(c * scale.x, s * scale.y), glm::vec2(-s * scale.x, c * scale.y)};
    }
    // Whether the transform turns directions as `other`'s does, up to a positive uniform scale (which leaves
    // a tangent frame as it is; an offset moves no direction).
    bool turnsAs(const TextureSlot& other) const {
        const std::array<glm::vec2, 2> a = linearRows(), b = other.linearRows();
        const float na = std::sqrt(glm::dot(a[0], a[0]) + glm::dot(a[1], a[1]));
        const float nb = std::sqrt(glm::dot(b[0], b[0]) + glm::dot(b[1], b[1]));
        if (!(na > 0.0f) || !(nb > 0.0f)) return na == nb;
        for (int r = 0; r < 2; ++r)
            if (glm::length(a[r] / na - b[r] / nb) > 1e-5f) return false;
        return true;
    }
};

// glTF metallic-roughness material with the transmission, ior, volume and emissive-strength extensions.
// docs/materials.md explains how the Whitted model interprets these values.
struct Material {
    std::string name;
    glm::vec4 baseColor{1.0f};
    TextureSlot baseColorTexture;          // sRGB, multiplies baseColor
    TextureSlot metallicRoughnessTexture;  // linear: blue multiplies metallic, green roughness
    float metallic = 1.0f;
    float roughness = 1.0f;
    glm::vec3 emission{0.0f};        // emissiveFactor * KHR_materials_emissive_strength
    TextureSlot emissiveTexture;     // sRGB, multiplies `emission`
    TextureSlot occlusionTexture;    // linear, red: how much ambient light reaches the surface
    float occlusionStrength = 1.0f;  // occlusion = 1 + strength (red - 1)
    // KHR_materials_specular: the dielectric's reflection, scaled (0: purely Lambertian) and tinted.
    float specularFactor = 1.0f;
    glm::vec3 specularColor{1.0f};
    TextureSlot specularTexture;       // linear, alpha multiplies specularFactor
    TextureSlot specularColorTexture;  // sRGB, multiplies specularColor
    TextureSlot normalTexture;  // linear, tangent-space normal (TANGENT or tangents from the slot's coordinates)
    float normalScale = 1.0f;   // scales the normal's tangent-space x and y
    AlphaMode alphaMode = AlphaMode::Opaque;
    float alphaCutoff = 0.5f;   // MASK: alpha below it is a hole
    float transmission = 0.0f;
    TextureSlot transmissionTexture;  // linear, red multiplies `transmission`
    bool unlit = false;               // KHR_materials_unlit: shows its base colour, lit by nothing
    // KHR_materials_clearcoat: a clear dielectric coat (index 1.5) over the material, with its own roughness and
    // normal texture.
    float clearcoat = 0.0f;
    TextureSlot clearcoatTexture;  // linear, red multiplies `clearcoat`
    float clearcoatRoughness = 0.0f;
    TextureSlot clearcoatRoughnessTexture;  // linear, green multiplies `clearcoatRoughness`
    TextureSlot clearcoatNormalTexture;     // linear, tangent space, as normalTexture
    float clearcoatNormalScale = 1.0f;
    // KHR_materials_sheen: a layer of fibres reflecting sheenColor at grazing angles.
    glm::vec3 sheenColor{0.0f};
    TextureSlot sheenColorTexture;  // sRGB, multiplies sheenColor
    float sheenRoughness = 0.0f;
    TextureSlot sheenRoughnessTexture;  // linear, alpha multiplies sheenRoughness
    float ior = 1.5f;
    float thickness = 0.0f;  // KHR_materials_volume; 0 means thin-walled
    glm::vec3 attenuationColor{1.0f};
    float attenuationDistance = std::numeric_limits<float>::infinity();
    bool doubleSided = false;

    // Emits light (an unlit material shows its base colour instead, and lights nothing).
    bool emissive() const { return !unlit && (emission.x > 0.0f || emission.y > 0.0f || emission.z > 0.0f); }
    // Every texture slot (const or not, as the material is).
    template <typename Self>
    static auto slotsOf(Self& m) {
        return std::array{&m.baseColorTexture,       &m.metallicRoughnessTexture,
                          &m.emissiveTexture,        &m.occlusionTexture,
                          &m.specularTexture,        &m.specularColorTexture,
                          &m.normalTexture,          &m.transmissionTexture,
                          &m.clearcoatTexture,       &m.clearcoatRoughnessTexture,
                          &m.clearcoatNormalTexture, &m.sheenColorTexture,
                          &m.sheenRoughnessTexture};
    }
    std::array<const TextureSlot*, 13> textureSlots() const { return slotsOf(*this); }
    std::array<TextureSlot*, 13> textureSlots() { return slotsOf(*this); }
    // Whether `slot` (one of this material's) holds colours, sRGB-encoded (base, emissive, specular and sheen
    // colour), whose mipmaps average as light; the others hold linear data.
    bool holdsColour(const TextureSlot* slot) const {
        return slot == &baseColorTexture || slot == &emissiveTexture || slot == &specularColorTexture ||
               slot == &sheenColorTexture;
    }
    bool hasSheen() const { return sheenColor.x > 0.0f || sheenColor.y > 0.0f || sheenColor.z > 0.0f; }
    // Some of the surface may be missing: alpha MASK or BLEND, with an alpha that can fall below the cutoff
    // (MASK) or 1 (BLEND) through the factor or the texture. COLOR_0's alpha multiplies it as well
    // (SceneFeatures counts that).
    bool partlyCovered() const {
        if (alphaMode == AlphaMode::Opaque) return false;
        return baseColorTexture.used() || baseColor.a < (alphaMode == AlphaMode::Mask ? alphaCutoff : 1.0f);
    }
    bool hasVolume() const { return thickness > 0.0f; }
    // Transmits light: a metallic-roughness texture can lower a metallic factor of 1.
    bool transmits() const {
        return transmission > 0.0f && (metallic < 1.0f || metallicRoughnessTexture.used());
    }
    // The normal texture whose texture coordinates define the tangent frames (the coat's normal texture follows
    // the same frames).
    const TextureSlot& tangentFrameSlot() const {
        return normalTexture.used() ? normalTexture : clearcoatNormalTexture;
    }
};

enum class LightType : uint8_t { Point, Spot, Directional };

// KHR_lights_punctual in its photometric units: point and spot intensity in candela, directional in lux.
struct PunctualLight {
    std::string name;
    LightType type = LightType::Point;
    glm::dvec3 position{0.0};
    glm::dvec3 direction{0.0, 0.0, -1.0};  // the direction the light shines (the node's -Z)
    glm::vec3 color{1.0f};
    float intensity = 1.0f;
    float range = 0.0f;  // 0 means unlimited
    float innerConeAngle = 0.0f;
    float outerConeAngle = 0.7853981633974483f;
};

enum class Projection : uint8_t { Perspective, Orthographic };

// A camera placed in the world. It looks along `forward`, with `up` and `right` completing an
// orthonormal frame (glTF cameras look down their node's -Z with +Y up).
struct Camera {
    std::string name;
    Projection projection = Projection::Perspective;
    glm::dvec3 position{0.0};
    glm::dvec3 forward{0.0, 0.0, -1.0};
    glm::dvec3 up{0.0, 1.0, 0.0};
    glm::dvec3 right{1.0, 0.0, 0.0};
    double yfov = 0.8;           // perspective: vertical field of view in radians
    double xmag = 1.0;           // orthographic: half width of the view
    double ymag = 1.0;           // orthographic: half height of the view
    double aspectRatio = 0.0;    // from the file; 0 when absent (the image's own aspect is used)
    double aperture = 0.0;       // thin-lens radius (perspective only); 0 is a pinhole
    double focusDistance = 0.0;  // distance of the plane in focus, along `forward`
    bool generated = false;      // true for the default camera made when the file has none
    std::string
        unusable;  // why the camera cannot view the scene (a singular node transform); empty if it can
};

inline constexpr std::array<glm::vec4, 3> kVertexColorWhite = {glm::vec4(1.0f), glm::vec4(1.0f),
                                                               glm::vec4(1.0f)};

// Motion segments for animations that are not a pure linear translation over the shutter: a step inside the
// shutter ramps over 1/16 of it, and a rotation follows 16 chords of its arc.
inline constexpr int kMotionSegments = 16;

struct Scene {
    std::string sourcePath;
    // Positions, cameras and lights are stored relative to this point (world = stored + origin), chosen
    // near the middle of the scene so that single precision keeps its digits for scenes far from the
    // file's origin.
    glm::dvec3 origin{0.0};
    std::vector<Triangle> triangles;
    std::vector<TriangleShading> shading;  // parallel to triangles
    // COLOR_0 at each corner (multiplying the base colour), parallel to triangles; empty when no primitive
    // has vertex colours (kVertexColorWhite for triangles without).
    std::vector<std::array<glm::vec4, 3>> vertexColors;
    // TEXCOORD_1 at each corner, parallel to triangles; empty when no primitive has it (zero for those
    // without).
    std::vector<std::array<glm::vec2, 3>> uv1;
    // Tangent frames of normal-mapped triangles at each corner: the tangent (unit, world space) in xyz and
    // the bitangent's sign in w (bitangent = w * cross(normal, tangent)), parallel to triangles; empty when no
    // triangle's material has a normal texture (zero, meaning none, for triangles without).
    std::vector<std::array<glm::vec4, 3>> tangents;
    std::vector<Sphere> spheres;  // primitives triangles.size() + i
    std::vector<Shape> shapes;    // the solids' shapes
    std::vector<Solid> solids;    // primitives triangles.size() + spheres.size() + i
    // Motion blur: the shutter interval is cut into motionSegments equal segments (0: nothing moves), and
    // each primitive moves linearly from its pose at one segment's start to the next. Pose 0 is the
    // primitive itself; pose k >= 1 of triangle i is trianglePoses[i * motionSegments + k - 1] (and
    // likewise for sphere i in spherePoses).
    int motionSegments = 0;
    std::vector<Triangle> trianglePoses;
    std::vector<Sphere> spherePoses;
    std::vector<glm::mat4>
        shapePoses;  // object to world of shape i at pose k >= 1: [i * motionSegments + k - 1]
    double shutterOpen = 0.0, shutterClose = 0.0;  // seconds of the file's animation timeline
    std::vector<Material> materials;
    std::vector<Texture> textures;
    std::vector<PunctualLight> lights;
    std::vector<Camera> cameras;              // camera instances in node order
    std::vector<uint32_t> emissiveTriangles;  // indices of triangles whose material emits
    std::vector<uint32_t> emissiveSpheres;    // indices into `spheres` whose material emits
    std::vector<uint32_t> emissiveShapes;     // indices into `shapes` whose material emits
    std::vector<std::string> warnings;
    std::vector<std::string> files;  // what the file refers to and was read: external buffers and images
    Aabb bounds;
    // The environment light (--environment), not part of the glTF file; absent unless one is given.
    EnvironmentMap environment;

    // Primitives are the triangles, then the spheres, then the solids.
    uint32_t primitiveCount() const {
        return static_cast<uint32_t>(triangles.size() + spheres.size() + solids.size());
    }
    uint32_t firstSolid() const { return static_cast<uint32_t>(triangles.size() + spheres.size()); }
    bool isSphere(uint32_t primitive) const {
        return primitive >= triangles.size() && primitive < firstSolid();
    }
    bool isSolid(uint32_t primitive) const { return primitive >= firstSolid(); }
    bool isTriangle(uint32_t primitive) const { return primitive < triangles.size(); }
    const Sphere& sphereOf(uint32_t primitive) const { return spheres[primitive - triangles.size()]; }
    const Solid& solidOf(uint32_t primitive) const { return solids[primitive - firstSolid()]; }
    // A solid's material is its first shape's (each of its surfaces has its own shape's).
    uint32_t materialOf(uint32_t primitive) const {
        if (isSolid(primitive)) return shapes[solidOf(primitive).firstShape].material;
        return isSphere(primitive) ? sphereOf(primitive).material : triangles[primitive].material;
    }
    bool moving() const { return motionSegments > 0; }
    Triangle trianglePose(uint32_t index, int pose) const {
        return pose == 0 ? triangles[index] : trianglePoses[index * motionSegments + pose - 1];
    }
    Sphere spherePose(uint32_t primitive, int pose) const {
        const size_t index = primitive - triangles.size();
        return pose == 0 ? spheres[index] : spherePoses[index * motionSegments + pose - 1];
    }
    // The segment holding shutter time `time` in [0, 1] (0: open, 1: close) and the fraction through it.
    int segmentAt(double time, float& fraction) const {
        const float x = static_cast<float>(time) * static_cast<float>(motionSegments);
        const int segment = std::min(static_cast<int>(x), motionSegments - 1);
        fraction = x - static_cast<float>(segment);
        return segment;
    }
    // The primitive at shutter time `time`.
    Triangle triangleAt(uint32_t index, double time) const {
        if (!moving() || time == 0.0) return triangles[index];
        float s;
        const int segment = segmentAt(time, s);
        const Triangle a = trianglePose(index, segment), b = trianglePose(index, segment + 1);
        return {a.v0 + s * (b.v0 - a.v0), a.v1 + s * (b.v1 - a.v1), a.v2 + s * (b.v2 - a.v2), a.material};
    }
    Sphere sphereAt(uint32_t primitive, double time) const {
        if (!moving() || time == 0.0) return sphereOf(primitive);
        float s;
        const int segment = segmentAt(time, s);
        const Sphere a = spherePose(primitive, segment), b = spherePose(primitive, segment + 1);
        return {a.center + s * (b.center - a.center), a.radius + s * (b.radius - a.radius), a.material};
    }
    // Shape i's object-to-world map at pose k.
    glm::mat4 shapePose(uint32_t shape, int pose) const {
        return pose == 0 ? shapes[shape].toWorld : shapePoses[shape * motionSegments + pose - 1];
    }
    // Shape i's object-to-world map at shutter time `time` (interpolated as triangles' corners are) and its
    // inverse.
    void shapeAt(uint32_t shape, double time, glm::dmat4& toWorld, glm::dmat4& toObject) const {
        if (!moving() || time == 0.0) {
            toWorld = glm::dmat4(shapes[shape].toWorld);
            toObject = shapes[shape].toObject;
            return;
        }
        float s;
        const int segment = segmentAt(time, s);
        const glm::mat4 a = shapePose(shape, segment), b = shapePose(shape, segment + 1);
        toWorld = glm::dmat4(a + s * (b - a));
        toObject = glm::inverse(toWorld);
    }
    // Whether material `m` can leave holes: partly covered, or not opaque where COLOR_0's alpha multiplies
    // its own.
    bool leavesHoles(const Material& m) const {
        return m.partlyCovered() || (m.alphaMode != AlphaMode::Opaque && !vertexColors.empty());
    }
    // Whether a surface of material `m` bounds a medium that rays can be in: a volume that transmits light,
    // or whose surface's holes let rays in and out (shaders/shade_hit.h's mediaBeyondHole; a metal's too,
    // which transmits nothing through its surface).
    bool boundsMedium(const Material& m) const {
        return m.hasVolume() && m.transmission > 0.0f && (m.transmits() || leavesHoles(m));
    }
    // Whether some primitive's material satisfies `holds`.
    template <typename Predicate>
    bool somePlacedMaterial(const Predicate& holds) const {
        const auto placed = [&](const auto& primitive) { return holds(materials[primitive.material]); };
        return std::any_of(triangles.begin(), triangles.end(), placed) ||
               std::any_of(spheres.begin(), spheres.end(), placed) ||
               std::any_of(shapes.begin(), shapes.end(), placed);
    }
    // Whether some surface can have holes. Where none can, both devices take every surface as opaque,
    // whatever its alphaMode (a BLEND material of alpha 1 is opaque; a double-sided sphere lamp of it is
    // sampled as an opaque one: area_light.h).
    bool surfacesHaveHoles() const {
        return somePlacedMaterial([&](const Material& m) { return leavesHoles(m); });
    }
    // Whether the surface of a volume that some primitive bounds can have holes, where a ray passing them
    // enters or leaves the volume (shaders/shade_hit.h's mediaBeyondHole): paths' shadow rays then meet
    // surfaces in order, on both devices (lightSampleShadow).
    bool volumesHaveHoles() const {
        return somePlacedMaterial([&](const Material& m) { return boundsMedium(m) && leavesHoles(m); });
    }
    // Whether some triangle's vertex normals turn away from its face by more than 1e-4 radians. The rounding
    // of float corners and normals in real files stays below that (a Cornell box's are up to 5e-5 off; a
    // bound of 1.4e-3 once dropped the normals that matter of a finely tessellated curved mirror, 6e-4 off
    // its faces). Where none does, both devices shade every triangle with its face's normal (the GPU's shader
    // then leaves the vertex normals out).
    bool smoothNormals() const {
        for (size_t i = 0; i < triangles.size(); ++i) {
            const glm::dvec3 face = faceNormal(triangles[i]);
            for (const glm::vec3& n : shading[i].normal) {
                if (!(1.0 - glm::dot(glm::normalize(glm::dvec3(n)), face) < 5e-9)) return true;  // cos(1e-4)
            }
        }
        return false;
    }
    // Bounds over the whole shutter (linear motion between poses stays inside the union of the poses).
    Aabb boundsOf(uint32_t primitive) const {
        if (isSolid(primitive)) return solidOf(primitive).bounds;
        Aabb b;
        for (int pose = 0; pose <= motionSegments; ++pose) {
            b.grow(isSphere(primitive) ? spherePose(primitive, pose).bounds()
                                       : trianglePose(primitive, pose).bounds());
        }
        return b;
    }
};

}  // namespace vkrt
