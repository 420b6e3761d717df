// The order in which a dispatch's workgroups take their work: the render kernel's 8 x 8 tiles along each
// band of rows, the raycast kernel's blocks of rays. lavapipe (Mesa 22.3's llvmpipe) hands each of its
// threads one contiguous run of a dispatch's workgroups in launch order (lp_cs_tpool: a run of groups /
// threads each, no stealing), so with workgroups in image order one thread took the sky and the other the
// spheres, and the dispatch lasted as long as the costlier run. Spread for T threads, n items are a grid of
// ceil(n / T) workgroups by T columns, the column the slowest dimension: thread t runs column t, whose k-th
// workgroup takes item k * T + t, so every thread's items interleave over the whole range, each a fixed step
// from its last (its rays as coherent as in order), and no workgroup divides to find its item. Workgroups
// past the last item do nothing. One column is the order itself (GPUs hand workgroups out as their units
// free up).
#ifndef VKRT_SPREAD_WORKGROUPS_H
#define VKRT_SPREAD_WORKGROUPS_H

#include "shading_language.h"

VKRT_SHADING_BEGIN

// The item workgroup `k` of column `column` (of `columns`) takes.
VKRT_FN uint spreadItem(uint k, uint column, uint columns) {
    return k * columns + column;
}

VKRT_SHADING_END

#endif  // VKRT_SPREAD_WORKGROUPS_H
