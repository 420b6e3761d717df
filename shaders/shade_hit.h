// One shading step of vkrt's two integrators, shared by both devices' loops (trace.comp on the GPU,
// host/cpu/reference_renderer.cpp on the CPU): at a hit, the light leaving towards the viewer from the hit
// itself (emission, Whitted's ambient term, direct light from punctual and area lights and the environment with
// shadow rays) and the continuation rays with their weights: reflection and transmission through one sampled
// microfacet normal, which distributed Whitted ray tracing follows both of, and for the path integrator a
// third, the lobes that are not traced (diffuse, sheen, a matte specular lobe or coat) sampled by the cosine;
// continuePath picks one of the three for the path's next bounce.
// What each device owns, it provides through VKRT_DEVICE (shading_language.h): materials (material, materialOf),
// textures (textureInfo, texel, textureCoordinates), lights (punctualLightCount, punctualLight, hasAreaLights,
// sampleAreaLight, lightSolidAnglePdf), the environment (hasEnvironment and the tables environment.h reads),
// shadow rays (shadowTransmittance), and in its own precision the rules shared.h sets for both: the ray offset
// (offsetOrigin) and how far short of a light point a shadow ray stops (shadowRayLength).
#ifndef VKRT_SHADE_HIT_H
#define VKRT_SHADE_HIT_H

#include "area_light.h"
#include "media.h"
#include "microfacet.h"
#include "optics.h"
#include "punctual_light.h"
#include "random.h"
#include "shading_language.h"
#include "surface_response.h"
#include "texture_sampling.h"
#ifdef VKRT_HAS_ENVIRONMENT
#include "environment.h"  // after the device's environment functions (GLSL: device_lights.glsl)
#endif

VKRT_SHADING_BEGIN

#ifdef __cplusplus
using ::vkrt::vkrtLayered;
using ::vkrt::vkrtNodeDimension;
using ::vkrt::vkrtStratifiedFrom;
#endif

// What stays fixed for every ray of one camera sample.
struct ShadingContext {
    real3 ambient;       // Whitted's ambient radiance, lighting the diffuse albedo
    real3 background;    // the radiance of rays that leave the scene, when there is no environment
    bool paths;          // the path integrator (else distributed Whitted ray tracing)
    bool environmentBackdrop;  // camera rays that leave the scene see the environment (else the background)
    real minThroughput;  // Whitted: branches weighted less than this are cut (branchSurvival)
    int maxDepth;        // reflection and refraction bounces after the camera ray's hit
    uint lightSamples;   // area-light samples per shading point
    bool multipleImportanceSampling;
    bool energyCompensation;   // GGX lobes make up for what single scattering loses (energy_compensation.h)
    uint stream;         // the pixel's random numbers (random.h's vkrtPixelStream of the seed and the pixel)
    uint pairRoot;       // and its stratified pairs' (vkrtPairRoot)
    uint sampleIndex;
};

// One ray of the ray tree: where it starts and goes, and what it carries.
struct RayState {
    real3 origin;
    real3 direction;
    real3 throughput;  // the weight of this branch of the tree so far
    uint node;         // whose random dimensions the ray's hit draws (childNode)
    int depth;
    uint exclude;      // the primitive the ray leaves (VKRT_NO_PRIMITIVE: none)
    real arrivalPdf;   // the density with which a glossy lobe chose the ray (0: camera, mirror, refraction)
    real3 shadingPoint;  // where that lobe was sampled: the hit the ray left, before the origin's offset (else origin)
    uvec2 media;       // the volumes the ray is inside (media.h)
    real coneWidth;    // the ray's cone (camera.h's cameraCone): its width at the origin
    real coneSpread;   // and its spread angle
    bool backdrop;     // a camera ray, or one only passed through surfaces since: it sees the background
};

// Where a ray met a surface, as the device computed it in its own precision.
struct HitPoint {
    real3 position;
    real errorScale;        // the magnitude of the numbers `position` came from (for the ray offset)
    real3 geometricNormal;  // unit normals of the front (outside) side, at the hit's shutter time
    real3 normal;
    real4 tangent;  // normal-mapped triangles: the tangent frame (surface_response.h's normalMapped), else 0
    real2 uv;       // barycentric weights of v1 and v2 (triangles), texture coordinates (spheres, solids)
    uint primitive;
    uint material;
    bool sphere;
    uint shape;  // solids: the scene's shape whose surface this is; else VKRT_NO_PRIMITIVE
    uint face;   // solids: which face of that shape (shape_geometry.h's VKRT_FACE_...)
};

// A hit seen from the ray that found it: normals turned towards the viewer, where new rays start, and which
// primitive they skip.
struct ShadingFrame {
    real3 position;
    real3 toViewer;         // back along the arriving ray
    real3 geometricNormal;  // on the viewer's side
    real3 normal;           // the shading normal, on the viewer's side (the geometric one where it faced away)
    real3 coatNormal;       // the clear coat's, likewise (KHR_materials_clearcoat; else the shading normal)
    bool frontFace;         // the viewer is outside (in front of) the surface
    real3 viewerSide;       // where rays to the viewer's side start (shadow rays, reflections)
    uint primitive;
    uint excludeOnViewerSide;  // what those rays skip: the primitive, unless they leave a sphere's inside
    uint excludeBeyond;        // what transmitted rays skip: the primitive, unless they enter a sphere
};

// The shading step's result. A continuation's throughput already includes its weight.
struct ShadedHit {
    real3 radiance;  // towards the viewer from the hit itself
    bool reflects;
    real3 reflectionWeight;
    RayState reflection;
    bool transmits;
    real3 transmissionWeight;
    RayState transmission;
    bool scatters;  // paths: the untraced lobes' continuation, sampled by the cosine
    real3 scatterWeight;
    RayState scattered;
    // At a volume's surface, the indices of the medium the ray is in and of the one beyond, which continuePath
    // reads for the energy its continuations carry; 1 elsewhere.
    real indexHere;
    real indexBeyond;
};

// Whether a traced lobe whose `mirror` flag (SurfaceResponse's `mirror` or `coatMirror`) is given is traced
// as a delta (exact mirror and refraction). In a shader for a scene whose traced lobes are all mirrors (no
// VKRT_HAS_GLOSSY_LOBES: scene_features.cpp's tracesGlossyLobe), always: sampling GGX's visible normals and
// the G2 / G1 weights then drop out of the kernel, which a SIMD device (lavapipe) would otherwise run,
// masked, at every hit (issue 13).
VKRT_FN bool tracedAsMirror(bool mirror) {
#ifdef VKRT_HAS_GLOSSY_LOBES
    return mirror;
#else
    return true;
#endif
}

// The random-number node of a continuation of `ray` (`branch` 1: reflection, 2: transmission, 3: the untraced
// lobes): Whitted's ray tree numbers its nodes as a binary heap (the children of k are 2k + 1 and 2k + 2); a
// path has one node per bounce.
VKRT_FN uint childNode(VKRT_IN(ShadingContext) context, VKRT_IN(RayState) ray, uint branch) {
    return context.paths ? ray.node + 1u : 2u * ray.node + branch;
}

VKRT_FN RayState rayState(real3 origin, real3 direction, real3 throughput, uint node, int depth, uint exclude,
                          real arrivalPdf, uvec2 media) {
    RayState ray;
    ray.origin = origin;
    ray.direction = direction;
    ray.throughput = throughput;
    ray.node = node;
    ray.depth = depth;
    ray.exclude = exclude;
    ray.arrivalPdf = arrivalPdf;
    ray.shadingPoint = origin;
    ray.media = media;
    ray.coneWidth = 0.0;
    ray.coneSpread = 0.0;
    ray.backdrop = depth == 0;
    return ray;
}

// The ray `ray` continued from a hit where its cone is `width` wide: the cone goes on with the same spread
// (surfaces are taken as flat: curvature and roughness do not widen it).
VKRT_FN RayState withCone(RayState ray, real width, real spread) {
    ray.coneWidth = width;
    ray.coneSpread = spread;
    return ray;
}

