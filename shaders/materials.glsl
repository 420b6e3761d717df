// Materials in vkrt's Whitted model, as docs/materials.md defines them and host/cpu/whitted_model.h
// computes them. Requires `params` in scope.
#ifndef VKRT_MATERIALS_GLSL
#define VKRT_MATERIALS_GLSL

const float PI = 3.14159265358979323846;
#define VKRT_MIRROR_ROUGHNESS 1e-3  // as kMirrorRoughness in host/cpu/microfacet.h

#include "microfacet.glsl"

#ifdef VKRT_HAS_TEXTURES
uint wrapTexel(int i, int size, uint mode) {
    if (mode == 1u) return uint(clamp(i, 0, size - 1));  // clamp to edge
    if (mode == 2u) {                                     // mirrored repeat
        const int period = 2 * size;
        const int m = ((i % period) + period) % period;
        return uint(m < size ? m : period - 1 - m);
    }
    return uint(((i % size) + size) % size);  // repeat
}

float srgbToLinear(float encoded) {
    return encoded <= 0.04045 ? encoded / 12.92 : pow((encoded + 0.055) / 1.055, 2.4);
}

vec4 texel(GpuTexture texture, int x, int y) {
    const uint column = wrapTexel(x, int(texture.width), texture.flags & 3u);
    const uint row = wrapTexel(y, int(texture.height), (texture.flags >> 2u) & 3u);
    const vec4 rgba = unpackUnorm4x8(params.texels.texels[texture.firstTexel + row * texture.width + column]);
    return vec4(srgbToLinear(rgba.r), srgbToLinear(rgba.g), srgbToLinear(rgba.b), rgba.a);
}

// Linear RGBA at `uv`: texel centres at half-integers, bilinear unless the sampler says nearest.
vec4 sampleTexture(int index, vec2 uv) {
    const GpuTexture texture = params.textures.textures[index];
    const float x = uv.x * float(texture.width) - 0.5, y = uv.y * float(texture.height) - 0.5;
    if ((texture.flags & 16u) != 0u) return texel(texture, int(floor(x + 0.5)), int(floor(y + 0.5)));
    const float x0 = floor(x), y0 = floor(y);
    const float fx = x - x0, fy = y - y0;
    const int ix = int(x0), iy = int(y0);
    return (1.0 - fx) * (1.0 - fy) * texel(texture, ix, iy) + fx * (1.0 - fy) * texel(texture, ix + 1, iy) +
           (1.0 - fx) * fy * texel(texture, ix, iy + 1) + fx * fy * texel(texture, ix + 1, iy + 1);
}

vec2 uvAt(uint triangle, float u, float v) {
#ifdef VKRT_HAS_SPHERES
    if (VKRT_TRIANGLE(triangle).kind == VKRT_PRIMITIVE_SPHERE) return vec2(u, v);  // spheres carry their own
#endif
    const GpuShading s = params.shading.shading[triangle];
    return (1.0 - u - v) * vec2(s.normalU0.w, s.v012.x) + u * vec2(s.normalU1.w, s.v012.y) +
           v * vec2(s.normalU2.w, s.v012.z);
}
#endif

uint materialOf(uint triangle) { return VKRT_TRIANGLE(triangle).material; }

// A colour factor times its texture (index -1: none) at the hit's texture coordinates.
vec3 textured(vec3 factor, int texture, uint triangle, float u, float v) {
#ifdef VKRT_HAS_TEXTURES
    if (texture >= 0) return factor * sampleTexture(texture, uvAt(triangle, u, v)).rgb;
#endif
    return factor;
}

vec3 albedoAt(GpuMaterial material, uint triangle, float u, float v) {
    return textured(material.baseColorMetallic.rgb, material.textures.x, triangle, u, v);
}

vec3 emissionAt(GpuMaterial material, uint triangle, float u, float v) {
    return textured(material.emissionRoughness.rgb, material.textures.y, triangle, u, v);
}

struct SurfaceResponse {
    vec3 albedo;
    vec3 diffuse;
    vec3 specular;  // F0
    float alpha;    // GGX width
    bool mirror;    // a delta lobe (roughness 0)
    bool traced;    // the specular lobe is traced
    float transmission;
    float metallic;
    float ior;
};

