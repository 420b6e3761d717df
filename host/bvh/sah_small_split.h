// The binned SAH split of a node with few primitives, found without bins: most nodes of a BVH hold a handful
// of primitives (in a 1M-triangle mesh, 85% of the nodes the build splits hold 16 or fewer), and for them
// clearing, filling and sweeping 3 x 16 bins costs more than the primitives themselves.
//
// The primitives are sorted by bin along each axis and swept once from each end; a plane may fall only
// between two primitives in different bins. Every plane is priced on the same primitive sets, with the
// same arithmetic (planeCost), in the same order (axes 0 to 2, bins ascending, a strictly lower cost
// replaces the best) as findSahSplit over the bins, so the split is the one binning would choose.
#pragma once

#include <cstdint>

#include "bvh/sah_binning.h"

namespace vkrt::sah {

class SmallNodeSplit {
  public:
    static constexpr uint32_t kMaxCount = 16;

    // The cheapest plane for refs[0, count), count <= kMaxCount, with the bins of `mapping`; the bounds of
    // its two sides follow from leftBounds() and rightBounds().
    Split find(const PrimRef* refs, uint32_t count, const BinMapping& mapping, const Aabb& nodeBounds,
               const Box4& doubledCenterBounds, const BvhConfig& config) {
        for (uint32_t i = 0; i < count; ++i) bins_[i] = mapping.binsOf(refs[i]);
        const float nodeArea = nodeBounds.surfaceArea();
        Split best;
        for (int axis = 0; axis < 3; ++axis) {
            if (!(doubledCenterBounds.max[axis] > doubledCenterBounds.min[axis])) continue;
            // Insertion sort by bin (few primitives).
            uint8_t order[kMaxCount];
            for (uint32_t i = 0; i < count; ++i) {
                const int32_t bin = bins_[i][axis];
                uint32_t j = i;
                for (; j > 0 && bins_[order[j - 1]][axis] > bin; --j) order[j] = order[j - 1];
                order[j] = static_cast<uint8_t>(i);
            }
            // Sweep from the right: the box of the primitives from position j on.
            Box4 right[kMaxCount];
            Box4 accumulated;
            for (uint32_t j = count - 1; j > 0; --j) {
                accumulated.grow(refs[order[j]].min, refs[order[j]].max);
                right[j] = accumulated;
            }
            // Sweep from the left, pricing the plane after each run of primitives in one bin.
            accumulated = Box4{};
            for (uint32_t j = 0; j + 1 < count; ++j) {
                accumulated.grow(refs[order[j]].min, refs[order[j]].max);
                const int32_t bin = bins_[order[j]][axis];
                if (bins_[order[j + 1]][axis] == bin) continue;
                const float cost = planeCost(config, accumulated.surfaceArea(), j + 1,
                                             right[j + 1].surfaceArea(), count - j - 1, nodeArea);
                if (cost < best.cost) {
                    best = Split{axis, bin, cost};
                    left_ = accumulated;
                    right_ = right[j + 1];
                }
            }
        }
        return best;
    }

    // Whether primitive i (of the last find) goes to the left of `split`.
    bool goesLeft(uint32_t i, const Split& split) const { return bins_[i][split.axis] <= split.bin; }
    // The bounds of the two sides of the last split found.
    Aabb leftBounds() const { return left_.toAabb(); }
    Aabb rightBounds() const { return right_.toAabb(); }

  private:
    Int4 bins_[kMaxCount];
    Box4 left_, right_;
};

}  // namespace vkrt::sah
