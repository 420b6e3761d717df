#include "scene/gltf_compression.h"

#include <cstring>
#include <limits>
#include <memory>
#include <optional>
#include <set>

#include <draco/compression/decode.h>
#include <draco/compression/point_cloud/point_cloud_decoder.h>
#include <draco/core/varint_decoding.h>
#include <draco/metadata/metadata_decoder.h>
#include <meshoptimizer.h>
#include <tiny_gltf.h>
#include <nlohmann/json.hpp>

#include "common/memory_need.h"
#include "scene/scene_error.h"

namespace vkrt {
namespace {

constexpr const char* kMeshopt = "EXT_meshopt_compression";
constexpr const char* kDraco = "KHR_draco_mesh_compression";

// meshoptimizer's codecs decode at most 64 bytes from each compressed one (a vertex stream's bytes go in
// groups of 16 under a 2-bit header at best; a triangle takes at least 4 bits, an index sequence's index a
// byte): a larger declared size is refused before anything is allocated.
constexpr size_t kMaxMeshoptRatio = 64;
constexpr size_t kMaxDecodedBytes = size_t{1} << 32;

// The host memory decoding a Draco mesh takes, estimated from the counts its header declares: Draco's
// corner table (24 bytes a triangle), its traversal's and its symbols' buffers and the faces it decodes,
// then the indices copied here; and, a vertex, its attributes' values in Draco's form and in the accessors'.
constexpr uint64_t kDracoBytesPerTriangle = 96;
constexpr uint64_t kDracoBytesPerVertex = 64;

// The triangles and vertices a Draco mesh declares.
struct DracoCounts {
    uint64_t triangles = 0;
    uint64_t vertices = 0;
};

// The counts of the Draco mesh in `data`, read from its header the way Draco's decoders read them
// (mesh_sequential_decoder.cc and mesh_edgebreaker_decoder_impl.cc, Draco 1.5) before they allocate for
// them; none when the header does not read as a mesh's, which Draco's decoder would refuse as well.
std::optional<DracoCounts> dracoCounts(const unsigned char* data, size_t size) {
    draco::DecoderBuffer buffer;
    buffer.Init(reinterpret_cast<const char*>(data), size);
    draco::DracoHeader header;
    if (!draco::PointCloudDecoder::DecodeHeader(&buffer, &header).ok() ||
        header.encoder_type != draco::TRIANGULAR_MESH)
        return std::nullopt;
    const uint16_t version = DRACO_BITSTREAM_VERSION(header.version_major, header.version_minor);
    buffer.set_bitstream_version(version);
    if (version >= DRACO_BITSTREAM_VERSION(1, 3) && (header.flags & METADATA_FLAG_MASK)) {
        draco::GeometryMetadata metadata;
        if (!draco::MetadataDecoder().DecodeGeometryMetadata(&buffer, &metadata)) return std::nullopt;
    }
    // Each count is a varint from the version given, a 32-bit word before it.
    const auto count = [&](uint16_t varintsFrom, uint64_t& out) {
        uint32_t value = 0;
        const bool read =
            version >= varintsFrom ? draco::DecodeVarint(&value, &buffer) : buffer.Decode(&value);
        out += value;
        return read;
    };
    DracoCounts counts;
    if (header.encoder_method == draco::MESH_SEQUENTIAL_ENCODING) {
        const uint16_t varints = DRACO_BITSTREAM_VERSION(2, 2);
        if (!count(varints, counts.triangles) || !count(varints, counts.vertices)) return std::nullopt;
        return counts;
    }
    if (header.encoder_method != draco::MESH_EDGEBREAKER_ENCODING) return std::nullopt;
    // Edgebreaker: the traversal's type, before version 2.2 the vertices added at seams, the vertices, the
    // triangles.
    const uint16_t varints = DRACO_BITSTREAM_VERSION(2, 0);
    uint8_t traversal = 0;
    if (!buffer.Decode(&traversal) ||
        (version < DRACO_BITSTREAM_VERSION(2, 2) && !count(varints, counts.vertices)) ||
        !count(varints, counts.vertices) || !count(varints, counts.triangles))
        return std::nullopt;
    return counts;
}

class Decoder {
  public:
    Decoder(tinygltf::Model& model, const std::string& path, uint64_t availableBytes,
            const std::string& memorySource)
        : model_(model), path_(path), availableBytes_(availableBytes), memorySource_(memorySource) {}

