// How a glTF metallic-roughness material shades in vkrt's distributed Whitted model (docs/materials.md
// explains the choices): Lambert diffuse lit by the lights; a GGX specular lobe lit by the lights and, where
// it can show the scene, traced (a mirror ray at roughness 0, a ray sampled from the visible normals above);
// refraction through the same microfacet normal, weighted by Fresnel.
#ifndef VKRT_SURFACE_RESPONSE_H
#define VKRT_SURFACE_RESPONSE_H

#include "energy_compensation.h"
#include "microfacet.h"
#include "optics.h"
#include "shading_language.h"
#include "sheen.h"
#include "texture_sampling.h"

// SurfaceMaterial::alphaMode: glTF's alphaMode.
#define VKRT_ALPHA_OPAQUE 0u
#define VKRT_ALPHA_MASK 1u   // alpha below the cutoff is a hole, else the surface is opaque
#define VKRT_ALPHA_BLEND 2u  // the surface covers the fraction alpha

VKRT_SHADING_BEGIN

// A material's factors as both renderers read them (textures are looked up separately).
struct SurfaceMaterial {
    real3 baseColor;  // linear factor; a base colour texture multiplies it
    real metallic;
    real3 emission;  // emissiveFactor * KHR_materials_emissive_strength; an emissive texture multiplies it
    real roughness;
    real3 attenuationColor;  // KHR_materials_volume
    real attenuationDistance;  // infinity: no absorption
    real transmission;
    real ior;
    bool volume;       // thickness > 0: the surface bounds a volume (else thin-walled)
    bool doubleSided;  // emits from both sides
    int baseColorTexture;          // texture binding (texture_sampling.h), -1: none
    int emissiveTexture;           // likewise
    int metallicRoughnessTexture;  // likewise: blue multiplies metallic, green roughness
    int occlusionTexture;          // likewise: red is how much ambient light reaches the surface
    real occlusionStrength;        // occlusion = 1 + strength (red - 1)
    real specularFactor;           // KHR_materials_specular: scales the dielectric's reflection (0: Lambertian)
    real3 specularColor;           // tints it at normal incidence
    int specularTexture;           // texture binding: alpha multiplies specularFactor
    int specularColorTexture;      // texture binding (sRGB): multiplies specularColor
    int normalTexture;             // texture binding: the tangent-space normal
    real normalScale;              // scales the normal's tangent-space x and y
    uint alphaMode;                // VKRT_ALPHA_*
    real alpha;                    // the base colour factor's alpha
    real alphaCutoff;              // VKRT_ALPHA_MASK: alpha below it is a hole
    int transmissionTexture;       // texture binding: red multiplies transmission
    bool unlit;                    // KHR_materials_unlit: the base colour is the radiance
    real clearcoat;                // KHR_materials_clearcoat: how much of the surface the coat covers
    real clearcoatRoughness;
    int clearcoatTexture;           // texture binding: red multiplies clearcoat
    int clearcoatRoughnessTexture;  // texture binding: green multiplies clearcoatRoughness
    int clearcoatNormalTexture;     // texture binding: the coat's tangent-space normal
    real clearcoatNormalScale;
    real3 sheenColor;               // KHR_materials_sheen (black: none)
    real sheenRoughness;
    int sheenColorTexture;          // texture binding (sRGB): multiplies sheenColor
    int sheenRoughnessTexture;      // texture binding: alpha multiplies sheenRoughness
    uint textureSlots;              // bit k: slot k (VKRT_SLOT_*) has a binding (materialTextureSlots)
};

// A material's inputs at one point: each factor times its texture.
struct MaterialSample {
    real3 albedo;  // base colour, linear
    real metallic;
    real roughness;
    real specular;        // KHR_materials_specular's factor
    real3 specularColor;  // and colour
    real occlusion;       // how much of the ambient light reaches the point
    real3 tangentNormal;  // the normal texture's normal in the tangent frame, x and y scaled; (0, 0, 1): none
    real coverage;        // how much of the point the surface covers (alphaMode)
    real transmission;    // KHR_materials_transmission's factor
    real clearcoat;       // KHR_materials_clearcoat's factor, roughness and normal (as tangentNormal)
    real clearcoatRoughness;
    real3 coatTangentNormal;
    real3 sheenColor;     // KHR_materials_sheen's colour and roughness
    real sheenRoughness;
    real3 emission;       // the emissive factor, times the emissive texture where sampleMaterial reads it
};

