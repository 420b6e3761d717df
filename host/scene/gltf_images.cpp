#include "scene/gltf_images.h"

#include <cstring>

#include <tiny_gltf.h>
#include <webp/decode.h>

namespace vkrt {

bool loadGltfImage(tinygltf::Image* image, int imageIndex, std::string* error, std::string* warning,
                   int requiredWidth, int requiredHeight, const unsigned char* bytes, int size,
                   void* userData) {
    // A WebP file is a RIFF container of type WEBP.
    const bool webp =
        size >= 12 && std::memcmp(bytes, "RIFF", 4) == 0 && std::memcmp(bytes + 8, "WEBP", 4) == 0;
    if (!webp) {
        std::string decodeError;
        if (tinygltf::LoadImageData(image, imageIndex, &decodeError, warning, requiredWidth, requiredHeight,
                                    bytes, size, userData)) {
            return true;
        }
        // tinygltf's message names neither the file nor what it could be: say both.
        if (error) {
            *error += "image " + std::to_string(imageIndex) +
                      (image->uri.empty() ? std::string(" (embedded)") : " ('" + image->uri + "')") +
                      " is not an image vkrt can decode (PNG, JPEG, BMP, TGA, GIF, HDR, PNM or WebP). ";
        }
        return false;
    }
    int width = 0, height = 0;
    uint8_t* rgba = WebPDecodeRGBA(bytes, static_cast<size_t>(size), &width, &height);
    if (rgba == nullptr || width <= 0 || height <= 0) {
        WebPFree(rgba);
        if (error)
            *error += "image " + std::to_string(imageIndex) + " is not a WebP image libwebp can decode. ";
        return false;
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

int imageSource(const tinygltf::Texture& texture) {
    const auto webp = texture.extensions.find("EXT_texture_webp");
    if (webp != texture.extensions.end() && webp->second.IsObject() && webp->second.Has("source") &&
        webp->second.Get("source").IsInt()) {
        return webp->second.Get("source").GetNumberAsInt();
    }
    return texture.source;
}

}  // namespace vkrt
