// Image files (render/output/image_io.h): EXR and PNG round trips, channel order, and bad files.
#include <gtest/gtest.h>

#include <filesystem>
#include <fstream>

#include "common/util/error.h"
#include "render/output/image_io.h"
#include "test_util.h"

using namespace firstshot;

// Float EXR with AOV channels: every value back exactly, colour channels first whatever EXR's sorted order.
TEST(ImageIo, ExrRoundTripKeepsValuesAndPutsColourFirst) {
  const std::string path = test::tempDir() + "/a.exr";
  const std::vector<std::string> names = {"R", "G", "B", "albedo.R", "normal.X"};
  const int w = 5, h = 3;
  std::vector<float> data(size_t(w) * h * names.size());
  for (size_t i = 0; i < data.size(); ++i) data[i] = float(i) * 0.37f - 3.0f;  // one value per pixel and channel
  image::writeExr(path, w, h, names, data.data());
  const image::Image im = image::read(path);
  ASSERT_EQ(im.width, w);
  ASSERT_EQ(im.height, h);
  ASSERT_EQ(im.channels.size(), names.size());
  EXPECT_EQ(im.channels[0], "R");
  EXPECT_EQ(im.channels[1], "G");
  EXPECT_EQ(im.channels[2], "B");
  for (size_t c = 0; c < names.size(); ++c) {
    const size_t src = size_t(std::find(names.begin(), names.end(), im.channels[c]) - names.begin());
    ASSERT_LT(src, names.size()) << im.channels[c];
    for (size_t p = 0; p < size_t(w) * h; ++p)
      ASSERT_EQ(im.data[p * names.size() + c], data[p * names.size() + src]) << im.channels[c] << " pixel " << p;
  }
}

// 8-bit PNG: bytes back as byte / 255, rows top first.
TEST(ImageIo, PngRoundTrip) {
  const std::string path = test::tempDir() + "/a.png";
  const int w = 4, h = 2;
  std::vector<uint8_t> rgb(size_t(w) * h * 3);
  for (size_t i = 0; i < rgb.size(); ++i) rgb[i] = uint8_t(i * 11);
  image::writePng(path, w, h, rgb.data());
  const image::Image im = image::read(path);
  ASSERT_EQ(im.width, w);
  ASSERT_EQ(im.height, h);
  ASSERT_EQ(im.channels, (std::vector<std::string>{"R", "G", "B"}));
  for (size_t i = 0; i < rgb.size(); ++i) EXPECT_FLOAT_EQ(im.data[i], float(rgb[i]) / 255.0f) << i;
}

// Missing, foreign and truncated files: InputError naming the file, never a crash.
TEST(ImageIo, BadFilesNameTheFile) {
  const std::string dir = test::tempDir();
  auto expectInputError = [](const std::string& path) {
    try {
      image::read(path);
      ADD_FAILURE() << path << " was read";
    } catch (const InputError& e) {
      EXPECT_NE(std::string(e.what()).find(path), std::string::npos) << e.what();
    }
  };
  expectInputError(dir + "/missing.exr");
  test::writeText(dir + "/text.exr", "not an image\n");
  expectInputError(dir + "/text.exr");
  const std::vector<std::string> names = {"R", "G", "B"};
  const std::vector<float> data(64 * 64 * 3, 0.5f);
  std::vector<uint8_t> rgb(64 * 64 * 3, 100);
  image::writeExr(dir + "/full.exr", 64, 64, names, data.data());
  image::writePng(dir + "/full.png", 64, 64, rgb.data());
  for (const std::string ext : {"exr", "png"}) {
    const std::string full = dir + "/full." + ext, cut = dir + "/cut." + ext;
    const auto size = std::filesystem::file_size(full);
    std::filesystem::copy_file(full, cut);
    std::filesystem::resize_file(cut, size / 2);
    expectInputError(cut);
  }
}

// A failed write leaves nothing behind: no target, no temporary file.
TEST(ImageIo, FailedWriteLeavesNoFile) {
  const std::string dir = test::tempDir() + "/no-such-folder";
  const std::vector<float> data(3, 1.0f);
  EXPECT_THROW(image::writeExr(dir + "/a.exr", 1, 1, {"R", "G", "B"}, data.data()), std::runtime_error);
  EXPECT_FALSE(std::filesystem::exists(dir));
}