// How much of a point a surface whose base colour has alpha `alpha` there covers.
VKRT_FN real coverageOf(VKRT_IN(SurfaceMaterial) material, real alpha) {
    if (material.alphaMode == VKRT_ALPHA_MASK) return alpha >= material.alphaCutoff ? 1.0 : 0.0;
    if (material.alphaMode == VKRT_ALPHA_BLEND) return clamp(alpha, 0.0, 1.0);
    return 1.0;
}

// The factors alone, with base colour `albedo`.
VKRT_FN MaterialSample untexturedSample(VKRT_IN(SurfaceMaterial) material, real3 albedo) {
    MaterialSample s;
    s.albedo = albedo;
    s.metallic = material.metallic;
    s.roughness = material.roughness;
    s.specular = material.specularFactor;
    s.specularColor = material.specularColor;
    s.occlusion = 1.0;
    s.tangentNormal = real3(0.0, 0.0, 1.0);
    s.coverage = coverageOf(material, material.alpha);
    s.transmission = material.transmission;
    s.clearcoat = material.clearcoat;
    s.clearcoatRoughness = material.clearcoatRoughness;
    s.coatTangentNormal = real3(0.0, 0.0, 1.0);
    s.sheenColor = material.sheenColor;
    s.sheenRoughness = material.sheenRoughness;
    s.emission = material.emission;
    return s;
}

// The material's texture slots that sampleMaterial reads, in order.
#define VKRT_SLOT_BASE_COLOR 0
#define VKRT_SLOT_METALLIC_ROUGHNESS 1
#define VKRT_SLOT_OCCLUSION 2
#define VKRT_SLOT_SPECULAR 3
#define VKRT_SLOT_SPECULAR_COLOR 4
#define VKRT_SLOT_NORMAL 5
#define VKRT_SLOT_TRANSMISSION 6
#define VKRT_SLOT_CLEARCOAT 7
#define VKRT_SLOT_CLEARCOAT_ROUGHNESS 8
#define VKRT_SLOT_CLEARCOAT_NORMAL 9
#define VKRT_SLOT_SHEEN_COLOR 10
#define VKRT_SLOT_SHEEN_ROUGHNESS 11
#define VKRT_SLOT_EMISSIVE 12
#define VKRT_MATERIAL_SLOTS 13
// The slots shadowPassage depends on: base colour (the tint and alpha), metallic and transmission.
#define VKRT_SHADOW_SLOTS \
    ((1u << VKRT_SLOT_BASE_COLOR) | (1u << VKRT_SLOT_METALLIC_ROUGHNESS) | (1u << VKRT_SLOT_TRANSMISSION))

VKRT_FN int materialTexture(VKRT_IN(SurfaceMaterial) m, int slot) {
    if (slot == VKRT_SLOT_BASE_COLOR) return m.baseColorTexture;
    if (slot == VKRT_SLOT_METALLIC_ROUGHNESS) return m.metallicRoughnessTexture;
    if (slot == VKRT_SLOT_OCCLUSION) return m.occlusionTexture;
    if (slot == VKRT_SLOT_SPECULAR) return m.specularTexture;
    if (slot == VKRT_SLOT_SPECULAR_COLOR) return m.specularColorTexture;
    if (slot == VKRT_SLOT_NORMAL) return m.normalTexture;
    if (slot == VKRT_SLOT_TRANSMISSION) return m.transmissionTexture;
    if (slot == VKRT_SLOT_CLEARCOAT) return m.clearcoatTexture;
    if (slot == VKRT_SLOT_CLEARCOAT_ROUGHNESS) return m.clearcoatRoughnessTexture;
    if (slot == VKRT_SLOT_CLEARCOAT_NORMAL) return m.clearcoatNormalTexture;
    if (slot == VKRT_SLOT_SHEEN_COLOR) return m.sheenColorTexture;
    if (slot == VKRT_SLOT_SHEEN_ROUGHNESS) return m.sheenRoughnessTexture;
    return m.emissiveTexture;
}

// Which of the material's slots have a texture binding, one bit per slot: sampleMaterial visits only those.
VKRT_FN uint materialTextureSlots(VKRT_IN(SurfaceMaterial) m) {
    uint slots = 0u;
    for (int slot = 0; slot < VKRT_MATERIAL_SLOTS; ++slot) {
        if (materialTexture(m, slot) >= 0) slots |= 1u << uint(slot);
    }
    return slots;
}