// The width of `ray`'s cone at `position` (0 in shaders where no texture has levels of detail: cones are not
// followed there).
VKRT_FN real coneWidthAt(VKRT_IN(RayState) ray, real3 position) {
#ifdef VKRT_HAS_MIPMAPS
    return ray.coneWidth + ray.coneSpread * length(position - ray.origin);
#else
    return 0.0;
#endif
}

// The footprint a texture lookup filters over (texture_sampling.h's sampleBinding) where `ray` meets the surface
// at `hit`: the cone's width, stretched by the obliquity as an isotropic filter can: the circle with the area of
// the elliptical footprint, width / sqrt(|cos|). On a solid it is in the texture coordinates of the shape hit
// (the device's textureDensity is 1 there): a CSG object's shapes each have their own scale.
VKRT_DEVICE_TEMPLATE
VKRT_FN real textureFootprint(VKRT_DEVICE_PARAM VKRT_IN(RayState) ray, VKRT_IN(HitPoint) hit) {
#ifdef VKRT_HAS_MIPMAPS
    real width = coneWidthAt(ray, hit.position) / sqrt(max(abs(dot(hit.geometricNormal, ray.direction)), 1e-4));
#ifdef VKRT_HAS_SHAPES
    if (hit.shape != VKRT_NO_PRIMITIVE) {
        AffineRows toObject, toWorld;
        VKRT_DEVICE(shapeMaps)(hit.shape, toObject, toWorld);
        width *= shapeTextureDensity(VKRT_DEVICE(shapeType)(hit.shape), hit.face, hit.uv,
                                     dot(real3(toWorld.row0), cross(real3(toWorld.row1), real3(toWorld.row2))));
    }
#endif
    return width;
#else
    return 0.0;
#endif
}

VKRT_FN real stratified(VKRT_IN(ShadingContext) context, uint dimension, uint axis) {
    return real(vkrtStratifiedFrom(context.pairRoot, context.sampleIndex, dimension, axis));
}

// The most surfaces with holes (alpha) a ray passes through; the next one it meets stops it as if covered.
#define VKRT_MAX_ALPHA_LAYERS 64u

// Whether `ray`, which met a surface at `hit`, goes on through it: where the surface's
// alpha leaves a hole (MASK), or with probability 1 - alpha (BLEND, an unbiased estimate of partial coverage).
// `layer` counts the surfaces it has passed so far.
VKRT_DEVICE_TEMPLATE
VKRT_FN bool passesThrough(VKRT_DEVICE_PARAM VKRT_IN(ShadingContext) context, VKRT_IN(RayState) ray, uint layer,
                           VKRT_IN(HitPoint) hit) {
    VKRT_IN(SurfaceMaterial) material = VKRT_DEVICE(material)(hit.material);
    if (material.alphaMode == VKRT_ALPHA_OPAQUE || layer >= VKRT_MAX_ALPHA_LAYERS) return false;
    // An emitter's coverage at the finest level, where its emission is read (shadeHit).
    const real coverage = coverageAt(VKRT_DEVICE_ARG material, hit.primitive, hit.uv,
                                     maxComponent(material.emission) > 0.0 ? 0.0
                                                                           : textureFootprint(VKRT_DEVICE_ARG ray, hit));
    if (coverage >= 1.0) return false;
    if (coverage <= 0.0) return true;
    return real(vkrtLayered(context.stream, context.pairRoot, context.sampleIndex,
                            vkrtNodeDimension(ray.node, VKRT_DIM_COVERAGE), layer)) >= coverage;
}

// A GGX microfacet normal of width `alpha` about `normal` visible from `toViewer` (Heitz 2018), drawn with the
// stratified pair at `dimension`.
VKRT_FN real3 visibleMicroNormalAt(real3 normal, real3 toViewer, real alpha, real u1, real u2) {
    real3 tangent, bitangent;
    orthonormalBasis(normal, tangent, bitangent);
    const real3 m = sampleGgxVisibleNormal(real3(dot(toViewer, tangent), dot(toViewer, bitangent), dot(normal, toViewer)),
                                           alpha, u1, u2);
    return normalize(m.x * tangent + m.y * bitangent + m.z * normal);
}

VKRT_FN real3 visibleMicroNormal(VKRT_IN(ShadingContext) context, uint dimension, real3 normal, real3 toViewer,
                                 real alpha) {
    return visibleMicroNormalAt(normal, toViewer, alpha, stratified(context, dimension, 0u),
                                stratified(context, dimension, 1u));
}

#if defined(VKRT_HAS_VOLUMES) && defined(VKRT_HAS_ROUGH_REFRACTION)
// The most visible normals compensatedMicroNormal draws for one scattering.
#define VKRT_COMPENSATION_TRIES 8u

// What a rough refracting interface sends on through the visible normal m, with the exact Fresnel term F at
// relative index eta: F G2 / G1 where the reflection leaves above the surface, plus (1 - F) G2 / G1 where the
// refraction leaves below; between 0 and 1. Its mean over visible normals is the dielectric table's E_eta (the
// integrand of ggxAlbedoIntegral), here with the geometric normal's checks that the traced rays make too.
VKRT_FN real refractingLobeShare(real3 normal, real3 geometricNormal, real3 toViewer, real3 m, real alpha,
                                 real eta) {
    const real cosOut = dot(normal, toViewer);
    const real fresnel = fresnelDielectric(max(0.0, dot(m, toViewer)), eta);
    const real3 reflected = reflectAbout(toViewer, m);
    const real cosReflected = dot(normal, reflected);
    real share = 0.0;
    if (cosReflected > 0.0 && dot(geometricNormal, reflected) > 0.0) {
        share += fresnel * ggxG2(cosOut, cosReflected, alpha);
    }
    real3 refracted;
    if (fresnel < 1.0 && refractThrough(toViewer, m, eta, refracted)) {
        const real cosRefracted = dot(normal, refracted);
        if (cosRefracted < 0.0 && dot(geometricNormal, refracted) < 0.0) {
            share += (1.0 - fresnel) * ggxG2(cosOut, -cosRefracted, alpha);
        }
    }
    return share / ggxG1(cosOut, alpha);
}

// A rough refracting dielectric's visible normal with its energy compensation drawn rather than weighed.
// Weighing both continuations of a visible normal by 1 / E_eta (Turquin 2019) gives each scattering a weight
// of up to 1 / E_eta (3.3 inside glass of index 3 at roughness 1, where E_eta is 0.3) for a mean of 1, and the
// weights multiply along the chains of internal reflections inside dense glass: a white furnace showed
// single pixels of 20 to 170. Here a visible normal m is kept with probability a(m) = refractingLobeShare, whose
// mean is E_eta, so that kept normals are distributed as the energy the lobe scatters; up to
// VKRT_COMPENSATION_TRIES are drawn (the first with the lobe's stratified pair, the others hashed from it).
// `scale`, by which the kept normal's continuations are weighed besides 1 / E_eta (lobeAlbedo, the table's), is
// E_eta / (a(m) (1 - (1 - E_eta)^N)) (N the tries): the same expectation, each scattering's weight now at most
// 1 / (1 - (1 - E_eta)^N) (1.06 at E_eta 0.3); 0 where no normal was kept, which ends the continuations.
VKRT_FN real3 compensatedMicroNormal(VKRT_IN(ShadingContext) context, uint node, real3 normal, real3 geometricNormal,
                                     real3 toViewer, real alpha, real eta, real lobeAlbedo, VKRT_OUT(real) scale) {
    const uint dimension = vkrtNodeDimension(node, VKRT_DIM_LOBE_U);
    const uint acceptDimension = vkrtNodeDimension(node, VKRT_DIM_LOBE_ACCEPT);
    scale = 0.0;
    real3 m = normal;
    for (uint k = 0u; k < VKRT_COMPENSATION_TRIES; ++k) {
        const real u1 = real(vkrtLayered(context.stream, context.pairRoot, context.sampleIndex, dimension, 2u * k));
        const real u2 = real(vkrtLayered(context.stream, context.pairRoot, context.sampleIndex, dimension, 2u * k + 1u));
        m = visibleMicroNormalAt(normal, toViewer, alpha, u1, u2);
        const real share = refractingLobeShare(normal, geometricNormal, toViewer, m, alpha, eta);
        if (real(vkrtLayered(context.stream, context.pairRoot, context.sampleIndex, acceptDimension, k)) < share) {
            scale = lobeAlbedo / (share * (1.0 - pow(1.0 - lobeAlbedo, real(VKRT_COMPENSATION_TRIES))));
            break;
        }
    }
    return m;
}
#endif

