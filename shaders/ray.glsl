// Rays, and spawning new rays off a surface without hitting it again.
#ifndef VKRT_RAY_GLSL
#define VKRT_RAY_GLSL

#define VKRT_NO_TRIANGLE 0xffffffffu
#define VKRT_INFINITY uintBitsToFloat(0x7f800000u)

struct Ray {
    vec3 origin;
    vec3 direction;
};

// Moves a point off a surface along the geometric normal `n` (pointing to the side the new ray leaves
// from) by a few units in the last place of its coordinates, so the offset scales with the rounding error
// of the hit point at any distance from the origin. Wachter and Binder, "A Fast and Robust Method for
// Avoiding Self-Intersection", Ray Tracing Gems (2019), chapter 6.
vec3 offsetRayOrigin(vec3 p, vec3 n) {
    const float originBand = 1.0 / 32.0;
    const float floatScale = 1.0 / 65536.0;
    const float intScale = 256.0;
    ivec3 offset = ivec3(intScale * n);
    vec3 moved = intBitsToFloat(floatBitsToInt(p) + ivec3(p.x < 0.0 ? -offset.x : offset.x,
                                                          p.y < 0.0 ? -offset.y : offset.y,
                                                          p.z < 0.0 ? -offset.z : offset.z));
    return vec3(abs(p.x) < originBand ? p.x + floatScale * n.x : moved.x,
                abs(p.y) < originBand ? p.y + floatScale * n.y : moved.y,
                abs(p.z) < originBand ? p.z + floatScale * n.z : moved.z);
}

float maxComponent(vec3 v) { return max(v.x, max(v.y, v.z)); }

bool allFinite(vec3 v) { return !any(isnan(v)) && !any(isinf(v)); }

#endif
