// Tests of engine/render/png_file.hpp: a picture read back with libpng has
// its size and pixels; a file that cannot be written is an error that leaves
// nothing behind.
#include "engine/render/png_file.hpp"

#include <gtest/gtest.h>
#include <png.h>
#include <unistd.h>

#include <filesystem>
#include <vector>

#include "engine/core/error.hpp"

namespace sarmap::render {
namespace {

namespace fs = std::filesystem;

struct Decoded {
  int width = 0, height = 0;
  std::vector<std::uint8_t> rgb;
};

// libpng's simplified reader, converting whatever it finds to 8-bit RGB.
Decoded read_png(const fs::path& path) {
  png_image image{};
  image.version = PNG_IMAGE_VERSION;
  Decoded d;
  if (!png_image_begin_read_from_file(&image, path.c_str())) {
    ADD_FAILURE() << "libpng: " << image.message;
    return d;
  }
  EXPECT_EQ(image.format & PNG_FORMAT_FLAG_COLOR, PNG_FORMAT_FLAG_COLOR);
  EXPECT_EQ(image.format & PNG_FORMAT_FLAG_ALPHA, 0u);
  image.format = PNG_FORMAT_RGB;
  d.width = static_cast<int>(image.width);
  d.height = static_cast<int>(image.height);
  d.rgb.resize(PNG_IMAGE_SIZE(image));
  if (!png_image_finish_read(&image, nullptr, d.rgb.data(), 0, nullptr)) {
    ADD_FAILURE() << "libpng: " << image.message;
  }
  return d;
}

class PngFile : public ::testing::Test {
 protected:
  void SetUp() override {
    dir_ = fs::temp_directory_path() / ("sarmap_png_file_" + std::to_string(::getpid()));
    fs::remove_all(dir_);
    fs::create_directories(dir_);
  }
  void TearDown() override { fs::remove_all(dir_); }
  fs::path dir_;
};

TEST_F(PngFile, RoundTripsSizeAndPixels) {
  RgbImage image(7, 3, {255, 255, 255});
  image.set(0, 0, {1, 2, 3});
  image.set(6, 2, {250, 0, 128});
  image.set(3, 1, {0, 200, 0});
  const fs::path file = dir_ / "picture.png";
  write_png(image, file);
  const Decoded d = read_png(file);
  ASSERT_EQ(d.width, 7);
  ASSERT_EQ(d.height, 3);
  const auto pixel = [&d](int x, int y) {
    const std::size_t i = 3 * (static_cast<std::size_t>(y) * 7 + static_cast<std::size_t>(x));
    return std::vector<int>{d.rgb[i], d.rgb[i + 1], d.rgb[i + 2]};
  };
  EXPECT_EQ(pixel(0, 0), (std::vector<int>{1, 2, 3}));
  EXPECT_EQ(pixel(6, 2), (std::vector<int>{250, 0, 128}));
  EXPECT_EQ(pixel(3, 1), (std::vector<int>{0, 200, 0}));
  EXPECT_EQ(pixel(1, 0), (std::vector<int>{255, 255, 255}));
}

TEST_F(PngFile, AnUnwritableTargetLeavesNoFile) {
  const fs::path file = dir_ / "no_such_folder" / "picture.png";
  EXPECT_THROW(write_png(RgbImage(4, 4), file), Error);
  EXPECT_FALSE(fs::exists(file));
  // A target that is a folder: the temporary is removed, the folder kept.
  fs::create_directories(dir_ / "taken.png");
  EXPECT_THROW(write_png(RgbImage(4, 4), dir_ / "taken.png"), Error);
  EXPECT_TRUE(fs::is_directory(dir_ / "taken.png"));
  std::size_t files = 0;
  for (const auto& entry : fs::directory_iterator(dir_)) files += entry.is_regular_file() ? 1 : 0;
  EXPECT_EQ(files, 0u);
  EXPECT_THROW(RgbImage(0, 4), Error);
}

}  // namespace
}  // namespace sarmap::render
