// Writes a glTF scene again as a GLB with its meshes compressed by Draco (KHR_draco_mesh_compression) or its
// images as lossless WebP (EXT_texture_webp): how the scenes that show vkrt's decoding of both are made:
//
//   build/pack_scene --draco scenes/cornell.gltf scenes/cornell-draco.glb
//   build/pack_scene --webp scenes/textures.gltf scenes/textures-webp.glb
//
// Draco: positions are quantized to 14 bits and normals to 10, as glTF exporters do by default; the input's
// meshes may have float POSITION and NORMAL and integer indices, and nothing else may use its buffers (no
// textures, animations or skins). WebP: every image, decoded, is encoded again losslessly, and every texture
// shows it through the extension alone (no fallback); the input has one buffer. Anything else is refused.
#include <cstdio>
#include <cstring>
#include <fstream>
#include <iterator>
#include <stdexcept>
#include <string>
#include <vector>

#include <draco/compression/encode.h>
#include <draco/mesh/mesh.h>
#include <nlohmann/json.hpp>
#include <tiny_gltf.h>
#include <webp/encode.h>

#include "command_line.h"
#include "common/atomic_file.h"
#include "scene/gltf_schema.h"

namespace {

// The `components` floats (or, for indices, integers) per element of accessor `index`.
std::vector<double> readAccessor(const tinygltf::Model& model, int index, int components) {
    if (index < 0 || index >= static_cast<int>(model.accessors.size()))
        throw std::runtime_error("no accessor");
    const tinygltf::Accessor& accessor = model.accessors[index];
    if (accessor.sparse.isSparse || accessor.bufferView < 0) throw std::runtime_error("a sparse accessor");
    const tinygltf::BufferView& view = model.bufferViews[accessor.bufferView];
    const int size = tinygltf::GetComponentSizeInBytes(static_cast<uint32_t>(accessor.componentType));
    const size_t stride = view.byteStride != 0 ? view.byteStride : static_cast<size_t>(size) * components;
    const std::vector<unsigned char>& data = model.buffers[view.buffer].data;
    std::vector<double> values;
    for (size_t i = 0; i < accessor.count; ++i) {
        for (int c = 0; c < components; ++c) {
            const size_t at =
                view.byteOffset + accessor.byteOffset + i * stride + static_cast<size_t>(c) * size;
            if (at + size > data.size()) throw std::runtime_error("an accessor outside its buffer");
            const unsigned char* p = data.data() + at;
            switch (accessor.componentType) {
                case TINYGLTF_COMPONENT_TYPE_FLOAT: {
                    float v;
                    std::memcpy(&v, p, 4);
                    values.push_back(v);
                    break;
                }
                case TINYGLTF_COMPONENT_TYPE_UNSIGNED_INT: {
                    uint32_t v;
                    std::memcpy(&v, p, 4);
                    values.push_back(v);
                    break;
                }
                case TINYGLTF_COMPONENT_TYPE_UNSIGNED_SHORT: {
                    uint16_t v;
                    std::memcpy(&v, p, 2);
                    values.push_back(v);
                    break;
                }
                case TINYGLTF_COMPONENT_TYPE_UNSIGNED_BYTE:
                    values.push_back(p[0]);
                    break;
                default:
                    throw std::runtime_error("an accessor that is neither float nor unsigned integers");
            }
        }
    }
    return values;
}

// Adds a float attribute of `components` values per point to `mesh`; returns its index.
int addAttribute(draco::Mesh& mesh, draco::GeometryAttribute::Type type, const std::vector<double>& values,
                 int components) {
    draco::GeometryAttribute attribute;
    attribute.Init(type, nullptr, static_cast<int8_t>(components), draco::DT_FLOAT32, false,
                   sizeof(float) * components, 0);
    const int index = mesh.AddAttribute(attribute, true, mesh.num_points());
    for (uint32_t i = 0; i < mesh.num_points(); ++i) {
        float value[4] = {};
        for (int c = 0; c < components; ++c) value[c] = static_cast<float>(values[i * components + c]);
        mesh.attribute(index)->SetAttributeValue(draco::AttributeValueIndex(i), value);
    }
    return index;
}

// Compresses `model`'s meshes (tinygltf's reading of the file) into `document` (the file's own JSON, which
// keeps everything else as it was); returns the binary chunk.
std::string dracoMeshes(const tinygltf::Model& model, nlohmann::json& document) {
    if (!model.images.empty() || !model.animations.empty() || !model.skins.empty())
        throw std::runtime_error("images, animations or skins use the buffers");
    std::string compressed;
    nlohmann::json views = nlohmann::json::array();
    std::vector<bool> meshAccessor(model.accessors.size(), false);
    for (size_t m = 0; m < model.meshes.size(); ++m) {
        for (size_t p = 0; p < model.meshes[m].primitives.size(); ++p) {
            const tinygltf::Primitive& primitive = model.meshes[m].primitives[p];
            if (primitive.mode != TINYGLTF_MODE_TRIANGLES || primitive.indices < 0 ||
                !primitive.targets.empty())
                throw std::runtime_error("a primitive that is not an indexed triangle list");
            const auto position = primitive.attributes.find("POSITION");
            if (position == primitive.attributes.end())
                throw std::runtime_error("a primitive without POSITION");
            for (const auto& [name, accessor] : primitive.attributes) {
                if (name != "POSITION" && name != "NORMAL") throw std::runtime_error("attribute " + name);
            }
            const std::vector<double> positions = readAccessor(model, position->second, 3);
            const std::vector<double> indices = readAccessor(model, primitive.indices, 1);
            draco::Mesh encoded;
            encoded.set_num_points(static_cast<uint32_t>(positions.size() / 3));
            nlohmann::json attributes;
            const int positionAttribute =
                addAttribute(encoded, draco::GeometryAttribute::POSITION, positions, 3);
            attributes["POSITION"] = encoded.attribute(positionAttribute)->unique_id();
            const auto normal = primitive.attributes.find("NORMAL");
            if (normal != primitive.attributes.end()) {
                const int normalAttribute = addAttribute(encoded, draco::GeometryAttribute::NORMAL,
                                                         readAccessor(model, normal->second, 3), 3);
                attributes["NORMAL"] = encoded.attribute(normalAttribute)->unique_id();
            }
            for (size_t i = 0; i + 2 < indices.size(); i += 3) {
                encoded.AddFace({draco::PointIndex(static_cast<uint32_t>(indices[i])),
                                 draco::PointIndex(static_cast<uint32_t>(indices[i + 1])),
                                 draco::PointIndex(static_cast<uint32_t>(indices[i + 2]))});
            }
            draco::Encoder encoder;
            encoder.SetAttributeQuantization(draco::GeometryAttribute::POSITION, 14);
            encoder.SetAttributeQuantization(draco::GeometryAttribute::NORMAL, 10);
            draco::EncoderBuffer buffer;
            const draco::Status status = encoder.EncodeMeshToBuffer(encoded, &buffer);
            if (!status.ok()) throw std::runtime_error("Draco: " + status.error_msg_string());

            views.push_back(
                {{"buffer", 0}, {"byteOffset", compressed.size()}, {"byteLength", buffer.size()}});
            compressed.append(buffer.data(), buffer.size());
            compressed.resize((compressed.size() + 3) / 4 * 4, '\0');
            // The accessors keep their types, counts and bounds; their data is in the compressed view.
            std::vector<int> used = {primitive.indices};
            for (const auto& [name, accessor] : primitive.attributes) used.push_back(accessor);
            for (const int accessor : used) {
                document["accessors"][accessor].erase("bufferView");
                document["accessors"][accessor].erase("byteOffset");
                meshAccessor[accessor] = true;
            }
            document["meshes"][m]["primitives"][p]["extensions"]["KHR_draco_mesh_compression"] = {
                {"bufferView", views.size() - 1}, {"attributes", attributes}};
        }
    }
    for (size_t a = 0; a < meshAccessor.size(); ++a) {
        if (!meshAccessor[a]) throw std::runtime_error("accessor " + std::to_string(a) + " is no mesh's");
    }
    document["bufferViews"] = views;
    document["buffers"] = {{{"byteLength", compressed.size()}}};
    for (const char* list : {"extensionsUsed", "extensionsRequired"})
        document[list].push_back("KHR_draco_mesh_compression");
    return compressed;
}

// Re-encodes `model`'s images (tinygltf's decoding of the file) as lossless WebP into `document` (the file's
// own JSON); returns the binary chunk: the file's one buffer, then the WebP images.
std::string webpImages(const tinygltf::Model& model, nlohmann::json& document) {
    if (model.buffers.size() != 1) throw std::runtime_error("the file has more buffers than one");
    std::string bin(model.buffers[0].data.begin(), model.buffers[0].data.end());
    bin.resize((bin.size() + 3) / 4 * 4, '\0');
    for (size_t i = 0; i < model.images.size(); ++i) {
        const tinygltf::Image& image = model.images[i];
        if (image.bits != 8 || image.component < 1 || image.component > 4 || image.image.empty())
            throw std::runtime_error("image " + std::to_string(i) + " is not 8-bit");
        std::vector<uint8_t> rgba;
        for (size_t p = 0; p < size_t(image.width) * image.height; ++p) {
            const uint8_t* texel = &image.image[p * image.component];
            const bool grey = image.component <= 2;
            rgba.insert(rgba.end(), {texel[0], grey ? texel[0] : texel[1], grey ? texel[0] : texel[2],
                                     image.component == 2   ? texel[1]
                                     : image.component == 4 ? texel[3]
                                                            : uint8_t(255)});
        }
        uint8_t* encoded = nullptr;
        const size_t size =
            WebPEncodeLosslessRGBA(rgba.data(), image.width, image.height, image.width * 4, &encoded);
        if (size == 0) throw std::runtime_error("libwebp cannot encode image " + std::to_string(i));
        document["bufferViews"].push_back({{"buffer", 0}, {"byteOffset", bin.size()}, {"byteLength", size}});
        bin.append(reinterpret_cast<const char*>(encoded), size);
        bin.resize((bin.size() + 3) / 4 * 4, '\0');
        WebPFree(encoded);
        nlohmann::json& entry = document["images"][i];
        entry.erase("uri");
        entry["bufferView"] = document["bufferViews"].size() - 1;
        entry["mimeType"] = "image/webp";
    }
    for (nlohmann::json& texture : document["textures"]) {
        if (!texture.contains("source")) continue;
        texture["extensions"]["EXT_texture_webp"] = {{"source", texture["source"]}};
        texture.erase("source");
    }
    document["buffers"] = {{{"byteLength", bin.size()}}};
    for (const char* list : {"extensionsUsed", "extensionsRequired"})
        document[list].push_back("EXT_texture_webp");
    return bin;
}

}  // namespace