// The index of refraction of the innermost volume, 1 (air) outside every volume.
VKRT_DEVICE_TEMPLATE
VKRT_FN real mediumIor(VKRT_DEVICE_PARAM uvec2 media) {
    const int top = innermostMedium(media);
    if (top < 0) return 1.0;
    VKRT_IN(SurfaceMaterial) medium = VKRT_DEVICE(material)(uint(top));
    return medium.ior;
}

// Beer-Lambert absorption of the innermost volume over `distance` (infinity: the ray left the scene).
VKRT_DEVICE_TEMPLATE
VKRT_FN real3 absorptionAlong(VKRT_DEVICE_PARAM uvec2 media, real distance) {
#ifdef VKRT_HAS_ABSORPTION  // else every volume's attenuation is 1 (scene_features.cpp's absorbs)
    const int top = innermostMedium(media);
    if (top >= 0) {
        VKRT_IN(SurfaceMaterial) medium = VKRT_DEVICE(material)(uint(top));
        return beerLambert(medium.attenuationColor, medium.attenuationDistance, distance);
    }
#endif
    return real3(1.0);
}

// The media beyond a hole (passesThrough) that a ray going along `direction` passes at `hit`. A transmissive
// volume's surface with holes bounds its medium all the same: alpha takes its interface away (no reflection,
// no refraction), not the medium, so the ray enters or leaves the volume there as through its surface. (Left
// as they were, a ray that left a volume through a hole was still taken to be inside it, and what it met beyond
// was absorbed as if at the end of an infinite path: black.)
VKRT_DEVICE_TEMPLATE
VKRT_FN uvec2 mediaBeyondHole(VKRT_DEVICE_PARAM uvec2 media, VKRT_IN(HitPoint) hit, real3 direction) {
#ifdef VKRT_HAS_VOLUMES
    VKRT_IN(SurfaceMaterial) material = VKRT_DEVICE(material)(hit.material);
    if (material.volume && material.transmission > 0.0) {
        return dot(hit.geometricNormal, direction) < 0.0 ? mediaEntered(media, hit.material)
                                                         : mediaExited(media, hit.material);
    }
#endif
    return media;
}

// The linear part of the texture transform that tangent frames follow, as rows (texturedTangent): that of the
// base's normal texture, else of the coat's (the host's Material::tangentFrameSlot); the identity without either.
// Meshes' frames follow it when the scene is loaded; spheres' and shapes' at their hits.
#ifdef VKRT_HAS_NORMAL_MAPS
VKRT_DEVICE_TEMPLATE
VKRT_FN void tangentFrameTurn(VKRT_DEVICE_PARAM uint materialIndex, VKRT_OUT(real2) row0, VKRT_OUT(real2) row1) {
    VKRT_IN(SurfaceMaterial) material = VKRT_DEVICE(material)(materialIndex);
    const int binding = material.normalTexture >= 0 ? material.normalTexture : material.clearcoatNormalTexture;
    row0 = real2(1.0, 0.0);
    row1 = real2(0.0, 1.0);
#ifdef VKRT_HAS_TEXTURES
    if (binding >= 0) {
        VKRT_IN(GpuTextureBinding) b = VKRT_DEVICE(textureBinding)(binding);
        row0 = real2(real(b.row0.x), real(b.row0.y));
        row1 = real2(real(b.row1.x), real(b.row1.y));
    }
#endif
}
#endif

// Orients a hit towards the ray that found it (shadeHit's first step).
VKRT_DEVICE_TEMPLATE
VKRT_FN ShadingFrame shadingFrame(VKRT_DEVICE_PARAM VKRT_IN(RayState) ray, VKRT_IN(HitPoint) hit) {
    ShadingFrame frame;
    frame.position = hit.position;
    frame.toViewer = -ray.direction;
    frame.primitive = hit.primitive;
    // Orient both normals towards the viewer; remember which side was hit.
    frame.frontFace = dot(hit.geometricNormal, frame.toViewer) > 0.0;
    frame.geometricNormal = frame.frontFace ? hit.geometricNormal : -hit.geometricNormal;
    frame.normal = frame.frontFace ? hit.normal : -hit.normal;
    if (!(dot(frame.normal, frame.toViewer) > 0.0)) frame.normal = frame.geometricNormal;  // faces away: the true one
    frame.coatNormal = frame.normal;
    frame.viewerSide = VKRT_DEVICE(offsetOrigin)(hit.position, hit.errorScale, frame.geometricNormal);
    // New rays skip the primitive they leave, except rays that go into a sphere (they must find its far
    // side); a ray leaving a sphere's outside cannot meet the sphere again. Solids are never skipped (a CSG
    // object need not be convex): their crossings lie beyond the offset origin (shape_geometry.h).
    const bool solid = hit.shape != VKRT_NO_PRIMITIVE;
    frame.excludeOnViewerSide = solid || (hit.sphere && !frame.frontFace) ? VKRT_NO_PRIMITIVE : hit.primitive;
    frame.excludeBeyond = solid || (hit.sphere && frame.frontFace) ? VKRT_NO_PRIMITIVE : hit.primitive;
    return frame;
}

// A front-side normal `front` turned to the viewer's side of `frame`, or the geometric normal where it faces away.
VKRT_FN real3 viewerSideNormal(VKRT_IN(ShadingFrame) frame, real3 front) {
    const real3 n = frame.frontFace ? front : -front;
    return dot(n, frame.toViewer) > 0.0 ? n : frame.geometricNormal;
}

// Whether light from `toLight` can reach the viewer's side of the surface and one of its lobes: above the
// geometric surface, and above the shading normal or the coat's (a normal texture can tilt them apart).
VKRT_FN bool facesLight(VKRT_IN(ShadingFrame) frame, real3 toLight) {
    return dot(frame.geometricNormal, toLight) > 0.0 &&
           (dot(frame.normal, toLight) > 0.0 || dot(frame.coatNormal, toLight) > 0.0);
}

// The density with which the untraced lobes' continuation (cosine-distributed about `normal`) would have chosen
// `toLight`.
VKRT_FN real cosinePdf(real3 normal, real3 toLight) {
    return max(dot(normal, toLight), 0.0) / VKRT_PI;
}

// One light sample of directLight: the shadow ray to trace, and what the light brings along it if nothing is
// in the way.
struct LightQuery {
    real3 toLight;          // from the shading point: the direction the lobes are evaluated for
    real3 shadowDirection;  // from the offset origin (an area light's point is reached exactly)
    real shadowLength;      // the shadow ray's end
    uint lightPrimitive;    // the emitter the shadow ray skips, else VKRT_NO_PRIMITIVE
    real distance;          // to the light, over which the viewer's volume absorbs (paths)
    real3 irradiance;       // on a surface facing the light, before the shadow ray (and `divisor`)
    real divisor;           // the environment sample's density, else 1 (divides the weights: see directLight)
    real weight;            // the power heuristic against the traced glossy lobe, else 1
    real untracedWeight;    // the same against the untraced lobes' continuation (paths), else 1
};

// One surface that a path's shadow ray meets, taken in order from the ray's origin (the devices'
// shadowThroughHoles): what the media before it absorb over `segment` into `absorbed`, what passes the surface
// (shadowPassage: a volume's surface stops the ray but for its holes) into `passage`; `media` then holds the
// media beyond it, which a hole in a volume's surface enters or leaves (mediaBeyondHole).
VKRT_DEVICE_TEMPLATE
VKRT_FN void crossInOrder(VKRT_DEVICE_PARAM VKRT_IN(HitPoint) hit, real3 direction, real segment,
                          VKRT_INOUT(uvec2) media, VKRT_INOUT(real4) passage, VKRT_INOUT(real3) absorbed) {
    absorbed *= absorptionAlong(VKRT_DEVICE_ARG media, segment);
    VKRT_IN(SurfaceMaterial) material = VKRT_DEVICE(material)(hit.material);
    passage *= shadowPassageAt(VKRT_DEVICE_ARG material, hit.primitive, hit.uv, material.volume);
    media = mediaBeyondHole(VKRT_DEVICE_ARG media, hit, direction);
}

