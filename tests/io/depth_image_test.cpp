#include "engine/io/depth_image.hpp"

#include <gmock/gmock.h>
#include <gtest/gtest.h>
#include <cmath>
#include <filesystem>
#include <fstream>
#include <iterator>
#include <string>
#include <vector>

#include "engine/core/error.hpp"
#include "engine/io/depth_image_back_projection.hpp"
#include "error_message.hpp"
#include "png_test_writer.hpp"
#include "scratch_folder.hpp"
#include "tests/file_bytes.hpp"

namespace sarmap {
namespace {

using test::slurp;

using test::error_message;
using ::testing::HasSubstr;

std::vector<std::uint16_t> ramp(int width, int height) {
  std::vector<std::uint16_t> pixels(static_cast<std::size_t>(width * height));
  // Values above 255 in both bytes catch a byte-order mistake.
  for (std::size_t i = 0; i < pixels.size(); ++i) pixels[i] = static_cast<std::uint16_t>(0x0102 + 0x1011 * i);
  return pixels;
}

TEST(DepthPng, Reads16BitGrayscaleSamplesExactly) {
  test::ScratchFolder dir;
  const auto pixels = ramp(5, 3);
  test::write_png_gray16(dir / "d.png", 5, 3, pixels);
  const DepthImage image = read_depth_png(dir / "d.png");
  EXPECT_EQ(image.width, 5);
  EXPECT_EQ(image.height, 3);
  EXPECT_EQ(image.pixels, pixels);
  EXPECT_EQ(image.at(1, 2), pixels[2 * 5 + 1]);
}

TEST(DepthPng, Rejects8BitAndColourImagesByName) {
  test::ScratchFolder dir;
  test::write_png_gray8(dir / "eight.png", 2, 2, {1, 2, 3, 4});
  std::string msg = error_message([&] { read_depth_png(dir / "eight.png"); });
  EXPECT_THAT(msg, HasSubstr("eight.png"));
  EXPECT_THAT(msg, HasSubstr("16-bit grayscale"));
  EXPECT_THAT(msg, HasSubstr("8-bit"));
  test::write_png_rgb16(dir / "rgb.png", 2, 2, {1, 2, 3, 4});
  msg = error_message([&] { read_depth_png(dir / "rgb.png"); });
  EXPECT_THAT(msg, HasSubstr("rgb.png"));
  EXPECT_THAT(msg, HasSubstr("RGB colour"));
}

TEST(DepthPng, TruncatedFileIsAnErrorAtEveryCutPoint) {
  test::ScratchFolder dir;
  test::write_png_gray16(dir / "full.png", 16, 16, ramp(16, 16));
  const std::string bytes = slurp(dir / "full.png");
  // Every prefix: inside the signature, the header, the data, the end chunk.
  for (std::size_t cut = 0; cut < bytes.size(); ++cut) {
    std::ofstream(dir / "cut.png", std::ios::binary) << bytes.substr(0, cut);
    const std::string msg = error_message([&] { read_depth_png(dir / "cut.png"); });
    EXPECT_THAT(msg, HasSubstr("cut.png")) << "cut at " << cut;
  }
  const std::string at_half = error_message([&] {
    std::ofstream(dir / "half.png", std::ios::binary) << bytes.substr(0, bytes.size() / 2);
    read_depth_png(dir / "half.png");
  });
  EXPECT_THAT(at_half, HasSubstr("truncated"));
}

// CRC-32 (the PNG chunk checksum) of bytes, bit by bit.
std::uint32_t crc32_of(const std::string& bytes) {
  std::uint32_t crc = 0xFFFFFFFFu;
  for (const char c : bytes) {
    crc ^= static_cast<std::uint8_t>(c);
    for (int bit = 0; bit < 8; ++bit) crc = (crc >> 1) ^ (0xEDB88320u & (0u - (crc & 1u)));
  }
  return ~crc;
}

void put_u32_big_endian(std::string& bytes, std::size_t at, std::uint32_t value) {
  for (int i = 0; i < 4; ++i) bytes[at + i] = static_cast<char>(value >> (24 - 8 * i));
}

// A small file whose header declares a huge image is refused before the
// reader allocates for it (32768 x 32768 took 2 GB before its error).
TEST(DepthPng, AHeaderDeclaringMoreThanTheFileCanHoldIsRefused) {
  test::ScratchFolder dir;
  test::write_png_gray16(dir / "small.png", 8, 8, ramp(8, 8));
  std::string bytes = slurp(dir / "small.png");
  // Signature (8), IHDR length (4), "IHDR" (4), width (4), height (4), ..., CRC over type and data at 29.
  ASSERT_EQ(bytes.substr(12, 4), "IHDR");
  put_u32_big_endian(bytes, 16, 32768);
  put_u32_big_endian(bytes, 20, 32768);
  put_u32_big_endian(bytes, 29, crc32_of(bytes.substr(12, 17)));
  std::ofstream(dir / "huge.png", std::ios::binary) << bytes;
  EXPECT_THAT(error_message([&] { read_depth_png(dir / "huge.png"); }),
              HasSubstr("huge.png: declares a 32768x32768 image but holds only"));
  // An image at the edge of what deflate can pack stays readable: all zeros, 1024 x 1024.
  test::write_png_gray16(dir / "zeros.png", 1024, 1024, std::vector<std::uint16_t>(1024 * 1024, 0));
  EXPECT_EQ(read_depth_png(dir / "zeros.png").width, 1024);
}

TEST(DepthPng, CorruptDataMissingFileAndNonPngAreErrors) {
  test::ScratchFolder dir;
  test::write_png_gray16(dir / "good.png", 8, 8, ramp(8, 8));
  std::string bytes = slurp(dir / "good.png");
  bytes[bytes.size() / 2] = static_cast<char>(bytes[bytes.size() / 2] ^ 0x5A);  // breaks the IDAT CRC
  std::ofstream(dir / "flipped.png", std::ios::binary) << bytes;
  EXPECT_THAT(error_message([&] { read_depth_png(dir / "flipped.png"); }), HasSubstr("flipped.png"));
  EXPECT_THAT(error_message([&] { read_depth_png(dir / "absent.png"); }), HasSubstr("cannot open"));
  dir.write("text.png", "depth, but as text\n");
  EXPECT_THAT(error_message([&] { read_depth_png(dir / "text.png"); }), HasSubstr("not a PNG"));
}

TEST(BackProjection, MatchesThePinholeFormulaOnKnownPixels) {
  const int w = 4, h = 3;
  DepthImage image{w, h, std::vector<std::uint16_t>(w * h, 0)};
  image.pixels[0 * w + 0] = 5000;   // (0,0): 1 m
  image.pixels[1 * w + 2] = 12345;  // (2,1)
  image.pixels[2 * w + 3] = 65535;  // (3,2): valid for TUM
  const PinholeIntrinsics k{w, h, 500.0, 400.0, 1.5, 1.25};
  DepthDecoding tum;
  tum.units_per_metre = 5000.0;
  const PointBuffer points = back_project(image, k, tum);
  ASSERT_EQ(points.size(), 3u);
  const int us[] = {0, 2, 3}, vs[] = {0, 1, 2};
  const double raw[] = {5000, 12345, 65535};
  for (std::size_t i = 0; i < 3; ++i) {
    const double d = raw[i] / 5000.0;
    EXPECT_FLOAT_EQ(points.z()[i], static_cast<float>(d));
    EXPECT_FLOAT_EQ(points.x()[i], static_cast<float>((us[i] - k.cx) * d / k.fx));
    EXPECT_FLOAT_EQ(points.y()[i], static_cast<float>((vs[i] - k.cy) * d / k.fy));
  }
}

TEST(BackProjection, DropsInvalidAndFarPixels) {
  DepthImage image{3, 1, {0, 65535, 2500}};
  const PinholeIntrinsics k{0, 0, 100.0, 100.0, 1.0, 0.0};
  DepthDecoding mm;
  mm.units_per_metre = 1000.0;
  mm.max_value_is_invalid = true;
  PointBuffer points = back_project(image, k, mm);
  ASSERT_EQ(points.size(), 1u);
  EXPECT_FLOAT_EQ(points.z()[0], 2.5f);
  EXPECT_FLOAT_EQ(points.x()[0], 0.025f);  // (2 - 1) * 2.5 / 100
  mm.max_value_is_invalid = false;
  EXPECT_EQ(back_project(image, k, mm).size(), 2u);
  mm.max_depth = 2.0;  // drops 2.5 m and 65.535 m
  EXPECT_EQ(back_project(image, k, mm).size(), 0u);
}

TEST(BackProjection, ImageSizeMustMatchTheIntrinsics) {
  test::ScratchFolder dir;
  test::write_png_gray16(dir / "d.png", 4, 2, std::vector<std::uint16_t>(8, 1000));
  const PinholeIntrinsics k{640, 480, 525.0, 525.0, 319.5, 239.5};
  const std::string msg = error_message([&] { read_depth_png_points(dir / "d.png", k, DepthDecoding{}); });
  EXPECT_THAT(msg, HasSubstr("d.png"));
  EXPECT_THAT(msg, HasSubstr("4x2"));
  EXPECT_THAT(msg, HasSubstr("640x480"));
}

}  // namespace
}  // namespace sarmap