int main(int argc, char** argv) {
    CLI::App app{
        "Writes a glTF scene as a GLB with its meshes Draco-compressed (KHR_draco_mesh_compression) or "
        "its images as WebP (EXT_texture_webp).",
        "pack_scene"};
    bool draco = false, webp = false;
    std::string input, output;
    CLI::Option* dracoFlag = app.add_flag("--draco", draco, "compress every mesh with Draco");
    app.add_flag("--webp", webp, "re-encode every image as lossless WebP")->excludes(dracoFlag);
    app.add_option("input", input, "the glTF scene (.gltf)")->required()->check(CLI::ExistingFile);
    app.add_option("output", output, "the GLB to write")->required();
    if (const std::optional<int> exitCode = vkrt::parseCommandLine(app, argc, argv)) return *exitCode;
    if (draco == webp) {
        std::fprintf(stderr, "pack_scene: error: give --draco or --webp (see --help)\n");
        return 2;
    }
    tinygltf::TinyGLTF gltf;
    tinygltf::Model model;
    std::string error, warning;
    if (!gltf.LoadASCIIFromFile(&model, &error, &warning, input)) {
        std::fprintf(stderr, "pack_scene: error: %s: %s\n", input.c_str(), error.c_str());
        return 2;
    }
    try {
        std::ifstream in(input);
        nlohmann::json document = nlohmann::json::parse(std::string(std::istreambuf_iterator<char>(in), {}));
        const std::string bin = draco ? dracoMeshes(model, document) : webpImages(model, document);
        vkrt::writeFileAtomically(output, [&](const std::string& temporary) {
            std::ofstream out(temporary, std::ios::binary);
            out << vkrt::glbFile(document.dump(), bin);
            if (!out) throw std::runtime_error("cannot write " + output);
        });
    } catch (const std::exception& e) {
        std::fprintf(stderr, "pack_scene: error: %s: %s\n", input.c_str(), e.what());
        return 2;
    }
    return 0;
}
