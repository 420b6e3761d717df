#include "scene/gltf_images.h"

#include <cstring>

#include <tiny_gltf.h>
#include <webp/decode.h>

#include "scene/gltf_context.h"

namespace vkrt {

bool loadGltfImage(tinygltf::Image* image, int imageIndex, std::string* /*error*/, std::string* warning,
                   int requiredWidth, int requiredHeight, const unsigned char* bytes, int size,
                   void* userData) {
    ImageFailures& failures = *static_cast<ImageFailures*>(userData);
    // A WebP file is a RIFF container of type WEBP.
    const bool webp =
        size >= 12 && std::memcmp(bytes, "RIFF", 4) == 0 && std::memcmp(bytes + 8, "WEBP", 4) == 0;
    if (!webp) {
        std::string decodeError;
        if (tinygltf::LoadImageData(image, imageIndex, &decodeError, warning, requiredWidth, requiredHeight,
                                    bytes, size, nullptr)) {
            return true;
        }
        image->image.clear();
        failures[imageIndex] =
            "it is not an image vkrt can decode (PNG, JPEG, BMP, TGA, GIF, HDR, PNM or WebP)";
        return true;
    }
    int width = 0, height = 0;
    uint8_t* rgba = WebPDecodeRGBA(bytes, static_cast<size_t>(size), &width, &height);
    if (rgba == nullptr || width <= 0 || height <= 0) {
        WebPFree(rgba);
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
