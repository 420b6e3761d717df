#include "bvh/flat_bvh.h"

namespace vkrt {

FlatBvh flatten(const Bvh& bvh) {
    FlatBvh flat;
    flat.nodes.resize(bvh.nodes.size());
    for (size_t i = 0; i < bvh.nodes.size(); ++i) {
        const BvhBuildNode& node = bvh.nodes[i];
        flat.nodes[i] = gpu::BvhNode{node.bounds.min, node.leftOrFirst, node.bounds.max, node.primCount};
    }
    flat.primIndices = bvh.primIndices;
    return flat;
}

}  // namespace vkrt