// The material at a hit on `primitive` (hitUv: barycentrics, or a sphere's texture coordinates), its textures of
// the slots `slots` (bits, as textureSlots) filtered over `footprint`, the emissive one over `emissionFootprint`
// (sampleBinding); the others are left at their factors. The texture slots are read in a loop around one
// lookup: every inlined bilinear lookup costs code and registers in the whole kernel (on lavapipe, five separate
// lookup sites made textured scenes twice as slow). The loop visits the material's bound slots only, lowest first: a SIMD
// group on lavapipe runs a loop's whole body at every pass any of its lanes needs, so a loop over all twelve
// slots paid twelve lookups wherever a lane had one texture (textures.gltf's GPU time 2.1 times as long).
VKRT_DEVICE_TEMPLATE
VKRT_FN MaterialSample sampleSlots(VKRT_DEVICE_PARAM VKRT_IN(SurfaceMaterial) material, uint primitive, real2 hitUv,
                                   real footprint, real emissionFootprint, uint slots) {
    MaterialSample s = untexturedSample(material, material.baseColor);
    real alpha = material.alpha;
#ifdef VKRT_HAS_VERTEX_COLORS
    const real4 vertexColor = VKRT_DEVICE(vertexColor)(primitive, hitUv);
    s.albedo *= real3(vertexColor.x, vertexColor.y, vertexColor.z);
    alpha *= vertexColor.w;
#endif
#ifdef VKRT_HAS_TEXTURES
    for (; slots != 0u; slots &= slots - 1u) {
        const int slot = findLSB(slots);
        const int binding = materialTexture(material, slot);
        const real4 texel = sampleBinding(VKRT_DEVICE_ARG binding, primitive, hitUv,
                                          slot == VKRT_SLOT_EMISSIVE ? emissionFootprint : footprint);
        if (slot == VKRT_SLOT_BASE_COLOR) {
            s.albedo *= real3(texel.x, texel.y, texel.z);
            alpha *= texel.w;
        } else if (slot == VKRT_SLOT_METALLIC_ROUGHNESS) {
            s.roughness *= texel.y;
            s.metallic *= texel.z;
        } else if (slot == VKRT_SLOT_OCCLUSION) {
            s.occlusion = 1.0 + material.occlusionStrength * (texel.x - 1.0);
        } else if (slot == VKRT_SLOT_SPECULAR) {
            s.specular *= texel.w;
        } else if (slot == VKRT_SLOT_SPECULAR_COLOR) {
            s.specularColor *= real3(texel.x, texel.y, texel.z);
        } else if (slot == VKRT_SLOT_TRANSMISSION) {
            s.transmission *= texel.x;
        } else if (slot == VKRT_SLOT_CLEARCOAT) {
            s.clearcoat *= texel.x;
        } else if (slot == VKRT_SLOT_CLEARCOAT_ROUGHNESS) {
            s.clearcoatRoughness *= texel.y;
        } else if (slot == VKRT_SLOT_SHEEN_COLOR) {
            s.sheenColor *= real3(texel.x, texel.y, texel.z);
        } else if (slot == VKRT_SLOT_SHEEN_ROUGHNESS) {
            s.sheenRoughness *= texel.w;
        } else if (slot == VKRT_SLOT_EMISSIVE) {
            s.emission *= real3(texel.x, texel.y, texel.z);
        } else {
            // glTF: (2 texel - 1) * (scale, scale, 1), normalised where the frame is applied.
            const real scale = slot == VKRT_SLOT_NORMAL ? material.normalScale : material.clearcoatNormalScale;
            const real3 mapped = (2.0 * real3(texel.x, texel.y, texel.z) - 1.0) * real3(scale, scale, 1.0);
            if (slot == VKRT_SLOT_NORMAL) {
                s.tangentNormal = mapped;
            } else {
                s.coatTangentNormal = mapped;
            }
        }
    }
#endif
    s.coverage = coverageOf(material, alpha);
    return s;
}

// The material's inputs at a hit (sampleSlots): every texture it has, the emissive one only where it emits.
VKRT_DEVICE_TEMPLATE
VKRT_FN MaterialSample sampleMaterial(VKRT_DEVICE_PARAM VKRT_IN(SurfaceMaterial) material, uint primitive,
                                      real2 hitUv, real footprint, real emissionFootprint) {
    uint slots = material.textureSlots;
    if (!(maxComponent(material.emission) > 0.0)) slots &= ~(1u << uint(VKRT_SLOT_EMISSIVE));
    return sampleSlots(VKRT_DEVICE_ARG material, primitive, hitUv, footprint, emissionFootprint, slots);
}

// Whether a sphere light of `material` can be seen through: double-sided, with holes (alpha), so that the inside
// of its far half lights points outside (area_light.h's sphereSampledByArea).
VKRT_FN bool sphereSeenThrough(VKRT_IN(SurfaceMaterial) material) {
    return material.doubleSided && material.alphaMode != VKRT_ALPHA_OPAQUE;
}

