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

// Walks that go on past the hits they meet (the holes of alpha) take them in the order of the rule above: tie
// groups nearest first, and within a group by scene index. A group is the window a closest-hit walk judged its
// ties in: from its nearest hit, a tie's width (or to the end of a passed solid crossing's own tie group, where
// that is farther). Passing hits one at a time by distance alone lost a face coincident with the one just passed
// wherever rounding put it at or before that one's distance (a double-sided leaf made of two faces), and
// crossed one twice where it put it beyond. `WalkPast` is where such a walk stands.
struct WalkPast {
    real floor;  // hits up to here were passed (the groups before the current one, or where the walk began)
    real start;  // the current group: its nearest hit,
    real end;    // its end,
    uint index;  // the scene index of the hit of it passed last (the group's hits of lower index were passed),
    real after;  // and where that hit's own tie group ends (a solid's crossing), else its distance
};

// A walk past hits beyond `tMin`, before it has passed any.
VKRT_FN WalkPast walkPastFrom(real tMin) {
    WalkPast walk;
    walk.floor = tMin;
    walk.start = tMin;
    walk.end = tMin;
    walk.index = 0u;
    walk.after = tMin;
    return walk;
}

// Where a search for primitive `index`'s next hit starts (exclusive): past the current group for the primitives
// whose hits in it were all passed, past its last hit passed for the primitive of that hit (a sphere or a solid
// can be met again within the group: a thin one, or one far from the origin, where a tie is wider; its exit was
// lost, and a ray through a holed volume stayed inside), and where the walk stands for the others.
VKRT_FN real searchFloor(VKRT_IN(WalkPast) walk, uint index) {
    return index < walk.index ? walk.end : index == walk.index ? walk.after : walk.floor;
}

// The distance a hit at `t` counts as in the closest-hit rule: the current group's hits not yet passed are ties at
// its start, nearer than any hit beyond it, so the next is the one of least scene index.
VKRT_FN real rankedDistance(VKRT_IN(WalkPast) walk, real t) {
    return t <= walk.end ? walk.start : t;
}

// The walk once it has passed the hit at `t` of scene index `index` (a solid's crossing's tie group ending at
// `groupEnd`, else t), found by a closest-hit walk whose nearest ranked hit was `nearest`: the next of the
// current group, or the first of a new group from `nearest`.
VKRT_FN WalkPast walkPast(VKRT_IN(WalkPast) walk, real t, uint index, real groupEnd, real nearest,
                          real originScale) {
    WalkPast next = walk;
    if (t > walk.end) {
        next.floor = walk.end;
        next.start = nearest;
        next.end = nearest + tieWidth(nearest, originScale);
    }
    next.end = max(next.end, groupEnd);
    next.index = index;
    next.after = groupEnd;
    return next;
}

VKRT_SHADING_END

#endif
