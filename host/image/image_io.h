// Writing and reading images. PNG is tonemapped 8-bit sRGB; EXR (tinyexr) and PFM are linear floats.
// Writers go through a temporary file in the same folder and rename it into place, so a failed or
// interrupted run never leaves a partial image behind.
#pragma once

#include <cstdint>
#include <stdexcept>
#include <string>

#include "image/image.h"
#include "image/tone_map.h"

namespace vkrt {

class FileBatch;

class ImageError : public std::runtime_error {
  public:
    using std::runtime_error::runtime_error;
};

enum class ImageFormat { Png, Exr, Pfm };

// The format named by the file's extension; throws ImageError for anything else.
ImageFormat imageFormatFromPath(const std::string& path);

// `exposure` (in stops) and `toneMap` apply to PNG only; linear formats store the radiance as rendered.
void writeImage(const Image& image, const std::string& path, double exposure = 0.0,
                ToneMap toneMap = ToneMap::Clamp);

// The same, written under a temporary name that `batch` renames into place with the files written beside it.
void stageImage(FileBatch& batch, const Image& image, const std::string& path, double exposure,
                ToneMap toneMap);

// Reads PFM and EXR (for references and tests). Throws MemoryError, before decoding, when an EXR's decoding
// would take more than `maxBytes` (its header can claim a display window of billions of pixels).
Image readImage(const std::string& path, uint64_t maxBytes = UINT64_MAX);

// Reads a linear radiance map for lighting: Radiance .hdr (stb_image) or OpenEXR (tinyexr). Throws
// ImageError naming the file for any other extension or an unreadable file, and MemoryError, before decoding,
// when decoding the size its header gives would take more than `maxBytes` (a few hundred bytes of
// run-length or compressed data can claim a map of gigabytes).
Image readRadianceImage(const std::string& path, uint64_t maxBytes = UINT64_MAX);

// A display value in [0, 1] to an 8-bit sRGB value (the sRGB transfer curve).
unsigned char toSrgb8(double display);

}  // namespace vkrt