// The coverage alone at a hit (sampleMaterial's, reading only what alpha depends on).
VKRT_DEVICE_TEMPLATE
VKRT_FN real coverageAt(VKRT_DEVICE_PARAM VKRT_IN(SurfaceMaterial) material, uint primitive, real2 hitUv,
                        real footprint) {
    if (material.alphaMode == VKRT_ALPHA_OPAQUE) return 1.0;
    real alpha = material.alpha;
#ifdef VKRT_HAS_VERTEX_COLORS
    alpha *= VKRT_DEVICE(vertexColor)(primitive, hitUv).w;
#endif
#ifdef VKRT_HAS_TEXTURES
    // A MASK cut-out is tested at the finest level: thresholding mip-averaged alpha would shrink it with
    // distance, and its shadow (shadow rays read level 0) would no longer match it.
    if (material.baseColorTexture >= 0) {
        alpha *= sampleBinding(VKRT_DEVICE_ARG material.baseColorTexture, primitive, hitUv,
                               material.alphaMode == VKRT_ALPHA_MASK ? 0.0 : footprint).w;
    }
#endif
    return coverageOf(material, alpha);
}

// The shading normal with a normal map applied: the tangent-space normal `tangentNormal` in the frame of the
// unit normal, the tangent (made orthogonal to it) and the bitangent w * cross(normal, tangent) (glTF 2.0,
// 3.9.3). Without a usable tangent (zero where a mesh's texture coordinates give none) the normal stays.
VKRT_FN real3 normalMapped(real3 normal, real4 tangent, real3 tangentNormal) {
    const real3 along = real3(tangent.x, tangent.y, tangent.z);
    const real3 t = along - normal * dot(normal, along);
    const real tLength = length(t);
    if (!(tLength > 0.0)) return normal;
    const real3 unitTangent = t / tLength;
    const real3 bitangent = (tangent.w < 0.0 ? -1.0 : 1.0) * cross(normal, unitTangent);
    const real3 mapped = tangentNormal.x * unitTangent + tangentNormal.y * bitangent + tangentNormal.z * normal;
    const real mappedLength = length(mapped);
    return mappedLength > 0.0 ? mapped / mappedLength : normal;
}

struct SurfaceResponse {
    real3 albedo;    // base colour (factor times texture), linear
    real3 diffuse;   // Lambert reflectance: albedo * (1 - metallic) * (1 - transmission), times diffuseShare
                     // once the viewer is known (shadeHit)
    real3 specular;  // F0: of the dielectric, or the base colour for metals
    real alpha;      // GGX width, roughness^2
    bool mirror;     // roughness 0: the lobe is a delta (exact mirror and refraction)
    bool traced;     // the specular lobe is traced (metals, transmission, roughness < 1)
    real transmission;  // (1 - metallic) * transmission
    real metallic;
    real ior;
    real specularWeight;  // KHR_materials_specular: the dielectric's reflection scale
    real3 specularTint;   // and its tint at normal incidence
    real clearcoat;       // KHR_materials_clearcoat: the coat's weight (0: none)
    real coatAlpha;       // its GGX width
    bool coatMirror;      // its lobe is a delta
    bool coatTraced;      // its lobe is traced (roughness < 1)
    real3 sheenColor;     // KHR_materials_sheen's colour (black: none)
    real sheenAlpha;      // its Charlie width
    real sheenScaling;    // what the sheen lets through to the layers below: 1 - max(sheenColor) E(mu_view)
    real sheenAlbedo;     // E(mu_view): the sheen's directional albedo towards the viewer
    // The energy compensation of the GGX lobes (energy_compensation.h; addEnergyCompensation sets them where
    // the viewer is known, 1 without):
    real3 metalCompensation;        // the metal's reflection: 1 + F0 (1 - E) / E, F0 the base colour
    real3 dielectricCompensation;   // the dielectric's: 1 + F0 (1 - E) / E, 1 / E_eta where it refracts
    real transmissionCompensation;  // its refraction: 1 / E_eta (1 for thin walls, which pass light straight)
    real coatCompensation;          // the coat's lobe: 1 / E (its Fresnel term is taken at the viewer)
};

