// The table-driven evaluation behind tests/shading_functions_test.cpp: one case names a shared shading
// function (shaders/*.h) and its inputs, and evaluateCase() calls it. This file is itself written in the
// shared language, so the GPU (shading_functions.comp, float) and the test (C++, double) run the same calls
// and only the precision differs.
#ifndef VKRT_SHADING_CASES_H
#define VKRT_SHADING_CASES_H

#include "area_light.h"
#include "camera.h"
#include "environment.h"
#include "media.h"
#include "microfacet.h"
#include "optics.h"
#include "punctual_light.h"
#include "shading_language.h"
#include "sphere_geometry.h"
#include "surface_response.h"
#include "texture_sampling.h"

#define VKRT_CASE_FRESNEL 0u
#define VKRT_CASE_REFRACT 1u
#define VKRT_CASE_GGX 2u
#define VKRT_CASE_VISIBLE_NORMAL 3u
#define VKRT_CASE_SURFACE 4u
#define VKRT_CASE_PUNCTUAL 5u
#define VKRT_CASE_TRIANGLE_LIGHT 6u
#define VKRT_CASE_SPHERE_LIGHT 7u
#define VKRT_CASE_SPHERE 8u
#define VKRT_CASE_ABSORPTION 9u
#define VKRT_CASE_MEDIA 10u
#define VKRT_CASE_TEXTURE 11u
#define VKRT_CASE_CAMERA 12u
#define VKRT_CASE_FILTER 13u
#define VKRT_CASE_BASIS 14u
#define VKRT_CASE_ROTATE 15u
#define VKRT_CASE_SURFACE_LIGHT 16u
#define VKRT_CASE_BINDING 17u
#define VKRT_CASE_ENVIRONMENT 18u
#define VKRT_CASE_COUNT 19u

// The test texture: 4 x 3 texels at the start of the texel buffer. Texture bindings 0 and 1 (the devices'
// textureBinding) bind it as sRGB unchanged, and as linear data under a KHR_texture_transform.
#define VKRT_CASE_BINDING0_ROW0 vec3(1.0, 0.0, 0.0)
#define VKRT_CASE_BINDING0_ROW1 vec3(0.0, 1.0, 0.0)
#define VKRT_CASE_BINDING1_ROW0 vec3(3.5, -0.75, 0.1)
#define VKRT_CASE_BINDING1_ROW1 vec3(1.9, 1.4, -0.2)
#define VKRT_CASE_TEXTURE_WIDTH 4u
#define VKRT_CASE_TEXTURE_HEIGHT 3u

// The test environment map: 8 x 4 texels turned by 30 degrees, in the texel buffer after the test texture
// (from word VKRT_CASE_ENVIRONMENT_FIRST): per texel four floats (radiance, the row's cumulative probability),
// then the marginal table, one float per row (the devices' environment* functions).
#define VKRT_CASE_ENVIRONMENT_WIDTH 8u
#define VKRT_CASE_ENVIRONMENT_HEIGHT 4u
#define VKRT_CASE_ENVIRONMENT_FIRST 16u
#define VKRT_CASE_ENVIRONMENT_COS 0.8660254037844387
#define VKRT_CASE_ENVIRONMENT_SIN 0.5

#ifdef __cplusplus
namespace vkrt::shading {
using vec3 = glm::vec3;
using vec4 = glm::vec4;
}
#endif

VKRT_SHADING_BEGIN

// One case, 96 bytes (std430): the function, an integer argument and five rows of float arguments.
struct FunctionCase {
    uint function;  // VKRT_CASE_*
    uint integer;
    uint unused0;
    uint unused1;
    vec4 a;
    vec4 b;
    vec4 c;
    vec4 d;
    vec4 e;
};

VKRT_FN real3 xyz(real4 v) { return real3(v.x, v.y, v.z); }

