#include "bvh/binned_sah_builder.h"

#include <algorithm>
#include <atomic>
#include <stdexcept>

#include "common/fork_join.h"
#include "common/parallel_for.h"

namespace vkrt {
namespace {

// Subtrees with fewer primitives than this are built on the thread that reached them.
constexpr uint32_t kParallelThreshold = 16 * 1024;

struct Bin {
    Aabb bounds;
    uint32_t count = 0;
};

struct Split {
    int axis = -1;
    int bin = 0;  // primitives in bins [0, bin] go left
    float cost = std::numeric_limits<float>::infinity();
};

// Levels that a balanced (median-split) subtree over `count` primitives needs, itself included.
int levelsNeeded(uint32_t count, int maxLeafSize) {
    int levels = 1;
    uint64_t capacity = static_cast<uint64_t>(maxLeafSize);
    while (capacity < count) {
        capacity *= 2;
        ++levels;
    }
    return levels;
}

class Builder {
  public:
    Builder(std::span<const Aabb> bounds, const BvhConfig& config)
        : bounds_(bounds), config_(config), forkJoin_(threadCount(config.threads)) {
        centers_.resize(bounds.size());
        for (size_t i = 0; i < bounds.size(); ++i) centers_[i] = bounds[i].center();
    }

    Bvh build() {
        const uint32_t count = static_cast<uint32_t>(bounds_.size());
        bvh_.primIndices.resize(count);
        for (uint32_t i = 0; i < count; ++i) bvh_.primIndices[i] = i;
        // A binary tree with at least one primitive per leaf has at most 2n - 1 nodes.
        bvh_.nodes.resize(count == 0 ? 1 : 2 * static_cast<size_t>(count) - 1);
        nextNode_ = 1;
        buildNode(0, 0, count, 1);
        bvh_.nodes.resize(nextNode_);
        return std::move(bvh_);
    }

  private:
    void buildNode(uint32_t nodeIndex, uint32_t begin, uint32_t end, int level) {
        BvhBuildNode& node = bvh_.nodes[nodeIndex];
        Aabb centerBounds;
        for (uint32_t i = begin; i < end; ++i) {
            node.bounds.grow(bounds_[bvh_.primIndices[i]]);
            centerBounds.grow(centers_[bvh_.primIndices[i]]);
        }
        const uint32_t count = end - begin;
        if (count <= 1) {
            makeLeaf(node, begin, count);
            return;
        }

        // Split: SAH where the depth budget allows it, otherwise a median split that halves the count.
        const bool mustBalance = level - 1 + levelsNeeded(count, config_.maxLeafSize) >= config_.maxDepth;
        uint32_t middle = begin;
        if (!mustBalance) {
            Split split = findSahSplit(node.bounds, centerBounds, begin, end);
            const float leafCost = config_.intersectionCost * static_cast<float>(count);
            if (count <= static_cast<uint32_t>(config_.maxLeafSize) && leafCost <= split.cost) {
                makeLeaf(node, begin, count);
                return;
            }
            if (split.axis >= 0) middle = partition(split, centerBounds, begin, end);
        } else if (count <= static_cast<uint32_t>(config_.maxLeafSize)) {
            makeLeaf(node, begin, count);
            return;
        }
        if (middle == begin || middle == end) middle = medianSplit(centerBounds, begin, end);

        // Put the two children next to each other, then build them (in parallel when both are large).
        const uint32_t left = nextNode_.fetch_add(2);
        node.leftOrFirst = left;
        node.primCount = 0;
        forkJoin_.invoke(
            std::min(middle - begin, end - middle) >= kParallelThreshold,
            [&] { buildNode(left, begin, middle, level + 1); },
            [&] { buildNode(left + 1, middle, end, level + 1); });
    }

    void makeLeaf(BvhBuildNode& node, uint32_t begin, uint32_t count) {
        node.leftOrFirst = begin;
        node.primCount = count;
        if (count == 0) node.bounds = Aabb{};  // the empty tree: a leaf no ray can hit
    }

    int binOf(const glm::vec3& center, const Aabb& centerBounds, int axis) const {
        const float extent = centerBounds.max[axis] - centerBounds.min[axis];
        const float scaled =
            (center[axis] - centerBounds.min[axis]) * (static_cast<float>(config_.binCount) / extent);
        return std::clamp(static_cast<int>(scaled), 0, config_.binCount - 1);
    }