VKRT_FN SurfaceResponse surfaceResponse(VKRT_IN(SurfaceMaterial) material, VKRT_IN(MaterialSample) inputs) {
    SurfaceResponse s;
    s.albedo = inputs.albedo;
    s.metallic = inputs.metallic;
    s.ior = material.ior;
    s.transmission = (1.0 - s.metallic) * inputs.transmission;
    s.diffuse = inputs.albedo * (1.0 - s.metallic) * (1.0 - inputs.transmission);
    s.specularWeight = inputs.specular;
    s.specularTint = inputs.specularColor;
    const real3 dielectricF0Tinted = min(dielectricF0(material.ior) * inputs.specularColor, real3(1.0)) * inputs.specular;
    s.specular = mix(dielectricF0Tinted, inputs.albedo, s.metallic);
    s.alpha = ggxAlpha(inputs.roughness);
    s.mirror = inputs.roughness < VKRT_MIRROR_ROUGHNESS;
    // A matte opaque dielectric (roughness 1, glTF's default) keeps its faint sheen to the lights and the
    // ambient term: tracing a ray per hit for it would double the cost of every diffuse scene. A dielectric
    // without specular reflection (KHR_materials_specular factor 0) has no lobe to trace. (The GPU's shader
    // leaves the traced lobes' code out where no material can trace one: scene_features.cpp's tracesLobe.)
    s.traced = s.metallic > 0.0 || s.transmission > 0.0 || (inputs.roughness < 1.0 && inputs.specular > 0.0);
    s.clearcoat = inputs.clearcoat;
    s.coatAlpha = ggxAlpha(inputs.clearcoatRoughness);
    s.coatMirror = inputs.clearcoatRoughness < VKRT_MIRROR_ROUGHNESS;
    s.coatTraced = inputs.clearcoat > 0.0 && inputs.clearcoatRoughness < 1.0;
    s.sheenColor = inputs.sheenColor;
    s.sheenAlpha = sheenAlpha(inputs.sheenRoughness);
    s.sheenScaling = 1.0;  // addSheen() sets these two where the viewer is known
    s.sheenAlbedo = 0.0;
    s.metalCompensation = real3(1.0);
    s.dielectricCompensation = real3(1.0);
    s.transmissionCompensation = 1.0;
    s.coatCompensation = 1.0;
    return s;
}

#ifdef VKRT_HAS_SHEEN
// The sheen's albedo towards a viewer at cosine cosView, and the scaling of the layers below it. Where the
// fitted shadowing makes the lobe reflect more than it receives (E > 1: the smoothest sheens seen within a few
// degrees of grazing, E up to 1.6), its colour is divided by E: it then reflects all the light and lets none
// below (a white sheen in a white furnace showed 1.6 at 0.3 degrees from grazing, 1.4 at 1 degree).
VKRT_DEVICE_TEMPLATE
VKRT_FN void addSheen(VKRT_DEVICE_PARAM VKRT_INOUT(SurfaceResponse) s, real sheenRoughness, real cosView) {
    const real albedo = sheenAlbedo(VKRT_DEVICE_ARG cosView, sheenRoughness);
    if (albedo > 1.0) s.sheenColor /= albedo;
    s.sheenAlbedo = albedo;
    s.sheenScaling = 1.0 - maxComponent(s.sheenColor) * s.sheenAlbedo;
}
#endif

// KHR_materials_clearcoat's coat: a dielectric of index 1.5 whose Fresnel term the extension defines by
// Schlick's approximation with F0 = 0.04.
#define VKRT_CLEARCOAT_F0 0.04

VKRT_FN real coatFresnel(real cosTheta) {
    return VKRT_CLEARCOAT_F0 + (1.0 - VKRT_CLEARCOAT_F0) * pow(1.0 - clamp(cosTheta, 0.0, 1.0), 5.0);
}

// The fraction of the light leaving the base towards a viewer at cosine cosView from the coat's normal that
// the coat lets through: 1 - clearcoat F(cosView), as the extension layers it.
VKRT_FN real coatTransmittance(VKRT_IN(SurfaceResponse) s, real cosView) {
    return s.clearcoat > 0.0 ? 1.0 - s.clearcoat * coatFresnel(cosView) : 1.0;
}

// The coat's specular lobe for light from `toLight` (its weight included), about the coat's normal; zero for a
// mirror coat (as specularBrdf). Its Fresnel term is taken at the viewer, F(Nc . V), as the extension layers
// it (so that what the coat reflects is what it takes from the layers below).
VKRT_FN real coatBrdf(VKRT_IN(SurfaceResponse) s, real3 coatNormal, real3 toViewer, real3 toLight) {
    const real cosOut = dot(coatNormal, toViewer), cosIn = dot(coatNormal, toLight);
    if (!(s.clearcoat > 0.0) || s.coatMirror || cosOut <= 0.0 || cosIn <= 0.0) return 0.0;
    const real3 halfway = normalize(toViewer + toLight);
    return s.clearcoat * coatFresnel(cosOut) * s.coatCompensation * ggxD(coatNormal, halfway, s.coatAlpha) *
           ggxG2(cosOut, cosIn, s.coatAlpha) / (4.0 * cosOut * cosIn);
}