// As host/cpu/whitted_model.h.
SurfaceResponse surfaceResponse(GpuMaterial material, vec3 albedo) {
    SurfaceResponse s;
    const float roughness = material.emissionRoughness.w;
    s.albedo = albedo;
    s.metallic = material.baseColorMetallic.w;
    s.ior = material.transmission.y;
    s.transmission = (1.0 - s.metallic) * material.transmission.x;
    s.diffuse = albedo * (1.0 - s.metallic) * (1.0 - material.transmission.x);
    const float r = (s.ior - 1.0) / (s.ior + 1.0);
    s.specular = mix(vec3(r * r), albedo, s.metallic);
    s.alpha = max(roughness * roughness, VKRT_MIRROR_ROUGHNESS * VKRT_MIRROR_ROUGHNESS);
    s.mirror = roughness < VKRT_MIRROR_ROUGHNESS;
    s.traced = s.metallic > 0.0 || s.transmission > 0.0 || roughness < 1.0;
    return s;
}

// Unpolarised Fresnel reflectance of a dielectric interface; eta = n_transmitted / n_incident.
float fresnelDielectric(float cosI, float eta) {
    cosI = clamp(cosI, 0.0, 1.0);
    const float sin2T = (1.0 - cosI * cosI) / (eta * eta);
    if (sin2T >= 1.0) return 1.0;
    const float cosT = sqrt(1.0 - sin2T);
    const float rs = (cosI - eta * cosT) / (cosI + eta * cosT);
    const float rp = (eta * cosI - cosT) / (eta * cosI + cosT);
    return 0.5 * (rs * rs + rp * rp);
}

vec3 fresnelSchlick(vec3 f0, float cosI) {
    const float m = pow(1.0 - clamp(cosI, 0.0, 1.0), 5.0);
    return f0 + (vec3(1.0) - f0) * m;
}

vec3 fresnelAt(SurfaceResponse s, float cosH, float eta) {
    return (1.0 - s.metallic) * vec3(fresnelDielectric(cosH, eta)) + s.metallic * fresnelSchlick(s.albedo, cosH);
}

vec3 specularBrdf(SurfaceResponse s, vec3 normal, vec3 toViewer, vec3 toLight) {
    const float cosOut = dot(normal, toViewer), cosIn = dot(normal, toLight);
    if (s.mirror || cosOut <= 0.0 || cosIn <= 0.0) return vec3(0.0);
    const vec3 halfway = normalize(toViewer + toLight);
    return fresnelAt(s, dot(toViewer, halfway), s.ior) * ggxD(dot(normal, halfway), s.alpha) *
           ggxG2(cosOut, cosIn, s.alpha) / (4.0 * cosOut * cosIn);
}

float lobePdf(SurfaceResponse s, vec3 normal, vec3 toViewer, vec3 toLight) {
    if (!s.traced || s.mirror) return 0.0;
    const vec3 halfway = normalize(toViewer + toLight);
    return ggxReflectionPdf(dot(normal, toViewer), dot(normal, halfway), s.alpha);
}

vec3 reflectAbout(vec3 toViewer, vec3 normal) { return 2.0 * dot(toViewer, normal) * normal - toViewer; }

// Snell's law; false on total internal reflection.
bool refractThrough(vec3 toViewer, vec3 normal, float eta, out vec3 transmitted) {
    const float cosI = dot(toViewer, normal);
    const float sin2I = max(0.0, 1.0 - cosI * cosI);
    const float sin2T = sin2I / (eta * eta);
    transmitted = vec3(0.0);
    if (sin2T >= 1.0) return false;
    const float cosT = sqrt(1.0 - sin2T);
    transmitted = -toViewer / eta + (cosI / eta - cosT) * normal;
    return true;
}

#ifdef VKRT_HAS_VOLUMES
// Beer-Lambert transmittance over `distance` inside a volume material.
vec3 beerLambert(GpuMaterial material, float distance) {
    vec3 result = vec3(1.0);
    const float attenuationDistance = material.attenuation.w;
    if (isinf(attenuationDistance)) return result;
    for (int c = 0; c < 3; ++c) {
        const float color = material.attenuation[c];
        if (color >= 1.0) continue;
        if (color <= 0.0 || isinf(distance)) {
            result[c] = distance > 0.0 ? 0.0 : 1.0;
            continue;
        }
        result[c] = exp(log(color) / attenuationDistance * distance);
    }
    return result;
}
#endif

#endif
