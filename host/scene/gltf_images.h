// Images of a glTF file: tinygltf's decoder (stb_image: PNG, JPEG and the rest) and, for EXT_texture_webp,
// libwebp; and which image a texture shows.
#pragma once

#include <cstdint>
#include <map>
#include <optional>
#include <set>
#include <string>

#include <nlohmann/json.hpp>

namespace tinygltf {
class Model;
struct Image;
struct Texture;
}  // namespace tinygltf

namespace vkrt {

// Why images could not be decoded, by image index.
using ImageFailures = std::map<int, std::string>;

// What loadGltfImage is given and keeps, its `userData`: the images that the textures vkrt reads show (the
// others are not decoded: they would only take memory; every image when unknown), the host memory the decoded
// images may take, and why images could not be decoded.
struct ImageDecoding {
    std::optional<std::set<int>> shown;
    uint64_t maxBytes = UINT64_MAX;
    std::string memorySource = "unlimited";
    uint64_t decodedBytes = 0;
    ImageFailures failures;
};

// The images that the textures a material slot vkrt reads names show (imageSource of each), read from a glTF
// document's JSON for `materials` (every material when nullopt): a texture no such slot names is not decoded.
std::set<int> shownImages(const nlohmann::json& document, const std::optional<std::set<int>>& materials);

// tinygltf's image loader (TinyGLTF::SetImageLoader): WebP data by libwebp, as 8-bit RGBA, anything else by
// tinygltf's own loader. The size an image would take decoded is read from its header first and counted
// against the memory `userData` (an ImageDecoding) allows: a file of a few megabytes can claim billions of
// pixels (three 16384 x 16384 PNGs took 6.3 GB before --max-memory 1GiB refused them). An image that does not
// decode, or would not fit, is left empty and its reason recorded: only a texture vkrt reads fails for it,
// not an image behind an extension's fallback (a KHR_texture_basisu texture's KTX2 image) or one that no
// texture uses.
bool loadGltfImage(tinygltf::Image* image, int imageIndex, std::string* error, std::string* warning,
                   int requiredWidth, int requiredHeight, const unsigned char* bytes, int size,
                   void* userData);

// Whether loadGltfImage decoded `image` to pixels vkrt reads: 1 to 4 channels of 8 or 16 bits.
bool holdsPixels(const tinygltf::Image& image);

// Gives images whose data URI has a media type tinygltf does not know (image/webp, image/ktx2) the type
// application/octet-stream, which it decodes (and then loadGltfImage reads the bytes for what they are); true
// when the document changed.
bool retypeImageDataUris(nlohmann::json& document);

// An image as messages name it: "image i ('file.png')", a data URI cut short.
std::string describeImage(const tinygltf::Model& model, int imageIndex);

// The image texture `texture` shows: EXT_texture_webp's source where the texture has one, else its own (the
// extension's `source` is the WebP image, the core one a fallback for viewers without it). -1 for none.
int imageSource(const tinygltf::Texture& texture);

}  // namespace vkrt
