#include "scene/gltf_animation.h"

#include <algorithm>
#include <cmath>
#include <string>

#include "common/memory_need.h"
#include "scene/gltf_transforms.h"
#include "scene/scene_error.h"

namespace vkrt {
namespace {

// The key interval holding `time`: k with times[k] <= time < times[k + 1], and the fraction within it. The
// keys are floats, and a time is compared at their precision: the time 0.1 lies just below the key 0.1f, and
// compared in double it took the key before it (a STEP animation rendered at a key showed the previous key's
// value). The fraction is the double time's, within [0, 1].
void locate(const std::vector<float>& times, double time, size_t& k, double& fraction) {
    const float at = static_cast<float>(time);
    if (times.size() < 2 || at <= times.front()) {
        k = 0;
        fraction = 0.0;
        return;
    }
    if (at >= times.back()) {
        k = times.size() - 2;
        fraction = 1.0;
        return;
    }
    k = static_cast<size_t>(std::upper_bound(times.begin(), times.end(), at) - times.begin()) - 1;
    fraction = std::clamp((time - times[k]) / (static_cast<double>(times[k + 1]) - times[k]), 0.0, 1.0);
}

// Component `c` of a key's value (`part` 0, 1, 2: a CUBICSPLINE key's in-tangent, value, out-tangent).
double keyComponent(const AnimationChannel& channel, size_t key, int part, int c) {
    const int stride = channel.interpolation == Interpolation::CubicSpline ? 3 : 1;
    return channel.values[(key * stride + part) * channel.components + c];
}

glm::dvec4 keyValue(const AnimationChannel& channel, size_t key, int part) {
    glm::dvec4 v(0.0);
    for (int c = 0; c < std::min(channel.components, 4); ++c) v[c] = keyComponent(channel, key, part, c);
    return v;
}

// The channel's component `c` at `time`, interpolated on its own (a vector's or the weights' component).
double sampleComponent(const AnimationChannel& channel, int c, double time) {
    const int valuePart = channel.interpolation == Interpolation::CubicSpline ? 1 : 0;
    size_t k;
    double s;
    locate(channel.times, time, k, s);
    if (channel.times.size() == 1) return keyComponent(channel, 0, valuePart, c);
    const double a = keyComponent(channel, k, valuePart, c);
    const double b = keyComponent(channel, k + 1, valuePart, c);
    if (channel.interpolation == Interpolation::Step) return s >= 1.0 ? b : a;
    if (channel.interpolation == Interpolation::CubicSpline) {
        // glTF 2.0 Appendix C: Hermite spline with the keys' out- and in-tangents scaled by the interval.
        const double dt = static_cast<double>(channel.times[k + 1]) - channel.times[k];
        const double outTangent = keyComponent(channel, k, 2, c);
        const double inTangent = keyComponent(channel, k + 1, 0, c);
        const double s2 = s * s, s3 = s2 * s;
        return (2 * s3 - 3 * s2 + 1) * a + dt * (s3 - 2 * s2 + s) * outTangent + (-2 * s3 + 3 * s2) * b +
               dt * (s3 - s2) * inTangent;
    }
    return a + s * (b - a);
}

// The channel's value at `time` (xyz for vectors, xyzw for quaternions).
glm::dvec4 sample(const AnimationChannel& channel, double time) {
    if (channel.path == AnimatedPath::Rotation && channel.interpolation == Interpolation::Linear &&
        channel.times.size() > 1) {
        size_t k;
        double s;
        locate(channel.times, time, k, s);
        const glm::dvec4 a = keyValue(channel, k, 0), b = keyValue(channel, k + 1, 0);
        const glm::dquat qa(a.w, a.x, a.y, a.z), qb(b.w, b.x, b.y, b.z);
        const glm::dquat q = glm::slerp(glm::normalize(qa), glm::normalize(qb), s);
        return {q.x, q.y, q.z, q.w};
    }
    glm::dvec4 v(0.0);
    for (int c = 0; c < std::min(channel.components, 4); ++c) v[c] = sampleComponent(channel, c, time);
    if (channel.path == AnimatedPath::Rotation && channel.interpolation == Interpolation::CubicSpline)
        v = v / glm::length(v);
    return v;
}

}  // namespace

glm::dmat4 NodeTrs::matrix() const {
    return trsMatrix(translation, rotation, scale);
}

NodeAnimations::NodeAnimations(
    const tinygltf::Model& model, const AccessorReader& accessors, const std::string& path, int selected,
    const std::function<void(uint64_t keptBytes, uint64_t passingBytes, const std::string& what)>& reserve)
    : path_(path) {
    auto fail = [&](const std::string& message) { throw SceneError(path + ": " + message); };
    // An accessor's floats, counted before they are read: those kept, and the doubles the reader builds them
    // from and frees.
    auto readCounted = [&](int accessor, int components, const std::string& what) {
        const double values = static_cast<double>(accessors.count(accessor, what)) * components;
        reserve(saturatedBytes(values * sizeof(float)), saturatedBytes(values * sizeof(double)), what);
        return accessors.readFloats(accessor, components, what);
    };
    if (selected >= 0 && selected < static_cast<int>(model.animations.size())) {
        const size_t a = static_cast<size_t>(selected);
        const tinygltf::Animation& animation = model.animations[a];
        const std::string where = "animation " + std::to_string(a);
        for (size_t c = 0; c < animation.channels.size(); ++c) {
            const tinygltf::AnimationChannel& source = animation.channels[c];
            const std::string channelWhere = where + " channel " + std::to_string(c);
            AnimationChannel channel;
            if (source.target_path == "translation")
                channel.path = AnimatedPath::Translation;
            else if (source.target_path == "rotation")
                channel.path = AnimatedPath::Rotation;
            else if (source.target_path == "scale")
                channel.path = AnimatedPath::Scale;
            else if (source.target_path == "weights")
                channel.path = AnimatedPath::Weights;
            else
                continue;  // extension paths do not move geometry
            if (source.target_node < 0 || source.target_node >= static_cast<int>(model.nodes.size()))
                fail(channelWhere + " targets node " + std::to_string(source.target_node) +
                     ", which does not exist");
            if (channel.path != AnimatedPath::Weights && !model.nodes[source.target_node].matrix.empty())
                fail(channelWhere + " animates a node that has a matrix (glTF allows only TRS nodes)");
            if (source.sampler < 0 || source.sampler >= static_cast<int>(animation.samplers.size()))
                fail(channelWhere + " refers to sampler " + std::to_string(source.sampler) +
                     ", which does not exist");
            const tinygltf::AnimationSampler& sampler = animation.samplers[source.sampler];
            if (sampler.interpolation == "STEP")
                channel.interpolation = Interpolation::Step;
            else if (sampler.interpolation == "CUBICSPLINE")
                channel.interpolation = Interpolation::CubicSpline;
            else if (sampler.interpolation.empty() || sampler.interpolation == "LINEAR")
                channel.interpolation = Interpolation::Linear;
            else
                fail(channelWhere + " has unknown interpolation '" + sampler.interpolation + "'");
            channel.times = readCounted(sampler.input, 1, channelWhere + " input");
            const size_t parts = channel.interpolation == Interpolation::CubicSpline ? 3 : 1;
            if (channel.path == AnimatedPath::Weights) {
                // Scalars, one per morph target for each key (and each tangent).
                channel.values = readCounted(sampler.output, 1, channelWhere + " output");
                const size_t perKey =
                    channel.times.empty() ? 0 : channel.values.size() / (channel.times.size() * parts);
                if (perKey == 0 || perKey > 65536)
                    fail(channelWhere + ": the sampler's input and output counts do not match");
                channel.components = static_cast<int>(perKey);
            } else {
                channel.components = channel.path == AnimatedPath::Rotation ? 4 : 3;
                channel.values = readCounted(sampler.output, channel.components, channelWhere + " output");
            }
            const size_t perKey = parts * static_cast<size_t>(channel.components);
            if (channel.times.empty() || channel.values.size() != channel.times.size() * perKey)
                fail(channelWhere + ": the sampler's input and output counts do not match");
            for (size_t i = 0; i < channel.times.size(); ++i) {
                if (!std::isfinite(channel.times[i]) || (i > 0 && !(channel.times[i] > channel.times[i - 1])))
                    fail(channelWhere + ": key times must be finite and increasing");
            }
            for (float v : channel.values) {
                if (!std::isfinite(v)) fail(channelWhere + " has a non-finite value");
            }
            channels_[source.target_node].push_back(std::move(channel));
        }
    }
}

bool NodeAnimations::linearTranslationOnly(double open, double close) const {
    for (const auto& [node, channels] : channels_) {
        for (const AnimationChannel& channel : channels) {
            if (channel.path == AnimatedPath::Rotation || channel.path == AnimatedPath::Scale ||
                channel.interpolation != Interpolation::Linear)
                return false;
            for (float t : channel.times) {
                if (t > open && t < close) return false;
            }
        }
    }
    return true;
}

bool NodeAnimations::animates(int node) const {
    const auto it = channels_.find(node);
    if (it == channels_.end()) return false;
    return std::any_of(it->second.begin(), it->second.end(),
                       [](const AnimationChannel& channel) { return channel.path != AnimatedPath::Weights; });
}

bool NodeAnimations::animatesWeights(int node) const {
    const auto it = channels_.find(node);
    if (it == channels_.end()) return false;
    return std::any_of(it->second.begin(), it->second.end(),
                       [](const AnimationChannel& channel) { return channel.path == AnimatedPath::Weights; });
}

std::vector<double> NodeAnimations::evaluateWeights(int node, std::vector<double> rest, double time) const {
    const auto it = channels_.find(node);
    if (it == channels_.end()) return rest;
    for (const AnimationChannel& channel : it->second) {
        if (channel.path != AnimatedPath::Weights) continue;
        if (static_cast<size_t>(channel.components) != rest.size()) {
            throw SceneError(path_ + ": an animation gives node " + std::to_string(node) + " " +
                             std::to_string(channel.components) +
                             " morph-target weight(s) per key; its mesh has " + std::to_string(rest.size()) +
                             " morph target(s)");
        }
        for (int c = 0; c < channel.components; ++c)
            rest[static_cast<size_t>(c)] = sampleComponent(channel, c, time);
    }
    return rest;
}

NodeTrs NodeAnimations::evaluate(int node, const NodeTrs& rest, double time) const {
    NodeTrs trs = rest;
    auto it = channels_.find(node);
    if (it == channels_.end()) return trs;
    for (const AnimationChannel& channel : it->second) {
        if (channel.path == AnimatedPath::Weights) continue;  // evaluateWeights
        const glm::dvec4 v = sample(channel, time);
        switch (channel.path) {
            case AnimatedPath::Translation:
                trs.translation = glm::dvec3(v);
                break;
            case AnimatedPath::Rotation: {
                const glm::dquat q(v.w, v.x, v.y, v.z);
                if (!(glm::length(q) > 0.0)) throw SceneError("animated rotation quaternion has zero length");
                trs.rotation = glm::normalize(q);
                break;
            }
            case AnimatedPath::Scale:
                trs.scale = glm::dvec3(v);
                break;
            case AnimatedPath::Weights:
                break;
        }
    }
    return trs;
}

}  // namespace vkrt
