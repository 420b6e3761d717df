// The inner loops of the binned SAH build (Wald, "On fast construction of SAH-based bounding volume
// hierarchies", 2007), shared by the parallel top of the tree and the subtrees below it: primitive
// references with their bounds side by side, binning on all three axes in one pass, the SAH sweep over
// the bins and the partition by the chosen plane.
//
// Centroids are kept doubled (min + max, one add, no multiply): doubling is exact in floating point, so
// every bin, plane and cost is the one the halved centroids would give.
#pragma once

#include <algorithm>
#include <bit>
#include <cstddef>
#include <cstdint>
#include <limits>
#include <vector>

#include "bvh/bvh.h"

namespace vkrt::sah {

// Four floats in one SIMD register (GCC and Clang vector extensions; SSE on x86-64, NEON on arm64).
// Lane 3 of every vector below carries nothing the build reads.
using Float4 = float __attribute__((vector_size(16)));
using Int4 = int32_t __attribute__((vector_size(16)));

inline Float4 min4(Float4 a, Float4 b) {
    return a < b ? a : b;
}
inline Float4 max4(Float4 a, Float4 b) {
    return a > b ? a : b;
}
inline Float4 toFloat4(const glm::vec3& v) {
    return Float4{v.x, v.y, v.z, 0.0f};
}
inline glm::vec3 toVec3(Float4 v) {
    return {v[0], v[1], v[2]};
}

// Lanes 0 to 2 of an Int4 mask.
inline constexpr Int4 kXyzLanes = {-1, -1, -1, 0};

// A primitive's bounds and its index, 32 bytes: what binning and partitioning read and move.
struct PrimRef {
    Float4 min;  // lane 3: the primitive's index, as bits
    Float4 max;
    // Lane 3 is zero: the index's bits read as a float are a denormal for indices below 2^23, and
    // arithmetic on denormals is slow (a microcode assist per instruction on many x86 cores).
    Float4 doubledCenter() const { return std::bit_cast<Float4>(std::bit_cast<Int4>(min) & kXyzLanes) + max; }
    uint32_t index() const { return std::bit_cast<uint32_t>(min[3]); }
};

inline PrimRef makePrimRef(const Aabb& bounds, uint32_t index) {
    return {Float4{bounds.min.x, bounds.min.y, bounds.min.z, std::bit_cast<float>(index)},
            toFloat4(bounds.max)};
}

// A box as two vectors; starts empty.
struct Box4 {
    Float4 min = Float4{} + std::numeric_limits<float>::infinity();
    Float4 max = Float4{} - std::numeric_limits<float>::infinity();
    void grow(Float4 lo, Float4 hi) {
        min = min4(min, lo);
        max = max4(max, hi);
    }
    void grow(Float4 point) { grow(point, point); }
    void grow(const Box4& box) { grow(box.min, box.max); }
    Aabb toAabb() const { return Aabb{toVec3(min), toVec3(max)}; }
    // Aabb::surfaceArea's value, for a box that is not empty. Lane 3 of `min` may hold a primitive index
    // (a denormal, slow to subtract); it is cleared first.
    float surfaceArea() const {
        const Float4 e = max - std::bit_cast<Float4>(std::bit_cast<Int4>(min) & kXyzLanes);
        return 2.0f * (e[0] * e[1] + e[1] * e[2] + e[2] * e[0]);
    }
};

// Where a doubled centroid falls among `binCount` equal bins per axis over the node's centroid bounds
// (the bins and clamping of Wald 2007, eq. 1).
class BinMapping {
  public:
    BinMapping(const Box4& doubledCenterBounds, int binCount)
        : origin_(doubledCenterBounds.min), last_(binCount - 1) {
        const Float4 extent = doubledCenterBounds.max - doubledCenterBounds.min;
        for (int axis = 0; axis < 3; ++axis) {
            scale_[axis] = extent[axis] > 0.0f ? static_cast<float>(binCount) / extent[axis] : 0.0f;
        }
        scale_[3] = 0.0f;
    }
    Int4 binsOf(const PrimRef& ref) const {
        const Int4 bins = __builtin_convertvector((ref.doubledCenter() - origin_) * scale_, Int4);
        const Int4 zero = Int4{} + 0, last = Int4{} + last_;
        return bins < zero ? zero : (bins > last ? last : bins);
    }

