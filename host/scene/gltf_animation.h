// glTF node animations (translation, rotation and scale channels; STEP, LINEAR and CUBICSPLINE samplers)
// evaluated at a time, for motion blur. Weights (morph targets) are not animated.
#pragma once

#include <map>
#include <string>
#include <vector>

#include <glm/glm.hpp>
#include <glm/gtc/quaternion.hpp>

#include <tiny_gltf.h>

#include "scene/gltf_accessors.h"

namespace vkrt {

enum class AnimatedPath { Translation, Rotation, Scale };
enum class Interpolation { Step, Linear, CubicSpline };

struct AnimationChannel {
    AnimatedPath path = AnimatedPath::Translation;
    Interpolation interpolation = Interpolation::Linear;
    std::vector<float> times;   // strictly increasing, seconds
    std::vector<float> values;  // 3 or 4 per key; CUBICSPLINE: in-tangent, value, out-tangent per key
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
    // Reads every animation of the model; throws SceneError on malformed channels and samplers.
    NodeAnimations(const tinygltf::Model& model, const AccessorReader& accessors, const std::string& path);

    bool animates(int node) const { return channels_.count(node) > 0; }
    bool empty() const { return channels_.empty(); }
    // True when every channel translates with LINEAR interpolation and has no key strictly inside
    // (open, close): then world positions move linearly over the shutter, exactly.
    bool linearTranslationOnly(double open, double close) const;
    // `rest` with the node's animated channels evaluated at `time` (before the first key: the first key's
    // value; after the last: the last's).
    NodeTrs evaluate(int node, const NodeTrs& rest, double time) const;

  private:
    std::map<int, std::vector<AnimationChannel>> channels_;
};

}  // namespace vkrt