// What of a light passes along a light sample's shadow ray from `origin` (shadowTransmittance's passage), and
// in `absorbed` what the volumes on the way absorb over `query.distance`, the way to the light (paths; Whitted's
// shadow rays pass transmissive surfaces, tinted, and are not absorbed). A path's shadow ray stops at a
// volume's surface, so it stays in the media it starts in (`media`), unless the surface has holes: a hole
// takes away the interface, not the medium, and a shadow ray through it enters or leaves the volume. Where a
// scene has such holes, the devices walk a path's shadow ray surface by surface, in order, over its first
// VKRT_MAX_ALPHA_LAYERS surfaces (shadowThroughHoles), and leave the rest, if any, to the walk that takes
// surfaces in any order, in the media the ray is in by then; elsewhere that walk takes them all.
VKRT_DEVICE_TEMPLATE
VKRT_FN real4 lightSampleShadow(VKRT_DEVICE_PARAM VKRT_IN(ShadingContext) context, real3 origin, uint exclude,
                                VKRT_IN(LightQuery) query, uvec2 media, VKRT_OUT(real3) absorbed) {
    absorbed = real3(1.0);
    real4 passage = real4(1.0);
    real tMin = 0.0;   // the surfaces before it are crossed
    bool rest = true;  // surfaces may lie beyond tMin
#ifdef VKRT_HAS_VOLUME_HOLES
    if (context.paths && VKRT_DEVICE(hasVolumeHoles)()) {
        rest = VKRT_DEVICE(shadowThroughHoles)(origin, query.shadowDirection, query.shadowLength, exclude,
                                               query.lightPrimitive, media, passage, absorbed, tMin);
    }
#endif
    if (rest) {
        passage *= VKRT_DEVICE(shadowTransmittance)(origin, query.shadowDirection, tMin, query.shadowLength, exclude,
                                                    query.lightPrimitive);
    }
#ifdef VKRT_HAS_VOLUMES
    // (tMin, a tie group's end, can lie a tie's width beyond a point light.)
    if (context.paths) absorbed *= absorptionAlong(VKRT_DEVICE_ARG media, max(query.distance - tMin, 0.0));
#endif
    return passage;
}

// A light sample's weights by the power heuristic against the lobes that also reach the light by the rays they
// trace: the glossy lobe (`lobeSampled`) and, for paths, the untraced lobes' cosine-distributed continuation
// (`untracedSampled`); `lightPdf` is the sample's density per solid angle towards `query.toLight`.
VKRT_FN void weighAgainstLobes(VKRT_IN(ShadingContext) context, VKRT_IN(ShadingFrame) frame,
                               VKRT_IN(SurfaceResponse) surface, bool lobeSampled, bool untracedSampled, real lightPdf,
                               VKRT_INOUT(LightQuery) query) {
    query.weight = 1.0;
    query.untracedWeight = 1.0;
    if (!context.multipleImportanceSampling) return;
    if (lobeSampled) {
        query.weight = powerHeuristic(real(context.lightSamples), lightPdf,
                                      lobePdf(surface, frame.normal, frame.coatNormal, frame.toViewer, query.toLight));
    }
    if (untracedSampled) {
        query.untracedWeight =
            powerHeuristic(real(context.lightSamples), lightPdf, cosinePdf(frame.normal, query.toLight));
    }
}

#ifdef VKRT_HAS_PUNCTUAL_LIGHTS
// The query for punctual light `index`; false where it cannot light the point.
VKRT_DEVICE_TEMPLATE
VKRT_FN bool punctualQuery(VKRT_DEVICE_PARAM VKRT_IN(ShadingFrame) frame, uint index, VKRT_OUT(LightQuery) query) {
    const LightArrival arrival = arriveFrom(VKRT_DEVICE(punctualLight)(index), frame.position);
    if (!facesLight(frame, arrival.toLight) || maxComponent(arrival.irradiance) <= 0.0) return false;
    query.toLight = arrival.toLight;
    query.shadowDirection = arrival.toLight;
    query.shadowLength = arrival.distance;
    query.lightPrimitive = VKRT_NO_PRIMITIVE;
    query.distance = arrival.distance;
    query.irradiance = arrival.irradiance;
    query.divisor = 1.0;
    query.weight = 1.0;
    query.untracedWeight = 1.0;
    return true;
}
#endif

#ifdef VKRT_HAS_AREA_LIGHTS
// The query for area-light sample `k` of `context.lightSamples`: one emissive primitive chosen by power, a point
// on it; false where that point cannot light the shading point.
VKRT_DEVICE_TEMPLATE
VKRT_FN bool areaLightQuery(VKRT_DEVICE_PARAM VKRT_IN(ShadingContext) context, uint node, VKRT_IN(ShadingFrame) frame,
                            VKRT_IN(SurfaceResponse) surface, bool lobeSampled, bool untracedSampled, uint k,
                            VKRT_OUT(LightQuery) query) {
    const real3 point = frame.position;
    // The pick's pair gives the 48-bit number the light table is read with (host/scene/light_table.h).
    const LightPoint light = VKRT_DEVICE(sampleAreaLight)(
        stratified(context, vkrtNodeDimension(node, VKRT_DIM_LIGHT(k, VKRT_DIM_LIGHT_PICK)), 0u),
        stratified(context, vkrtNodeDimension(node, VKRT_DIM_LIGHT(k, VKRT_DIM_LIGHT_PICK)), 1u),
        stratified(context, vkrtNodeDimension(node, VKRT_DIM_LIGHT(k, VKRT_DIM_LIGHT_U)), 0u),
        stratified(context, vkrtNodeDimension(node, VKRT_DIM_LIGHT(k, VKRT_DIM_LIGHT_U)), 1u), point);
    const real3 offset = light.position - point;
    const real distance2 = dot(offset, offset);
    const real distance = sqrt(distance2);
    // A primitive the new rays skip cannot light the point (a triangle its own plane, a sphere its outside); one
    // they do not skip can (a concave CSG lamp its own faces, a double-sided sphere its inside).
    if (light.primitive == frame.excludeOnViewerSide || !(distance > 0.0) || !(light.pdfArea > 0.0)) return false;
    // Nor can a light in the point's own plane, the point in the light's (its tangent plane at the sample), both
    // to within a ray's offset (shared.h): the cosines at both ends are 0 but for rounding, whose signs decided on
    // each device whether a shadow ray was traced (the other triangle of a quad lamp, or of a double-sided
    // emissive floor, seen from its own surface: a third of a random scene's shadow rays on one device and not
    // the other; tools/random_scenes.py). One plane alone says nothing: far from the scene's middle the offset
    // outgrows a lamp's height above a floor, whose samples near the lamp's rim still light it.
    const real planeTolerance = real(VKRT_RAY_OFFSET_EPSILON) * (maxAbs(point) + distance);
    if (!(abs(dot(light.normal, offset)) > planeTolerance) &&
        !(abs(dot(frame.geometricNormal, offset)) > planeTolerance)) {
        return false;
    }
    const real3 toLight = offset / distance;
    VKRT_IN(SurfaceMaterial) emitter = VKRT_DEVICE(material)(light.material);
    real cosLight = -dot(light.normal, toLight);
    if (emitter.doubleSided) cosLight = abs(cosLight);
    if (!(cosLight > 0.0) || !facesLight(frame, toLight)) return false;
    // The shadow ray runs from the offset origin to the light's point, so it ends at the point whatever the
    // offset (solids are not skipped: a CSG light can shadow itself).
    const real3 originToLight = light.position - frame.viewerSide;
    const real shadowDistance = length(originToLight);
    query.toLight = toLight;
    query.shadowDirection = originToLight / shadowDistance;
    query.shadowLength = VKRT_DEVICE(shadowRayLength)(shadowDistance);
    query.lightPrimitive = light.primitive;
    query.distance = distance;
    // Irradiance estimate: L_e cos(theta_light) / (d^2 pdf_area).
    query.irradiance =
        textured(VKRT_DEVICE_ARG emitter.emission, emitter.emissiveTexture, light.primitive, light.uv, 0.0) *
        cosLight / (distance2 * light.pdfArea);
#ifdef VKRT_HAS_ALPHA
    query.irradiance *= coverageAt(VKRT_DEVICE_ARG emitter, light.primitive, light.uv, 0.0);  // an emitter's holes
    // A sphere's inside seen through its near side (which the shadow ray skips): through that side's holes.
    if (light.behindNearSide) {
        query.irradiance *= 1.0 - coverageAt(VKRT_DEVICE_ARG emitter, light.primitive, light.nearSideUv, 0.0);
    }
#endif
#ifdef VKRT_HAS_CLEARCOAT
    query.irradiance *= coatedEmission(emitter.clearcoat, abs(dot(light.normal, toLight)));
#endif
    query.divisor = 1.0;
    weighAgainstLobes(context, frame, surface, lobeSampled, untracedSampled, light.pdfArea * distance2 / cosLight,
                      query);
    return true;
}
#endif

