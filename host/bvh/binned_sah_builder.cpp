#include "bvh/binned_sah_builder.h"

#include <algorithm>
#include <atomic>
#include <memory>
#include <numeric>
#include <optional>
#include <stdexcept>

#include "bvh/sah_binning.h"
#include "bvh/sah_subtree_builder.h"
#include "common/large_buffer.h"
#include "common/parallel_for.h"

namespace vkrt {
namespace {

using namespace sah;

// A node whose split is still to be found, with what its parent learned about it.
struct PendingNode {
    uint32_t node;  // index among the top nodes
    uint32_t begin, end;
    int level;     // the root: 1
    Box4 centers;  // bounds of the doubled centroids
    int buffer;    // which of the two reference arrays holds refs[begin, end)
};

// Consecutive primitives of one pending node: the unit of parallel work at the top of the tree.
struct Block {
    uint32_t pending;
    uint32_t begin, end;
};

// How one pending node is split (by an SAH plane, or at the median without one) and what its children get.
struct TopSplit {
    std::optional<SplitSide> side;
    Aabb leftBounds, rightBounds;
    Box4 leftCenters, rightCenters;
    uint32_t middle = 0;
};

// One block's share of a partition: its left count (from its bins), where its two sides go, and the
// centroid bounds of each side.
struct BlockPartition {
    uint32_t leftCount = 0;
    Box4 leftCenters, rightCenters;
    uint32_t leftOut = 0, rightOut = 0;  // where the block's left and right primitives go
};

// The nodes of every subtree: subtree s's lie at nodes[first[s], first[s] + counts[s]), its root first,
// children numbered from it.
struct SubtreeNodes {
    LargeBuffer<BvhBuildNode> nodes;
    std::vector<size_t> first;
    std::vector<uint32_t> counts;
};

class Builder {
  public:
    Builder(std::span<const Aabb> bounds, const BvhConfig& config, const BinnedSahSchedule& schedule)
        : bounds_(bounds),
          config_(config),
          threads_(threadCount(config.threads)),
          blockSize_(std::max<uint32_t>(1, schedule.blockSize)),
          // A node that may still become a leaf stays with the subtree builder.
          subtreeSize_(std::max(schedule.subtreeSize, static_cast<uint32_t>(config.maxLeafSize))) {}

    Bvh build() {
        const uint32_t count = static_cast<uint32_t>(bounds_.size());
        bvh_.primIndices.resize(count);
        refs_[0] = LargeBuffer<PrimRef>(count);
        refs_[1] = LargeBuffer<PrimRef>(count);
        PendingNode root{0, 0, count, 1, {}, 0};
        topNodes_.push_back(BvhBuildNode{makeRefs(root.centers)});

        std::vector<PendingNode> subtrees;
        if (count > subtreeSize_) {
            buildTop(root, subtrees);
        } else {
            subtrees.push_back(root);
        }
        // Each subtree is built in its thread's scratch nodes (a few MB, in cache), then copied to the next
        // free place in one shared array: its nodes, dense, whatever order the subtrees finish in.
        SubtreeNodes built{LargeBuffer<BvhBuildNode>(2 * static_cast<size_t>(count) + 1),
                           std::vector<size_t>(subtrees.size()), std::vector<uint32_t>(subtrees.size())};
        buildSubtrees(subtrees, built);
        assemble(subtrees, built);
        return std::move(bvh_);
    }

  private:
    // The references, with the root's bounds and centroid bounds; returns the bounds.
    Aabb makeRefs(Box4& rootCenters) {
        const size_t count = bounds_.size();
        const size_t blocks = (count + blockSize_ - 1) / blockSize_;
        std::vector<Box4> blockBounds(blocks), blockCenters(blocks);
        parallelFor(blocks, threads_, [&](size_t block, unsigned) {
            const size_t begin = block * blockSize_, end = std::min(count, begin + blockSize_);
            for (size_t i = begin; i < end; ++i) {
                const PrimRef ref = makePrimRef(bounds_[i], static_cast<uint32_t>(i));
                refs_[0][i] = ref;
                blockBounds[block].grow(ref.min, ref.max);
                blockCenters[block].grow(ref.doubledCenter());
            }
        });
        Box4 rootBounds;
        for (size_t block = 0; block < blocks; ++block) {
            rootBounds.grow(blockBounds[block]);
            rootCenters.grow(blockCenters[block]);
        }
        return count == 0 ? Aabb{} : rootBounds.toAabb();
    }