  private:
    Float4 origin_;
    Float4 scale_{};
    int32_t last_;
};

// The bins of one node (or of one block of its primitives): bounds and counts per axis, and which bins
// hold primitives, so that clearing and sweeping visit only those (most nodes are small).
class Bins {
  public:
    explicit Bins(int binCount)
        : binCount_(binCount),
          words_((binCount + 63) / 64),
          boxes_(6 * binCount),
          counts_(6 * binCount, 0),
          occupied_(3 * words_, 0) {}

    int binCount() const { return binCount_; }

    // Empties the bins that hold primitives.
    void clear() {
        for (int axis = 0; axis < 3; ++axis) {
            forEachOccupied(axis, [&](int bin) {
                boxes_[axis * binCount_ + bin] = Box4{};
                counts_[axis * binCount_ + bin] = 0;
            });
        }
        std::fill(occupied_.begin(), occupied_.end(), 0);
    }

    // Adds the primitives refs[begin, end). Neighbouring primitives tend to fall in the same bins, and
    // each update waits for the one before it in the same bin; many primitives go to two sets of bins in
    // turn, merged at the end, so that two chains of updates run at once.
    void add(const PrimRef* refs, size_t begin, size_t end, const BinMapping& mapping) {
        const size_t perSet = 3 * static_cast<size_t>(binCount_);
        if (end - begin >= kTwoSetsFrom) {
            size_t i = begin;
            for (; i + 1 < end; i += 2) {
                addOne(refs[i], mapping, 0);
                addOne(refs[i + 1], mapping, perSet);
            }
            if (i < end) addOne(refs[i], mapping, 0);
            for (size_t b = 0; b < perSet; ++b) {
                boxes_[b].grow(boxes_[perSet + b]);
                counts_[b] += counts_[perSet + b];
                boxes_[perSet + b] = Box4{};
                counts_[perSet + b] = 0;
            }
        } else {
            for (size_t i = begin; i < end; ++i) addOne(refs[i], mapping, 0);
        }
        markOccupied();
    }

    void merge(const Bins& other) {
        for (size_t i = 0; i < 3 * static_cast<size_t>(binCount_); ++i) {
            boxes_[i].grow(other.boxes_[i]);
            counts_[i] += other.counts_[i];
        }
        for (size_t i = 0; i < occupied_.size(); ++i) occupied_[i] |= other.occupied_[i];
    }

    const Box4& box(int axis, int bin) const { return boxes_[axis * binCount_ + bin]; }
    uint32_t count(int axis, int bin) const { return counts_[axis * binCount_ + bin]; }

    // Calls visit(bin) for each bin of the axis that holds primitives, in ascending order.
    template <typename Visit>
    void forEachOccupied(int axis, Visit&& visit) const {
        for (int word = 0; word < words_; ++word) {
            for (uint64_t bits = occupied_[axis * words_ + word]; bits != 0; bits &= bits - 1) {
                visit(64 * word + std::countr_zero(bits));
            }
        }
    }
    // The same in descending order.
    template <typename Visit>
    void forEachOccupiedDescending(int axis, Visit&& visit) const {
        for (int word = words_ - 1; word >= 0; --word) {
            for (uint64_t bits = occupied_[axis * words_ + word]; bits != 0;) {
                const int top = 63 - std::countl_zero(bits);
                bits &= ~(uint64_t{1} << top);
                visit(64 * word + top);
            }
        }
    }

  private:
    static constexpr size_t kTwoSetsFrom = 128;

    void addOne(const PrimRef& ref, const BinMapping& mapping, size_t set) {
        const Int4 bin = mapping.binsOf(ref);
        for (int axis = 0; axis < 3; ++axis) {
            const size_t slot = set + static_cast<size_t>(axis * binCount_ + bin[axis]);
            boxes_[slot].grow(ref.min, ref.max);
            ++counts_[slot];
        }
    }

