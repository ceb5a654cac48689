#include "engine/core/point_buffer.hpp"

#include <cmath>
#include <cstdint>
#include <gtest/gtest.h>
#include <limits>

namespace sarmap {
namespace {

TEST(PointBuffer, ArraysAreCacheLineAligned) {
  PointBuffer points(37);
  points.enable_labels();
  points.add_score("wall");
  EXPECT_EQ(reinterpret_cast<std::uintptr_t>(points.x().data()) % 64, 0u);
  EXPECT_EQ(reinterpret_cast<std::uintptr_t>(points.z().data()) % 64, 0u);
  EXPECT_EQ(reinterpret_cast<std::uintptr_t>(points.labels().data()) % 64, 0u);
  EXPECT_EQ(reinterpret_cast<std::uintptr_t>(points.score(0).data()) % 64, 0u);
}

TEST(PointBuffer, PushBackGrowsEnabledAttributes) {
  PointBuffer points;
  points.enable_labels();
  points.enable_colors();
  points.push_back(1, 2, 3);
  points.labels()[0] = 4;
  points.push_back(4, 5, 6);
  ASSERT_EQ(points.size(), 2u);
  EXPECT_EQ(points.labels().size(), 2u);
  EXPECT_EQ(points.labels()[0], 4);
  EXPECT_EQ(points.labels()[1], 0);
  EXPECT_EQ(points.red().size(), 2u);
  EXPECT_FALSE(points.has_normals());
  EXPECT_EQ(points.normal_x().size(), 0u);
}

TEST(PointBuffer, AppendUnitesAttributes) {
  PointBuffer a;
  a.push_back(0, 0, 0);
  PointBuffer b;
  b.enable_labels();
  b.push_back(1, 1, 1);
  b.labels()[0] = 2;
  b.add_score("terrain");
  b.score(0)[0] = 0.5f;
  a.append(b);
  ASSERT_EQ(a.size(), 2u);
  ASSERT_TRUE(a.has_labels());
  EXPECT_EQ(a.labels()[0], 0);
  EXPECT_EQ(a.labels()[1], 2);
  ASSERT_EQ(a.score_count(), 1u);
  EXPECT_FLOAT_EQ(a.score(0)[0], 0.0f);
  EXPECT_FLOAT_EQ(a.score(0)[1], 0.5f);
}

TEST(PointBuffer, RemoveNonFiniteKeepsAttributesInStep) {
  PointBuffer points;
  points.enable_labels();
  const float nan = std::numeric_limits<float>::quiet_NaN();
  const float inf = std::numeric_limits<float>::infinity();
  const float xs[] = {0, nan, 2, 3, 4};
  const float ys[] = {0, 0, inf, 0, 0};
  for (int i = 0; i < 5; ++i) {
    points.push_back(xs[i], ys[i], 0);
    points.labels()[static_cast<std::size_t>(i)] = static_cast<std::uint8_t>(i);
  }
  EXPECT_EQ(points.remove_non_finite(), 2u);
  ASSERT_EQ(points.size(), 3u);
  EXPECT_EQ(points.labels()[0], 0);
  EXPECT_EQ(points.labels()[1], 3);
  EXPECT_EQ(points.labels()[2], 4);
  EXPECT_FLOAT_EQ(points.x()[2], 4.0f);
}

TEST(PointBuffer, SelectAndBounds) {
  PointBuffer points;
  for (int i = 0; i < 10; ++i) points.push_back(static_cast<float>(i), -static_cast<float>(i), 1.0f);
  const std::uint32_t pick[] = {7, 2};
  const PointBuffer picked = points.select(pick);
  ASSERT_EQ(picked.size(), 2u);
  EXPECT_FLOAT_EQ(picked.x()[0], 7.0f);
  EXPECT_FLOAT_EQ(picked.y()[1], -2.0f);
  const Bounds b = points.bounds();
  EXPECT_DOUBLE_EQ(b.min.x(), 0.0);
  EXPECT_DOUBLE_EQ(b.max.x(), 9.0);
  EXPECT_DOUBLE_EQ(b.min.y(), -9.0);
  EXPECT_TRUE(PointBuffer().bounds().empty());
}

}  // namespace
}  // namespace sarmap
