// The volumes a ray is inside, for nested dielectrics (glass in water), and their absorption. Entering a
// volume through its front face pushes it, leaving through its back face removes its innermost occurrence,
// and the relative index at each interface is between the medium the ray is in and the one it passes into.
// The stack holds up to four 16-bit material indices, outermost in the low half of .x, 0xffff in an empty
// slot; a fifth volume forgets the outermost.
#ifndef VKRT_MEDIA_H
#define VKRT_MEDIA_H

#include "shading_language.h"

#define VKRT_NO_MEDIUM 0xffffu
#define VKRT_MEDIA_CAPACITY 4

VKRT_SHADING_BEGIN

VKRT_FN uvec2 emptyMedia() { return uvec2(0xffffffffu, 0xffffffffu); }

VKRT_FN uint mediumAt(uvec2 media, int i) {
    return ((i < 2 ? media.x : media.y) >> uint(16 * (i & 1))) & 0xffffu;
}

VKRT_FN uvec2 withMediumAt(uvec2 media, int i, uint material) {
    const uint shift = uint(16 * (i & 1));
    const uint cleared = ~(0xffffu << shift);
    if (i < 2) media.x = (media.x & cleared) | ((material & 0xffffu) << shift);
    else media.y = (media.y & cleared) | ((material & 0xffffu) << shift);
    return media;
}

VKRT_FN int mediaSize(uvec2 media) {
    int size = 0;
    VKRT_UNROLL for (int i = 0; i < VKRT_MEDIA_CAPACITY; ++i) {
        size += mediumAt(media, i) != VKRT_NO_MEDIUM ? 1 : 0;
    }
    return size;
}

// The material of the innermost volume, -1 outside every volume.
VKRT_FN int innermostMedium(uvec2 media) {
    const int size = mediaSize(media);
    return size > 0 ? int(mediumAt(media, size - 1)) : -1;
}

VKRT_FN uvec2 mediaEntered(uvec2 media, uint material) {
    int size = mediaSize(media);
    if (size == VKRT_MEDIA_CAPACITY) {
        VKRT_UNROLL for (int i = 1; i < VKRT_MEDIA_CAPACITY; ++i) {
            media = withMediumAt(media, i - 1, mediumAt(media, i));
        }
        size = VKRT_MEDIA_CAPACITY - 1;
    }
    return withMediumAt(media, size, material);
}

// Without `material` (its innermost occurrence); unchanged when the ray was not inside it.
VKRT_FN uvec2 mediaExited(uvec2 media, uint material) {
    const int size = mediaSize(media);
    int found = -1;
    VKRT_UNROLL for (int i = 0; i < VKRT_MEDIA_CAPACITY; ++i) {
        if (i < size && mediumAt(media, i) == material) found = i;
    }
    if (found < 0) return media;
    VKRT_UNROLL for (int i = 0; i < VKRT_MEDIA_CAPACITY - 1; ++i) {
        if (i >= found && i + 1 < size) media = withMediumAt(media, i, mediumAt(media, i + 1));
    }
    return withMediumAt(media, size - 1, VKRT_NO_MEDIUM);
}

// Whether light fades inside a volume whose light keeps `attenuationColor` after `attenuationDistance`: a
// finite distance and some channel below 1; otherwise beerLambert is 1 everywhere (and the GPU's shader for a
// scene where no volume attenuates leaves absorption out: scene_features.cpp).
VKRT_FN bool attenuates(real3 attenuationColor, real attenuationDistance) {
    return !(isinf(attenuationDistance) || isnan(attenuationDistance)) &&
           min(attenuationColor.x, min(attenuationColor.y, attenuationColor.z)) < 1.0;
}

// Beer-Lambert transmittance over `distance` inside a volume whose light keeps `attenuationColor` after
// `attenuationDistance` (KHR_materials_volume; infinity: no absorption).
VKRT_FN real3 beerLambert(real3 attenuationColor, real attenuationDistance, real distance) {
    real3 result = real3(1.0);
    if (!attenuates(attenuationColor, attenuationDistance)) return result;
    VKRT_UNROLL for (int c = 0; c < 3; ++c) {
        const real color = attenuationColor[c];
        if (color >= 1.0) continue;
        if (color <= 0.0 || isinf(distance)) {
            result[c] = distance > 0.0 ? 0.0 : 1.0;
            continue;
        }
        result[c] = exp(log(color) / attenuationDistance * distance);
    }
    return result;
}

VKRT_SHADING_END

#endif  // VKRT_MEDIA_H
