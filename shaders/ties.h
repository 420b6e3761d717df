// The closest-hit rule both devices' walks keep (README, "Deterministic ties"): hits within a tie's width of
// the nearest hit are ties, won by the smallest scene index, whatever order the walk meets them in. Shared by
// the CPU reference (host/cpu/closest_hit.h, in double) and the GPU's walk (traverse.glsl, in float).
#ifndef VKRT_TIES_H
#define VKRT_TIES_H

#include "shading_language.h"

VKRT_SHADING_BEGIN

// The width of a tie (shared.h's VKRT_TIE_EPSILON) at distance t along a ray whose origin's largest coordinate
// is `originScale`: relative to the magnitude of the numbers the distance came from, as its rounding is.
VKRT_FN real tieWidth(real t, real originScale) {
    return real(VKRT_TIE_EPSILON) * (originScale + t);
}

// Whether a hit at `t` on scene primitive `index` becomes the best, the best so far (when `found`) at `bestT`
// on `bestIndex`; `nearest` is the nearest hit so far (the walk's search limit keeps t within a tie's width of
// it), and becomes t where t is nearer. A nearer hit narrows the window: when the best falls out of it while
// an earlier hit may stay inside, that candidate was not kept, `lost` turns true, and the walk must run once
// more with the nearest distance known (then every hit in its window is seen; rare: three surfaces within two
// ties' widths).
VKRT_FN bool takesClosestHit(real t, uint index, bool found, real bestT, uint bestIndex, real originScale,
                             VKRT_INOUT(real) nearest, VKRT_INOUT(bool) lost) {
    const real reach = t + tieWidth(t, originScale);
    const bool dropsBest = found && t < nearest && bestT > reach;
    lost = lost || (dropsBest && nearest <= reach);
    nearest = min(nearest, t);
    return !found || dropsBest || index < bestIndex;
}

VKRT_SHADING_END

#endif