#ifdef VKRT_HAS_ENVIRONMENT
// The query for environment sample `k` of `context.lightSamples`: a direction drawn from the environment map,
// with a shadow ray to infinity; false where it cannot light the point.
VKRT_DEVICE_TEMPLATE
VKRT_FN bool environmentQuery(VKRT_DEVICE_PARAM VKRT_IN(ShadingContext) context, uint node,
                              VKRT_IN(ShadingFrame) frame, VKRT_IN(SurfaceResponse) surface, bool lobeSampled,
                              bool untracedSampled, uint k, VKRT_OUT(LightQuery) query) {
    const uint dimension = vkrtNodeDimension(node, VKRT_DIM_LIGHT(k, VKRT_DIM_LIGHT_ENVIRONMENT));
    // The pair's first two numbers choose the texel, and two more hashed from its dimension the point below the
    // grid's step (environment.h).
    const EnvironmentSample light = sampleEnvironment(
        VKRT_DEVICE_ARG stratified(context, dimension, 0u), stratified(context, dimension, 1u),
        real(vkrtLayered(context.stream, context.pairRoot, context.sampleIndex, dimension, 2u)),
        real(vkrtLayered(context.stream, context.pairRoot, context.sampleIndex, dimension, 3u)));
    const real3 toLight = light.direction;
    if (!(light.pdf > 0.0) || !facesLight(frame, toLight)) return false;
    query.toLight = toLight;
    query.shadowDirection = toLight;
    query.shadowLength = VKRT_INFINITY;
    query.lightPrimitive = VKRT_NO_PRIMITIVE;
    query.distance = VKRT_INFINITY;
    query.irradiance = light.radiance;
    query.divisor = light.pdf;
    weighAgainstLobes(context, frame, surface, lobeSampled, untracedSampled, light.pdf, query);
    return true;
}
#endif

// Light from the punctual lights (hard shadows: from each, or, beyond VKRT_EVERY_PUNCTUAL_LIGHT_UP_TO of them,
// from `lightSamples` picked by power), `lightSamples` samples of the area lights, each of one emissive
// primitive chosen by power, and `lightSamples` directions of the environment, reflected towards the viewer by
// `surface`; `node` is the ray-tree node whose random dimensions the light samples use, `media` the volumes the
// viewer's side is in. `lobeSampled`: the glossy lobe is also traced; `untracedSampled`: so are the other lobes
// (paths); light samples weigh each against them by the power heuristic. `lobeThroughGlass`: Whitted's traced
// glossy rays go on through a transmissive surface they meet (they are not at the last depth there).
//
// One loop runs over the samples of every kind of light, so that the shadow ray's walk and the lobes'
// evaluation have one call site each and are inlined once in a GPU kernel: a walk (csg.gltf's was 160 KiB
// of SPIR-V) for each kind of light made pipeline creation and the kernel grow with every kind a scene has.
VKRT_DEVICE_TEMPLATE
VKRT_FN real3 directLight(VKRT_DEVICE_PARAM VKRT_IN(ShadingContext) context, uint node, uvec2 media,
                          VKRT_IN(ShadingFrame) frame, VKRT_IN(SurfaceResponse) surface, bool lobeSampled,
                          bool untracedSampled, bool lobeThroughGlass) {
    if (!reflectsLights(surface)) return real3(0.0);  // no shadow rays from mirrors and smooth glass
    uint punctualQueries = 0u, areaQueries = 0u, environmentQueries = 0u;
    bool punctualPicked = false;  // each punctual query picks a light from the table
#ifdef VKRT_HAS_PUNCTUAL_LIGHTS
    punctualQueries = VKRT_DEVICE(punctualLightCount)();
#ifdef VKRT_HAS_PUNCTUAL_LIGHT_TABLE
    punctualPicked = punctualQueries > VKRT_EVERY_PUNCTUAL_LIGHT_UP_TO;
    if (punctualPicked) punctualQueries = context.lightSamples;
#endif
#endif
#ifdef VKRT_HAS_AREA_LIGHTS
    if (VKRT_DEVICE(hasAreaLights)()) areaQueries = context.lightSamples;
#endif
#ifdef VKRT_HAS_ENVIRONMENT
    if (VKRT_DEVICE(hasEnvironment)()) environmentQueries = context.lightSamples;
#endif
    const uint areaEnd = punctualQueries + areaQueries;
    real3 punctualSum = real3(0.0), areaSum = real3(0.0), environmentSum = real3(0.0);
    for (uint q = 0u; q < areaEnd + environmentQueries; ++q) {
        // Counted against llvmpipe's loop budget (traverse.glsl), which cut this loop short after 16384 of
        // 20000 point lights, the sample kept without the others' light.
        VKRT_DEVICE(loopPass)();
        LightQuery query;
        bool lit = false;
#ifdef VKRT_HAS_PUNCTUAL_LIGHTS
        if (q < punctualQueries) {
            uint light = q;
            real share = 1.0;  // of the light's irradiance this query carries: one over its expected queries
#ifdef VKRT_HAS_PUNCTUAL_LIGHT_TABLE
            if (punctualPicked) {
                // Two more numbers of the area lights' pick pair (which reads its first two).
                const uint dimension = vkrtNodeDimension(node, VKRT_DIM_LIGHT(q, VKRT_DIM_LIGHT_PICK));
                real probability = 0.0;
                light = VKRT_DEVICE(pickPunctualLight)(
                    real(vkrtLayered(context.stream, context.pairRoot, context.sampleIndex, dimension, 2u)),
                    real(vkrtLayered(context.stream, context.pairRoot, context.sampleIndex, dimension, 3u)),
                    probability);
                share = probability * real(context.lightSamples);
            }
#endif
            lit = punctualQuery(VKRT_DEVICE_ARG frame, light, query);
            query.divisor = share;
        }
#endif
#ifdef VKRT_HAS_AREA_LIGHTS
        if (q >= punctualQueries && q < areaEnd) {
            lit = areaLightQuery(VKRT_DEVICE_ARG context, node, frame, surface, lobeSampled, untracedSampled,
                                 q - punctualQueries, query);
        }
#endif
#ifdef VKRT_HAS_ENVIRONMENT
        if (q >= areaEnd) {
            lit = environmentQuery(VKRT_DEVICE_ARG context, node, frame, surface, lobeSampled, untracedSampled,
                                   q - areaEnd, query);
        }
#endif
        if (!lit) continue;
        real3 absorbed;
        const real4 passage = lightSampleShadow(VKRT_DEVICE_ARG context, frame.viewerSide, frame.excludeOnViewerSide,
                                                query, media, absorbed);
        // Paths see an area light or the environment through holes alone (shadowPassage): their own bounces bring
        // the light that transmissive surfaces let through. No path finds a punctual light, so its light sample
        // passes thin-walled transmissive surfaces, tinted (a window under the sun cast a black shadow); a
        // volume's boundary stops it (shadowTint).
        const bool pathsThroughHoles = context.paths && q >= punctualQueries;
        const real3 visible = absorbed * (pathsThroughHoles ? real3(passage.w) : real3(passage));
        // Whitted's traced lobes see an area light or the environment through holes alone where their own rays
        // find those through glass (lobeThroughGlass). No ray finds a punctual light, so its light sample lights
        // them through glass too, as every light's does where the lobe's rays end at the glass or are not traced.
        // Paths trace no lobe apart, so both groups see the same.
        const real3 tracedVisible = lobeThroughGlass && q >= punctualQueries ? real3(passage.w) : visible;
        // The density divides the weights, not the irradiance: L / pdf is about 4 pi L for a uniform environment,
        // which overflows a float where the light the surface reflects (about albedo L) does not.
        const real3 reflected =
            reflectedLight(surface, frame.normal, frame.coatNormal, frame.toViewer, query.toLight, query.irradiance,
                           query.weight * tracedVisible / query.divisor,
                           query.untracedWeight * visible / query.divisor);
        if (q < punctualQueries) {
            punctualSum += reflected;
        } else if (q < areaEnd) {
            areaSum += reflected;
        } else {
            environmentSum += reflected;
        }
    }
    real3 sum = punctualSum;
    if (areaQueries > 0u) sum += areaSum / real(context.lightSamples);
    if (environmentQueries > 0u) sum += environmentSum / real(context.lightSamples);
    return sum;
}

