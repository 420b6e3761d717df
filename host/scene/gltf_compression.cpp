#include "scene/gltf_compression.h"

#include <cstring>
#include <limits>

#include <meshoptimizer.h>
#include <tiny_gltf.h>
#include <nlohmann/json.hpp>

#include "scene/scene_error.h"

namespace vkrt {
namespace {

constexpr const char* kMeshopt = "EXT_meshopt_compression";

// meshoptimizer's codecs decode at most 64 bytes from each compressed one (a vertex stream's bytes go in
// groups of 16 under a 2-bit header at best; a triangle takes at least 4 bits, an index sequence's index a
// byte): a larger declared size is refused before anything is allocated.
constexpr size_t kMaxMeshoptRatio = 64;
constexpr size_t kMaxDecodedBytes = size_t{1} << 32;

class Decoder {
  public:
    Decoder(tinygltf::Model& model, const std::string& path) : model_(model), path_(path) {}

    void meshoptViews() {
        for (size_t i = 0; i < model_.bufferViews.size(); ++i) {
            const auto extension = model_.bufferViews[i].extensions.find(kMeshopt);
            if (extension != model_.bufferViews[i].extensions.end()) meshoptView(i, extension->second);
        }
    }

  private:
    [[noreturn]] void fail(const std::string& message) const { throw SceneError(path_ + ": " + message); }

    size_t size(const tinygltf::Value& object, const char* key, const std::string& where, bool required,
                size_t fallback = 0) const {
        if (!object.Has(key)) {
            if (required) fail(where + ": '" + key + "' is missing");
            return fallback;
        }
        const tinygltf::Value& value = object.Get(key);
        const double number = value.IsNumber() ? value.GetNumberAsDouble() : -1.0;
        if (!(number >= 0.0) || number > 9.0e15 ||
            number != static_cast<double>(static_cast<uint64_t>(number)))
            fail(where + ": '" + key + "' must be an integer >= 0");
        return static_cast<size_t>(number);
    }

    // `length` bytes at `offset` of buffer `buffer`, every byte checked to exist.
    const unsigned char* bytes(size_t buffer, size_t offset, size_t length, const std::string& where) const {
        if (buffer >= model_.buffers.size())
            fail(where + " refers to buffer " + std::to_string(buffer) + ", which does not exist");
        const std::vector<unsigned char>& data = model_.buffers[buffer].data;
        if (offset > data.size() || length > data.size() - offset) {
            fail(where + " needs bytes [" + std::to_string(offset) + ", " + std::to_string(offset) + " + " +
                 std::to_string(length) + ") of buffer " + std::to_string(buffer) + ", which holds " +
                 std::to_string(data.size()));
        }
        return data.data() + offset;
    }

