// The GPU's side of the shared shading code for materials and textures (VKRT_DEVICE in
// shading_language.h): reads the scene's buffers. Requires `params` and scene_arrays.glsl in scope. The
// texture functions come first: the shared material code below calls them.
#ifndef VKRT_DEVICE_MATERIALS_GLSL
#define VKRT_DEVICE_MATERIALS_GLSL

#include "optics.h"
#include "texture_density.h"

uint device_materialOf(uint primitive) { return VKRT_PRIMITIVE(primitive).material; }

#ifdef VKRT_HAS_TEXTURES
GpuTexture device_textureInfo(int index) { return gpuTextureAt(index); }

uint device_texel(uint index) { return gpuImageTexel(index); }

GpuTextureBinding device_textureBinding(int index) { return gpuTextureBindingAt(index); }

// A triangle's texture coordinates of set `set` (0 or 1) at barycentrics hitUv; spheres and solids carry their own.
vec2 device_textureCoordinates(uint primitive, vec2 hitUv, uint set) {
#if defined(VKRT_HAS_SPHERES) || defined(VKRT_HAS_SHAPES)
    if (VKRT_PRIMITIVE(primitive).kind != VKRT_PRIMITIVE_TRIANGLE) return hitUv;
#endif
#ifdef VKRT_HAS_TEXCOORD1
    if (set == 1u) {
        const GpuTexCoords1 t = gpuTexCoords1At(primitive);
        return barycentric(t.corners01.xy, t.corners01.zw, t.corner2.xy, hitUv);
    }
#endif
    const GpuShading s = gpuShadingAt(primitive);
    return barycentric(vec2(s.normalU0.w, s.v012.x), vec2(s.normalU1.w, s.v012.y), vec2(s.normalU2.w, s.v012.z), hitUv);
}

#ifdef VKRT_HAS_MIPMAPS
// Texture coordinates of set `set` per world unit on `primitive` (texture_sampling.h).
float device_textureDensity(uint primitive, vec2 hitUv, uint set) {
    const GpuPrimitive p = primitiveAt(primitive);
#ifdef VKRT_HAS_SPHERES
    if (p.kind == VKRT_PRIMITIVE_SPHERE) return sphereTextureDensity(p.v1.x, hitUv.y);
#endif
#ifdef VKRT_HAS_SHAPES
    if (p.kind != VKRT_PRIMITIVE_TRIANGLE) return 1.0;  // a solid's footprint is in its shape's units (shade_hit.h)
#endif
    return triangleTextureDensity(p.v0, p.v1, p.v2, device_textureCoordinates(primitive, vec2(0.0), set),
                                  device_textureCoordinates(primitive, vec2(1.0, 0.0), set),
                                  device_textureCoordinates(primitive, vec2(0.0, 1.0), set));
}
#endif
#endif

#ifdef VKRT_HAS_VERTEX_COLORS
// COLOR_0 at barycentrics hitUv; spheres have none.
vec4 device_vertexColor(uint primitive, vec2 hitUv) {
#if defined(VKRT_HAS_SPHERES) || defined(VKRT_HAS_SHAPES)
    if (VKRT_PRIMITIVE(primitive).kind != VKRT_PRIMITIVE_TRIANGLE) return vec4(1.0);
#endif
    const GpuVertexColors c = gpuVertexColorsAt(primitive);
    return barycentric(c.corner0, c.corner1, c.corner2, hitUv);
}
#endif

#ifdef VKRT_HAS_SHEEN
float device_sheenTable(uint entry) { return gpuSheenAlbedo(entry); }
#endif

#ifdef VKRT_HAS_ROUGH_SPECULAR
float device_ggxAlbedoTable(uint entry) { return gpuGgxAlbedo(entry); }
#if defined(VKRT_HAS_VOLUMES) && defined(VKRT_HAS_ROUGH_REFRACTION)
float device_ggxDielectricAlbedoTable(uint entry) { return gpuGgxDielectricAlbedo(entry); }
#endif
#endif

#include "surface_response.h"

SurfaceMaterial device_material(uint index) {
    const GpuMaterial m = gpuMaterialAt(index);
    SurfaceMaterial s;
    s.baseColor = m.baseColor;
    s.metallic = m.metallic;
    s.emission = m.emission;
    s.roughness = m.roughness;
    s.attenuationColor = m.attenuationColor;
    s.attenuationDistance = m.attenuationDistance;
    s.transmission = m.transmission;
    s.ior = m.ior;
    s.volume = m.thickness > 0.0;
    s.doubleSided = m.doubleSided != 0u;
    s.baseColorTexture = m.baseColorTexture;
    s.emissiveTexture = m.emissiveTexture;
    s.metallicRoughnessTexture = m.metallicRoughnessTexture;
    s.occlusionTexture = m.occlusionTexture;
    s.occlusionStrength = m.occlusionStrength;
    s.specularFactor = m.specularFactor;
    s.specularColor = m.specularColor;
    s.specularTexture = m.specularTexture;
    s.specularColorTexture = m.specularColorTexture;
    s.normalTexture = m.normalTexture;
    s.normalScale = m.normalScale;
    s.alphaMode = m.alphaMode;
    s.alpha = m.alpha;
    s.alphaCutoff = m.alphaCutoff;
    s.transmissionTexture = m.transmissionTexture;
    s.unlit = m.unlit != 0u;
    s.clearcoat = m.clearcoat;
    s.clearcoatRoughness = m.clearcoatRoughness;
    s.clearcoatTexture = m.clearcoatTexture;
    s.clearcoatRoughnessTexture = m.clearcoatRoughnessTexture;
    s.clearcoatNormalTexture = m.clearcoatNormalTexture;
    s.clearcoatNormalScale = m.clearcoatNormalScale;
    s.sheenColor = m.sheenColor;
    s.sheenRoughness = m.sheenRoughness;
    s.sheenColorTexture = m.sheenColorTexture;
    s.sheenRoughnessTexture = m.sheenRoughnessTexture;
    s.textureSlots = m.textureSlots;
    return s;
}

#endif