// Radiance reaching `ray` from beyond the scene: the environment, weighed against light sampling when a
// glossy lobe chose the ray (as emission is in shadeHit), else the constant background. An environment that
// only lights the scene (the neutral default) is not seen by camera rays, nor through transmissive surfaces
// from the camera: they see the background.
VKRT_DEVICE_TEMPLATE
VKRT_FN real3 escapedRadiance(VKRT_DEVICE_PARAM VKRT_IN(ShadingContext) context, VKRT_IN(RayState) ray) {
#ifdef VKRT_HAS_ENVIRONMENT
    if (VKRT_DEVICE(hasEnvironment)() && (!ray.backdrop || context.environmentBackdrop)) {
        real weight = 1.0;
        if (ray.arrivalPdf > 0.0) {
            weight = context.multipleImportanceSampling
                         ? powerHeuristic(1.0, ray.arrivalPdf,
                                          real(context.lightSamples) *
                                              environmentPdf(VKRT_DEVICE_ARG ray.direction))
                         : 0.0;
        }
        return weight > 0.0 ? weight * environmentRadiance(VKRT_DEVICE_ARG ray.direction) : real3(0.0);
    }
#endif
    return context.background;
}

// Whitted's branch of weight `weight` (the largest channel of its throughput) against the cut: traced when at
// least the cut; else, where light samples count on it (`owed`), with probability weight / cut (axis `axis` of
// the node's roulette pair), its weight then divided by that; 0 when not traced. That is a glossy reflection
// whose lobe light samples are weighed against, and the transmission of such a glossy ray through a surface on
// its way to the lights: the light samples' weights count on it bringing the rest, which a cut branch lost (a
// highlight seen through a pane passing 2% came out 1.47% as bright in Gpu.WhittedBranchesBelowTheCutKeepTheirShare).
// Other branches answer to no light sample and are cut (roulette for every branch made the Whitted scene's
// render 13% slower on lavapipe for 5% more rays); a cut branch loses less than 1e-3 of what it would bring.
VKRT_FN real branchSurvival(VKRT_IN(ShadingContext) context, uint node, uint axis, bool owed, real weight, real cut) {
    if (weight >= cut) return 1.0;
    if (!owed) return 0.0;
    const real p = weight / cut;
    return stratified(context, vkrtNodeDimension(node, VKRT_DIM_BRANCH_ROULETTE), axis) < p ? p : 0.0;
}