// What an emissive surface under a coat (factor `clearcoat`) sends out at cosine cosTheta from its normal:
// 1 - clearcoat F(cosTheta) of its emission (KHR_materials_clearcoat, "Emission"). Both ways of finding an
// emitter (hits and light samples) use the geometric normal and the factor, so they estimate the same light.
VKRT_FN real coatedEmission(real clearcoat, real cosTheta) {
    return clearcoat > 0.0 ? 1.0 - clearcoat * coatFresnel(cosTheta) : 1.0;
}

// The probability with which the reflection continuation follows the coat's lobe rather than the base's.
VKRT_FN real coatPick(VKRT_IN(SurfaceResponse) s) {
    if (!s.coatTraced) return 0.0;
    return s.traced ? 0.5 : 1.0;
}

// The dielectric part's reflectance at a microfacet seen at cosine cosH, eta relative across the interface:
// the exact Fresnel term, tinted and scaled as KHR_materials_specular says. The extension tints f0 (to
// min(f0 cs, 1)) and leaves f90 white on Schlick's curve, so the tint moves the reflectance by
// (min(f0 cs, 1) - f0) (1 - (1 - cos)^5); that shift is added to the exact term, which it leaves exact where
// the tint is white. (Scaling the whole term by a tint that faded as (1 - cos)^5 made a tint of 2 reflect 1.6
// times the extension's reflectance at 60 degrees.) Beyond the critical angle inside a volume it is 1,
// neither scaled nor tinted: no light can pass there, and what the layer did not reflect was lost (a clear
// cube of specularFactor 0 in a white furnace showed 0.71, some pixels black).
VKRT_FN real3 dielectricReflectance(VKRT_IN(SurfaceResponse) s, real cosH, real eta) {
    if (totallyReflects(cosH, eta)) return real3(1.0);
    real3 reflectance = real3(fresnelDielectric(cosH, eta));
    if (s.specularTint != real3(1.0)) {  // most materials: white, and no fifth power to take
        const real f0 = dielectricF0(eta);
        const real weight = 1.0 - pow(1.0 - clamp(cosH, 0.0, 1.0), 5.0);
        reflectance = clamp(reflectance + (min(f0 * s.specularTint, real3(1.0)) - f0) * weight, real3(0.0),
                            real3(1.0));
    }
    return reflectance * s.specularWeight;
}

// The fraction of light a surface lets through a shadow ray: all of it where the surface is missing (alpha),
// and where it covers the point, what its transmission lets through (shadow rays do not refract, and no Fresnel
// loss is taken), unless `transmissionBlocks` (the path integrator's shadow rays at a volume's boundary: light
// refracted into and out of glass reaches a point along a bent line, which a straight shadow ray does not follow).
VKRT_FN real3 shadowTint(VKRT_IN(MaterialSample) inputs, bool transmissionBlocks) {
    const real3 transmitted = transmissionBlocks ? real3(0.0) : (1.0 - inputs.metallic) * inputs.transmission * inputs.albedo;
    return (1.0 - inputs.coverage) + inputs.coverage * transmitted;
}

// A shadow ray's passage, as the shadow walk returns it: in xyz the product of the crossed surfaces' shadowTint,
// which lights the lobes no ray is traced for, and paths by punctual lights; in w the product of their holes
// alone (1 - coverage), by which area lights and the environment light Whitted's traced lobes and paths: their
// own rays bring the light of those that transmissive surfaces let through, and with the transmission in the
// light sample too, a glossy surface behind glass counted that light twice.
VKRT_FN real4 shadowPassage(VKRT_IN(MaterialSample) inputs, bool transmissionBlocks) {
    return real4(shadowTint(inputs, transmissionBlocks), 1.0 - inputs.coverage);
}

// What of a shadow ray passes a surface of `material` at a hit (shadowPassage), its textures read at the finest
// level, and only those the passage depends on.
VKRT_DEVICE_TEMPLATE
VKRT_FN real4 shadowPassageAt(VKRT_DEVICE_PARAM VKRT_IN(SurfaceMaterial) material, uint primitive, real2 hitUv,
                              bool transmissionBlocks) {
    return shadowPassage(
        sampleSlots(VKRT_DEVICE_ARG material, primitive, hitUv, 0.0, 0.0, material.textureSlots & VKRT_SHADOW_SLOTS),
        transmissionBlocks);
}