    void meshoptViews() {
        for (size_t i = 0; i < model_.bufferViews.size(); ++i) {
            const auto extension = model_.bufferViews[i].extensions.find(kMeshopt);
            if (extension != model_.bufferViews[i].extensions.end()) meshoptView(i, extension->second);
        }
    }

    void dracoPrimitives() {
        for (size_t m = 0; m < model_.meshes.size(); ++m) {
            for (size_t p = 0; p < model_.meshes[m].primitives.size(); ++p) {
                tinygltf::Primitive& primitive = model_.meshes[m].primitives[p];
                const auto extension = primitive.extensions.find(kDraco);
                if (extension == primitive.extensions.end()) continue;
                dracoPrimitive(
                    primitive, extension->second,
                    "mesh " + std::to_string(m) + " primitive " + std::to_string(p) + " " + kDraco);
            }
        }
    }

  private:
    [[noreturn]] void fail(const std::string& message) const { throw SceneError(path_ + ": " + message); }

    // object[key] as a count or an index. tinygltf keeps an extension's integers as 32-bit ints, which wrap:
    // the schema check (gltf_schema.cpp) has refused, from the file's own JSON, those beyond an int's range.
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

    // A new buffer holding `data`, and a tightly packed buffer view over all of it.
    int addView(std::vector<unsigned char> data) {
        tinygltf::BufferView view;
        view.buffer = static_cast<int>(model_.buffers.size());
        view.byteOffset = 0;
        view.byteLength = data.size();
        model_.buffers.emplace_back().data = std::move(data);
        model_.bufferViews.push_back(view);
        return static_cast<int>(model_.bufferViews.size() - 1);
    }

    // Accessor `accessor` of a Draco primitive, made to read `data`; one that another primitive's data has
    // already replaced is copied first, so that each primitive keeps its own.
    int replaceAccessor(int accessor, std::vector<unsigned char> data, int componentType, size_t count,
                        const std::string& where) {
        if (accessor < 0 || accessor >= static_cast<int>(model_.accessors.size()))
            fail(where + " refers to accessor " + std::to_string(accessor) + ", which does not exist");
        if (!decodedAccessors_.insert(accessor).second) {
            model_.accessors.push_back(model_.accessors[accessor]);
            accessor = static_cast<int>(model_.accessors.size() - 1);
            decodedAccessors_.insert(accessor);
        }
        tinygltf::Accessor& target = model_.accessors[accessor];
        target.bufferView = addView(std::move(data));
        target.byteOffset = 0;
        target.componentType = componentType;
        target.count = count;
        target.sparse = {};
        return accessor;
    }

    // Every point's value of `attribute`, converted to T.
    template <typename T>
    std::vector<unsigned char> pointValues(const draco::Mesh& mesh, const draco::PointAttribute& attribute,
                                           int components, const std::string& where) const {
        std::vector<unsigned char> data(size_t{mesh.num_points()} * components * sizeof(T));
        T values[16] = {};
        for (draco::PointIndex i(0); i < mesh.num_points(); ++i) {
            if (!attribute.ConvertValue<T>(attribute.mapped_index(i), static_cast<int8_t>(components),
                                           values))
                fail(where + ": a value does not convert to the accessor's component type");
            std::memcpy(data.data() + size_t{i.value()} * components * sizeof(T), values,
                        components * sizeof(T));
        }
        return data;
    }