// The shading step at `hit` of `ray`, whose weight including absorption on the way is `pathThroughput`.
VKRT_DEVICE_TEMPLATE
VKRT_FN ShadedHit shadeHit(VKRT_DEVICE_PARAM VKRT_IN(ShadingContext) context, VKRT_IN(RayState) ray, VKRT_IN(HitPoint) hit,
                           real3 pathThroughput) {
    ShadedHit result;
    result.reflects = false;
    result.transmits = false;
    result.scatters = false;
    result.indexHere = 1.0;
    result.indexBeyond = 1.0;
    VKRT_IN(SurfaceMaterial) material = VKRT_DEVICE(material)(hit.material);
    const real footprint = textureFootprint(VKRT_DEVICE_ARG ray, hit);
    // The emission at the finest level where light samples weigh the ray or the surface has holes: light samples
    // read level 0, and so do a MASK's cut-outs and an emitter's coverage (passesThrough), so that a mip-averaged
    // emission would count the light of the holes' texels (a checkered, cut-out lamp over a glossy floor came out
    // 15% dark at 32 x 32, 21% with BLEND).
    const real emissionFootprint = ray.arrivalPdf > 0.0 || material.alphaMode != VKRT_ALPHA_OPAQUE ? 0.0 : footprint;
    const MaterialSample inputs =
        sampleMaterial(VKRT_DEVICE_ARG material, hit.primitive, hit.uv, footprint, emissionFootprint);
#ifdef VKRT_HAS_UNLIT
    if (material.unlit) {  // KHR_materials_unlit: the base colour, from either side, and nothing else
        result.radiance = inputs.albedo;
        return result;
    }
#endif
    ShadingFrame frame = shadingFrame(VKRT_DEVICE_ARG ray, hit);
    // The normal textures turn the shading normal, and the coat's normal (which otherwise stays the surface's
    // own: the base's normal texture lies below the coat).
#ifdef VKRT_HAS_NORMAL_MAPS
    if (material.normalTexture >= 0) {
        frame.normal = viewerSideNormal(frame, normalMapped(hit.normal, hit.tangent, inputs.tangentNormal));
    }
#ifdef VKRT_HAS_CLEARCOAT
    if (material.clearcoatNormalTexture >= 0) {
        frame.coatNormal = viewerSideNormal(frame, normalMapped(hit.normal, hit.tangent, inputs.coatTangentNormal));
    }
#endif
#endif
    const real3 toViewer = frame.toViewer, normal = frame.normal, geometricNormal = frame.geometricNormal;

    // Emission, weighed against light sampling when a glossy lobe chose the ray (multiple importance
    // sampling; without it, light samples alone light the lobe).
    real3 local = real3(0.0);
    if ((frame.frontFace || material.doubleSided) && maxComponent(material.emission) > 0.0) {
        real emissionWeight = 1.0;
#ifdef VKRT_HAS_AREA_LIGHTS
        if (ray.arrivalPdf > 0.0 && VKRT_DEVICE(hasAreaLights)()) {
            emissionWeight = 0.0;
            if (context.multipleImportanceSampling) {
                // Seen from the point the light samples were drawn from (areaLightQuery), not from the ray's
                // offset origin: far from the scene's middle the offset (VKRT_RAY_OFFSET_EPSILON times the
                // coordinates) is no longer small beside a nearby lamp, and the two densities then weighed the
                // same directions by more than 1 in all.
                const real3 arrival = hit.position - ray.shadingPoint;
                const real arrivalDistance = length(arrival);
                const real3 seen = arrivalDistance > 0.0 ? arrival / arrivalDistance : ray.direction;
                const real lightPdf =
                    VKRT_DEVICE(lightSolidAnglePdf)(hit.primitive, hit.shape, ray.shadingPoint, hit.position,
                                                    abs(dot(geometricNormal, seen)));
                emissionWeight = powerHeuristic(1.0, ray.arrivalPdf, real(context.lightSamples) * lightPdf);
            }
        }
#endif
        real3 emitted = inputs.emission;
#ifdef VKRT_HAS_CLEARCOAT
        emitted *= coatedEmission(material.clearcoat, abs(dot(geometricNormal, ray.direction)));
#endif
        local += emissionWeight * emitted;
    }

    SurfaceResponse surface = surfaceResponse(material, inputs);
#ifdef VKRT_HAS_SHEEN
    if (maxComponent(surface.sheenColor) > 0.0) addSheen(VKRT_DEVICE_ARG surface, inputs.sheenRoughness, dot(normal, toViewer));
#endif
    // A volume is entered through its front face and left through its back face, from the medium the ray is in
    // into the one beyond (nested dielectrics); thin-walled and opaque surfaces look the same from both sides.
    bool volume = false;
    uvec2 beyond = ray.media;
    real eta = surface.ior;
#ifdef VKRT_HAS_VOLUMES
    volume = material.volume && surface.transmission > 0.0;
    if (volume) {
        beyond = frame.frontFace ? mediaEntered(ray.media, hit.material) : mediaExited(ray.media, hit.material);
        result.indexHere = mediumIor(VKRT_DEVICE_ARG ray.media);
        result.indexBeyond = mediumIor(VKRT_DEVICE_ARG beyond);
        eta = result.indexBeyond / result.indexHere;
        // The lobes that lights are evaluated on see the interface the traced ones do: its relative index (a
        // light reflected off glass of index 1.5 inside glass of index 1.5, where no interface is, or off its
        // inside at the outer index).
        surface.ior = eta;
    }
#endif
#if defined(VKRT_HAS_ROUGH_SPECULAR) || defined(VKRT_HAS_TRACED_LOBES)  // else no specular layer anywhere
    // What the specular layer leaves the base, at the index the reflection and transmission see: inside a
    // volume, none beyond the critical angle, where the layer reflects everything.
    surface.diffuse *= diffuseShare(surface, dot(normal, toViewer), eta);
#endif
#ifdef VKRT_HAS_ROUGH_SPECULAR
    if (context.energyCompensation) {
        addEnergyCompensation(VKRT_DEVICE_ARG surface, inputs.transmission, dot(normal, toViewer),
                              dot(frame.coatNormal, toViewer), eta, volume);
    }
#endif
    // Ambient light reaches the diffuse part, and the specular part where it is not traced, as much as the
    // material's occlusion lets it; a coat lets through what it does not reflect, and reflects its share where
    // it is not traced.
    real3 ambientReflectance = surface.diffuse + (surface.traced ? real3(0.0) : surface.specular);
#ifdef VKRT_HAS_SHEEN
    ambientReflectance = ambientReflectance * surface.sheenScaling + surface.sheenColor * surface.sheenAlbedo;
#endif
#ifdef VKRT_HAS_CLEARCOAT
    const real coatThrough = coatTransmittance(surface, dot(frame.coatNormal, toViewer));
    if (surface.clearcoat > 0.0) {
        ambientReflectance = ambientReflectance * coatThrough +
                             (surface.coatTraced ? 0.0 : surface.clearcoat * coatFresnel(dot(frame.coatNormal, toViewer)));
    }
#endif
    if (!context.paths) local += inputs.occlusion * context.ambient * ambientReflectance;  // Whitted's alone
    const bool continues = ray.depth < context.maxDepth;
#ifdef VKRT_HAS_TRACED_LOBES
    const bool lobeSampled = continues && ((surface.traced && !tracedAsMirror(surface.mirror)) ||
                                           (surface.coatTraced && !tracedAsMirror(surface.coatMirror)));
#else
    const bool lobeSampled = false;  // a constant: directLight's weights against traced lobes compile out
#endif
    const bool untracedSampled = continues && context.paths;
    // Whitted's glossy rays, traced from here at depth + 1, go on through a transmissive surface they meet there
    // unless that depth is the last.
    const bool lobeThroughGlass = !context.paths && lobeSampled && ray.depth + 1 < context.maxDepth;
    local += directLight(VKRT_DEVICE_ARG context, ray.node, ray.media, frame, surface, lobeSampled, untracedSampled,
                         lobeThroughGlass);
    result.radiance = local;
    // Whitted cuts branches that would add little (branchSurvival); a path goes on until Russian roulette ends it
    // (continuePath).
    const real cut = context.paths ? 0.0 : context.minThroughput;

    // The path's continuation through the untraced lobes: a direction with density cos / pi about the shading
    // normal, weighted by what those lobes reflect from it over that density.
    if (untracedSampled) {
        const uint dimension = vkrtNodeDimension(ray.node, VKRT_DIM_SCATTER_U);
        const real3 lobeLocal = sampleCosineHemisphere(stratified(context, dimension, 0u), stratified(context, dimension, 1u));
        real3 tangent, bitangent;
        orthonormalBasis(normal, tangent, bitangent);
        const real3 direction = normalize(lobeLocal.x * tangent + lobeLocal.y * bitangent + lobeLocal.z * normal);
        const real pdf = cosinePdf(normal, direction);
        if (pdf > 0.0 && dot(geometricNormal, direction) > 0.0) {
            const real3 weight = reflectedLight(surface, normal, frame.coatNormal, toViewer, direction,
                                                real3(1.0 / pdf), real3(0.0), real3(1.0));
            if (maxComponent(weight) > 0.0) {
                result.scatters = true;
                result.scatterWeight = weight;
                result.scattered = withCone(rayState(frame.viewerSide, direction, pathThroughput * weight,
                                                     childNode(context, ray, 3u), ray.depth + 1,
                                                     frame.excludeOnViewerSide, pdf, ray.media),
                                            coneWidthAt(ray, hit.position), ray.coneSpread);
                result.scattered.shadingPoint = hit.position;
            }
        }
    }
    if (!continues || !(surface.traced || surface.coatTraced)) return result;
#ifdef VKRT_HAS_TRACED_LOBES  // else no lane gets here, but a SIMD device (lavapipe) would run it all, masked

    // The microfacet normal both branches share: the shading normal for a mirror, else a visible normal.
    const real cosOut = dot(normal, toViewer);
    // `lobeScale` weighs the base's continuations through a microfacet normal drawn with its compensation.
    real lobeScale = 1.0;
    real3 microNormal = normal;
    if (!tracedAsMirror(surface.mirror)) {
        bool drawn = false;
#if defined(VKRT_HAS_VOLUMES) && defined(VKRT_HAS_ROUGH_REFRACTION)
        // A compensated rough refracting dielectric (not thin, no metal in it: the metal's reflection does not
        // follow the dielectric's share) draws its compensation.
        if (volume && eta != 1.0 && surface.transmissionCompensation > 1.0 && surface.metallic == 0.0) {
            microNormal = compensatedMicroNormal(context, ray.node, normal, geometricNormal, toViewer, surface.alpha,
                                                 eta, 1.0 / surface.transmissionCompensation, lobeScale);
            drawn = true;
        }
#endif
        if (!drawn) {
            microNormal = visibleMicroNormal(context, vkrtNodeDimension(ray.node, VKRT_DIM_LOBE_U), normal,
                                             toViewer, surface.alpha);
        }
    }
    const real cosMicro = max(0.0, dot(microNormal, toViewer));

    // Reflection: Fresnel (energy compensated), times G2 / G1 for a sampled visible normal (Heitz 2018,
    // eq. 19).
    real3 reflected = reflectAbout(toViewer, microNormal);
    real3 reflectWeight = compensatedFresnelAt(surface, cosMicro, eta);
    real reflectPdf = 0.0;  // 0: a delta lobe, whose rays see lights at full weight
    if (!tracedAsMirror(surface.mirror)) {
        const real cosIn = dot(normal, reflected);
        const bool above = cosIn > 0.0 && dot(geometricNormal, reflected) > 0.0;
        reflectWeight *= above ? lobeScale * ggxG2(cosOut, cosIn, surface.alpha) / ggxG1(cosOut, surface.alpha) : 0.0;
        reflectPdf = ggxReflectionPdf(cosOut, normal, microNormal, surface.alpha);
    }
#ifdef VKRT_HAS_SHEEN
    reflectWeight *= surface.sheenScaling;  // the layers below the sheen
#endif
#ifdef VKRT_HAS_CLEARCOAT
    // With a coat, the reflection follows the coat's lobe with probability coatPick, else the base's, seen
    // through the coat; either weight is divided by its probability, and the density is that of both.
    if (surface.clearcoat > 0.0) {
        const real pick = coatPick(surface);
        const bool coatChosen =
            pick >= 1.0 || (pick > 0.0 && stratified(context, vkrtNodeDimension(ray.node, VKRT_DIM_COAT_PICK), 0u) < pick);
        bool delta = tracedAsMirror(surface.mirror);
        if (coatChosen) {
            const real3 coatNormal = frame.coatNormal;
            const real cosCoat = dot(coatNormal, toViewer);
            const real3 coatMicro =
                tracedAsMirror(surface.coatMirror)
                    ? coatNormal
                    : visibleMicroNormal(context, vkrtNodeDimension(ray.node, VKRT_DIM_COAT_U), coatNormal,
                                         toViewer, surface.coatAlpha);
            reflected = reflectAbout(toViewer, coatMicro);
            real weight = surface.clearcoat * coatFresnel(cosCoat) * surface.coatCompensation / pick;
            if (!tracedAsMirror(surface.coatMirror)) {
                const real cosIn = dot(coatNormal, reflected);
                const bool above = cosIn > 0.0 && dot(geometricNormal, reflected) > 0.0;
                weight *= above ? ggxG2(cosCoat, cosIn, surface.coatAlpha) / ggxG1(cosCoat, surface.coatAlpha) : 0.0;
            }
            reflectWeight = real3(weight);
            delta = tracedAsMirror(surface.coatMirror);
        } else {
            reflectWeight *= coatThrough / (1.0 - pick);
        }
        reflectPdf = delta ? 0.0 : lobePdf(surface, normal, frame.coatNormal, toViewer, reflected);
    }
#endif
    const real reflectSurvival =
        branchSurvival(context, ray.node, 0u, lobeSampled, maxComponent(pathThroughput * reflectWeight), cut);
    if (reflectSurvival > 0.0) {
        reflectWeight /= reflectSurvival;
        result.reflects = true;
        result.reflectionWeight = reflectWeight;
        result.reflection = withCone(rayState(frame.viewerSide, reflected, pathThroughput * reflectWeight,
                                              childNode(context, ray, 1u), ray.depth + 1, frame.excludeOnViewerSide, reflectPdf,
                                              ray.media),
                                     coneWidthAt(ray, hit.position), ray.coneSpread);
        result.reflection.shadingPoint = hit.position;
    }

#ifdef VKRT_HAS_TRANSMISSION
    // Transmission through the same microfacet; thin-walled surfaces pass rays straight through. It keeps
    // 1 - max(F), as the diffuse base does (diffuseShare) and KHR_materials_specular's fresnel_mix says: a
    // tinted specular colour does not tint the light passing through (1 - F per channel tinted it with the
    // colour's complement).
    real3 transmitWeight = surface.transmission *
                           (1.0 - maxComponent(dielectricReflectance(surface, cosMicro, eta))) * surface.albedo;
#ifdef VKRT_HAS_SHEEN
    transmitWeight *= surface.sheenScaling;
#endif
#ifdef VKRT_HAS_CLEARCOAT
    if (surface.clearcoat > 0.0) transmitWeight *= coatThrough;
#endif
    real3 direction = ray.direction;
    bool passes = maxComponent(transmitWeight) > 0.0;
    // Between media of one index (eta 1) light goes straight on, whatever the microfacets: weighing it by
    // G2 / G1 and the compensation's interpolated 1 / E added up to 0.3% at roughness 0.5.
    const bool bends = volume && eta != 1.0;
    if (passes && bends) passes = refractThrough(toViewer, microNormal, eta, direction);
    if (passes && bends && !tracedAsMirror(surface.mirror)) {
        const real cosIn = dot(normal, direction);
        passes = cosIn < 0.0 && dot(geometricNormal, direction) < 0.0;
        if (passes) {
            transmitWeight *= lobeScale * surface.transmissionCompensation * ggxG2(cosOut, -cosIn, surface.alpha) /
                              ggxG1(cosOut, surface.alpha);
        }
    }
    // Radiance over the index squared is what crosses an interface unchanged (Veach 1997, 5.2): the viewer's side
    // sees 1 / eta^2 of the radiance beyond. A ray entering a volume and leaving it again takes both factors,
    // which cancel; a lamp inside water seen from the air had been 1.33^2 times too bright.
    if (bends) transmitWeight /= eta * eta;
    // A glossy ray on its way to the lights (it arrived with a lobe's density) is owed its transmission.
    const real transmitSurvival = passes ? branchSurvival(context, ray.node, 1u, ray.arrivalPdf > 0.0,
                                                          maxComponent(pathThroughput * transmitWeight), cut)
                                         : 0.0;
    if (transmitSurvival > 0.0) {
        transmitWeight /= transmitSurvival;
        result.transmits = true;
        result.transmissionWeight = transmitWeight;
        result.transmission = withCone(rayState(VKRT_DEVICE(offsetOrigin)(hit.position, hit.errorScale, -geometricNormal),
                                                direction, pathThroughput * transmitWeight, childNode(context, ray, 2u),
                                                ray.depth + 1, frame.excludeBeyond, 0.0, beyond),
                                       coneWidthAt(ray, hit.position), ray.coneSpread);
        result.transmission.backdrop = ray.backdrop;
    }
#endif
#endif  // VKRT_HAS_TRACED_LOBES
    return result;
}