    bool mustBalance(const PendingNode& pending) const {
        return pending.level - 1 + levelsNeeded(pending.end - pending.begin, config_.maxLeafSize) >=
               config_.maxDepth;
    }

    // Splits the nodes over more than subtreeSize_ primitives level by level, each level's binning and
    // partitioning spread over all threads in blocks; collects the nodes below as subtree roots.
    void buildTop(const PendingNode& root, std::vector<PendingNode>& subtrees) {
        std::vector<PendingNode> level{root};
        std::vector<float> rightArea;
        std::vector<uint32_t> rightCount;
        while (!level.empty()) {
            // Blocks of every node of the level, in order.
            std::vector<Block> blocks;
            std::vector<size_t> firstBlock;
            for (uint32_t k = 0; k < level.size(); ++k) {
                firstBlock.push_back(blocks.size());
                for (uint32_t begin = level[k].begin; begin < level[k].end;
                     begin += std::min(blockSize_, level[k].end - begin)) {
                    blocks.push_back({k, begin, std::min(level[k].end, begin + blockSize_)});
                }
            }
            firstBlock.push_back(blocks.size());
            std::vector<BinMapping> mappings;
            for (const PendingNode& pending : level) mappings.emplace_back(pending.centers, config_.binCount);

            // Bin every block, then merge each node's bins and find its plane.
            std::vector<Bins> blockBins(blocks.size(), Bins(config_.binCount));
            parallelFor(blocks.size(), threads_, [&](size_t b, unsigned) {
                const Block& block = blocks[b];
                const PendingNode& pending = level[block.pending];
                if (!mustBalance(pending)) {
                    blockBins[b].add(refs_[pending.buffer].get(), block.begin, block.end,
                                     mappings[block.pending]);
                }
            });
            std::vector<TopSplit> splits(level.size());
            for (uint32_t k = 0; k < level.size(); ++k) {
                if (mustBalance(level[k])) continue;
                Bins bins(config_.binCount);
                for (size_t b = firstBlock[k]; b < firstBlock[k + 1]; ++b) bins.merge(blockBins[b]);
                const Split split = findSahSplit(bins, topNodes_[level[k].node].bounds, level[k].centers,
                                                 config_, rightArea, rightCount);
                if (split.axis < 0) continue;
                splits[k].side = SplitSide{mappings[k], split.axis, split.bin};
                splitBounds(bins, split, splits[k].leftBounds, splits[k].rightBounds);
            }

            // Partition: each block's left count is in its bins; the blocks' sides go one after another to
            // the other reference array (a stable partition), in parallel, gathering centroid bounds.
            std::vector<BlockPartition> parts(blocks.size());
            for (uint32_t k = 0; k < level.size(); ++k) {
                TopSplit& split = splits[k];
                if (!split.side) continue;
                uint32_t left = level[k].begin;
                for (size_t b = firstBlock[k]; b < firstBlock[k + 1]; ++b) {
                    for (int bin = 0; bin <= split.side->bin; ++bin) {
                        parts[b].leftCount += blockBins[b].count(split.side->axis, bin);
                    }
                    parts[b].leftOut = left;
                    left += parts[b].leftCount;
                }
                split.middle = left;
                uint32_t right = left;
                for (size_t b = firstBlock[k]; b < firstBlock[k + 1]; ++b) {
                    parts[b].rightOut = right;
                    right += blocks[b].end - blocks[b].begin - parts[b].leftCount;
                }
            }
            parallelFor(blocks.size(), threads_, [&](size_t b, unsigned) {
                const Block& block = blocks[b];
                const TopSplit& split = splits[block.pending];
                if (!split.side) return;
                const int buffer = level[block.pending].buffer;
                const PrimRef* in = refs_[buffer].get();
                PrimRef* out = refs_[1 - buffer].get();
                BlockPartition& part = parts[b];
                const SplitSide side = *split.side;
                partitionRefs(in, block.begin, block.end, out + part.leftOut, out + part.rightOut, 1,
                              part.leftCenters, part.rightCenters,
                              [&](uint32_t i) { return side.goesLeft(in[i]); });
            });
            for (uint32_t k = 0; k < level.size(); ++k) {
                for (size_t b = firstBlock[k]; b < firstBlock[k + 1]; ++b) {
                    splits[k].leftCenters.grow(parts[b].leftCenters);
                    splits[k].rightCenters.grow(parts[b].rightCenters);
                }
            }

            // Nodes without an SAH plane (near the depth limit, or all centroids alike): the median.
            for (uint32_t k = 0; k < level.size(); ++k) {
                TopSplit& split = splits[k];
                if (split.side) continue;
                const PendingNode& pending = level[k];
                PrimRef* out = refs_[1 - pending.buffer].get();
                std::copy(refs_[pending.buffer].get() + pending.begin,
                          refs_[pending.buffer].get() + pending.end, out + pending.begin);
                split.middle = medianSplit(out, pending.begin, pending.end, pending.centers);
                Box4 left, right;
                boundsOf(out, pending.begin, split.middle, left, split.leftCenters);
                boundsOf(out, split.middle, pending.end, right, split.rightCenters);
                split.leftBounds = left.toAabb();
                split.rightBounds = right.toAabb();
            }

            // The children, in pairs: split further at the top, or left to a subtree builder.
            std::vector<PendingNode> next;
            for (uint32_t k = 0; k < level.size(); ++k) {
                const PendingNode& pending = level[k];
                const TopSplit& split = splits[k];
                const uint32_t left = static_cast<uint32_t>(topNodes_.size());
                topNodes_[pending.node].leftOrFirst = left;
                topNodes_[pending.node].primCount = 0;
                topNodes_.push_back(BvhBuildNode{split.leftBounds});
                topNodes_.push_back(BvhBuildNode{split.rightBounds});
                const PendingNode children[2] = {{left, pending.begin, split.middle, pending.level + 1,
                                                  split.leftCenters, 1 - pending.buffer},
                                                 {left + 1, split.middle, pending.end, pending.level + 1,
                                                  split.rightCenters, 1 - pending.buffer}};
                for (const PendingNode& child : children) {
                    (child.end - child.begin > subtreeSize_ ? next : subtrees).push_back(child);
                }
            }
            level = std::move(next);
        }
    }

