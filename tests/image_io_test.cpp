// Image writers and metrics: exact round trips for linear formats, the sRGB curve, atomic writes.
#include <cmath>
#include <filesystem>

#include <gtest/gtest.h>

#include "image/image_io.h"
#include "image/image_metrics.h"
#include "support/temporary_folder.h"

namespace vkrt {
namespace {

Image gradient(int w, int h) {
    Image image(w, h);
    for (int y = 0; y < h; ++y)
        for (int x = 0; x < w; ++x) image.at(x, y) = glm::vec3(x * 0.37f, y * 1e-3f, 1e4f / (1 + x + y));
    return image;
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

TEST(ImageIo, SrgbEncoding) {
    EXPECT_EQ(toSrgb8(0.0f, 0.0), 0);
    EXPECT_EQ(toSrgb8(1.0f, 0.0), 255);
    EXPECT_EQ(toSrgb8(7.0f, 0.0), 255);                  // clamped
    EXPECT_EQ(toSrgb8(0.5f, 0.0), 188);                  // 1.055 * 0.5^(1/2.4) - 0.055 = 0.7354
    EXPECT_EQ(toSrgb8(0.001f, 0.0), 3);                  // linear toe: 12.92 * 0.001 * 255 = 3.29
    EXPECT_EQ(toSrgb8(0.25f, 1.0), toSrgb8(0.5f, 0.0));  // one stop of exposure doubles
    EXPECT_EQ(toSrgb8(std::nanf(""), 0.0), 0);
    EXPECT_EQ(toSrgb8(-1.0f, 0.0), 0);
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

}  // namespace
}  // namespace vkrt
