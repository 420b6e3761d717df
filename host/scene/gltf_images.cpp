#include "scene/gltf_images.h"

#include <algorithm>
#include <cstring>

#include <stb_image.h>
#include <tiny_gltf.h>
#include <webp/decode.h>

#include "common/memory_need.h"
#include "scene/gltf_context.h"
#include "scene/gltf_texture_slots.h"

namespace vkrt {

std::set<int> shownImages(const nlohmann::json& document, const std::optional<std::set<int>>& materials) {
    std::set<int> shown;
    if (!document.is_object() || !document.contains("textures") || !document["textures"].is_array())
        return shown;
    const nlohmann::json& textures = document["textures"];
    for (const int index : texturesReadByMaterials(document, materials)) {
        if (index < 0 || static_cast<size_t>(index) >= textures.size()) continue;
        const nlohmann::json& texture = textures[static_cast<size_t>(index)];
        if (!texture.is_object()) continue;
        const nlohmann::json* source = texture.contains("source") ? &texture["source"] : nullptr;
        if (texture.contains("extensions") && texture["extensions"].is_object() &&
            texture["extensions"].contains("EXT_texture_webp")) {
            const nlohmann::json& webp = texture["extensions"]["EXT_texture_webp"];
            if (webp.is_object() && webp.contains("source") && webp["source"].is_number_integer())
                source = &webp["source"];
        }
        if (source != nullptr && source->is_number_integer()) shown.insert(source->get<int>());
    }
    return shown;
}

bool loadGltfImage(tinygltf::Image* image, int imageIndex, std::string* /*error*/, std::string* warning,
                   int requiredWidth, int requiredHeight, const unsigned char* bytes, int size,
                   void* userData) {
    ImageDecoding& decoding = *static_cast<ImageDecoding*>(userData);
    ImageFailures& failures = decoding.failures;
    if (decoding.shown && decoding.shown->count(imageIndex) == 0) {
        image->image.clear();  // no texture shows it
        return true;
    }
    // Radiance HDR data is refused undecoded: glTF textures are PNG or JPEG (WebP and KTX2 by extension), and
    // stb_image, which would decode it, loops forever on a run-length encoded scanline cut short or holding a
    // run of length 0. vkrt reads HDR maps as --environment, through a reader that checks every run.
    if (stbi_is_hdr_from_memory(bytes, size)) {
        image->image.clear();
        failures[imageIndex] =
            "it holds Radiance HDR data, which a glTF texture cannot hold (vkrt reads HDR maps as "
            "--environment)";
        return true;
    }
    // A WebP file is a RIFF container of type WEBP.
    const bool webp =
        size >= 12 && std::memcmp(bytes, "RIFF", 4) == 0 && std::memcmp(bytes + 8, "WEBP", 4) == 0;
    // The size it would take: the decoder's pixels (4 channels, 8 or 16 bits) and the texture made of them.
    int width = 0, height = 0, channels = 0;
    const bool known = webp ? WebPGetInfo(bytes, static_cast<size_t>(size), &width, &height) != 0
                            : stbi_info_from_memory(bytes, size, &width, &height, &channels) != 0;
    // Sides beyond stb_image's limit (2^24) it refuses to decode, as it does sizes its header reader does not
    // check (a BMP's 31-bit sides); counted, their product could wrap.
    constexpr int kLongestSide = 1 << 24;
    uint64_t counted = 0;
    if (known && width > 0 && height > 0 && width <= kLongestSide && height <= kLongestSide) {
        const uint64_t bytesPerChannel = !webp && stbi_is_16_bit_from_memory(bytes, size) ? 2 : 1;
        const uint64_t need =
            static_cast<uint64_t>(width) * static_cast<uint64_t>(height) * 4 * (bytesPerChannel + 1);
        if (need > decoding.maxBytes - std::min(decoding.maxBytes, decoding.decodedBytes)) {
            image->image.clear();
            failures[imageIndex] = "its " + std::to_string(width) + " x " + std::to_string(height) +
                                   " pixels would take " + formatBytes(need) + " of host memory beside " +
                                   formatBytes(decoding.decodedBytes) + " of other images, and " +
                                   formatBytes(decoding.maxBytes) + " is available (" +
                                   decoding.memorySource + ")";
            return true;
        }
        counted = need;
        decoding.decodedBytes += need;
    }
    if (!webp) {
        std::string decodeError;
        if (tinygltf::LoadImageData(image, imageIndex, &decodeError, warning, requiredWidth, requiredHeight,
                                    bytes, size, nullptr)) {
            return true;
        }
        decoding.decodedBytes -= counted;  // an image that does not decode takes nothing
        image->image.clear();
        failures[imageIndex] = "it is not an image vkrt can decode (PNG, JPEG, BMP, TGA, GIF, PNM or WebP)";
        return true;
    }
    width = height = 0;
    uint8_t* rgba = WebPDecodeRGBA(bytes, static_cast<size_t>(size), &width, &height);
    if (rgba == nullptr || width <= 0 || height <= 0) {
        WebPFree(rgba);
        decoding.decodedBytes -= counted;
        image->image.clear();
        failures[imageIndex] = "it is not a WebP image libwebp can decode";
        return true;
    }
    image->width = width;
    image->height = height;
    image->component = 4;
    image->bits = 8;
    image->pixel_type = TINYGLTF_COMPONENT_TYPE_UNSIGNED_BYTE;
    image->image.assign(rgba, rgba + static_cast<size_t>(width) * height * 4);
    WebPFree(rgba);
    return true;
}

bool holdsPixels(const tinygltf::Image& image) {
    return !image.image.empty() && image.width > 0 && image.height > 0 && image.component >= 1 &&
           image.component <= 4 && (image.bits == 8 || image.bits == 16);
}

bool retypeImageDataUris(nlohmann::json& document) {
    if (!document.is_object() || !document.contains("images") || !document["images"].is_array()) return false;
    static const char* const kKnown[] = {"data:application/octet-stream;base64,",
                                         "data:image/jpeg;base64,",
                                         "data:image/png;base64,",
                                         "data:image/bmp;base64,",
                                         "data:image/gif;base64,",
                                         "data:text/plain;base64,",
                                         "data:application/gltf-buffer;base64,"};
    bool changed = false;
    for (nlohmann::json& image : document["images"]) {
        if (!image.is_object() || !image.contains("uri") || !image["uri"].is_string()) continue;
        std::string& uri = image["uri"].get_ref<std::string&>();
        if (uri.rfind("data:", 0) != 0) continue;
        bool known = false;
        for (const char* prefix : kKnown) known |= uri.rfind(prefix, 0) == 0;
        const size_t base64 = uri.find(";base64,");
        if (known || base64 == std::string::npos) continue;
        uri = "data:application/octet-stream" + uri.substr(base64);
        changed = true;
    }
    return changed;
}

std::string describeImage(const tinygltf::Model& model, int imageIndex) {
    if (imageIndex < 0 || imageIndex >= static_cast<int>(model.images.size()))
        return "image " + std::to_string(imageIndex);
    const tinygltf::Image& image = model.images[static_cast<size_t>(imageIndex)];
    if (image.uri.rfind("data:", 0) == 0) {
        const std::string embedded = "image " + std::to_string(imageIndex) + " (a data URI)";
        return image.name.empty() ? embedded : embedded + " ('" + image.name + "')";
    }
    return describe("image", imageIndex, image.uri.empty() ? image.name : image.uri);
}

int imageSource(const tinygltf::Texture& texture) {
    const auto webp = texture.extensions.find("EXT_texture_webp");
    if (webp != texture.extensions.end() && webp->second.IsObject() && webp->second.Has("source") &&
        webp->second.Get("source").IsInt()) {
        return webp->second.Get("source").GetNumberAsInt();
    }
    return texture.source;
}

}  // namespace vkrt
