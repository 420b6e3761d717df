// Meshes stored compressed, decoded into plain glTF before the conversion reads them: the buffer views of
// EXT_meshopt_compression (meshoptimizer's codecs and filters) and the primitives of
// KHR_draco_mesh_compression (Google's Draco decoder). Each decoded block becomes a buffer of its own, which
// the view, or the primitive's accessors, then refer to; the accessor reader checks every bound over it as it
// does for any file.
#pragma once

#include <cstdint>
#include <string>

#include <nlohmann/json_fwd.hpp>

namespace tinygltf {
class Model;
}

namespace vkrt {

// Compressed data that tinygltf would refuse, made loadable; true when `document` changed. Fallback buffers
// of EXT_meshopt_compression (data for loaders without the extension) may have no data at all: no uri, or in
// a GLB more bytes than its binary chunk holds; each is given one byte of its own (a data URI), which nothing
// reads, since the views over it are all decoded. A Draco primitive's index accessor has no bufferView, which
// tinygltf requires; it is given the compressed one, which decompressMeshes replaces.
bool stubCompressedData(nlohmann::json& document);

// Decodes, in place, every compressed buffer view and primitive of `model`; throws SceneError naming `path`
// for data that does not decode or does not fit its declared sizes, and MemoryError, before decoding, for a
// Draco mesh whose decoding would take more than `availableBytes` of host memory (`memorySource` says where
// that figure comes from).
void decompressMeshes(tinygltf::Model& model, const std::string& path, uint64_t availableBytes,
                      const std::string& memorySource);

}  // namespace vkrt
