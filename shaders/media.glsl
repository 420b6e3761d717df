// The volumes a ray is inside, for nested dielectrics: up to four 16-bit material indices, outermost in
// the low half of .x, 0xffff for an empty slot. The same rules as host/cpu/medium_stack.h: entering a
// volume pushes it (a fifth forgets the outermost), leaving removes its innermost occurrence.
#ifndef VKRT_MEDIA_GLSL
#define VKRT_MEDIA_GLSL

#define VKRT_NO_MEDIUM 0xffffu
#define VKRT_EMPTY_MEDIA uvec2(0xffffffffu)

uint mediumAt(uvec2 media, int i) { return ((i < 2 ? media.x : media.y) >> (16 * (i & 1))) & 0xffffu; }

uvec2 withMediumAt(uvec2 media, int i, uint material) {
    const uint shift = uint(16 * (i & 1));
    const uint cleared = ~(0xffffu << shift);
    if (i < 2) media.x = (media.x & cleared) | ((material & 0xffffu) << shift);
    else media.y = (media.y & cleared) | ((material & 0xffffu) << shift);
    return media;
}

int mediaSize(uvec2 media) {
    int size = 0;
    for (int i = 0; i < 4; ++i) size += mediumAt(media, i) != VKRT_NO_MEDIUM ? 1 : 0;
    return size;
}

// The material of the innermost volume, -1 outside every volume.
int innermostMedium(uvec2 media) {
    const int size = mediaSize(media);
    return size > 0 ? int(mediumAt(media, size - 1)) : -1;
}

uvec2 mediaEntered(uvec2 media, uint material) {
    int size = mediaSize(media);
    if (size == 4) {
        for (int i = 1; i < 4; ++i) media = withMediumAt(media, i - 1, mediumAt(media, i));
        size = 3;
    }
    return withMediumAt(media, size, material);
}

uvec2 mediaExited(uvec2 media, uint material) {
    const int size = mediaSize(media);
    int found = -1;
    for (int i = 0; i < 4; ++i) {
        if (i < size && mediumAt(media, i) == material) found = i;
    }
    if (found < 0) return media;
    for (int i = 0; i < 3; ++i) {
        if (i >= found && i + 1 < size) media = withMediumAt(media, i, mediumAt(media, i + 1));
    }
    return withMediumAt(media, size - 1, VKRT_NO_MEDIUM);
}

// The index of refraction of the innermost volume, 1 (air) outside every volume.
float mediaIor(uvec2 media) {
    const int top = innermostMedium(media);
    return top >= 0 ? params.materials.materials[top].transmission.y : 1.0;
}

#endif