// Fresnel reflectance at a microfacet seen at cosine cosH; eta relative across the interface.
VKRT_FN real3 fresnelAt(VKRT_IN(SurfaceResponse) s, real cosH, real eta) {
    return (1.0 - s.metallic) * dielectricReflectance(s, cosH, eta) + s.metallic * fresnelSchlick(s.albedo, cosH);
}

// What the dielectric's specular layer leaves its diffuse base, seen at cosine cosView from the normal, eta the
// relative index across the surface: 1 - max(F(cosView)), F the dielectric part's reflectance (scaled and
// tinted by KHR_materials_specular), as KHR_materials_clearcoat layers its coat. The base loses what the layer
// reflects towards the viewer, so a white surface reflects at most what it receives: all of it where the layer
// is smooth, a little less at grazing where it is rough (a white furnace, gpu_energy_test.cpp). glTF's sample
// BRDF (2.0, Appendix B) takes F at the half vector instead, and its mix over a white Lambertian base reflects
// up to 2% more than it receives.
VKRT_FN real diffuseShare(VKRT_IN(SurfaceResponse) s, real cosView, real eta) {
    return 1.0 - maxComponent(dielectricReflectance(s, clamp(cosView, 0.0, 1.0), eta));
}

// fresnelAt with each part's energy compensation: the specular lobe's reflection, traced or lit.
VKRT_FN real3 compensatedFresnelAt(VKRT_IN(SurfaceResponse) s, real cosH, real eta) {
    return (1.0 - s.metallic) * dielectricReflectance(s, cosH, eta) * s.dielectricCompensation +
           s.metallic * fresnelSchlick(s.albedo, cosH) * s.metalCompensation;
}

// The specular lobe for light from `toLight`: F D G2 / (4 cos_o cos_i), energy compensated; zero for a
// mirror (a delta lobe meets a light of zero size with probability zero, and area lights reach mirrors
// through traced rays).
VKRT_FN real3 specularBrdf(VKRT_IN(SurfaceResponse) s, real3 normal, real3 toViewer, real3 toLight) {
    const real cosOut = dot(normal, toViewer), cosIn = dot(normal, toLight);
    if (s.mirror || cosOut <= 0.0 || cosIn <= 0.0) return real3(0.0);
    const real3 halfway = normalize(toViewer + toLight);
    return compensatedFresnelAt(s, dot(toViewer, halfway), s.ior) * ggxD(normal, halfway, s.alpha) *
           ggxG2(cosOut, cosIn, s.alpha) / (4.0 * cosOut * cosIn);
}

#ifdef VKRT_HAS_ROUGH_SPECULAR
// The energy compensation of the GGX lobes (energy_compensation.h) for a viewer at cosine cosView from the
// normal and cosCoatView from the coat's; `transmission` is the dielectric's transmission factor and `eta`
// the relative index across the interface, read when `refracts` (a volume: light refracts through the
// microfacets; a thin wall passes it straight and loses none there). The material is a blend of a metal
// (weight m), a refracting dielectric ((1 - m) t) and an opaque one ((1 - m) (1 - t)), each compensated as
// its own. The coat's Fresnel term is taken at the viewer, outside the lobe's integral, so its lobe is
// scaled by 1 / E: it then reflects exactly what it takes from the layers below. Mirrors lose nothing and
// keep 1.
VKRT_DEVICE_TEMPLATE
VKRT_FN void addEnergyCompensation(VKRT_DEVICE_PARAM VKRT_INOUT(SurfaceResponse) s, real transmission,
                                   real cosView, real cosCoatView, real eta, bool refracts) {
    if (!s.mirror && (maxComponent(s.specular) > 0.0 || s.transmission > 0.0)) {
        const real roughness = sqrt(s.alpha);
        const real loss = 1.0 / ggxAlbedo(VKRT_DEVICE_ARG cosView, roughness) - 1.0;  // (1 - E) / E
        s.metalCompensation = real3(1.0) + s.albedo * loss;
        const real3 opaqueF0 = min(dielectricF0(s.ior) * s.specularTint, real3(1.0)) * s.specularWeight;
        s.dielectricCompensation = real3(1.0) + opaqueF0 * loss;
#if defined(VKRT_HAS_VOLUMES) && defined(VKRT_HAS_ROUGH_REFRACTION)
        if (refracts) {
            s.transmissionCompensation = 1.0 / ggxDielectricAlbedo(VKRT_DEVICE_ARG cosView, roughness, eta);
            s.dielectricCompensation =
                mix(s.dielectricCompensation, real3(s.transmissionCompensation), transmission);
        }
#endif
    }
#ifdef VKRT_HAS_CLEARCOAT
    if (s.clearcoat > 0.0 && !s.coatMirror) {
        s.coatCompensation = 1.0 / ggxAlbedo(VKRT_DEVICE_ARG cosCoatView, sqrt(s.coatAlpha));
    }
#endif
}
#endif