    // EXT_meshopt_compression: the view's bytes are `count` elements of `byteStride` bytes decoded from
    // another buffer's bytes by one of three codecs, then, for attributes, undone by a filter.
    void meshoptView(size_t index, const tinygltf::Value& extension) {
        const std::string where = "bufferView " + std::to_string(index) + " " + kMeshopt;
        if (!extension.IsObject()) fail(where + " must be an object");
        const size_t buffer = size(extension, "buffer", where, true);
        const size_t offset = size(extension, "byteOffset", where, false);
        const size_t length = size(extension, "byteLength", where, true);
        const size_t stride = size(extension, "byteStride", where, true);
        const size_t count = size(extension, "count", where, true);
        const std::string mode = extension.Has("mode") && extension.Get("mode").IsString()
                                     ? extension.Get("mode").Get<std::string>()
                                     : std::string();
        const std::string filter = extension.Has("filter") && extension.Get("filter").IsString()
                                       ? extension.Get("filter").Get<std::string>()
                                       : std::string("NONE");
        const unsigned char* source = bytes(buffer, offset, length, where);

        if (stride == 0 || stride > 256 || count > kMaxDecodedBytes / stride)
            fail(where + ": byteStride " + std::to_string(stride) + " and count " + std::to_string(count) +
                 " are out of range");
        const size_t decodedSize = count * stride;
        if (decodedSize > kMaxMeshoptRatio * length + 4096) {
            fail(where + ": " + std::to_string(decodedSize) + " bytes cannot come from " +
                 std::to_string(length) + " compressed ones");
        }
        tinygltf::BufferView& view = model_.bufferViews[index];
        if (decodedSize > view.byteLength) {
            fail(where + " decodes to " + std::to_string(decodedSize) +
                 " bytes, more than the view's byteLength " + std::to_string(view.byteLength));
        }
        std::vector<unsigned char> decoded(decodedSize);
        int status = -1;
        if (mode == "ATTRIBUTES") {
            if (stride % 4 != 0) fail(where + ": ATTRIBUTES need a byteStride that is a multiple of 4");
            status = meshopt_decodeVertexBuffer(decoded.data(), count, stride, source, length);
        } else if (mode == "TRIANGLES" || mode == "INDICES") {
            if (stride != 2 && stride != 4) fail(where + ": " + mode + " need a byteStride of 2 or 4");
            if (mode == "TRIANGLES" && count % 3 != 0)
                fail(where + ": TRIANGLES need a count that is a multiple of 3");
            status = mode == "TRIANGLES"
                         ? meshopt_decodeIndexBuffer(decoded.data(), count, stride, source, length)
                         : meshopt_decodeIndexSequence(decoded.data(), count, stride, source, length);
        } else {
            fail(where + ": unknown mode '" + mode + "' (ATTRIBUTES, TRIANGLES or INDICES)");
        }
        if (status != 0)
            fail(where + ": the compressed data does not decode (meshoptimizer error " +
                 std::to_string(status) + ")");

        if (filter != "NONE" && mode != "ATTRIBUTES")
            fail(where + ": filter " + filter + " applies to ATTRIBUTES only");
        if (filter == "OCTAHEDRAL") {
            if (stride != 4 && stride != 8)
                fail(where + ": the OCTAHEDRAL filter needs a byteStride of 4 or 8");
            meshopt_decodeFilterOct(decoded.data(), count, stride);
        } else if (filter == "QUATERNION") {
            if (stride != 8) fail(where + ": the QUATERNION filter needs a byteStride of 8");
            meshopt_decodeFilterQuat(decoded.data(), count, stride);
        } else if (filter == "EXPONENTIAL") {
            meshopt_decodeFilterExp(decoded.data(), count, stride);
        } else if (filter != "NONE") {
            fail(where + ": unknown filter '" + filter + "' (NONE, OCTAHEDRAL, QUATERNION or EXPONENTIAL)");
        }

        view.buffer = static_cast<int>(model_.buffers.size());
        view.byteOffset = 0;
        view.byteLength = decodedSize;
        model_.buffers.emplace_back().data = std::move(decoded);
    }

    tinygltf::Model& model_;
    const std::string& path_;
};

}  // namespace

bool stubMeshoptFallbackBuffers(nlohmann::json& document) {
    if (!document.is_object()) return false;
    auto extensionOf = [](const nlohmann::json& object, const char* name) -> const nlohmann::json* {
        if (!object.is_object() || !object.contains("extensions") || !object["extensions"].is_object())
            return nullptr;
        const nlohmann::json& extensions = object["extensions"];
        return extensions.contains(name) && extensions[name].is_object() ? &extensions[name] : nullptr;
    };
    bool changed = false;
    if (document.contains("buffers") && document["buffers"].is_array()) {
        for (nlohmann::json& buffer : document["buffers"]) {
            const nlohmann::json* extension = extensionOf(buffer, kMeshopt);
            if (extension == nullptr || !extension->contains("fallback") || (*extension)["fallback"] != true)
                continue;
            buffer["uri"] = "data:application/octet-stream;base64,AA==";
            buffer["byteLength"] = 1;
            changed = true;
        }
    }
    return changed;
}

void decompressMeshes(tinygltf::Model& model, const std::string& path) {
    Decoder decoder(model, path);
    decoder.meshoptViews();
}

}  // namespace vkrt