    // KHR_draco_mesh_compression: the primitive's indices and the attributes the extension names are decoded
    // from one buffer view; each accessor then reads its decoded values, in its own component type, and the
    // indices as 32-bit integers.
    void dracoPrimitive(tinygltf::Primitive& primitive, const tinygltf::Value& extension,
                        const std::string& where) {
        if (!extension.IsObject()) fail(where + " must be an object");
        // (The schema check has found 'attributes' an object; tinygltf leaves out one that is empty.)
        const std::vector<std::string> attributeNames =
            extension.Has("attributes") ? extension.Get("attributes").Keys() : std::vector<std::string>();
        if (primitive.mode != TINYGLTF_MODE_TRIANGLES) fail(where + ": only triangle lists are decoded");
        const size_t viewIndex = size(extension, "bufferView", where, true);
        if (viewIndex >= model_.bufferViews.size())
            fail(where + " refers to bufferView " + std::to_string(viewIndex) + ", which does not exist");
        const tinygltf::BufferView& view = model_.bufferViews[viewIndex];
        if (view.buffer < 0) fail(where + ": bufferView " + std::to_string(viewIndex) + " has no buffer");
        const unsigned char* data =
            bytes(static_cast<size_t>(view.buffer), view.byteOffset, view.byteLength, where);

        // Draco allocates for the triangles its header declares before it reads them (a 4 KB file declaring
        // 10^8 had it take 2.4 GB): they must be the ones the indices accessor counts, and fit in memory.
        const std::optional<DracoCounts> counts = dracoCounts(data, view.byteLength);
        if (!counts) fail(where + ": the compressed data does not decode (its header is not a Draco mesh's)");
        if (primitive.indices >= 0 && static_cast<size_t>(primitive.indices) < model_.accessors.size() &&
            model_.accessors[primitive.indices].count != counts->triangles * 3) {
            fail(where + ": the compressed data holds " + std::to_string(counts->triangles) +
                 " triangles, and its indices accessor declares " +
                 std::to_string(model_.accessors[primitive.indices].count) + " indices");
        }
        const uint64_t need =
            counts->triangles * kDracoBytesPerTriangle + counts->vertices * kDracoBytesPerVertex;
        if (need > availableBytes_) {
            throw MemoryError(path_ + ": " + where + ": decoding its " + std::to_string(counts->triangles) +
                              " triangles and " + std::to_string(counts->vertices) + " vertices would take " +
                              formatBytes(need) + " of host memory, and " + formatBytes(availableBytes_) +
                              " is available (" + memorySource_ + ")");
        }

        draco::DecoderBuffer buffer;
        buffer.Init(reinterpret_cast<const char*>(data), view.byteLength);
        draco::Decoder decoder;
        auto decoded = decoder.DecodeMeshFromBuffer(&buffer);
        if (!decoded.ok())
            fail(where + ": the compressed data does not decode (" + decoded.status().error_msg_string() +
                 ")");
        const std::unique_ptr<draco::Mesh> mesh = std::move(decoded).value();

        std::vector<unsigned char> indices(size_t{mesh->num_faces()} * 3 * sizeof(uint32_t));
        for (draco::FaceIndex f(0); f < mesh->num_faces(); ++f) {
            const draco::Mesh::Face& face = mesh->face(f);
            const uint32_t corners[3] = {face[0].value(), face[1].value(), face[2].value()};
            std::memcpy(indices.data() + size_t{f.value()} * sizeof(corners), corners, sizeof(corners));
        }
        if (primitive.indices < 0) {  // the decoded mesh is indexed whether or not the primitive was
            tinygltf::Accessor created;
            created.type = TINYGLTF_TYPE_SCALAR;
            model_.accessors.push_back(created);
            primitive.indices = static_cast<int>(model_.accessors.size() - 1);
        }
        primitive.indices =
            replaceAccessor(primitive.indices, std::move(indices), TINYGLTF_COMPONENT_TYPE_UNSIGNED_INT,
                            size_t{mesh->num_faces()} * 3, where + " indices");

        const tinygltf::Value& attributes = extension.Get("attributes");
        for (const std::string& name : attributeNames) {
            const std::string attributeWhere = where + " " + name;
            const auto slot = primitive.attributes.find(name);
            if (slot == primitive.attributes.end())
                fail(attributeWhere + ": the primitive has no such attribute");
            const size_t id = size(attributes, name.c_str(), attributeWhere, true);
            const draco::PointAttribute* attribute =
                id <= std::numeric_limits<uint32_t>::max()
                    ? mesh->GetAttributeByUniqueId(static_cast<uint32_t>(id))
                    : nullptr;
            if (attribute == nullptr)
                fail(attributeWhere + ": the compressed mesh has no attribute " + std::to_string(id));
            if (slot->second < 0 || slot->second >= static_cast<int>(model_.accessors.size()))
                fail(attributeWhere + " refers to accessor " + std::to_string(slot->second) +
                     ", which does not exist");
            const tinygltf::Accessor& accessor = model_.accessors[slot->second];
            const int components = tinygltf::GetNumComponentsInType(static_cast<uint32_t>(accessor.type));
            if (components < 1 || components > 16 || components != attribute->num_components()) {
                fail(attributeWhere + ": the accessor has " + std::to_string(components) +
                     " components, the compressed data " + std::to_string(attribute->num_components()));
            }
            std::vector<unsigned char> values;
            switch (accessor.componentType) {
                case TINYGLTF_COMPONENT_TYPE_FLOAT:
                    values = pointValues<float>(*mesh, *attribute, components, attributeWhere);
                    break;
                case TINYGLTF_COMPONENT_TYPE_BYTE:
                    values = pointValues<int8_t>(*mesh, *attribute, components, attributeWhere);
                    break;
                case TINYGLTF_COMPONENT_TYPE_UNSIGNED_BYTE:
                    values = pointValues<uint8_t>(*mesh, *attribute, components, attributeWhere);
                    break;
                case TINYGLTF_COMPONENT_TYPE_SHORT:
                    values = pointValues<int16_t>(*mesh, *attribute, components, attributeWhere);
                    break;
                case TINYGLTF_COMPONENT_TYPE_UNSIGNED_SHORT:
                    values = pointValues<uint16_t>(*mesh, *attribute, components, attributeWhere);
                    break;
                default:
                    fail(attributeWhere + ": component type " + std::to_string(accessor.componentType) +
                         " is not an attribute's");
            }
            slot->second = replaceAccessor(slot->second, std::move(values), accessor.componentType,
                                           mesh->num_points(), attributeWhere);
        }
    }