// Paths start Russian roulette after this many bounces.
#define VKRT_ROULETTE_DEPTH 3

// The path's next ray after the shading step `shaded` at the hit of `ray`: one of its continuations, picked with
// probability proportional to its energy weight (the largest component), its throughput divided by that
// probability, so the one ray estimates the sum of all three without bias; past VKRT_ROULETTE_DEPTH bounces it
// survives Russian roulette with probability min(1, energy throughput) and is divided by that too. False when
// the path ends. Energy rather than radiance: a refraction's weight carries 1 / eta^2 (shadeHit), so it is
// picked times eta^2 (by its Fresnel share), and the roulette reads the throughput times the square of the
// index of the medium the path is in (camera rays start in air), as pbrt's etaScale does: smooth glass in a
// white furnace still weighs every path exactly 1. (The indices are the volume's surface's, from shadeHit; at
// other surfaces 1, where the roulette then reads radiance: unbiased still, but cut more often inside a medium.)
VKRT_FN bool continuePath(VKRT_IN(ShadingContext) context, VKRT_IN(RayState) ray, VKRT_IN(ShadedHit) shaded,
                          VKRT_OUT(RayState) next) {
    const real reflect = shaded.reflects ? maxComponent(shaded.reflectionWeight) : 0.0;
    const real ratio = shaded.indexBeyond / shaded.indexHere;
    const real transmit = shaded.transmits ? maxComponent(shaded.transmissionWeight) * ratio * ratio : 0.0;
    const real scatter = shaded.scatters ? maxComponent(shaded.scatterWeight) : 0.0;
    const real total = reflect + transmit + scatter;
    if (!(total > 0.0)) return false;
    const real u = stratified(context, vkrtNodeDimension(ray.node, VKRT_DIM_PATH_BRANCH), 0u) * total;
    real probability;
    real index = shaded.indexHere;  // of the medium the next ray is in
    // Only a continuation of positive weight is taken: u can round up to its weight's end where the weights
    // are subnormal (a smooth sheen's lobe over a black base, 1e-320 in double precision), and the reflection
    // the next test then took did not exist (its ray unset, its probability 0: the CPU's sample NaN).
    if (u < scatter || (scatter > 0.0 && reflect + transmit <= 0.0)) {
        next = shaded.scattered;
        probability = scatter / total;
    } else if ((u < scatter + reflect || transmit <= 0.0) && reflect > 0.0) {
        next = shaded.reflection;
        probability = reflect / total;
    } else {
        next = shaded.transmission;
        probability = transmit / total;
        index = shaded.indexBeyond;
    }
    next.throughput = next.throughput / probability;
    if (next.depth > VKRT_ROULETTE_DEPTH) {
        const real survival = min(1.0, maxComponent(next.throughput) * index * index);
        if (!(stratified(context, vkrtNodeDimension(ray.node, VKRT_DIM_PATH_BRANCH), 1u) < survival)) return false;
        next.throughput = next.throughput / survival;
    }
    return true;
}

VKRT_SHADING_END

#endif  // VKRT_SHADE_HIT_H
