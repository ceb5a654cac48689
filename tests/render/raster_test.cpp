// Tests of engine/render/raster.hpp: the exact pixels a line, a disc and a
// polygon outline cover, and shapes off the image clipped without harm.
#include "engine/render/raster.hpp"

#include <gtest/gtest.h>

#include <array>
#include <limits>

namespace sarmap::render {
namespace {

constexpr Rgb kInk{10, 20, 30};

bool inked(const RgbImage& image, int x, int y) {
  const Rgb c = image.at(x, y);
  return c.r == kInk.r && c.g == kInk.g && c.b == kInk.b;
}

int inked_count(const RgbImage& image) {
  int n = 0;
  for (int y = 0; y < image.height(); ++y) {
    for (int x = 0; x < image.width(); ++x) n += inked(image, x, y) ? 1 : 0;
  }
  return n;
}

TEST(Raster, AHorizontalLineCoversTheRowsWithinHalfItsWidth) {
  RgbImage image(64, 32);
  // Along y = 10.5 (the centres of row 10) from x = 10 to 50, 3 pixels wide:
  // rows 9 to 11, columns whose centres lie in [8.5, 51.5] by the round caps.
  draw_line(image, {10, 10.5f}, {50, 10.5f}, 3.0f, kInk);
  for (int y = 0; y < 32; ++y) {
    for (int x = 0; x < 64; ++x) {
      const bool body = y >= 9 && y <= 11 && x >= 10 && x <= 49;
      if (body) {
        EXPECT_TRUE(inked(image, x, y)) << x << ", " << y;
      }
      if (y < 9 || y > 11 || x < 8 || x > 51) {
        EXPECT_FALSE(inked(image, x, y)) << x << ", " << y;
      }
    }
  }
}

TEST(Raster, ADiscCoversThePixelsWhoseCentresLieWithinItsRadius) {
  RgbImage image(20, 20);
  fill_disc(image, {10, 10}, 2.0f, kInk);
  // Centres at (x + 0.5, y + 0.5) within 2 of (10, 10): x, y in 8..11 less the
  // four corners (distance 2.12).
  EXPECT_EQ(inked_count(image), 12);
  EXPECT_TRUE(inked(image, 9, 9));
  EXPECT_FALSE(inked(image, 8, 8));
}

TEST(Raster, APolygonOutlineLeavesItsInsideAlone) {
  RgbImage image(40, 40);
  const std::array<Eigen::Vector2f, 4> square{{{5, 5}, {35, 5}, {35, 35}, {5, 35}}};
  draw_polygon(image, square, 2.0f, kInk);
  EXPECT_TRUE(inked(image, 20, 4));
  EXPECT_TRUE(inked(image, 34, 20));
  EXPECT_FALSE(inked(image, 20, 20));
}

TEST(Raster, ShapesOffTheImageAreClipped) {
  RgbImage image(10, 10);
  draw_line(image, {-1e30f, 5.5f}, {1e30f, 5.5f}, 1.0f, kInk);
  EXPECT_EQ(inked_count(image), 10);
  const float nan = std::numeric_limits<float>::quiet_NaN();
  draw_line(image, {nan, 0}, {5, 5}, 1.0f, {0, 0, 0});
  fill_disc(image, {100, 100}, 3.0f, {0, 0, 0});
  EXPECT_EQ(inked_count(image), 10);
}

}  // namespace
}  // namespace sarmap::render
