// The volumes a ray is inside, innermost last, for nested dielectrics (glass in water): entering a volume
// through its front face pushes it, leaving through its back face removes it, and the relative index at
// each interface is between the medium the ray is in and the one it passes into. Up to four levels; a
// fifth forgets the outermost. The GPU keeps the same stack (shaders/trace.comp).
#pragma once

#include <array>

#include "scene/scene.h"

namespace vkrt {

struct MediumStack {
    static constexpr int kCapacity = 4;
    std::array<int, kCapacity> media{};  // material indices, innermost at size - 1
    int size = 0;

    int top() const { return size > 0 ? media[size - 1] : -1; }

    MediumStack entered(int material) const {
        MediumStack next = *this;
        if (next.size == kCapacity) {
            for (int i = 1; i < kCapacity; ++i) next.media[i - 1] = next.media[i];
            --next.size;
        }
        next.media[next.size++] = material;
        return next;
    }

    // Without `material` (its innermost occurrence); unchanged when the ray was not inside it.
    MediumStack exited(int material) const {
        MediumStack next = *this;
        for (int i = next.size - 1; i >= 0; --i) {
            if (next.media[i] == material) {
                for (int j = i + 1; j < next.size; ++j) next.media[j - 1] = next.media[j];
                --next.size;
                break;
            }
        }
        return next;
    }
};

// The index of refraction of the medium on top of a stack: the material's, or 1 (air) when empty.
inline double mediumIor(const Scene& scene, const MediumStack& stack) {
    return stack.top() >= 0 ? static_cast<double>(scene.materials[stack.top()].ior) : 1.0;
}

}  // namespace vkrt
