#include "scene/sheen_table.h"

#include <algorithm>

#include "sheen.h"

namespace vkrt {

const std::vector<float>& sheenAlbedoTable() {
    // 64 x 64 midpoint cells per entry (over half the circle of azimuths). Interpolating the 32 x 32 entries is within 3% of the integral
    // (tests/gpu_surface_test.cpp checks a point between entries against a finer integration).
    static const std::vector<float> table = [] {
        constexpr int kSize = VKRT_SHEEN_TABLE_SIZE;
        std::vector<float> values(kSize * kSize);
        for (int j = 0; j < kSize; ++j) {
            for (int i = 0; i < kSize; ++i) {
                // The fitted shadowing overestimates the albedo of the smoothest sheen seen at exactly grazing
                // angles (E reaches 1.6 at cos 0): E is clamped to 1, so the layers below never get a negative
                // weight. From cos 2/31 on the integral stays below 1 unclamped.
                values[j * kSize + i] = static_cast<float>(std::min(
                    1.0, shading::sheenAlbedoIntegral(static_cast<double>(i) / (kSize - 1),
                                                      static_cast<double>(j) / (kSize - 1), 64)));
            }
        }
        return values;
    }();
    return table;
}

}  // namespace vkrt
