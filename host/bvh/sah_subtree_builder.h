// One subtree of the binned SAH BVH, built on the calling thread: binning on all three axes in one pass,
// the SAH plane, a branch-free partition into a second array that also gathers each side's centroid
// bounds; median splits near the depth limit, so the depth bound holds for any input.
#pragma once

#include <vector>

#include "bvh/sah_binning.h"
#include "bvh/sah_small_split.h"

namespace vkrt::sah {

class SubtreeBuilder {
  public:
    // `primIndices` is the whole tree's: each leaf writes its range, in ascending primitive order.
    SubtreeBuilder(const BvhConfig& config, uint32_t* primIndices);

    // Builds the subtree over refs[begin, end), whose root sits `level` levels deep (the tree's root: 1),
    // into nodes[0, 2 * (end - begin)): nodes[0] is the subtree's root, children follow in pairs in
    // depth-first order, leaves refer to global ranges of primIndices. Partitions move the references
    // between `refs` and `spare` (the same range of both is the subtree's). Returns the number of nodes.
    uint32_t build(PrimRef* refs, PrimRef* spare, uint32_t begin, uint32_t end, int level, const Aabb& bounds,
                   const Box4& centers, BvhBuildNode* nodes);

  private:
    void buildNode(uint32_t node, uint32_t begin, uint32_t end, int level, const Box4& centers, PrimRef* refs,
                   PrimRef* spare);
    void makeLeaf(uint32_t node, const PrimRef* refs, uint32_t begin, uint32_t count);
    // Moves refs[begin, end) to spare[begin, end), those for which goesLeft(i) first; gathers each side's
    // centroid bounds; returns where the right side begins.
    template <typename GoesLeft>
    uint32_t partition(const PrimRef* refs, PrimRef* spare, uint32_t begin, uint32_t end, Box4& leftCenters,
                       Box4& rightCenters, GoesLeft&& goesLeft);

    const BvhConfig& config_;
    uint32_t* primIndices_;
    BvhBuildNode* nodes_ = nullptr;
    uint32_t nodeCount_ = 0;
    Bins bins_;
    SmallNodeSplit small_;
    std::vector<float> rightArea_;
    std::vector<uint32_t> rightCount_;
};

}  // namespace vkrt::sah