VKRT_DEVICE_TEMPLATE
VKRT_FN void evaluateCase(VKRT_DEVICE_PARAM FunctionCase fc, VKRT_OUT(real4) r0, VKRT_OUT(real4) r1) {
    const real4 a = real4(fc.a), b = real4(fc.b), c = real4(fc.c), d = real4(fc.d), e = real4(fc.e);
    r0 = real4(0.0);
    r1 = real4(0.0);
    if (fc.function == VKRT_CASE_FRESNEL) {
        r0.x = fresnelDielectric(a.x, a.y);
        r0.y = dielectricF0(a.y);
        const real3 schlick = fresnelSchlick(xyz(b), a.x);
        r1 = real4(schlick.x, schlick.y, schlick.z, 0.0);
    } else if (fc.function == VKRT_CASE_REFRACT) {
        real3 t;
        const bool ok = refractThrough(xyz(a), xyz(b), b.w, t);
        r0 = real4(t.x, t.y, t.z, ok ? 1.0 : 0.0);
        const real3 r = reflectAbout(xyz(a), xyz(b));
        r1 = real4(r.x, r.y, r.z, 0.0);
    } else if (fc.function == VKRT_CASE_GGX) {
        // Microfacet normals at cosines a.x and a.z from the z axis.
        const real3 z = real3(0.0, 0.0, 1.0);
        const real3 hx = real3(sqrt(max(0.0, 1.0 - a.x * a.x)), 0.0, a.x);
        const real3 hz = real3(0.0, sqrt(max(0.0, 1.0 - a.z * a.z)), a.z);
        r0 = real4(ggxD(z, hx, a.y), ggxLambda(a.x, a.y), ggxG1(a.x, a.y), ggxG2(a.x, a.z, a.y));
        r1 = real4(ggxReflectionPdf(a.x, z, hz, a.y), ggxAlpha(a.w), 0.0, 0.0);
    } else if (fc.function == VKRT_CASE_VISIBLE_NORMAL) {
        const real3 m = sampleGgxVisibleNormal(normalize(xyz(a)), a.w, b.x, b.y);
        r0 = real4(m.x, m.y, m.z, 0.0);
    } else if (fc.function == VKRT_CASE_SURFACE || fc.function == VKRT_CASE_SURFACE_LIGHT) {
        SurfaceMaterial material;
        material.baseColor = xyz(a);
        material.metallic = a.w;
        material.emission = real3(0.0);
        material.roughness = b.w;
        material.attenuationColor = real3(1.0);
        material.attenuationDistance = VKRT_INFINITY;
        material.transmission = c.x;
        material.ior = c.y;
        material.volume = false;
        material.doubleSided = false;
        material.baseColorTexture = -1;
        material.emissiveTexture = -1;
        material.metallicRoughnessTexture = -1;
        material.occlusionTexture = -1;
        material.occlusionStrength = 1.0;
        material.specularFactor = c.w;
        material.specularColor = real3(0.9, 1.0, 0.7);
        material.specularTexture = -1;
        material.specularColorTexture = -1;
        material.normalTexture = -1;
        material.normalScale = 1.0;
        material.alphaMode = VKRT_ALPHA_OPAQUE;
        material.alpha = 1.0;
        material.alphaCutoff = 0.5;
        material.transmissionTexture = -1;
        material.unlit = false;
        material.clearcoat = 0.5 * c.w;  // a coat on the cases with a specular factor
        material.clearcoatRoughness = b.w;
        material.clearcoatTexture = -1;
        material.clearcoatRoughnessTexture = -1;
        material.clearcoatNormalTexture = -1;
        material.clearcoatNormalScale = 1.0;
        material.sheenColor = real3(0.0);  // sheen reads a table: tests/gpu_surface_test.cpp covers it
        material.sheenRoughness = 0.0;
        material.sheenColorTexture = -1;
        material.sheenRoughnessTexture = -1;
        material.textureSlots = 0u;
        const SurfaceResponse s = surfaceResponse(material, untexturedSample(material, xyz(a)));
        const real3 normal = real3(0.0, 0.0, 1.0), toViewer = normalize(xyz(d)), toLight = normalize(xyz(e));
        if (fc.function == VKRT_CASE_SURFACE) {
            const real3 brdf = specularBrdf(s, normal, toViewer, toLight);
            r0 = real4(brdf.x, brdf.y, brdf.z, lobePdf(s, normal, normal, toViewer, toLight));
            const real3 fresnel = fresnelAt(s, d.w, c.y);
            r1 = real4(fresnel.x, fresnel.y, fresnel.z, s.alpha);
        } else {
            const real3 light =
                reflectedLight(s, normal, normal, toViewer, toLight, xyz(b), real3(c.z), real3(1.0));
            r0 = real4(light.x, light.y, light.z, s.transmission);
            r1 = real4(s.diffuse.x, s.specular.x, s.specular.y, (s.mirror ? 1.0 : 0.0) + (s.traced ? 2.0 : 0.0));
        }
    } else if (fc.function == VKRT_CASE_PUNCTUAL) {
        PunctualLightParams light;
        light.type = fc.integer;
        light.position = xyz(a);
        light.range = a.w;
        light.direction = normalize(xyz(b));
        light.cosOuter = b.w;
        light.intensity = xyz(c);
        light.coneScale = c.w;
        const LightArrival arrival = arriveFrom(light, xyz(d));
        r0 = real4(arrival.irradiance.x, arrival.irradiance.y, arrival.irradiance.z,
                   isinf(arrival.distance) ? -1.0 : arrival.distance);
        r1 = real4(arrival.toLight.x, arrival.toLight.y, arrival.toLight.z, 0.0);
    } else if (fc.function == VKRT_CASE_TRIANGLE_LIGHT) {
        // Corners a, b and c, picked with probability b.w, seen from (c.w, d.z, d.w) at (d.x, d.y); the
        // density per unit area is the pick over the triangle's area, as the devices take it.
        const real3 from = real3(c.w, d.z, d.w);
        const real pdfArea = b.w / triangleArea(xyz(a), xyz(b), xyz(c));
        const LightPoint p =
            sampleTriangleLight(7u, xyz(a), xyz(b), xyz(c), b.w, pdfArea, from, true, d.x, d.y);
        const real3 offset = p.position - from;
        const real distance2 = dot(offset, offset);
        const real cosLight = abs(dot(p.normal, offset)) / sqrt(distance2);
        r0 = real4(p.position.x, p.position.y, p.position.z, p.pdfArea);
        r1 = real4(p.normal.x, sphericalTriangle(xyz(a), xyz(b), xyz(c), from).area, p.uv.x + p.uv.y,
                   triangleLightSolidAnglePdf(xyz(a), xyz(b), xyz(c), b.w, pdfArea, from, true, distance2,
                                              cosLight));
    } else if (fc.function == VKRT_CASE_SPHERE_LIGHT) {
        const LightPoint p = sampleSphereLight(7u, xyz(a), a.w, b.w, xyz(b), false, c.x, c.y);
        const real3 offset = p.position - xyz(b);
        const real distance2 = dot(offset, offset);
        const real cosLight = -dot(p.normal, offset) / sqrt(distance2);
        r0 = real4(p.position.x, p.position.y, p.position.z, p.pdfArea);
        r1 = real4(p.normal.x, p.uv.x, p.uv.y,
                   sphereLightSolidAnglePdf(xyz(a), a.w, b.w, xyz(b), false, distance2, cosLight));
    } else if (fc.function == VKRT_CASE_SPHERE) {
        real t0, t1;
        const bool hit = sphereRoots(xyz(a), a.w, xyz(b), xyz(c), t0, t1);
        const real3 toCenter = xyz(a) - xyz(b);
        r0 = real4(t0, t1, hit ? 1.0 : 0.0, coneOneMinusCos(a.w, dot(toCenter, toCenter)));
        const real2 uv = sphereUv(normalize(xyz(c)));
        real t;
        const bool near = intersectSphere(xyz(a), a.w, xyz(b), xyz(c), 0.0, VKRT_INFINITY, t);
        r1 = real4(uv.x, uv.y, near ? t : -1.0, 0.0);
    } else if (fc.function == VKRT_CASE_ABSORPTION) {
        const real3 beer = beerLambert(xyz(a), a.w, b.x);
        r0 = real4(beer.x, beer.y, beer.z, solidAnglePdfFromArea(b.y, b.z, b.w));
        r1 = real4(powerHeuristic(c.x, c.y, c.z), luminance(xyz(a)), lightPower(xyz(a), c.w), 0.0);
    } else if (fc.function == VKRT_CASE_MEDIA) {
        // Up to eight operations, four bits each: 1-7 enter that material, 9-15 leave material (code - 8).
        uvec2 media = emptyMedia();
        for (uint k = 0u; k < 8u; ++k) {
            const uint op = (fc.integer >> (4u * k)) & 15u;
            if (op > 0u && op < 8u) media = mediaEntered(media, op);
            if (op > 8u) media = mediaExited(media, op - 8u);
        }
        r0 = real4(real(media.x >> 16u), real(media.x & 0xffffu), real(media.y >> 16u), real(media.y & 0xffffu));
        r1 = real4(real(innermostMedium(media)), real(mediaSize(media)), 0.0, 0.0);
    } else if (fc.function == VKRT_CASE_TEXTURE) {
        GpuTexture texture;
        texture.firstTexel = 0u;
        texture.width = VKRT_CASE_TEXTURE_WIDTH;
        texture.height = VKRT_CASE_TEXTURE_HEIGHT;
        texture.flags = fc.integer & 31u;
        r0 = sampleTexture(VKRT_DEVICE_ARG texture, real2(a.x, a.y), (fc.integer & 32u) == 0u, 0.0);  // bit 5: linear
        const uvec2 wrapped = wrapTexels(int(b.x), int(b.y), uint(b.z));
        r1 = real4(srgbToLinear(a.z), real(wrapped.x), real(wrapped.y), 0.0);
    } else if (fc.function == VKRT_CASE_CAMERA) {
        CameraFrame camera;
        camera.projection = fc.integer;
        camera.position = xyz(a);
        camera.tanHalfFov = a.w;
        camera.forward = normalize(xyz(b));
        camera.lensRadius = b.w;
        camera.right = normalize(xyz(c));
        camera.focusDistance = c.w;
        camera.up = normalize(xyz(d));
        camera.xmag = d.w;
        camera.ymag = 0.75 * d.w;
        camera.width = 64.0;
        camera.height = 48.0;
        camera.sceneRadius = 100.0;  // a lens wider than that starts its rays nearer
        const CameraRay ray = cameraRay(camera, e.x, e.y, e.z, e.w);
        r0 = real4(ray.origin.x, ray.origin.y, ray.origin.z, 0.0);
        r1 = real4(ray.direction.x, ray.direction.y, ray.direction.z, 0.0);
    } else if (fc.function == VKRT_CASE_FILTER) {
        const real2 offset = filterOffset(fc.integer, a.x, a.y);
        const real2 disk = concentricDisk(a.x, a.y);
        r0 = real4(offset.x, offset.y, disk.x, disk.y);
        r1 = real4(tentInverse(a.z), 0.0, 0.0, 0.0);
    } else if (fc.function == VKRT_CASE_BINDING) {
        r0 = sampleBinding(VKRT_DEVICE_ARG int(fc.integer), 0u, real2(a.x, a.y), 0.0);
        GpuTextureBinding binding;
        binding.row0 = vec3(fc.b.x, fc.b.y, fc.b.z);
        binding.row1 = vec3(fc.c.x, fc.c.y, fc.c.z);
        binding.texture = 0;
        binding.flags = 0u;
        const real2 uv = transformUv(binding, real2(a.x, a.y));
        r1 = real4(uv.x, uv.y, 0.0, 0.0);
    } else if (fc.function == VKRT_CASE_ENVIRONMENT) {
        // A sample for (a.x, a.y) with fine parts (a.z, a.w), and the radiance and density of direction b.
        const EnvironmentSample s = sampleEnvironment(VKRT_DEVICE_ARG a.x, a.y, a.z, a.w);
        r0 = real4(s.direction.x, s.direction.y, s.direction.z, s.pdf);
        const real3 d = normalize(xyz(b));
        const real3 radiance = environmentRadiance(VKRT_DEVICE_ARG d);
        r1 = real4(radiance.x + 10.0 * radiance.y, environmentPdf(VKRT_DEVICE_ARG d),
                   environmentPdf(VKRT_DEVICE_ARG s.direction), s.radiance.x + 10.0 * s.radiance.y);
    } else if (fc.function == VKRT_CASE_BASIS) {
        real3 b1, b2;
        orthonormalBasis(normalize(xyz(a)), b1, b2);
        r0 = real4(b1.x, b1.y, b1.z, 0.0);
        r1 = real4(b2.x, b2.y, b2.z, 0.0);
    } else if (fc.function == VKRT_CASE_ROTATE) {
        const real3 v = rotateLike(normalize(xyz(c)), normalize(xyz(a)), normalize(xyz(b)), 1e-6);
        r0 = real4(v.x, v.y, v.z, maxComponent(xyz(a)));
        r1 = real4(maxAbs(xyz(a)), allFinite(xyz(a)) ? 1.0 : 0.0, 0.0, 0.0);
    }
}

VKRT_SHADING_END

#endif  // VKRT_SHADING_CASES_H
