#include "bvh/sah_subtree_builder.h"

namespace vkrt::sah {

SubtreeBuilder::SubtreeBuilder(const BvhConfig& config, uint32_t* primIndices)
    : config_(config), primIndices_(primIndices), bins_(config.binCount) {}

uint32_t SubtreeBuilder::build(PrimRef* refs, PrimRef* spare, uint32_t begin, uint32_t end, int level,
                               const Aabb& bounds, const Box4& centers, BvhBuildNode* nodes) {
    nodes_ = nodes;
    nodes_[0] = BvhBuildNode{bounds};
    nodeCount_ = 1;
    buildNode(0, begin, end, level, centers, refs, spare);
    return nodeCount_;
}

void SubtreeBuilder::buildNode(uint32_t node, uint32_t begin, uint32_t end, int level, const Box4& centers,
                               PrimRef* refs, PrimRef* spare) {
    const uint32_t count = end - begin;
    if (count <= 1) {
        makeLeaf(node, refs, begin, count);
        return;
    }
    const uint32_t maxLeafSize = static_cast<uint32_t>(config_.maxLeafSize);

    // Split: SAH where the depth budget allows it, otherwise a median split that halves the count.
    const bool mustBalance = level - 1 + levelsNeeded(count, config_.maxLeafSize) >= config_.maxDepth;
    Aabb leftBounds, rightBounds;
    Box4 leftCenters, rightCenters;
    uint32_t middle = begin;
    PrimRef* childRefs = refs;  // where the children's references lie
    PrimRef* childSpare = spare;
    if (!mustBalance) {
        // The SAH plane: binned (Wald 2007), or for a few primitives the same plane without bins.
        const BinMapping mapping(centers, config_.binCount);
        const bool small = count <= SmallNodeSplit::kMaxCount;
        Split split;
        if (small) {
            split = small_.find(refs + begin, count, mapping, nodes_[node].bounds, centers, config_);
        } else {
            bins_.clear();
            bins_.add(refs, begin, end, mapping);
            split = findSahSplit(bins_, nodes_[node].bounds, centers, config_, rightArea_, rightCount_);
        }
        const float leafCost = config_.intersectionCost * static_cast<float>(count);
        if (count <= maxLeafSize && leafCost <= split.cost) {
            makeLeaf(node, refs, begin, count);
            return;
        }
        if (split.axis >= 0) {
            if (small) {
                middle = partition(refs, spare, begin, end, leftCenters, rightCenters,
                                   [&](uint32_t i) { return small_.goesLeft(i - begin, split); });
                leftBounds = small_.leftBounds();
                rightBounds = small_.rightBounds();
            } else {
                const SplitSide side{mapping, split.axis, split.bin};
                middle = partition(refs, spare, begin, end, leftCenters, rightCenters,
                                   [&](uint32_t i) { return side.goesLeft(refs[i]); });
                splitBounds(bins_, split, leftBounds, rightBounds);
            }
            childRefs = spare;
            childSpare = refs;
        }
    } else if (count <= maxLeafSize) {
        makeLeaf(node, refs, begin, count);
        return;
    }
    if (middle == begin) {  // no SAH plane: halve the count, in place
        middle = medianSplit(refs, begin, end, centers);
        Box4 left, right;
        boundsOf(refs, begin, middle, left, leftCenters);
        boundsOf(refs, middle, end, right, rightCenters);
        leftBounds = left.toAabb();
        rightBounds = right.toAabb();
    }

    // Put the two children next to each other, then build them, left first (depth-first order).
    const uint32_t left = nodeCount_;
    nodeCount_ += 2;
    nodes_[node].leftOrFirst = left;
    nodes_[node].primCount = 0;
    nodes_[left] = BvhBuildNode{leftBounds};
    nodes_[left + 1] = BvhBuildNode{rightBounds};
    buildNode(left, begin, middle, level + 1, leftCenters, childRefs, childSpare);
    buildNode(left + 1, middle, end, level + 1, rightCenters, childRefs, childSpare);
}

// The right side is written from the end of the spare range down, so it comes out reversed, which no result
// depends on (leaves sort their primitives; median splits break ties by index).
template <typename GoesLeft>
uint32_t SubtreeBuilder::partition(const PrimRef* refs, PrimRef* spare, uint32_t begin, uint32_t end,
                                   Box4& leftCenters, Box4& rightCenters, GoesLeft&& goesLeft) {
    return begin + partitionRefs(refs, begin, end, spare + begin, spare + end - 1, -1, leftCenters,
                                 rightCenters, goesLeft);
}

void SubtreeBuilder::makeLeaf(uint32_t node, const PrimRef* refs, uint32_t begin, uint32_t count) {
    BvhBuildNode& leaf = nodes_[node];
    leaf.leftOrFirst = begin;
    leaf.primCount = count;
    if (count == 0) leaf.bounds = Aabb{};  // the empty tree: a leaf no ray can hit
    // The leaf's primitives in ascending order, whatever order the partitions left them in (insertion sort:
    // leaves are small).
    uint32_t* indices = primIndices_ + begin;
    for (uint32_t i = 0; i < count; ++i) {
        const uint32_t index = refs[begin + i].index();
        uint32_t j = i;
        for (; j > 0 && indices[j - 1] > index; --j) indices[j] = indices[j - 1];
        indices[j] = index;
    }
}

}  // namespace vkrt::sah
