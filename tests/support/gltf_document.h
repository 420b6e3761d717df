// glTF documents built in memory by tests: the JSON, and binary data appended to one buffer (a base64 data
// URI when written), each array its own buffer view and accessor.
#pragma once

#include <algorithm>
#include <cstdint>
#include <cstring>
#include <filesystem>
#include <string>
#include <vector>

#include <nlohmann/json.hpp>

#include "support/test_paths.h"

namespace vkrt::test {

inline std::string base64(const std::vector<uint8_t>& bytes) {
    static const char* alphabet = "ABCDEFGHIJKLMNOPQRSTUVWXYZabcdefghijklmnopqrstuvwxyz0123456789+/";
    std::string out;
    for (size_t i = 0; i < bytes.size(); i += 3) {
        const size_t available = std::min<size_t>(3, bytes.size() - i);
        uint32_t chunk = 0;
        for (size_t k = 0; k < 3; ++k) chunk = (chunk << 8) | (k < available ? bytes[i + k] : 0);
        for (size_t k = 0; k < 4; ++k) out += k <= available ? alphabet[(chunk >> (18 - 6 * k)) & 63] : '=';
    }
    return out;
}

class GltfDocument {
  public:
    nlohmann::json json = {
        {"asset", {{"version", "2.0"}}}, {"scene", 0}, {"scenes", {{{"nodes", nlohmann::json::array()}}}}};

    // An accessor of `type` ("SCALAR", "VEC3", "MAT4", ...) over `values`: floats (5126) or unsigned shorts
    // (5123).
    int floats(const std::vector<float>& values, const char* type) { return accessor(values, 5126, type); }
    int unsignedShorts(const std::vector<uint16_t>& values, const char* type) {
        return accessor(values, 5123, type);
    }

    // An accessor of `count` elements of `type` with no bufferView (glTF 2.0 section 3.6.2.3): zero but for
    // elements `indices`, which take `values`, floats (5126) or unsigned shorts (5123) as `componentType`
    // says. A few bytes of file that claim as many elements as they like.
    template <typename T>
    int sparseOnly(size_t count, const std::vector<uint16_t>& indices, const std::vector<T>& values,
                   int componentType, const char* type) {
        const int where = accessor(indices, 5123, "SCALAR");
        const int what = accessor(values, componentType, type);
        json["accessors"].push_back(
            {{"count", count},
             {"componentType", componentType},
             {"type", type},
             {"sparse",
              {{"count", indices.size()},
               {"indices", {{"bufferView", json["accessors"][where]["bufferView"]}, {"componentType", 5123}}},
               {"values", {{"bufferView", json["accessors"][what]["bufferView"]}}}}}});
        return static_cast<int>(json["accessors"].size()) - 1;
    }

    // POSITION accessors, with the bounds glTF requires of them: `values` as VEC3 floats, or a sparse-only
    // accessor of `count` positions, `values` at `indices` and the origin elsewhere.
    int positions(const std::vector<float>& values) { return bounded(floats(values, "VEC3"), values, false); }
    int sparsePositions(size_t count, const std::vector<uint16_t>& indices,
                        const std::vector<float>& values) {
        return bounded(sparseOnly(count, indices, values, 5126, "VEC3"), values, count > indices.size());
    }

    // Appends a node (a scene root when `root`) and returns its index.
    int node(const nlohmann::json& fields, bool root = true) {
        json["nodes"].push_back(fields);
        const int index = static_cast<int>(json["nodes"].size()) - 1;
        if (root) json["scenes"][0]["nodes"].push_back(index);
        return index;
    }

    void write(const std::filesystem::path& file) {
        nlohmann::json document = json;
        document["buffers"] = {{{"byteLength", bytes_.size()},
                                {"uri", "data:application/octet-stream;base64," + base64(bytes_)}}};
        writeText(file, document.dump());
    }

  private:
    // Sets the min and max of VEC3 accessor `index` over `values`, and the origin when `withOrigin`.
    int bounded(int index, const std::vector<float>& values, bool withOrigin) {
        std::vector<float> low(3), high(3);
        for (size_t c = 0; c < 3; ++c) {
            low[c] = high[c] = withOrigin || values.empty() ? 0.0f : values[c];
            for (size_t i = c; i < values.size(); i += 3) {
                low[c] = std::min(low[c], values[i]);
                high[c] = std::max(high[c], values[i]);
            }
        }
        json["accessors"][index]["min"] = low;
        json["accessors"][index]["max"] = high;
        return index;
    }

    template <typename T>
    int accessor(const std::vector<T>& values, int componentType, const char* type) {
        static const std::pair<const char*, size_t> kComponents[] = {
            {"SCALAR", 1}, {"VEC2", 2}, {"VEC3", 3}, {"VEC4", 4}, {"MAT4", 16}};
        size_t components = 1;
        for (const auto& [name, count] : kComponents)
            if (std::string(name) == type) components = count;
        while (bytes_.size() % 4 != 0) bytes_.push_back(0);
        const size_t offset = bytes_.size();
        bytes_.resize(offset + values.size() * sizeof(T));
        std::memcpy(bytes_.data() + offset, values.data(), values.size() * sizeof(T));
        json["bufferViews"].push_back(
            {{"buffer", 0}, {"byteOffset", offset}, {"byteLength", values.size() * sizeof(T)}});
        json["accessors"].push_back({{"bufferView", json["bufferViews"].size() - 1},
                                     {"componentType", componentType},
                                     {"count", values.size() / components},
                                     {"type", type}});
        return static_cast<int>(json["accessors"].size()) - 1;
    }

    std::vector<uint8_t> bytes_;
};

}  // namespace vkrt::test