    Split findSahSplit(const Aabb& nodeBounds, const Aabb& centerBounds, uint32_t begin, uint32_t end) const {
        Split best;
        const float nodeArea = nodeBounds.surfaceArea();
        const int binCount = config_.binCount;
        std::vector<Bin> bins(binCount);
        std::vector<float> rightArea(binCount);
        std::vector<uint32_t> rightCount(binCount);
        for (int axis = 0; axis < 3; ++axis) {
            if (!(centerBounds.max[axis] > centerBounds.min[axis])) continue;
            std::fill(bins.begin(), bins.end(), Bin{});
            for (uint32_t i = begin; i < end; ++i) {
                const uint32_t prim = bvh_.primIndices[i];
                Bin& bin = bins[binOf(centers_[prim], centerBounds, axis)];
                bin.bounds.grow(bounds_[prim]);
                ++bin.count;
            }
            // Sweep from the right to know each right-hand side, then from the left to price each plane.
            Aabb accumulated;
            uint32_t accumulatedCount = 0;
            for (int b = binCount - 1; b > 0; --b) {
                accumulated.grow(bins[b].bounds);
                accumulatedCount += bins[b].count;
                rightArea[b] = accumulated.surfaceArea();
                rightCount[b] = accumulatedCount;
            }
            accumulated = Aabb{};
            accumulatedCount = 0;
            for (int b = 0; b < binCount - 1; ++b) {
                accumulated.grow(bins[b].bounds);
                accumulatedCount += bins[b].count;
                if (accumulatedCount == 0 || rightCount[b + 1] == 0) continue;
                const float cost = config_.traversalCost + config_.intersectionCost *
                                                               (accumulated.surfaceArea() * accumulatedCount +
                                                                rightArea[b + 1] * rightCount[b + 1]) /
                                                               nodeArea;
                if (cost < best.cost) best = Split{axis, b, cost};
            }
        }
        return best;
    }

    uint32_t partition(const Split& split, const Aabb& centerBounds, uint32_t begin, uint32_t end) {
        auto first = bvh_.primIndices.begin() + begin;
        auto last = bvh_.primIndices.begin() + end;
        auto middle = std::partition(first, last, [&](uint32_t prim) {
            return binOf(centers_[prim], centerBounds, split.axis) <= split.bin;
        });
        return static_cast<uint32_t>(middle - bvh_.primIndices.begin());
    }

    // Halves the range along the widest centroid axis; identical centroids are split by index.
    uint32_t medianSplit(const Aabb& centerBounds, uint32_t begin, uint32_t end) {
        const uint32_t middle = begin + (end - begin) / 2;
        const glm::vec3 extent = centerBounds.extent();
        int axis = extent.x >= extent.y && extent.x >= extent.z ? 0 : (extent.y >= extent.z ? 1 : 2);
        if (extent[axis] > 0.0f) {
            std::nth_element(bvh_.primIndices.begin() + begin, bvh_.primIndices.begin() + middle,
                             bvh_.primIndices.begin() + end,
                             [&](uint32_t a, uint32_t b) { return centers_[a][axis] < centers_[b][axis]; });
        }
        return middle;
    }

    std::span<const Aabb> bounds_;
    const BvhConfig& config_;
    std::vector<glm::vec3> centers_;
    Bvh bvh_;
    std::atomic<uint32_t> nextNode_{0};
    ForkJoin forkJoin_;
};

}  // namespace

Bvh BinnedSahBuilder::build(std::span<const Aabb> bounds, const BvhConfig& config) {
    if (config.maxDepth < 2 || config.maxDepth > 64 || config.maxLeafSize < 1 || config.binCount < 2) {
        throw std::invalid_argument("BvhConfig out of range");
    }
    if (levelsNeeded(static_cast<uint32_t>(bounds.size()), config.maxLeafSize) > config.maxDepth) {
        throw std::invalid_argument("too many primitives for the BVH depth limit");
    }
    Builder builder(bounds, config);
    return builder.build();
}

BvhStats measureBvh(const Bvh& bvh, const BvhConfig& config) {
    BvhStats stats;
    stats.nodes = bvh.nodes.size();
    if (bvh.primIndices.empty()) {  // the empty tree: one node that nothing can hit
        stats.depth = 1;
        return stats;
    }
    const float rootArea = bvh.nodes[0].bounds.surfaceArea();
    // Walk the tree with an explicit stack of (node, level).
    std::vector<std::pair<uint32_t, int>> stack{{0u, 1}};
    while (!stack.empty()) {
        auto [index, level] = stack.back();
        stack.pop_back();
        const BvhBuildNode& node = bvh.nodes[index];
        stats.depth = std::max(stats.depth, level);
        const double relativeArea = rootArea > 0.0f ? node.bounds.surfaceArea() / rootArea : 0.0;
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
