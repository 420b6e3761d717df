#version 460
// Evaluates the shared shading functions (shaders/*.h) in single precision on a table of cases
// (shading_cases.h), for tests/shading_functions_test.cpp to compare with their double-precision C++
// evaluation.
#extension GL_GOOGLE_include_directive : require
#extension GL_EXT_buffer_reference : require
#include "ieee_floats.glsl"

#define VKRT_HAS_TEXTURES
#define VKRT_HAS_DEPTH_OF_FIELD
#define VKRT_HAS_CLEARCOAT
#define VKRT_HAS_ENVIRONMENT
#define VKRT_HAS_TRACED_LOBES  // reflectedLight's specular lobe (left out of Lambertian scenes' shaders)
#define VKRT_HAS_SOLID_ANGLE_TRIANGLES
#include "shared.h"
#include "shading_language.h"

layout(local_size_x = 64) in;

layout(std430, binding = 1) readonly buffer Texels { uint texels[]; };

// The device the texture functions read through (defined below, once the case constants are known): the
// texel buffer, one texture and two bindings of it.
uint device_texel(uint index);
GpuTexture device_textureInfo(int index);
GpuTextureBinding device_textureBinding(int index);
vec2 device_textureCoordinates(uint primitive, vec2 hitUv, uint set);
uvec2 device_environmentSize();
vec2 device_environmentRotation();
vec3 device_environmentTexel(uint i);
float device_environmentRowCdf(uint y);
float device_environmentColumnCdf(uint i);

#include "shading_cases.h"

uint device_texel(uint index) { return texels[index]; }
GpuTexture device_textureInfo(int index) {
    return GpuTexture(0u, VKRT_CASE_TEXTURE_WIDTH, VKRT_CASE_TEXTURE_HEIGHT, VKRT_WRAP_REPEAT);
}
GpuTextureBinding device_textureBinding(int index) {
    if (index == 0) return GpuTextureBinding(VKRT_CASE_BINDING0_ROW0, 0, VKRT_CASE_BINDING0_ROW1, VKRT_BINDING_SRGB);
    return GpuTextureBinding(VKRT_CASE_BINDING1_ROW0, 0, VKRT_CASE_BINDING1_ROW1, 0u);
}
vec2 device_textureCoordinates(uint primitive, vec2 hitUv, uint set) { return hitUv; }
uvec2 device_environmentSize() { return uvec2(VKRT_CASE_ENVIRONMENT_WIDTH, VKRT_CASE_ENVIRONMENT_HEIGHT); }
vec2 device_environmentRotation() { return vec2(VKRT_CASE_ENVIRONMENT_COS, VKRT_CASE_ENVIRONMENT_SIN); }
float environmentWord(uint i) { return uintBitsToFloat(texels[VKRT_CASE_ENVIRONMENT_FIRST + i]); }
vec3 device_environmentTexel(uint i) {
    return vec3(environmentWord(4u * i), environmentWord(4u * i + 1u), environmentWord(4u * i + 2u));
}
float device_environmentColumnCdf(uint i) { return environmentWord(4u * i + 3u); }
float device_environmentRowCdf(uint y) {
    return environmentWord(4u * VKRT_CASE_ENVIRONMENT_WIDTH * VKRT_CASE_ENVIRONMENT_HEIGHT + y);
}

layout(std430, binding = 0) readonly buffer Cases { FunctionCase cases[]; };
layout(std430, binding = 2) writeonly buffer Results { vec4 results[]; };
layout(push_constant) uniform Constants { uint count; };

void main() {
    const uint i = gl_GlobalInvocationID.x;
    if (i >= count) return;
    vec4 r0, r1;
    evaluateCase(cases[i], r0, r1);
    results[2u * i] = r0;
    results[2u * i + 1u] = r1;
}
