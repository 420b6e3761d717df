// Image writers and metrics: exact round trips for linear formats, the sRGB curve, atomic writes.
#include <algorithm>
#include <bit>
#include <cmath>
#include <csignal>
#include <cstdio>
#include <cstring>
#include <filesystem>
#include <fstream>
#include <initializer_list>
#include <iterator>
#include <string>
#include <vector>

#include <sys/resource.h>
#include <sys/wait.h>
#include <unistd.h>

#include <gtest/gtest.h>
#include <tinyexr.h>

#include "common/memory_need.h"
#include "image/image_io.h"
#include "image/image_metrics.h"
#include "support/temporary_folder.h"
#include "support/test_paths.h"

namespace vkrt {
namespace {

Image gradient(int w, int h) {
    Image image(w, h);
    for (int y = 0; y < h; ++y)
        for (int x = 0; x < w; ++x) image.at(x, y) = glm::vec3(x * 0.37f, y * 1e-3f, 1e4f / (1 + x + y));
    return image;
}

// A write that fails where the file's last bytes go out (here a file-size limit one byte short: stdio's
// buffer holds the end until the file is closed) is an error, and leaves no file: tinyexr's
// SaveEXR did not check the closing, and a cut-off EXR was reported as written.
TEST(ImageIo, AWriteThatFailsAtTheCloseLeavesNoFile) {
    const auto folder = test::temporaryFolder();
    const Image image = gradient(64, 64);
    for (const char* name : {"a.exr", "a.png", "a.pfm"}) {
        const std::string path = (folder / name).string();
        writeImage(image, path);
        const auto size = std::filesystem::file_size(path);
        std::filesystem::remove(path);
        // In a child process, limited to all but the last byte.
        const pid_t child = fork();
        ASSERT_GE(child, 0);
        if (child == 0) {
            std::signal(SIGXFSZ, SIG_IGN);
            const rlimit limit{size - 1, size - 1};
            setrlimit(RLIMIT_FSIZE, &limit);
            try {
                writeImage(image, path);
            } catch (const ImageError&) {
                _exit(std::filesystem::exists(path) ? 3 : 0);
            }
            _exit(2);
        }
        int status = 0;
        waitpid(child, &status, 0);
        ASSERT_TRUE(WIFEXITED(status)) << name;
        EXPECT_EQ(WEXITSTATUS(status), 0)
            << name << (WEXITSTATUS(status) == 2 ? ": reported as written" : ": a file is left");
        for (const auto& entry : std::filesystem::directory_iterator(folder))
            ADD_FAILURE() << name << ": left " << entry.path();
    }
}

TEST(ImageIo, LinearFormatsRoundTripExactly) {
    const auto folder = test::temporaryFolder();
    const Image image = gradient(13, 7);  // odd sizes catch row-order mistakes
    for (const char* name : {"a.pfm", "a.exr"}) {
        const std::string path = (folder / name).string();
        writeImage(image, path);
        const Image back = readImage(path);
        ASSERT_EQ(back.width, 13);
        ASSERT_EQ(back.height, 7);
        EXPECT_EQ(compareImages(back, image).rmse, 0.0) << name;
        EXPECT_EQ(back.at(12, 0), image.at(12, 0)) << name;  // top-right stays top-right
    }
}

// A PFM written on Windows ends its header's lines in CR LF: the LF is the header's, not the first pixel's.
TEST(ImageIo, PfmHeaderWithCrLfIsRead) {
    const auto folder = test::temporaryFolder();
    const Image image = gradient(5, 3);
    const std::string path = (folder / "a.pfm").string();
    writeImage(image, path);
    std::ifstream in(path, std::ios::binary);
    std::string bytes((std::istreambuf_iterator<char>(in)), std::istreambuf_iterator<char>());
    const std::string header = "PF\n5 3\n-1.0\n";
    ASSERT_EQ(bytes.compare(0, header.size(), header), 0);
    std::ofstream(path, std::ios::binary) << "PF\r\n5 3\r\n-1.0\r\n" << bytes.substr(header.size());
    const Image back = readImage(path);
    ASSERT_EQ(back.width, 5);
    ASSERT_EQ(back.height, 3);
    EXPECT_EQ(compareImages(back, image).rmse, 0.0);
    // A lone CR is the header's one separator: the pixels start right after it.
    std::ofstream(path, std::ios::binary) << "PF\r5 3\r-1.0\r" << bytes.substr(header.size());
    EXPECT_EQ(compareImages(readImage(path), image).rmse, 0.0);
    // No separator at all is not a PFM.
    std::ofstream(path, std::ios::binary) << "PF\n5 3\n-1.0" << bytes.substr(header.size());
    EXPECT_THROW(readImage(path), ImageError);
}

// A CR LF after the scale is one line end whatever follows the pixels: its LF was taken as the first pixel's
// byte when a byte (a trailing newline, say) followed them, and every value was read shifted by a byte. A
// file one byte short is still truncated.
TEST(ImageIo, PfmCrLfHeaderIsReadWhateverFollowsThePixels) {
    const auto folder = test::temporaryFolder();
    const Image image = gradient(5, 3);
    const std::string path = (folder / "a.pfm").string();
    writeImage(image, path);
    const std::string header = "PF\n5 3\n-1.0\n";
    const std::string pixels = test::readText(path).substr(header.size());
    ASSERT_EQ(pixels.size(), 5u * 3 * 12);
    for (const std::string& after : {std::string("\n"), std::string("\r\n"), std::string(13, '\0')}) {
        test::writeText(path, "PF\r\n5 3\r\n-1.0\r\n" + pixels + after);
        const Image back = readImage(path);
        ASSERT_EQ(back.width, 5);
        ASSERT_EQ(back.height, 3);
        EXPECT_EQ(compareImages(back, image).rmse, 0.0) << after.size() << " bytes after the pixels";
    }
    test::writeText(path, "PF\r\n5 3\r\n-1.0\r\n" + pixels.substr(0, pixels.size() - 1));
    EXPECT_THROW(readImage(path), ImageError);
}

// Big-endian PFMs (a positive scale, as Netpbm's pamtopfm writes them) and grey ones ("Pf") are read too:
// they were refused as references. The same pixels, rows bottom to top, as the little-endian colour file vkrt
// writes.
TEST(ImageIo, BigEndianAndGreyPfmsAreRead) {
    const auto folder = test::temporaryFolder();
    const Image image = gradient(5, 3);
    const std::string path = (folder / "a.pfm").string();
    auto bigEndian = [](float value) {
        uint32_t bits;
        std::memcpy(&bits, &value, 4);
        std::string bytes(4, '\0');
        for (int k = 0; k < 4; ++k) bytes[k] = static_cast<char>(bits >> (24 - 8 * k));
        return bytes;
    };
    std::string colour = "PF\n5 3\n1.0\n", grey = "Pf\n5 3\n1.0\n";
    for (int y = 2; y >= 0; --y) {
        for (int x = 0; x < 5; ++x) {
            for (int c = 0; c < 3; ++c) colour += bigEndian(image.at(x, y)[c]);
            grey += bigEndian(image.at(x, y).y);
        }
    }
    std::ofstream(path, std::ios::binary) << colour;
    EXPECT_EQ(compareImages(readImage(path), image).rmse, 0.0);
    std::ofstream(path, std::ios::binary) << grey;
    const Image back = readImage(path);
    for (int y = 0; y < 3; ++y) {
        for (int x = 0; x < 5; ++x) EXPECT_EQ(back.at(x, y), glm::vec3(image.at(x, y).y)) << x << ", " << y;
    }
    // A grey file one value short is truncated.
    std::ofstream(path, std::ios::binary) << grey.substr(0, grey.size() - 4);
    EXPECT_THROW(readImage(path), ImageError);
}

TEST(ImageIo, SrgbEncoding) {
    EXPECT_EQ(toSrgb8(0.0), 0);
    EXPECT_EQ(toSrgb8(1.0), 255);
    EXPECT_EQ(toSrgb8(7.0), 255);  // clamped
    EXPECT_EQ(toSrgb8(0.5), 188);  // 1.055 * 0.5^(1/2.4) - 0.055 = 0.7354
    EXPECT_EQ(toSrgb8(0.001), 3);  // linear toe: 12.92 * 0.001 * 255 = 3.29
    EXPECT_EQ(toSrgb8(std::nan("")), 0);
    EXPECT_EQ(toSrgb8(-1.0), 0);
}

TEST(ToneMap, ClampClipsEachChannelAndExposureDoubles) {
    EXPECT_EQ(toneMap({0.5, 2.0, -1.0}, ToneMap::Clamp), glm::dvec3(0.5, 1.0, 0.0));
    EXPECT_EQ(toneMap({0.25, 0.25, 0.25}, ToneMap::Clamp, 1.0), glm::dvec3(0.5));  // one stop doubles
    EXPECT_EQ(toneMap({std::nan(""), 0.5, 0.5}, ToneMap::PbrNeutral).x, 0.0);
    // Any exposure saturates to white, never to black (infinity over infinity was NaN, shown as 0).
    for (ToneMap curve : {ToneMap::Clamp, ToneMap::Aces, ToneMap::PbrNeutral}) {
        for (double exposure : {600.0, 1024.0}) {
            EXPECT_NEAR(toneMap({0.5, 0.5, 0.5}, curve, exposure).x, 1.0, 1e-6)
                << toneMapName(curve) << " at " << exposure;
        }
    }
}

TEST(ToneMap, AcesFollowsNarkowiczsFit) {
    EXPECT_EQ(toneMap(glm::dvec3(0.0), ToneMap::Aces), glm::dvec3(0.0));
    EXPECT_NEAR(toneMap(glm::dvec3(1.0), ToneMap::Aces).x, 2.54 / 3.16,
                1e-15);  // (2.51 + 0.03) / (2.43 + 0.59 + 0.14)
    EXPECT_EQ(toneMap(glm::dvec3(100.0), ToneMap::Aces), glm::dvec3(1.0));  // the fit passes 1; clipped
}

TEST(ToneMap, PbrNeutralKeepsBaseColoursAndRollsOffHighlights) {
    // Below the compression start (0.76 after the 0.04 offset) colours pass, less the offset.
    EXPECT_NEAR(toneMap(glm::dvec3(0.5), ToneMap::PbrNeutral).x, 0.46, 1e-15);
    const glm::dvec3 colour = toneMap({0.7, 0.3, 0.1}, ToneMap::PbrNeutral);
    EXPECT_NEAR(colour.r, 0.66, 1e-15);
    EXPECT_NEAR(colour.g, 0.26, 1e-15);
    EXPECT_NEAR(colour.b, 0.06, 1e-15);
    // Dark colours: the offset shrinks to x - 6.25 x^2 for the darkest channel below 0.08.
    EXPECT_NEAR(toneMap(glm::dvec3(0.05), ToneMap::PbrNeutral).x, 0.05 - (0.05 - 6.25 * 0.0025), 1e-15);
    // Highlights approach 1 and never pass it: grey 10 to 1 - 0.24^2 / (9.96 + 0.24 - 0.76).
    EXPECT_NEAR(toneMap(glm::dvec3(10.0), ToneMap::PbrNeutral).x, 1.0 - 0.0576 / 9.44, 1e-12);
    double previous = 0.0;
    for (double x = 0.0; x < 50.0; x += 0.01) {
        const double y = toneMap(glm::dvec3(x), ToneMap::PbrNeutral).x;
        ASSERT_GE(y, previous) << x;  // monotonic
        ASSERT_LT(y, 1.0) << x;
        previous = y;
    }
}

TEST(ToneMap, NamesRoundTrip) {
    for (ToneMap t : {ToneMap::Clamp, ToneMap::Aces, ToneMap::PbrNeutral}) {
        EXPECT_EQ(toneMapFromName(toneMapName(t)), t);
    }
    EXPECT_FALSE(toneMapFromName("filmic"));
}

TEST(ImageIo, PngIsWrittenAndFailedWritesLeaveNothing) {
    const auto folder = test::temporaryFolder();
    writeImage(gradient(4, 4), (folder / "ok.png").string());
    EXPECT_GT(std::filesystem::file_size(folder / "ok.png"), 0u);
    EXPECT_THROW(writeImage(gradient(4, 4), (folder / "missing-folder" / "x.exr").string()), std::exception);
    EXPECT_THROW(writeImage(gradient(4, 4), (folder / "x.bmp").string()), ImageError);
    size_t files = 0;
    for (const auto& entry : std::filesystem::directory_iterator(folder)) {
        ++files;
        EXPECT_EQ(entry.path().filename(), "ok.png");
    }
    EXPECT_EQ(files, 1u);
}

TEST(ImageMetrics, KnownDifferences) {
    Image a(2, 1), b(2, 1);
    a.at(0, 0) = glm::vec3(1.0f);
    b.at(0, 0) = glm::vec3(1.0f);
    a.at(1, 0) = glm::vec3(0.5f);
    b.at(1, 0) = glm::vec3(0.6f);
    const ImageDifference d = compareImages(a, b);
    EXPECT_NEAR(d.rmse, std::sqrt(3 * 0.01 / 6.0), 1e-7);
    EXPECT_NEAR(d.relMse, (3 * 0.01 / (0.36 + 0.01)) / 6.0, 1e-7);
    EXPECT_DOUBLE_EQ(d.fractionOff, 0.5);
    EXPECT_EQ(compareImages(a, a).rmse, 0.0);
    EXPECT_TRUE(std::isinf(compareImages(a, a).psnr));
}

TEST(ImageMetrics, BlocksCompareTheirMeans) {
    // A 4x2 image in 2x2 blocks: the left block's pixels differ by +-10% but its mean agrees; the right block's
    // red mean is 5% high. Partial blocks (a 5th column) are left out.
    Image image(5, 2), reference(5, 2);
    for (int y = 0; y < 2; ++y) {
        for (int x = 0; x < 5; ++x) reference.at(x, y) = image.at(x, y) = glm::vec3(1.0f);
    }
    image.at(0, 0) = glm::vec3(1.1f);
    image.at(1, 0) = glm::vec3(0.9f);
    image.at(2, 0).x = 1.2f;  // red mean of the right block: 1.05
    image.at(4, 1) = glm::vec3(100.0f);
    const BlockAgreement within = compareBlocks(image, reference, 2, 0.06, 0.0);
    EXPECT_EQ(within.blocks, 2);
    EXPECT_DOUBLE_EQ(within.fractionWithin, 1.0);
    EXPECT_NEAR(within.worstBlock, 0.05, 1e-6);
    const BlockAgreement strict = compareBlocks(image, reference, 2, 0.04, 0.0);
    EXPECT_DOUBLE_EQ(strict.fractionWithin, 0.5);
    EXPECT_NEAR(within.meanRatio.y, (9.0 + 100.0) / 10.0, 1e-5);  // the whole image's means count every pixel
}

TEST(ImageMetrics, AChannelBlackInTheReferenceAgreesOnlyWithBlack) {
    Image image(2, 2), reference(2, 2);
    for (glm::vec3& p : reference.pixels) p = glm::vec3(0.5f, 0.25f, 0.0f);
    image.pixels = reference.pixels;
    EXPECT_EQ(compareBlocks(image, reference, 2, 0.03).meanRatio, glm::dvec3(1.0));
    image.at(1, 1).z = 5.0f;
    EXPECT_TRUE(std::isinf(compareBlocks(image, reference, 2, 0.03).meanRatio.z));
}

// A Radiance HDR file cut anywhere before its last byte is refused: stb_image reads past the end as zeros,
// and a file cut in its run-length data rendered black, or its missing rows as copies of the last texel,
// without an error. Also files of unencoded texels: rows missing, or no pixel data at all.
TEST(ImageIo, CutOffRadianceFilesAreRefused) {
    const auto folder = test::temporaryFolder();
    const std::filesystem::path sky = test::sourceDir() / "scenes/sky.hdr";
    std::ifstream in(sky, std::ios::binary);
    const std::string bytes((std::istreambuf_iterator<char>(in)), {});
    const Image whole = readRadianceImage(sky.string());
    ASSERT_GT(whole.width, 8);
    const size_t data = bytes.find('\n', bytes.find("\n\n") + 2) + 1;
    const std::string cut = (folder / "cut.hdr").string();
    for (size_t end = data; end < bytes.size(); end += 7) {
        test::writeText(cut, bytes.substr(0, end));
        EXPECT_THROW(readRadianceImage(cut), ImageError) << "cut at " << end << " of " << bytes.size();
    }
    // Unencoded: 4 texels wide (stb_image encodes no scanline narrower than 8), 3 rows.
    const std::string header = "#?RADIANCE\nFORMAT=32-bit_rle_rgbe\n\n-Y 3 +X 4\n";
    std::string texels;
    for (int i = 0; i < 12; ++i) texels += std::string("\x80\x80\x80\x81", 4);  // 1.0 each
    test::writeText(cut, header + texels);
    EXPECT_EQ(readRadianceImage(cut).at(3, 2), glm::vec3(1.0f));
    for (const size_t keep : {0, 4, 16, 44, 47}) {
        test::writeText(cut, header + texels.substr(0, keep));
        EXPECT_THROW(readRadianceImage(cut), ImageError) << keep << " bytes of texels";
    }
}

// An EXR file of channels that are not radiance is refused: LoadEXR read a lone alpha or depth channel as
// grey radiance, a second layer's blue among the first four channels as the first's, and unsigned integers'
// bits as floats (7 as 1e-44). RGB and Y alone are read, of one layer too (LoadEXR reads diffuse.R as R).
TEST(ImageIo, ExrChannelsThatAreNotRadianceAreRefused) {
    const auto folder = test::temporaryFolder();
    const auto write = [&](const std::string& file, const std::vector<std::string>& names, int pixelType) {
        const size_t texels = 4;
        std::vector<std::vector<uint32_t>> planes(names.size(), std::vector<uint32_t>(texels));
        for (auto& plane : planes) {
            for (uint32_t& word : plane) {
                const float seven = 7.0f;
                if (pixelType == TINYEXR_PIXELTYPE_UINT)
                    word = 7u;
                else
                    std::memcpy(&word, &seven, 4);
            }
        }
        std::vector<unsigned char*> pointers;
        for (auto& plane : planes) pointers.push_back(reinterpret_cast<unsigned char*>(plane.data()));
        std::vector<EXRChannelInfo> channels(names.size());
        std::vector<int> types(names.size(), pixelType);
        for (size_t i = 0; i < names.size(); ++i) {
            std::memset(&channels[i], 0, sizeof channels[i]);
            std::snprintf(channels[i].name, sizeof channels[i].name, "%s", names[i].c_str());
        }
        EXRHeader header;
        InitEXRHeader(&header);
        header.num_channels = static_cast<int>(names.size());
        header.channels = channels.data();
        header.pixel_types = types.data();
        header.requested_pixel_types = types.data();
        EXRImage image;
        InitEXRImage(&image);
        image.num_channels = header.num_channels;
        image.images = pointers.data();
        image.width = image.height = 2;
        const char* error = nullptr;
        const std::string path = (folder / file).string();
        EXPECT_EQ(SaveEXRImageToFile(&image, &header, path.c_str(), &error), TINYEXR_SUCCESS)
            << (error ? error : "");
        return path;
    };
    // Channels sorted by name, as EXR stores them.
    const std::string rgb = write("rgb.exr", {"B", "G", "R"}, TINYEXR_PIXELTYPE_FLOAT);
    const std::string grey = write("y.exr", {"Y"}, TINYEXR_PIXELTYPE_FLOAT);
    const std::string alpha = write("a.exr", {"A"}, TINYEXR_PIXELTYPE_FLOAT);
    const std::string depth = write("z.exr", {"Z"}, TINYEXR_PIXELTYPE_FLOAT);
    const std::string integers = write("uint.exr", {"B", "G", "R"}, TINYEXR_PIXELTYPE_UINT);
    const std::string layer =
        write("layer.exr", {"diffuse.A", "diffuse.B", "diffuse.G", "diffuse.R", "depth.Z"},
              TINYEXR_PIXELTYPE_FLOAT);
    const std::string layerGrey = write("layer-y.exr", {"rgba.Y"}, TINYEXR_PIXELTYPE_FLOAT);
    const std::string red = write("r.exr", {"R"}, TINYEXR_PIXELTYPE_FLOAT);
    const std::string layers =
        write("layers.exr", {"B", "G", "R", "other.B", "other.G", "other.R"}, TINYEXR_PIXELTYPE_FLOAT);
    const std::string aovs = write("aovs.exr", {"A", "B", "G", "R", "diffuse.B", "diffuse.G", "diffuse.R"},
                                   TINYEXR_PIXELTYPE_FLOAT);
    for (const std::string& path : {rgb, grey, layer, layerGrey, aovs})
        EXPECT_EQ(readImage(path).at(1, 1), glm::vec3(7.0f));
    for (const std::string& path : {alpha, depth, integers, red, layers}) {
        SCOPED_TRACE(path);
        try {
            readImage(path);
            ADD_FAILURE() << "read";
        } catch (const ImageError& e) {
            EXPECT_NE(std::string(e.what()).find("cannot read EXR"), std::string::npos) << e.what();
        }
    }
}

// Where an EXR written by exrBytes puts its pixels, and in what order.
struct ExrLayout {
    int dataX = 0, dataY = 0;       // the data window's top-left pixel
    int display[4] = {0, 0, 0, 0};  // the display window: min x, min y, max x, max y (inclusive)
    int lineOrder = 0;              // 0: INCREASING_Y, 1: DECREASING_Y
    int tileSize = 0;               // tiled (one level, square tiles) when positive
};

// An uncompressed EXR of FLOAT channels B, G and R, written byte by byte: tinyexr's writer sets both windows
// to the image's size and the line order to INCREASING_Y. `pixels` fill the data window. A DECREASING_Y file
// stores its rows, or rows of tiles, bottom first, its offset table still ordered by y as OpenEXR requires.
std::string exrBytes(const Image& pixels, const ExrLayout& layout) {
    const auto words = [](std::initializer_list<uint32_t> values) {
        std::string bytes;
        for (uint32_t value : values) {
            for (int k = 0; k < 4; ++k) bytes += static_cast<char>(value >> (8 * k));
        }
        return bytes;
    };
    const auto ints = [&](std::initializer_list<int> values) {
        std::string bytes;
        for (int value : values) bytes += words({static_cast<uint32_t>(value)});
        return bytes;
    };
    const auto floats = [&](std::initializer_list<float> values) {
        std::string bytes;
        for (float value : values) bytes += words({std::bit_cast<uint32_t>(value)});
        return bytes;
    };
    std::string header = std::string("\x76\x2f\x31\x01", 4) + ints({layout.tileSize > 0 ? 0x202 : 2});
    const auto attribute = [&](const char* name, const char* type, const std::string& value) {
        header += std::string(name) + '\0' + type + '\0' + ints({static_cast<int>(value.size())}) + value;
    };
    std::string channels;
    for (const char* name : {"B", "G", "R"}) channels += std::string(name) + '\0' + ints({2, 0, 1, 1});
    attribute("channels", "chlist", channels + '\0');
    attribute("compression", "compression", std::string(1, '\0'));
    attribute("dataWindow", "box2i",
              ints({layout.dataX, layout.dataY, layout.dataX + pixels.width - 1,
                    layout.dataY + pixels.height - 1}));
    attribute("displayWindow", "box2i",
              ints({layout.display[0], layout.display[1], layout.display[2], layout.display[3]}));
    attribute("lineOrder", "lineOrder", std::string(1, static_cast<char>(layout.lineOrder)));
    attribute("pixelAspectRatio", "float", floats({1.0f}));
    attribute("screenWindowCenter", "v2f", floats({0.0f, 0.0f}));
    attribute("screenWindowWidth", "float", floats({1.0f}));
    if (layout.tileSize > 0) attribute("tiles", "tiledesc", ints({layout.tileSize, layout.tileSize}) + '\0');
    header += '\0';
    // A chunk's pixels: row by row, each row channel by channel.
    const auto texels = [&](int x0, int y0, int width, int height) {
        std::string bytes;
        for (int y = y0; y < y0 + height; ++y) {
            for (int c = 2; c >= 0; --c) {
                for (int x = x0; x < x0 + width; ++x) bytes += floats({pixels.at(x, y)[c]});
            }
        }
        return bytes;
    };
    // The chunks in the offset table's order: scanlines by y, tiles by row then column.
    std::vector<std::string> chunks;
    int chunksPerRow = 1;
    if (layout.tileSize > 0) {
        const int tile = layout.tileSize;
        chunksPerRow = (pixels.width + tile - 1) / tile;
        for (int ty = 0; ty * tile < pixels.height; ++ty) {
            for (int tx = 0; tx * tile < pixels.width; ++tx) {
                const int width = std::min(tile, pixels.width - tx * tile);
                const int height = std::min(tile, pixels.height - ty * tile);
                chunks.push_back(ints({tx, ty, 0, 0, 12 * width * height}) +
                                 texels(tx * tile, ty * tile, width, height));
            }
        }
    } else {
        for (int y = 0; y < pixels.height; ++y)
            chunks.push_back(ints({layout.dataY + y, 12 * pixels.width}) + texels(0, y, pixels.width, 1));
    }
    std::vector<size_t> fileOrder(chunks.size());
    for (size_t i = 0; i < chunks.size(); ++i) {
        const size_t row = i / chunksPerRow, rows = chunks.size() / chunksPerRow;
        fileOrder[i] = (layout.lineOrder == 0 ? row : rows - 1 - row) * chunksPerRow + i % chunksPerRow;
    }
    std::vector<uint64_t> offsets(chunks.size());
    std::string body;
    for (size_t index : fileOrder) {
        offsets[index] = header.size() + 8 * chunks.size() + body.size();
        body += chunks[index];
    }
    std::string table;
    for (uint64_t offset : offsets)
        table += words({static_cast<uint32_t>(offset), static_cast<uint32_t>(offset >> 32)});
    return header + table + body;
}

// A DECREASING_Y EXR reads as the same image written INCREASING_Y: tinyexr put row y of such a file at
// height - 1 - y, though each row carries its own y, and such maps and references were read upside down
// (tiled ones upside down within each tile).
TEST(ImageIo, ExrRowsAreReadWhereTheyLieInEitherLineOrder) {
    const auto folder = test::temporaryFolder();
    const Image image = gradient(13, 7);
    const std::string path = (folder / "a.exr").string();
    for (const int tileSize : {0, 4}) {  // 4 x 4 tiles, those on the right and bottom edges cut
        for (const int lineOrder : {0, 1}) {
            SCOPED_TRACE("tile size " + std::to_string(tileSize) + ", line order " +
                         std::to_string(lineOrder));
            ExrLayout layout;
            layout.display[2] = 12;
            layout.display[3] = 6;
            layout.lineOrder = lineOrder;
            layout.tileSize = tileSize;
            test::writeText(path, exrBytes(image, layout));
            const Image back = readImage(path);
            ASSERT_EQ(back.width, 13);
            ASSERT_EQ(back.height, 7);
            EXPECT_EQ(compareImages(back, image).rmse, 0.0);
            EXPECT_EQ(back.at(12, 0), image.at(12, 0));  // top-right stays top-right
        }
    }
}

// An EXR's image is its display window, its data window's pixels where they lie in it and zeros elsewhere
// (OpenEXR's meaning): the data window's pixels were stretched over the whole image, of the data window's
// size. Windows are inclusive, their corners may be negative, and what of the data window lies outside is
// cut.
TEST(ImageIo, ExrDataWindowIsPlacedInTheDisplayWindow) {
    const auto folder = test::temporaryFolder();
    const std::string path = (folder / "a.exr").string();
    struct Case {
        int dataX, dataY, width, height;
        int display[4];
    };
    for (const Case& c : {Case{2, 1, 3, 2, {0, 0, 6, 4}},          // inside
                          Case{-1, -1, 3, 2, {-3, -2, 3, 2}},      // negative corners
                          Case{5, 3, 4, 3, {0, 0, 6, 4}},          // over the right and bottom edges
                          Case{-2, -3, 12, 10, {10, 20, 12, 23}},  // no overlap
                          Case{8, 18, 9, 9, {10, 20, 12, 23}}}) {  // all around
        const Image data = gradient(c.width, c.height);
        const int width = c.display[2] - c.display[0] + 1, height = c.display[3] - c.display[1] + 1;
        Image expected(width, height);
        for (int y = 0; y < data.height; ++y) {
            for (int x = 0; x < data.width; ++x) {
                const int imageX = c.dataX + x - c.display[0], imageY = c.dataY + y - c.display[1];
                if (imageX >= 0 && imageY >= 0 && imageX < width && imageY < height)
                    expected.at(imageX, imageY) = data.at(x, y);
            }
        }
        for (const int tileSize : {0, 2}) {
            for (const int lineOrder : {0, 1}) {
                SCOPED_TRACE("data window at " + std::to_string(c.dataX) + ", " + std::to_string(c.dataY) +
                             ", display window from " + std::to_string(c.display[0]) + ", " +
                             std::to_string(c.display[1]) + ", tile size " + std::to_string(tileSize) +
                             ", line order " + std::to_string(lineOrder));
                ExrLayout layout;
                layout.dataX = c.dataX;
                layout.dataY = c.dataY;
                std::copy(c.display, c.display + 4, layout.display);
                layout.lineOrder = lineOrder;
                layout.tileSize = tileSize;
                test::writeText(path, exrBytes(data, layout));
                const Image back = readImage(path);
                ASSERT_EQ(back.width, width);
                ASSERT_EQ(back.height, height);
                for (int y = 0; y < height; ++y) {
                    for (int x = 0; x < width; ++x)
                        EXPECT_EQ(back.at(x, y), expected.at(x, y)) << "pixel " << x << ", " << y;
                }
            }
        }
    }
}

// An EXR whose display window claims 8 x 2e9 pixels around a data window of two rows is refused before it is
// decoded when that would take more than the bytes given: --reference passes the host's memory, and the
// image's allocation failed ("out of memory", exit 1) where --environment's map was refused with the figures.
TEST(ImageIo, ExrDisplayWindowBeyondTheMemoryGivenIsRefusedBeforeDecoding) {
    const auto folder = test::temporaryFolder();
    const std::string path = (folder / "huge.exr").string();
    ExrLayout layout;
    const int display[4] = {0, 0, 7, 1999999999};
    std::copy(display, display + 4, layout.display);
    test::writeText(path, exrBytes(gradient(8, 2), layout));
    EXPECT_THROW(readImage(path, uint64_t{1} << 30), MemoryError);
    layout.display[3] = 1;  // the same pixels in a display window of their own size
    test::writeText(path, exrBytes(gradient(8, 2), layout));
    EXPECT_EQ(readImage(path, uint64_t{1} << 30).height, 2);
}

}  // namespace
}  // namespace vkrt
