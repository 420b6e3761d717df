// How many texture coordinates a world unit spans on a surface, which a texture lookup's level of detail
// needs (texture_sampling.h's sampleBinding); each device evaluates it for its primitives (textureDensity).
#ifndef VKRT_TEXTURE_DENSITY_H
#define VKRT_TEXTURE_DENSITY_H

#include "shading_language.h"

VKRT_SHADING_BEGIN

// Texture coordinates per world unit on a triangle (corners v0, v1, v2 with texture coordinates t0, t1, t2):
// the square root of the ratio of its areas in texture and world space.
VKRT_FN real triangleTextureDensity(real3 v0, real3 v1, real3 v2, real2 t0, real2 t1, real2 t2) {
    const real2 a = t1 - t0, b = t2 - t0;
    const real world = length(cross(v1 - v0, v2 - v0));
    return world > 0.0 ? sqrt(abs(a.x * b.y - a.y * b.x) / world) : 0.0;
}

// The same on a sphere of `radius` at texture coordinate v (sphere_geometry.h's sphereUv: u the longitude over
// 2 pi, v the colatitude over pi): sqrt(du/ds dv/ds) = 1 / (pi radius sqrt(2 sin(pi v))).
VKRT_FN real sphereTextureDensity(real radius, real v) {
    return 1.0 / (VKRT_PI * radius * sqrt(2.0 * max(sin(VKRT_PI * v), 1e-4)));
}

VKRT_SHADING_END

#endif  // VKRT_TEXTURE_DENSITY_H
