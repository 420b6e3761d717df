// glTF node animations (translation, rotation, scale and morph-target weight channels; STEP, LINEAR and
// CUBICSPLINE samplers) evaluated at a time, for the shutter's poses.
#pragma once

#include <cstdint>
#include <functional>
#include <map>
#include <string>
#include <vector>

#include <glm/glm.hpp>
#include <glm/gtc/quaternion.hpp>

#include <tiny_gltf.h>

#include "scene/gltf_accessors.h"

namespace vkrt {

enum class AnimatedPath { Translation, Rotation, Scale, Weights };
enum class Interpolation { Step, Linear, CubicSpline };

struct AnimationChannel {
    AnimatedPath path = AnimatedPath::Translation;
    Interpolation interpolation = Interpolation::Linear;
    int components = 3;         // per key value: 3, 4 (rotation) or the weights' count
    std::vector<float> times;   // strictly increasing, seconds
    std::vector<float> values;  // `components` per key; CUBICSPLINE: in-tangent, value, out-tangent per key
};

// A node's local transform over time: its static TRS with the animated parts replaced.
struct NodeTrs {
    glm::dvec3 translation{0.0};
    glm::dquat rotation{1.0, 0.0, 0.0, 0.0};
    glm::dvec3 scale{1.0};
    glm::dmat4 matrix() const;
};

class NodeAnimations {
  public:
    // No animation: every node stays at rest.
    NodeAnimations() = default;
    // Reads animation `selected` of the model (none where -1); throws SceneError on malformed channels and
    // samplers. Before each accessor is read, `reserve` is given the bytes its keys keep for the rest of the
    // load and those the reading takes beside them for a moment, and throws when they do not fit.
    NodeAnimations(const tinygltf::Model& model, const AccessorReader& accessors, const std::string& path,
                   int selected,
                   const std::function<void(uint64_t keptBytes, uint64_t passingBytes,
                                            const std::string& what)>& reserve);

    // Whether a channel moves the node (translation, rotation or scale).
    bool animates(int node) const;
    // Whether a channel changes the node's morph-target weights.
    bool animatesWeights(int node) const;
    bool empty() const { return channels_.empty(); }
    // True when every channel translates or weighs morph targets with LINEAR interpolation and has no key
    // strictly inside (open, close): then world positions move linearly over the shutter, exactly (a skinned
    // vertex is a weighted sum of its joints' moves, a morphed one of its targets' weights).
    bool linearTranslationOnly(double open, double close) const;
    // `rest` with the node's animated channels evaluated at `time` (before the first key: the first key's
    // value; after the last: the last's).
    NodeTrs evaluate(int node, const NodeTrs& rest, double time) const;
    // `rest` (the node's or its mesh's weights) with the node's weights channel evaluated at `time`; throws
    // SceneError when the channel's count of weights is not the rest's (the mesh's count of morph targets).
    std::vector<double> evaluateWeights(int node, std::vector<double> rest, double time) const;

  private:
    std::string path_;  // the file, for messages
    std::map<int, std::vector<AnimationChannel>> channels_;
};

}  // namespace vkrt