    // The occupancy words from the counts (which only grow), each gathered in a register: an or into
    // memory per bin would wait on the one before it.
    void markOccupied() {
        for (int axis = 0; axis < 3; ++axis) {
            const uint32_t* counts = &counts_[axis * binCount_];
            for (int word = 0; word < words_; ++word) {
                uint64_t bits = 0;
                for (int b = 64 * word, end = std::min(binCount_, b + 64); b < end; ++b) {
                    bits |= uint64_t{counts[b] > 0} << (b % 64);
                }
                occupied_[axis * words_ + word] = bits;
            }
        }
    }

    int binCount_;
    int words_;  // 64-bit words of occupancy per axis
    std::vector<Box4> boxes_;
    std::vector<uint32_t> counts_;
    std::vector<uint64_t> occupied_;
};

struct Split {
    int axis = -1;  // -1: no plane separates the centroids
    int bin = 0;    // primitives in bins [0, bin] go left
    float cost = std::numeric_limits<float>::infinity();
};

// The SAH cost of a plane: one traversal step, then each side's primitives weighted by the probability that
// a ray through the node hits the side's box (surface area ratio; MacDonald and Booth 1990).
inline float planeCost(const BvhConfig& config, float leftArea, uint32_t leftCount, float rightArea,
                       uint32_t rightCount, float nodeArea) {
    return config.traversalCost +
           config.intersectionCost * (leftArea * leftCount + rightArea * rightCount) / nodeArea;
}

// The cheapest plane between bins by the SAH, the planes in order, axis by axis; a plane replaces the best
// only with a strictly lower cost. Planes are priced after bins that hold primitives only: a plane after
// an empty bin has the sides, and so the cost, of the plane before it, and would never replace it. The
// scratch vectors are the caller's, so that the loop over many small nodes allocates nothing.
inline Split findSahSplit(const Bins& bins, const Aabb& nodeBounds, const Box4& doubledCenterBounds,
                          const BvhConfig& config, std::vector<float>& rightArea,
                          std::vector<uint32_t>& rightCount) {
    Split best;
    const float nodeArea = nodeBounds.surfaceArea();
    rightArea.resize(bins.binCount());
    rightCount.resize(bins.binCount());
    for (int axis = 0; axis < 3; ++axis) {
        if (!(doubledCenterBounds.max[axis] > doubledCenterBounds.min[axis])) continue;
        // Sweep from the right to know each right-hand side (bins b and up), then from the left to price
        // each plane against the next occupied bin's right-hand side.
        Box4 accumulated;
        uint32_t accumulatedCount = 0;
        bins.forEachOccupiedDescending(axis, [&](int b) {
            accumulated.grow(bins.box(axis, b));
            accumulatedCount += bins.count(axis, b);
            rightArea[b] = accumulated.surfaceArea();
            rightCount[b] = accumulatedCount;
        });
        accumulated = Box4{};
        accumulatedCount = 0;
        int previous = -1;  // the last occupied bin to the left of the plane
        bins.forEachOccupied(axis, [&](int b) {
            if (previous >= 0) {
                const float cost = planeCost(config, accumulated.surfaceArea(), accumulatedCount,
                                             rightArea[b], rightCount[b], nodeArea);
                if (cost < best.cost) best = Split{axis, previous, cost};
            }
            accumulated.grow(bins.box(axis, b));
            accumulatedCount += bins.count(axis, b);
            previous = b;
        });
    }
    return best;
}

// The bounds of the two sides of a split, from the bins: exactly those of the primitives on each side.
inline void splitBounds(const Bins& bins, const Split& split, Aabb& left, Aabb& right) {
    Box4 leftBox, rightBox;
    bins.forEachOccupied(split.axis,
                         [&](int b) { (b <= split.bin ? leftBox : rightBox).grow(bins.box(split.axis, b)); });
    left = leftBox.toAabb();
    right = rightBox.toAabb();
}

// Which side of a split a primitive goes to.
struct SplitSide {
    BinMapping mapping;
    int axis;
    int bin;
    bool goesLeft(const PrimRef& ref) const { return mapping.binsOf(ref)[axis] <= bin; }
};

// Moves refs[begin, end) to two sides: those for which goesLeft(i) to leftOut, leftOut + 1, ..., the others
// to rightOut, rightOut + rightStep, ... (rightStep +1 or -1), in the order they come; gathers each side's
// centroid bounds. Returns how many went left. No branch to mispredict: each reference is stored once, at
// a selected address, and each side's bounds grow by the centroid or by an infinity that leaves them as
// they are (min with +inf, max with -inf).
template <typename GoesLeft>
inline uint32_t partitionRefs(const PrimRef* refs, uint32_t begin, uint32_t end, PrimRef* leftOut,
                              PrimRef* rightOut, ptrdiff_t rightStep, Box4& leftCenters, Box4& rightCenters,
                              GoesLeft&& goesLeft) {
    PrimRef* left = leftOut;
    PrimRef* right = rightOut;
    const Float4 infinity = Float4{} + std::numeric_limits<float>::infinity();
    const Int4 signBit = Int4{} + std::numeric_limits<int32_t>::min();
    Float4 leftMin = leftCenters.min, leftMax = leftCenters.max;
    Float4 rightMin = rightCenters.min, rightMax = rightCenters.max;
    for (uint32_t i = begin; i < end; ++i) {
        const PrimRef ref = refs[i];
        const bool toLeftSide = goesLeft(i);
        *(toLeftSide ? left : right) = ref;
        left += toLeftSide;
        right += toLeftSide ? 0 : rightStep;
        const Float4 center = ref.doubledCenter();
        const Int4 toLeft = Int4{} - static_cast<int32_t>(toLeftSide);  // all ones or all zeros
        const Float4 minusIfLeft = std::bit_cast<Float4>(std::bit_cast<Int4>(infinity) ^ (toLeft & signBit));
        const Float4 plusIfLeft = -minusIfLeft;
        leftMin = min4(leftMin, max4(center, minusIfLeft));
        leftMax = max4(leftMax, min4(center, plusIfLeft));
        rightMin = min4(rightMin, max4(center, plusIfLeft));
        rightMax = max4(rightMax, min4(center, minusIfLeft));
    }
    leftCenters = Box4{leftMin, leftMax};
    rightCenters = Box4{rightMin, rightMax};
    return static_cast<uint32_t>(left - leftOut);
}

// Levels that a balanced (median-split) subtree over `count` primitives needs, itself included.
inline int levelsNeeded(uint64_t count, int maxLeafSize) {
    int levels = 1;
    uint64_t capacity = static_cast<uint64_t>(maxLeafSize);
    while (capacity < count) {
        capacity *= 2;
        ++levels;
    }
    return levels;
}

// The widest axis of the centroids, for median splits.
inline int widestAxis(const Box4& doubledCenterBounds) {
    const Float4 extent = doubledCenterBounds.max - doubledCenterBounds.min;
    return extent[0] >= extent[1] && extent[0] >= extent[2] ? 0 : (extent[1] >= extent[2] ? 1 : 2);
}

// Orders refs[begin, end) so that the lower half by centroid along the widest axis comes first (ties by
// primitive index, so that the halves do not depend on the order the primitives arrive in); identical
// centroids stay as they are and are split by position. Returns the middle.
inline uint32_t medianSplit(PrimRef* refs, uint32_t begin, uint32_t end, const Box4& doubledCenterBounds) {
    const uint32_t middle = begin + (end - begin) / 2;
    const int axis = widestAxis(doubledCenterBounds);
    if (doubledCenterBounds.max[axis] - doubledCenterBounds.min[axis] > 0.0f) {
        std::nth_element(refs + begin, refs + middle, refs + end, [axis](const PrimRef& a, const PrimRef& b) {
            const float ca = a.doubledCenter()[axis], cb = b.doubledCenter()[axis];
            return ca < cb || (ca == cb && a.index() < b.index());
        });
    }
    return middle;
}

// The bounds and doubled-centroid bounds of refs[begin, end).
inline void boundsOf(const PrimRef* refs, uint32_t begin, uint32_t end, Box4& bounds, Box4& centers) {
    for (uint32_t i = begin; i < end; ++i) {
        bounds.grow(refs[i].min, refs[i].max);
        centers.grow(refs[i].doubledCenter());
    }
}

}  // namespace vkrt::sah
