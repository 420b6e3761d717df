// Meshes stored compressed, decoded into plain glTF before the conversion reads them: the buffer views of
// EXT_meshopt_compression (meshoptimizer's codecs and filters). Each decoded view becomes a buffer of its own
// that the view then refers to; the accessor reader checks every bound over it as it does for any file.
#pragma once

#include <string>

#include <nlohmann/json_fwd.hpp>

namespace tinygltf {
class Model;
}

namespace vkrt {

// EXT_meshopt_compression's fallback buffers (data for loaders without the extension) may have no data at
// all: no uri, or in a GLB more bytes than its binary chunk holds. tinygltf refuses both, so each is given
// one byte of its own (a data URI), which nothing reads: the views over it are all decoded. True when
// `document` changed.
bool stubMeshoptFallbackBuffers(nlohmann::json& document);

// Decodes, in place, every compressed buffer view of `model`; throws SceneError naming `path`
// for data that does not decode or does not fit its declared sizes.
void decompressMeshes(tinygltf::Model& model, const std::string& path);

}  // namespace vkrt
