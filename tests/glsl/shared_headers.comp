#version 460
// Compiles the headers that C++ and GLSL share (layouts, random numbers and the shading physics), so a change
// that only C++ accepts fails a test now rather than when the GPU tracer is built. Writes random numbers,
// node fields and a Fresnel term so nothing is optimised away. (shade_hit.h needs a device; the test that
// compiles trace.comp with every feature covers it.)
#extension GL_GOOGLE_include_directive : require
#extension GL_EXT_buffer_reference : require

#include "shared.h"
#include "random.h"
#include "area_light.h"
#include "camera.h"
#include "media.h"
#include "microfacet.h"
#include "optics.h"
#include "punctual_light.h"
#include "sphere_geometry.h"
#include "surface_response.h"
#include "texture_sampling.h"

layout(local_size_x = 64) in;

layout(std430, binding = VKRT_BINDING_PARAMS) readonly buffer Params { SceneParams params; };
layout(std430, binding = 1) writeonly buffer Out { float values[]; };

void main() {
    uint i = gl_GlobalInvocationID.x;
    WideBvhNode node = params.nodes.nodes[i];
    values[i] = vkrtRandom(1u, i, 2u, vkrtNodeDimension(3u, VKRT_DIM_LIGHT_U)) + node.originX +
                float(node.child0 + node.lowerX) + node.originY + fresnelDielectric(node.originZ, 1.5);
}
