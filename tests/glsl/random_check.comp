#version 460
// Writes vkrtRandomBits, vkrtRandom and vkrtStratified for a spread of (pixel, sample, dimension) keys, so the test can
// compare them with the C++ definition bit for bit.
#extension GL_GOOGLE_include_directive : require

#include "random.h"

layout(local_size_x = 64) in;
layout(std430, binding = 0) writeonly buffer Out { uint words[]; };
layout(push_constant) uniform Constants { uvec4 seedCount; };

void main() {
    const uint i = gl_GlobalInvocationID.x;
    if (i >= seedCount.y) return;
    const uint pixel = i * 7919u, sampleIndex = i % 1024u, dimension = i % 37u;
    words[4u * i] = vkrtRandomBits(seedCount.x, pixel, sampleIndex, dimension);
    words[4u * i + 1u] = floatBitsToUint(vkrtRandom(seedCount.x, pixel, sampleIndex, dimension));
    words[4u * i + 2u] = floatBitsToUint(vkrtStratified(seedCount.x, pixel, sampleIndex, dimension, 0u));
    words[4u * i + 3u] = floatBitsToUint(vkrtStratified(seedCount.x, pixel, sampleIndex, dimension, 1u));
}
