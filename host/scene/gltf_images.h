// Images of a glTF file: tinygltf's decoder (stb_image: PNG, JPEG and the rest) and, for EXT_texture_webp,
// libwebp; and which image a texture shows.
#pragma once

#include <string>

namespace tinygltf {
class Model;
struct Image;
struct Texture;
}  // namespace tinygltf

namespace vkrt {

// tinygltf's image loader (TinyGLTF::SetImageLoader): WebP data by libwebp, as 8-bit RGBA, anything else by
// tinygltf's own loader.
bool loadGltfImage(tinygltf::Image* image, int imageIndex, std::string* error, std::string* warning,
                   int requiredWidth, int requiredHeight, const unsigned char* bytes, int size,
                   void* userData);

// The image texture `texture` shows: EXT_texture_webp's source where the texture has one, else its own (the
// extension's `source` is the WebP image, the core one a fallback for viewers without it). -1 for none.
int imageSource(const tinygltf::Texture& texture);

}  // namespace vkrt
