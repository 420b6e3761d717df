// Rays, and spawning new rays off a surface without hitting it again.
#ifndef VKRT_RAY_GLSL
#define VKRT_RAY_GLSL

#define VKRT_NO_TRIANGLE 0xffffffffu
#define VKRT_INFINITY uintBitsToFloat(0x7f800000u)

struct Ray {
    vec3 origin;
    vec3 direction;
};

// A hit point and the size of the numbers it was computed from. Rounding errors of the point, and of
// the intersection test that found it, are a small multiple of float epsilon times that magnitude.
struct SurfacePoint {
    vec3 position;
    float errorScale;
};

float maxAbs(vec3 v) { return max(abs(v.x), max(abs(v.y), abs(v.z))); }

// The hit point, computed whichever way rounds less: from the barycentrics (error relative to the
// vertices' magnitude) or along the ray (error relative to |origin| + t). Huge triangles seen from nearby
// favour the ray; distant hits favour the barycentrics.
SurfacePoint hitPoint(vec3 origin, vec3 direction, float t, vec3 v0, vec3 v1, vec3 v2, float u, float v) {
    const float vertexScale = max(maxAbs(v0), max(maxAbs(v1), maxAbs(v2)));
    const float rayScale = maxAbs(origin) + t;
    if (rayScale < vertexScale) return SurfacePoint(origin + t * direction, rayScale);
    return SurfacePoint((1.0 - u - v) * v0 + u * v1 + v * v2, vertexScale);
}

// Moves a point off a surface along the geometric normal `n` (pointing to the side the new ray leaves
// from) by 2^-18 of its error scale, about 32 times the float rounding of that magnitude, so the new ray
// cannot start behind the surface. The offset scales with the scene, so tiny and huge scenes behave alike
// (a fixed absolute offset near the origin, as in Ray Tracing Gems ch. 6, breaks scenes a few microns
// across). The triangle just left is also excluded from the new ray's hits.
vec3 offsetRayOrigin(SurfacePoint p, vec3 n) {
    return p.position + (max(p.errorScale, maxAbs(p.position)) * 3.814697265625e-6) * n;
}

// `v` turned by the smallest rotation that takes unit vector `from` to unit vector `to` (Rodrigues), as
// rotateLike in host/cpu/optics.h.
vec3 rotateLike(vec3 v, vec3 from, vec3 to) {
    const vec3 axis = cross(from, to);
    const float sine = length(axis), cosine = dot(from, to);
    if (!(sine > 1e-6) || cosine <= -1.0 + 1e-6) return cosine < 0.0 ? to : v;
    const vec3 k = axis / sine;
    return v * cosine + cross(k, v) * sine + k * dot(k, v) * (1.0 - cosine);
}

float maxComponent(vec3 v) { return max(v.x, max(v.y, v.z)); }

bool allFinite(vec3 v) { return !any(isnan(v)) && !any(isinf(v)); }

#endif