    // Every subtree on one thread, the largest first, so that the last to finish are small.
    void buildSubtrees(const std::vector<PendingNode>& subtrees, SubtreeNodes& built) {
        std::vector<uint32_t> order(subtrees.size());
        std::iota(order.begin(), order.end(), 0u);
        std::stable_sort(order.begin(), order.end(), [&](uint32_t a, uint32_t b) {
            return subtrees[a].end - subtrees[a].begin > subtrees[b].end - subtrees[b].begin;
        });
        // A subtree over n primitives has at most 2n - 1 nodes.
        const size_t scratchNodes =
            subtrees.empty() ? 1 : 2 * size_t{subtrees[order[0]].end - subtrees[order[0]].begin} + 1;
        std::vector<std::optional<SubtreeBuilder>> builders(threads_);
        std::vector<LargeBuffer<BvhBuildNode>> scratch(threads_);
        std::atomic<size_t> used{0};
        parallelFor(order.size(), threads_, [&](size_t i, unsigned worker) {
            if (!builders[worker]) {
                builders[worker].emplace(config_, bvh_.primIndices.data());
                scratch[worker] = LargeBuffer<BvhBuildNode>(scratchNodes);
            }
            const uint32_t s = order[i];
            const PendingNode& subtree = subtrees[s];
            const uint32_t nodeCount = builders[worker]->build(
                refs_[subtree.buffer].get(), refs_[1 - subtree.buffer].get(), subtree.begin, subtree.end,
                subtree.level, topNodes_[subtree.node].bounds, subtree.centers, scratch[worker].get());
            const size_t at = used.fetch_add(nodeCount);
            std::copy(scratch[worker].get(), scratch[worker].get() + nodeCount, built.nodes.get() + at);
            built.first[s] = at;
            built.counts[s] = nodeCount;
        });
    }

