#include "scene/gltf_animation.h"

#include <algorithm>
#include <cmath>

#include "scene/gltf_transforms.h"
#include "scene/scene_error.h"

namespace vkrt {
namespace {

// The key interval holding `time`: k with times[k] <= time < times[k + 1], and the fraction within it.
void locate(const std::vector<float>& times, double time, size_t& k, double& fraction) {
    if (times.size() < 2 || time <= times.front()) {
        k = 0;
        fraction = 0.0;
        return;
    }
    if (time >= times.back()) {
        k = times.size() - 2;
        fraction = 1.0;
        return;
    }
    // Compared in double: a time just below the last key that rounds up to it in float found no key after it
    // (k = n - 1, and the reads beyond both arrays).
    k = static_cast<size_t>(
            std::upper_bound(times.begin(), times.end(), time,
                             [](double t, float key) { return t < static_cast<double>(key); }) -
            times.begin()) -
        1;
    fraction = (time - times[k]) / (static_cast<double>(times[k + 1]) - times[k]);
}

glm::dvec4 keyValue(const AnimationChannel& channel, size_t key, int components, int part) {
    const int stride = channel.interpolation == Interpolation::CubicSpline ? 3 : 1;
    const size_t base = (key * stride + part) * components;
    glm::dvec4 v(0.0);
    for (int c = 0; c < components; ++c) v[c] = channel.values[base + c];
    return v;
}

// The channel's value at `time` (xyz for vectors, xyzw for quaternions).
glm::dvec4 sample(const AnimationChannel& channel, double time) {
    const int components = channel.path == AnimatedPath::Rotation ? 4 : 3;
    const int valuePart = channel.interpolation == Interpolation::CubicSpline ? 1 : 0;
    size_t k;
    double s;
    locate(channel.times, time, k, s);
    if (channel.times.size() == 1) return keyValue(channel, 0, components, valuePart);
    const glm::dvec4 a = keyValue(channel, k, components, valuePart);
    const glm::dvec4 b = keyValue(channel, k + 1, components, valuePart);
    if (channel.interpolation == Interpolation::Step) return s >= 1.0 ? b : a;
    if (channel.interpolation == Interpolation::CubicSpline) {
        // glTF 2.0 Appendix C: Hermite spline with the keys' out- and in-tangents scaled by the interval.
        const double dt = static_cast<double>(channel.times[k + 1]) - channel.times[k];
        const glm::dvec4 outTangent = keyValue(channel, k, components, 2);
        const glm::dvec4 inTangent = keyValue(channel, k + 1, components, 0);
        const double s2 = s * s, s3 = s2 * s;
        glm::dvec4 v = (2 * s3 - 3 * s2 + 1) * a + dt * (s3 - 2 * s2 + s) * outTangent +
                       (-2 * s3 + 3 * s2) * b + dt * (s3 - s2) * inTangent;
        if (components == 4) v = v / glm::length(v);
        return v;
    }
    if (components == 4) {
        const glm::dquat qa(a.w, a.x, a.y, a.z), qb(b.w, b.x, b.y, b.z);
        const glm::dquat q = glm::slerp(glm::normalize(qa), glm::normalize(qb), s);
        return {q.x, q.y, q.z, q.w};
    }
    return a + s * (b - a);
}

}  // namespace

glm::dmat4 NodeTrs::matrix() const {
    return trsMatrix(translation, rotation, scale);
}

NodeAnimations::NodeAnimations(const tinygltf::Model& model, const AccessorReader& accessors,
                               const std::string& path) {
    auto fail = [&](const std::string& message) { throw SceneError(path + ": " + message); };
    for (size_t a = 0; a < model.animations.size(); ++a) {
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
            else
                continue;  // morph-target weights and extension paths do not move geometry here
            if (source.target_node < 0 || source.target_node >= static_cast<int>(model.nodes.size()))
                fail(channelWhere + " targets node " + std::to_string(source.target_node) +
                     ", which does not exist");
            if (!model.nodes[source.target_node].matrix.empty())
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
            channel.times = accessors.readFloats(sampler.input, 1, channelWhere + " input");
            const int components = channel.path == AnimatedPath::Rotation ? 4 : 3;
            channel.values = accessors.readFloats(sampler.output, components, channelWhere + " output");
            const size_t perKey = (channel.interpolation == Interpolation::CubicSpline ? 3 : 1) * components;
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
            if (channel.path != AnimatedPath::Translation || channel.interpolation != Interpolation::Linear)
                return false;
            for (float t : channel.times) {
                if (t > open && t < close) return false;
            }
        }
    }
    return true;
}

NodeTrs NodeAnimations::evaluate(int node, const NodeTrs& rest, double time) const {
    NodeTrs trs = rest;
    auto it = channels_.find(node);
    if (it == channels_.end()) return trs;
    for (const AnimationChannel& channel : it->second) {
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
        }
    }
    return trs;
}

}  // namespace vkrt