    tinygltf::Model& model_;
    const std::string& path_;
    uint64_t availableBytes_;          // the host memory a Draco mesh's decoding may take
    const std::string& memorySource_;  // where that figure comes from, for the error
    std::set<int> decodedAccessors_;  // accessors a Draco primitive's data has replaced
};

}  // namespace

bool stubCompressedData(nlohmann::json& document) {
    if (!document.is_object()) return false;
    auto extensionOf = [](const nlohmann::json& object, const char* name) -> const nlohmann::json* {
        if (!object.is_object() || !object.contains("extensions") || !object["extensions"].is_object())
            return nullptr;
        const nlohmann::json& extensions = object["extensions"];
        return extensions.contains(name) && extensions[name].is_object() ? &extensions[name] : nullptr;
    };
    // (The schema check, gltf_schema.cpp, has checked the types and indices read here.) tinygltf reads images
    // from their views when it loads the file, before any view is decoded: a fallback buffer an image's view
    // is in stays as it is, and tinygltf says what it lacks.
    std::set<size_t> imageBuffers;
    if (document.contains("images") && document.contains("bufferViews")) {
        for (const nlohmann::json& image : document["images"]) {
            if (image.contains("bufferView"))
                imageBuffers.insert(
                    document["bufferViews"][image["bufferView"].get<size_t>()]["buffer"].get<size_t>());
        }
    }
    bool changed = false;
    if (document.contains("buffers") && document["buffers"].is_array()) {
        for (size_t b = 0; b < document["buffers"].size(); ++b) {
            nlohmann::json& buffer = document["buffers"][b];
            if (imageBuffers.count(b)) continue;
            const nlohmann::json* extension = extensionOf(buffer, kMeshopt);
            if (extension == nullptr || !extension->contains("fallback") || (*extension)["fallback"] != true)
                continue;
            buffer["uri"] = "data:application/octet-stream;base64,AA==";
            buffer["byteLength"] = 1;
            changed = true;
        }
    }
    // A Draco primitive's index accessor has no bufferView, which tinygltf requires: it is given the
    // compressed one, and decompressMeshes replaces it.
    auto arrayAt = [](const nlohmann::json& object, const char* key) -> const nlohmann::json* {
        return object.is_object() && object.contains(key) && object[key].is_array() ? &object[key] : nullptr;
    };
    const nlohmann::json* meshes = arrayAt(document, "meshes");
    if (meshes != nullptr && arrayAt(document, "accessors") != nullptr) {
        nlohmann::json& accessors = document["accessors"];
        for (const nlohmann::json& mesh : *meshes) {
            const nlohmann::json* primitives = arrayAt(mesh, "primitives");
            for (size_t p = 0; primitives != nullptr && p < primitives->size(); ++p) {
                const nlohmann::json& primitive = (*primitives)[p];
                const nlohmann::json* extension = extensionOf(primitive, kDraco);
                if (extension == nullptr || !extension->contains("bufferView") ||
                    !primitive.contains("indices") || !primitive["indices"].is_number_unsigned() ||
                    primitive["indices"].get<size_t>() >= accessors.size())
                    continue;
                nlohmann::json& indices = accessors[primitive["indices"].get<size_t>()];
                if (!indices.is_object() || indices.contains("bufferView")) continue;
                indices["bufferView"] = (*extension)["bufferView"];
                changed = true;
            }
        }
    }
    return changed;
}

void decompressMeshes(tinygltf::Model& model, const std::string& path, uint64_t availableBytes,
                      const std::string& memorySource) {
    Decoder decoder(model, path, availableBytes, memorySource);
    decoder.meshoptViews();
    decoder.dracoPrimitives();
}

}  // namespace vkrt