    // The top nodes, then each subtree's nodes after its root, in the order the subtrees were found.
    void assemble(const std::vector<PendingNode>& subtrees, const SubtreeNodes& built) {
        std::vector<size_t> offsets(subtrees.size());
        size_t total = topNodes_.size();
        for (size_t s = 0; s < subtrees.size(); ++s) {
            offsets[s] = total - 1;  // local node i > 0 goes to offsets[s] + i
            total += built.counts[s] - 1;
        }
        bvh_.nodes.resize(total);
        std::copy(topNodes_.begin(), topNodes_.end(), bvh_.nodes.begin());
        parallelFor(subtrees.size(), threads_, [&](size_t s, unsigned) {
            const uint32_t offset = static_cast<uint32_t>(offsets[s]);
            const BvhBuildNode* local = built.nodes.get() + built.first[s];
            for (uint32_t i = 0; i < built.counts[s]; ++i) {
                BvhBuildNode node = local[i];
                if (!node.isLeaf()) node.leftOrFirst += offset;
                bvh_.nodes[i == 0 ? subtrees[s].node : offset + i] = node;
            }
        });
    }

    std::span<const Aabb> bounds_;
    const BvhConfig& config_;
    unsigned threads_;
    uint32_t blockSize_;
    uint32_t subtreeSize_;
    LargeBuffer<PrimRef> refs_[2];
    std::vector<BvhBuildNode> topNodes_;
    Bvh bvh_;
};

}  // namespace

Bvh BinnedSahBuilder::build(std::span<const Aabb> bounds, const BvhConfig& config,
                            const BinnedSahSchedule& schedule) {
    if (config.maxDepth < 2 || config.maxDepth > VKRT_BVH_MAX_DEPTH || config.maxLeafSize < 1 ||
        config.binCount < 2) {
        throw std::invalid_argument("BvhConfig out of range");
    }
    if (levelsNeeded(bounds.size(), config.maxLeafSize) > config.maxDepth) {
        throw std::invalid_argument("too many primitives for the BVH depth limit");
    }
    Builder builder(bounds, config, schedule);
    return builder.build();
}

BvhStats measureBvh(const Bvh& bvh, const BvhConfig& config) {
    BvhStats stats;
    stats.nodes = bvh.nodes.size();
    if (bvh.primIndices.empty()) {  // the empty tree: one node that nothing can hit
        stats.depth = 1;
        return stats;
    }
    // Areas in double: a scene wider than about 1e19 has a root area beyond float, and its cost came out NaN.
    const auto area = [](const Aabb& box) {
        if (box.empty()) return 0.0;
        const glm::dvec3 e = glm::dvec3(box.max) - glm::dvec3(box.min);
        return 2.0 * (e.x * e.y + e.y * e.z + e.z * e.x);
    };
    const double rootArea = area(bvh.nodes[0].bounds);
    // Walk the tree with an explicit stack of (node, level).
    std::vector<std::pair<uint32_t, int>> stack{{0u, 1}};
    while (!stack.empty()) {
        auto [index, level] = stack.back();
        stack.pop_back();
        const BvhBuildNode& node = bvh.nodes[index];
        stats.depth = std::max(stats.depth, level);
        const double relativeArea = rootArea > 0.0 ? area(node.bounds) / rootArea : 0.0;
        if (node.isLeaf()) {
            ++stats.leaves;
            stats.sahCost += relativeArea * config.intersectionCost * node.primCount;
        } else {
            stats.sahCost += relativeArea * config.traversalCost;
            stack.push_back({node.leftOrFirst, level + 1});
            stack.push_back({node.leftOrFirst + 1, level + 1});
        }
    }
    return stats;
}

}  // namespace vkrt
