#include "image/image_io.h"

#include <algorithm>
#include <bit>
#include <cctype>
#include <cmath>
#include <cstdint>
#include <cstdio>
#include <cstdlib>
#include <cstring>
#include <filesystem>
#include <fstream>
#include <iterator>
#include <memory>
#include <string>
#include <vector>

#include <stb_image.h>
#include <stb_image_write.h>
#include <tinyexr.h>

#include "common/atomic_file.h"
#include "common/file_names.h"
#include "common/memory_need.h"

namespace vkrt {
namespace {

// Writes `size` bytes to `path`, checking the closing too: some file systems (NFS, quotas, a full disk)
// report a failed write only when the last buffered bytes go out.
void writeBytes(const std::string& path, const char* data, size_t size) {
    std::ofstream file(path, std::ios::binary);
    if (!file) throw ImageError(path + ": cannot open for writing");
    file.write(data, static_cast<std::streamsize>(size));
    file.close();
    if (file.fail()) throw ImageError(cannotWrite(path));
}

void writePng(const Image& image, const std::string& path, double exposure, ToneMap toneMapping) {
    std::vector<unsigned char> bytes(static_cast<size_t>(image.width) * image.height * 3);
    for (size_t i = 0; i < image.pixels.size(); ++i) {
        const glm::dvec3 display = toneMap(glm::dvec3(image.pixels[i]), toneMapping, exposure);
        for (int c = 0; c < 3; ++c) bytes[3 * i + c] = toSrgb8(display[c]);
    }
    // Encoded in memory, then written and checked: stbi_write_png ignores failed writes (a full disk left a
    // cut-off PNG behind, reported as written).
    std::string encoded;
    const auto append = [](void* context, void* data, int size) {
        static_cast<std::string*>(context)->append(static_cast<const char*>(data), static_cast<size_t>(size));
    };
    if (!stbi_write_png_to_func(append, &encoded, image.width, image.height, 3, bytes.data(),
                                image.width * 3)) {
        throw ImageError(path + ": cannot encode PNG");
    }
    writeBytes(path, encoded.data(), encoded.size());
}

void writeExr(const Image& image, const std::string& path) {
    // Encoded in memory, then written and checked, as PNGs are: tinyexr's SaveEXR does not check the file's
    // closing, where the last buffered bytes are written (a full disk left a cut-off EXR, reported as
    // written). Channels B, G, R (the order EXR viewers expect), 32-bit floats so that references keep their
    // precision, ZIP-compressed but for tiny images (as SaveEXR does).
    const size_t count = image.pixels.size();
    std::vector<float> planes[3];
    for (int c = 0; c < 3; ++c) {
        planes[c].resize(count);
        for (size_t i = 0; i < count; ++i) planes[c][i] = image.pixels[i][2 - c];
    }
    float* channels[3] = {planes[0].data(), planes[1].data(), planes[2].data()};
    EXRImage exrImage;
    InitEXRImage(&exrImage);
    exrImage.num_channels = 3;
    exrImage.images = reinterpret_cast<unsigned char**>(channels);
    exrImage.width = image.width;
    exrImage.height = image.height;
    EXRChannelInfo info[3] = {};
    int pixelTypes[3], requestedTypes[3];
    for (int c = 0; c < 3; ++c) {
        info[c].name[0] = "BGR"[c];
        pixelTypes[c] = requestedTypes[c] = TINYEXR_PIXELTYPE_FLOAT;
    }
    EXRHeader header;
    InitEXRHeader(&header);
    header.compression_type =
        image.width < 16 && image.height < 16 ? TINYEXR_COMPRESSIONTYPE_NONE : TINYEXR_COMPRESSIONTYPE_ZIP;
    header.num_channels = 3;
    header.channels = info;
    header.pixel_types = pixelTypes;
    header.requested_pixel_types = requestedTypes;
    unsigned char* encoded = nullptr;
    const char* error = nullptr;
    const size_t size = SaveEXRImageToMemory(&exrImage, &header, &encoded, &error);
    if (size == 0) {
        std::string message = error ? error : "unknown error";
        if (error) FreeEXRErrorMessage(error);
        throw ImageError(path + ": cannot encode EXR: " + message);
    }
    const std::unique_ptr<unsigned char, decltype(&std::free)> owned(encoded, &std::free);
    writeBytes(path, reinterpret_cast<const char*>(encoded), size);
}

// Portable float map: little-endian (negative scale), rows stored bottom to top.
void writePfm(const Image& image, const std::string& path) {
    std::ofstream file(path, std::ios::binary);
    if (!file) throw ImageError(path + ": cannot open for writing");
    file << "PF\n" << image.width << " " << image.height << "\n-1.0\n";
    for (int y = image.height - 1; y >= 0; --y) {
        file.write(reinterpret_cast<const char*>(&image.at(0, y)),
                   static_cast<std::streamsize>(image.width) * 12);
    }
    file.close();  // a failed write may show only when the last bytes go out (writeBytes)
    if (file.fail()) throw ImageError(cannotWrite(path));
}

// A portable float map: "PF" (RGB) or "Pf" (grey, read as equal RGB), rows bottom to top, little-endian
// when the header's scale is negative and big-endian when it is positive (Netpbm's pamtopfm writes big-endian
// by default; both were refused but the little-endian colour kind). The scale's magnitude is not applied.
Image readPfm(const std::string& path) {
    std::ifstream file(path, std::ios::binary);
    if (!file) throw ImageError(path + ": cannot open");
    std::string magic;
    int width = 0, height = 0;
    double scale = 0.0;
    file >> magic >> width >> height >> scale;
    // One whitespace character ends the header, a line end: a CR LF pair (a header written on Windows) is
    // one, its LF the header's, not the first pixel's byte.
    int separator = file.get();
    if (separator == '\r' && file.peek() == '\n') separator = file.get();
    if ((magic != "PF" && magic != "Pf") || width <= 0 || height <= 0 || !(scale != 0.0) ||
        !std::isfinite(scale) || !std::isspace(separator)) {
        throw ImageError(path + ": not a PFM (PF or Pf, its size and a non-zero scale)");
    }
    const int channels = magic == "PF" ? 3 : 1;
    const std::streamoff rowBytes = static_cast<std::streamoff>(width) * channels * 4;
    // The pixels the header promises must be in the file before they are allocated.
    const std::streamoff start = file.tellg();
    file.seekg(0, std::ios::end);
    const std::streamoff end = file.tellg();
    file.seekg(start);
    if (start < 0 || (end - start) / rowBytes < height) {
        throw ImageError(path + ": file is truncated (its header says " + std::to_string(width) + "x" +
                         std::to_string(height) + ")");
    }
    const bool bigEndian = scale > 0.0;
    Image image(width, height);
    std::vector<uint32_t> row(static_cast<size_t>(width) * channels);
    for (int y = height - 1; y >= 0; --y) {
        file.read(reinterpret_cast<char*>(row.data()), rowBytes);
        for (int x = 0; x < width; ++x) {
            glm::vec3& pixel = image.at(x, y);
            for (int c = 0; c < 3; ++c) {
                uint32_t bits = row[static_cast<size_t>(x) * channels + (channels == 3 ? c : 0)];
                if (bigEndian) bits = __builtin_bswap32(bits);
                pixel[c] = std::bit_cast<float>(bits);
            }
        }
    }
    if (!file) throw ImageError(path + ": file is truncated");
    return image;
}

// Refuses a map whose decoding would take more than `maxBytes`: `texels` of `bytesPerTexel` each, and `more`.
void checkDecodingFits(const std::string& path, uint64_t texels, uint64_t bytesPerTexel, uint64_t more,
                       uint64_t maxBytes) {
    // Compared before multiplying: a header's size is two ints (2^62 texels), and an EXR's channels many.
    const uint64_t need =
        texels > (UINT64_MAX - more) / bytesPerTexel ? UINT64_MAX : texels * bytesPerTexel + more;
    if (need > maxBytes) {
        throw MemoryError(path + ": decoding its " + std::to_string(texels) + " texels needs about " +
                          formatBytes(need) + " of host memory, and " + formatBytes(maxBytes) +
                          " is available");
    }
}

// The channels of an EXR read as red, green and blue (a grey file's one channel, 0, as all three).
struct ExrColourChannels {
    int red = 0, green = 0, blue = 0;
};

// Picks the channels of an EXR that hold radiance, and refuses a file whose channels are not radiance.
// Channels are named by what follows their last '.' (diffuse.R is R), and the first four alone are looked at,
// as tinyexr's LoadEXR did; it took a file's one channel, whatever its name (alpha, depth), as grey radiance,
// a second layer's B among the first four in place of the first's (B, G, R, other.B read other.B as blue),
// and UINT channels' bits as floats (7 read as 1e-44). Radiance is R, G and B once each among the first four
// channels, or Y alone, in HALF or FLOAT, all of one layer (an AOV's or Cryptomatte's channels after them are
// not read). Refuses one whose decoding would take more than `maxBytes`: tinyexr's planes of each channel of
// the data window as floats, and the image of the display window made from them.
ExrColourChannels checkExrHeader(const std::string& path, const EXRHeader& header, uint64_t maxBytes) {
    const int channels = header.num_channels;
    std::string names, problem, layer;
    ExrColourChannels colours;
    int red = 0, green = 0, blue = 0;
    bool luminance = false, oneLayer = true;
    for (int i = 0; i < channels; ++i) {
        const std::string name = header.channels[i].name;
        names += (names.empty() ? "" : ", ") + name;
        const size_t dot = name.find_last_of('.');
        const std::string base = dot == std::string::npos ? name : name.substr(dot + 1);
        const std::string prefix = dot == std::string::npos ? "" : name.substr(0, dot);
        const bool colour = base == "R" || base == "G" || base == "B" || base == "Y";
        if (!colour || i >= 4) continue;  // the first four alone are read (AOVs after RGBA are left)
        if (header.pixel_types[i] == TINYEXR_PIXELTYPE_UINT)
            problem = "channel " + name + " holds unsigned integers, not radiance";
        if (red + green + blue == 0 && !luminance) layer = prefix;
        oneLayer = oneLayer && prefix == layer;
        red += base == "R";
        green += base == "G";
        blue += base == "B";
        luminance |= base == "Y";
        if (base == "R") colours.red = i;
        if (base == "G") colours.green = i;
        if (base == "B") colours.blue = i;
    }
    if (problem.empty() && !oneLayer) problem = "colour channels of several layers (" + names + ")";
    if (problem.empty() && !(red == 1 && green == 1 && blue == 1) && !(luminance && channels == 1))
        problem = "no R, G and B among its first four channels, nor Y alone (it has " + names + ")";
    // Windows are inclusive boxes of pixel coordinates; the display window is the image, of ints' size.
    const auto extent = [](int min, int max) { return std::max<int64_t>(0, int64_t{max} - min + 1); };
    const EXRBox2i& display = header.display_window;
    const int64_t width = extent(display.min_x, display.max_x), height = extent(display.min_y, display.max_y);
    if (problem.empty() && (width == 0 || height == 0)) problem = "its display window is empty";
    if (problem.empty() && (width > INT32_MAX || height > INT32_MAX))
        problem =
            "its display window is " + std::to_string(width) + " x " + std::to_string(height) + " pixels";
    if (!problem.empty()) throw ImageError(path + ": cannot read EXR: " + problem);
    const EXRBox2i& data = header.data_window;
    const uint64_t planes =
        saturatedBytes(static_cast<double>(extent(data.min_x, data.max_x)) *
                       static_cast<double>(extent(data.min_y, data.max_y)) * 4.0 * channels);
    checkDecodingFits(path, static_cast<uint64_t>(width * height), sizeof(glm::vec3), planes, maxBytes);
    return colours;
}

// Throws the error of a tinyexr call that failed, as one line.
[[noreturn]] void throwExrError(const std::string& path, const char* error) {
    std::string message = error ? error : "unknown error";
    if (error) FreeEXRErrorMessage(error);
    // tinyexr's messages can end in a newline, or span lines; the command line reports one.
    std::replace(message.begin(), message.end(), '\n', ' ');
    while (!message.empty() && message.back() == ' ') message.pop_back();
    throw ImageError(path + ": cannot read EXR: " + message);
}

// Reads an EXR's display window, which is the image in OpenEXR's meaning: the pixels of its data window
// (which may be smaller, larger or offset) where they lie in it, zeros elsewhere.
Image readExr(const std::string& path, uint64_t maxBytes = UINT64_MAX) {
    EXRVersion version;
    const int status = ParseEXRVersionFromFile(&version, path.c_str());
    if (status == TINYEXR_ERROR_CANT_OPEN_FILE) throw ImageError(path + ": cannot open");
    if (status != TINYEXR_SUCCESS) throw ImageError(path + ": cannot read EXR: not an OpenEXR 2 file");
    if (version.multipart || version.non_image)
        throw ImageError(path + ": cannot read EXR: multi-part and deep files are not read");
    EXRHeader header;
    InitEXRHeader(&header);
    const char* error = nullptr;
    if (ParseEXRHeaderFromFile(&header, &version, path.c_str(), &error) != TINYEXR_SUCCESS) {
        FreeEXRHeader(&header);
        throwExrError(path, error);
    }
    const std::unique_ptr<EXRHeader, decltype(&FreeEXRHeader)> ownedHeader(&header, &FreeEXRHeader);
    const ExrColourChannels colours = checkExrHeader(path, header, maxBytes);
    // Each row where the file says it lies. This tinyexr (Debian's 1.0.1) puts row y of a DECREASING_Y file
    // (line_order 1) at height - 1 - y, though the file stores each row with its own y (tinyexr issue 213):
    // scanline files read upside down, tiled ones upside down within each tile. As INCREASING_Y it puts a
    // compressed chunk's rows at the y they carry, an uncompressed row at its place in the offset table
    // (which OpenEXR orders by y in either line order), and a tile's rows in order at its tile coordinates.
    header.line_order = 0;
    for (int i = 0; i < header.num_channels; ++i) {
        if (header.pixel_types[i] == TINYEXR_PIXELTYPE_HALF)
            header.requested_pixel_types[i] = TINYEXR_PIXELTYPE_FLOAT;
    }
    EXRImage exrImage;
    InitEXRImage(&exrImage);
    // A load that fails has freed what it allocated (freeing it again would free it twice).
    if (LoadEXRImageFromFile(&exrImage, &header, path.c_str(), &error) != TINYEXR_SUCCESS)
        throwExrError(path, error);
    const std::unique_ptr<EXRImage, decltype(&FreeEXRImage)> ownedImage(&exrImage, &FreeEXRImage);
    const EXRBox2i& data = header.data_window;
    const EXRBox2i& display = header.display_window;
    Image image(display.max_x - display.min_x + 1, display.max_y - display.min_y + 1);
    // Texel (x, y) of the data window, at `index` in `planes`, goes where it lies in the display window.
    const auto place = [&](int64_t x, int64_t y, const unsigned char* const* planes, size_t index) {
        const int64_t imageX = data.min_x + x - display.min_x, imageY = data.min_y + y - display.min_y;
        if (imageX < 0 || imageY < 0 || imageX >= image.width || imageY >= image.height) return;
        const auto channel = [&](int c) { return reinterpret_cast<const float*>(planes[c])[index]; };
        image.at(static_cast<int>(imageX), static_cast<int>(imageY)) =
            glm::vec3(channel(colours.red), channel(colours.green), channel(colours.blue));
    };
    if (header.tiled) {
        // The first level's tiles (a mipmapped file's smaller levels are not read): each is tile_size_x
        // texels wide in memory, its width and height cut where the data window ends.
        for (int t = 0; t < exrImage.num_tiles; ++t) {
            const EXRTile& tile = exrImage.tiles[t];
            for (int j = 0; j < tile.height; ++j) {
                for (int i = 0; i < tile.width; ++i) {
                    place(int64_t{tile.offset_x} * header.tile_size_x + i,
                          int64_t{tile.offset_y} * header.tile_size_y + j, tile.images,
                          static_cast<size_t>(j) * header.tile_size_x + i);
                }
            }
        }
    } else {
        for (int y = 0; y < exrImage.height; ++y) {
            for (int x = 0; x < exrImage.width; ++x)
                place(x, y, exrImage.images, static_cast<size_t>(y) * exrImage.width + x);
        }
    }
    return image;
}

}  // namespace

ImageFormat imageFormatFromPath(const std::string& path) {
    const std::string extension = lowerExtension(path);
    if (extension == ".png") return ImageFormat::Png;
    if (extension == ".exr") return ImageFormat::Exr;
    if (extension == ".pfm") return ImageFormat::Pfm;
    throw ImageError(path + ": unknown image format '" + extension + "' (use .png, .exr or .pfm)");
}

unsigned char toSrgb8(double display) {
    if (!(display > 0.0)) return 0;  // negative and NaN both map to black
    const double v = std::min(display, 1.0);
    const double encoded = v <= 0.0031308 ? 12.92 * v : 1.055 * std::pow(v, 1.0 / 2.4) - 0.055;
    return static_cast<unsigned char>(std::lround(encoded * 255.0));
}

void writeImage(const Image& image, const std::string& path, double exposure, ToneMap toneMapping) {
    FileBatch batch;
    stageImage(batch, image, path, exposure, toneMapping);
    batch.commit();
}

void stageImage(FileBatch& batch, const Image& image, const std::string& path, double exposure,
                ToneMap toneMapping) {
    const ImageFormat format = imageFormatFromPath(path);
    batch.stage(path, [&](const std::string& temporary) {
        try {
            switch (format) {
                case ImageFormat::Png:
                    writePng(image, temporary, exposure, toneMapping);
                    break;
                case ImageFormat::Exr:
                    writeExr(image, temporary);
                    break;
                case ImageFormat::Pfm:
                    writePfm(image, temporary);
                    break;
            }
        } catch (const ImageError& e) {
            // The error names the file asked for, not the temporary name it is written under first.
            std::string message = e.what();
            if (message.rfind(temporary, 0) == 0) message = path + message.substr(temporary.size());
            throw ImageError(message);
        }
    });
}

Image readImage(const std::string& path, uint64_t maxBytes) {
    const std::string extension = lowerExtension(path);
    if (extension == ".pfm") return readPfm(path);  // the file holds every pixel its header claims
    if (extension == ".exr") return readExr(path, maxBytes);
    // PNG among the rest: its pixels are tone mapped, not radiance.
    throw ImageError(path + ": not .exr or .pfm, the formats of linear radiance vkrt reads");
}

namespace {

// Checks that a Radiance HDR file holds every scanline its resolution line claims, as stb_image decodes
// them, which reads past the end of the file as zeros without an error (a cut-off file rendered black, or its
// missing rows as copies of the last texel) and loops forever on a run of length 0. Scanlines are run-length
// encoded (each walked run by run; a run of 0 or one cut off is refused) or, for widths stb_image does not
// encode or a first scanline without the encoding's marker, 4 bytes a texel for the whole image. A scanline
// without the marker after encoded ones is refused: stb_image would start the image over from it.
void checkRadianceRuns(const std::string& bytes, const std::string& path) {
    const size_t headerEnd = bytes.find("\n\n");
    if (headerEnd == std::string::npos) return;  // stb_image reports the header's problem
    const size_t resolutionEnd = bytes.find('\n', headerEnd + 2);
    int height = 0, width = 0;
    if (resolutionEnd == std::string::npos ||
        std::sscanf(bytes.c_str() + headerEnd + 2, "-Y %d +X %d", &height, &width) != 2 || width <= 0 ||
        height <= 0) {
        return;  // a layout stb_image refuses
    }
    const auto fail = [&](const std::string& what) {
        throw ImageError(path + ": cannot read Radiance HDR: " + what);
    };
    const size_t start = resolutionEnd + 1;
    const auto requireFlat = [&] {
        const uint64_t need = 4ull * static_cast<uint64_t>(width) * static_cast<uint64_t>(height);
        if (bytes.size() - start < need) {
            fail("truncated: " + std::to_string(width) + " x " + std::to_string(height) + " texels need " +
                 std::to_string(need) + " bytes of data, the file has " +
                 std::to_string(bytes.size() - start));
        }
    };
    if (width < 8 || width >= 32768) return requireFlat();
    size_t at = start;
    const auto byteAt = [&](size_t i) {
        return i < bytes.size() ? static_cast<unsigned char>(bytes[i]) : 0u;
    };
    for (int y = 0; y < height; ++y) {
        if (byteAt(at) != 2 || byteAt(at + 1) != 2 || (byteAt(at + 2) & 0x80u) != 0) {
            if (y == 0) return requireFlat();
            fail("truncated or corrupt run-length data (scanline " + std::to_string(y) + " of " +
                 std::to_string(height) + ")");
        }
        at += 4;
        for (int component = 0; component < 4; ++component) {
            for (int x = 0; x < width;) {
                const unsigned count = byteAt(at);
                const size_t length = count > 128 ? 2 : 1 + count;
                if (count == 0 || at >= bytes.size() || bytes.size() - at < length)
                    fail("truncated or corrupt run-length data");
                x += static_cast<int>(count > 128 ? count - 128 : count);
                at += length;
            }
        }
    }
}

}  // namespace

Image readRadianceImage(const std::string& path, uint64_t maxBytes) {
    const std::string extension = lowerExtension(path);
    if (extension == ".exr") return readExr(path, maxBytes);
    if (extension != ".hdr") {
        throw ImageError(path + ": unknown radiance map format '" + extension + "' (use .hdr or .exr)");
    }
    // stb_image would also decode an 8-bit image under this name, guessing its gamma: only true HDR passes.
    if (!stbi_is_hdr(path.c_str())) {
        throw ImageError(path +
                         (std::filesystem::exists(path) ? ": not a Radiance HDR file" : ": cannot open"));
    }
    std::ifstream file(path, std::ios::binary);
    const std::string bytes((std::istreambuf_iterator<char>(file)), {});
    int width = 0, height = 0, channels = 0;
    // The size stb_image will decode; then stb_image's floats and the image made from them.
    if (stbi_info_from_memory(reinterpret_cast<const stbi_uc*>(bytes.data()), static_cast<int>(bytes.size()),
                              &width, &height, &channels)) {
        // stb_image takes "-Y -5 +X 3" for a size of -5 rows, which as a count of texels wrapped around.
        if (width < 1 || height < 1) {
            throw ImageError(path + ": its resolution line gives a size of " + std::to_string(width) + " x " +
                             std::to_string(height));
        }
        checkDecodingFits(path, static_cast<uint64_t>(width) * static_cast<uint64_t>(height),
                          3 * sizeof(float) + sizeof(glm::vec3), bytes.size(), maxBytes);
    }
    checkRadianceRuns(bytes, path);
    float* rgb = stbi_loadf_from_memory(reinterpret_cast<const stbi_uc*>(bytes.data()),
                                        static_cast<int>(bytes.size()), &width, &height, &channels, 3);
    if (!rgb) throw ImageError(path + ": cannot read Radiance HDR: " + stbi_failure_reason());
    Image image(width, height);
    for (size_t i = 0; i < image.pixels.size(); ++i) {
        image.pixels[i] = glm::vec3(rgb[3 * i], rgb[3 * i + 1], rgb[3 * i + 2]);
    }
    stbi_image_free(rgb);
    return image;
}

}  // namespace vkrt
