// What a scene uses, so the GPU tracer compiles and uploads only that: what a scene does not need is left
// out of its shader variant and its buffers.
#pragma once

#include <string>
#include <vector>

#include "scene/scene.h"

namespace vkrt {

struct SceneFeatures {
    bool smoothNormals = false;  // some vertex normal differs from its face normal
    bool textures = false;       // a material samples a texture
    bool transmission = false;   // a material transmits light
    bool volumes = false;        // a transmissive material bounds a volume (refraction, Beer's law)
    bool thinTransmission = false;  // a transmissive material is thin-walled (no volume)
    bool absorption = false;     // light fades inside such a volume (a finite attenuation distance)
    bool punctualLights = false;
    bool punctualLightTable = false;  // more than VKRT_EVERY_PUNCTUAL_LIGHT_UP_TO: light samples pick them
    bool areaLights = false;    // emissive triangles, spheres or shapes
    bool spheres = false;       // analytic spheres (VKRT_sphere)
    bool shapes = false;        // analytic shapes and CSG (VKRT_shape, VKRT_csg)
    // A shape of each type (VKRT_shape): a kernel whose shapes are of one type folds the others' code away.
    bool shapeSpheres = false;
    bool shapeBoxes = false;
    bool shapeCylinders = false;
    bool shapeCones = false;
    // A solid of more than one shape (VKRT_csg): else the kernel's loops over a solid's shapes fold away.
    bool csg = false;
    // The most shapes of one solid, 2 to 8 where there is CSG (the all-features shader's 8,
    // VKRT_CSG_MAX_SHAPES): a kernel's loops over a solid's shapes run this many passes, each past the
    // solid's own count doing nothing, so that lavapipe unrolls them.
    uint32_t solidShapes = 8;
    bool motion = false;        // primitives move during the shutter (motion blur)
    bool depthOfField = false;  // the camera has a lens (set from the camera, not the scene)
    bool vertexColors = false;  // COLOR_0 multiplies base colours
    bool texCoords1 = false;    // some texture slot reads TEXCOORD_1, and some mesh has it
    bool normalMaps = false;    // a material has a normal texture, and some triangle a tangent frame
    bool alpha = false;         // a material's alpha (MASK or BLEND) can leave holes
    bool volumeHoles = false;   // such holes in a volume's surface: paths' shadow rays meet surfaces in order
    bool unlit = false;         // a material is KHR_materials_unlit
    bool clearcoat = false;     // a material has KHR_materials_clearcoat
    bool sheen = false;         // a material has KHR_materials_sheen
    bool roughSpecular = false;  // a rough GGX lobe, whose energy loss is compensated
    bool tracedLobes = false;    // a material traces a lobe: mirror, glossy, metal, transmission or coat rays
    bool glossyLobes = false;    // a traced lobe can be rough (GGX visible-normal sampling), not a mirror
    bool roughRefraction = false;  // a volume's surface can refract roughly (its compensation reads a table)
    bool mipmaps = false;       // a texture can be minified differently from level 0 magnified (ray cones)
    bool environment = false;   // an environment map lights the scene (--environment)
    bool largeTriangles = false;  // a triangle 1024 times the median one, or the smallest sphere or shape
    bool largeSpheres = false;    // a sphere 1024 times as wide as those
    bool solidAngleTriangles = false;  // an emissive triangle large beside the scene (light_table.h)

    // Every feature on: the shader with every path compiled in (tests compare it with the lean one). A render
    // with it still takes largeTriangles and largeSpheres, which choose precisions, from its scene
    // (packScene).
    static SceneFeatures all();

    // Shader defines (VKRT_HAS_...), one per feature present, and solidShapesDefine's.
    std::vector<std::string> defines() const;
    // VKRT_SOLID_SHAPES where there is CSG and its solids have fewer shapes than the most (else none).
    std::vector<std::string> solidShapesDefine() const;
    // Short names of the features present, for the stats JSON.
    std::vector<std::string> names() const;
};

SceneFeatures detectFeatures(const Scene& scene);

// Sets `features`' largeTriangles and largeSpheres from `scene` (detectFeatures sets them too): where its
// large primitives are tested in double.
void findLargePrimitives(const Scene& scene, SceneFeatures& features);

}  // namespace vkrt