// Density with which the traced lobes would have chosen `toLight` (0 when none is traced): the base's, and the
// coat's (about `coatNormal`) with the probability coatPick gives it.
VKRT_FN real lobePdf(VKRT_IN(SurfaceResponse) s, real3 normal, real3 coatNormal, real3 toViewer, real3 toLight) {
    const real3 halfway = normalize(toViewer + toLight);
    const real pick = coatPick(s);
    real pdf = 0.0;
    if (s.traced && !s.mirror) pdf = (1.0 - pick) * ggxReflectionPdf(dot(normal, toViewer), normal, halfway, s.alpha);
    if (s.coatTraced && !s.coatMirror) {
        pdf += pick * ggxReflectionPdf(dot(coatNormal, toViewer), coatNormal, halfway, s.coatAlpha);
    }
    return pdf;
}

// Whether reflectedLight can be other than 0: the surface has a lobe that is not a delta (Lambert, a rough
// specular lobe, sheen, a rough coat). A mirror or smooth glass reflects lights only by its traced rays, and
// a shadow ray from it would add exactly 0.
VKRT_FN bool reflectsLights(VKRT_IN(SurfaceResponse) s) {
    bool reflects = maxComponent(s.diffuse) > 0.0 || !s.mirror;
#ifdef VKRT_HAS_SHEEN
    reflects = reflects || maxComponent(s.sheenColor) > 0.0;
#endif
#ifdef VKRT_HAS_CLEARCOAT
    reflects = reflects || (s.clearcoat > 0.0 && !s.coatMirror);
#endif
    return reflects;
}

// Light arriving from `toLight` with irradiance `irradiance` (on a surface facing it), reflected towards the
// viewer: Lambert plus the specular lobe, under the sheen, if any, which scales them and adds its own lobe, and
// the coat, if any, which adds its own lobe about `coatNormal`. The traced lobes are weighted `tracedWeight`,
// the others (diffuse, sheen, a specular lobe or coat that is not traced) `untracedWeight`: the multiple
// importance sampling weights of a light sample against the strategies that also reach each lobe, times what
// each group sees of the light (directLight's shadow passage), per channel.
//
// A scene without rough or traced lobes (VKRT_HAS_ROUGH_SPECULAR, VKRT_HAS_TRACED_LOBES; scene_features.cpp)
// has no metal, transmission, coat or KHR_materials_specular factor above 0: its specular lobe is 0 everywhere,
// and its shader leaves the lobe out.
VKRT_FN real3 reflectedLight(VKRT_IN(SurfaceResponse) s, real3 normal, real3 coatNormal, real3 toViewer,
                             real3 toLight, real3 irradiance, real3 tracedWeight, real3 untracedWeight) {
#if defined(VKRT_HAS_ROUGH_SPECULAR) || defined(VKRT_HAS_TRACED_LOBES)
    const real3 brdf = untracedWeight * s.diffuse / VKRT_PI +
                       (s.traced ? tracedWeight : untracedWeight) * specularBrdf(s, normal, toViewer, toLight);
#else
    const real3 brdf = untracedWeight * s.diffuse / VKRT_PI;
#endif
    real3 reflected = brdf * irradiance * max(dot(normal, toLight), 0.0);  // 0 where only the coat faces it
#ifdef VKRT_HAS_SHEEN
    if (maxComponent(s.sheenColor) > 0.0) {
        reflected = reflected * s.sheenScaling + untracedWeight * s.sheenColor *
                                                     sheenLobe(normal, toViewer, toLight, s.sheenAlpha) * irradiance *
                                                     max(dot(normal, toLight), 0.0);
    }
#endif
#ifdef VKRT_HAS_CLEARCOAT
    if (s.clearcoat > 0.0) {
        reflected = reflected * coatTransmittance(s, dot(coatNormal, toViewer)) +
                    (s.coatTraced ? tracedWeight : untracedWeight) * coatBrdf(s, coatNormal, toViewer, toLight) *
                        irradiance * max(dot(coatNormal, toLight), 0.0);
    }
#endif
    return reflected;
}

VKRT_SHADING_END

#endif  // VKRT_SURFACE_RESPONSE_H
