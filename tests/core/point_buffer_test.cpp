#include "engine/core/point_buffer.hpp"

#include <cmath>
#include <cstdint>
#include <gtest/gtest.h>
#include <limits>
#include <random>
#include <vector>

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

// Both removals against a plain check (std::isfinite; the distance in
// double) on random points with NaN, +-inf and the largest finite values in
// every axis, points exactly at the distance, and scans that lose nothing.
TEST(PointBuffer, RemovalsMatchAPlainCheckAndLeaveWholeScansAlone) {
  const float specials[] = {std::numeric_limits<float>::quiet_NaN(), std::numeric_limits<float>::infinity(),
                            -std::numeric_limits<float>::infinity(), std::numeric_limits<float>::max(),
                            -std::numeric_limits<float>::max(), 3.0f};
  std::mt19937 rng(5);
  std::uniform_real_distribution<float> coordinate(-5.0f, 5.0f);
  std::uniform_int_distribution<int> pick(0, 19);
  const Eigen::Vector3d centre(0.5, -0.25, 1.0);
  const double distance = 4.0;
  for (int round = 0; round < 20; ++round) {
    PointBuffer points;
    points.enable_labels();
    for (std::size_t i = 0; i < 300; ++i) {
      float p[3];
      for (float& v : p) {
        const int k = pick(rng);
        v = round % 4 == 0 || k >= 6 ? coordinate(rng) : specials[k];  // every fourth round: all finite
      }
      points.push_back(p[0], p[1], p[2]);
      points.labels()[i] = static_cast<std::uint8_t>(i % 251);
    }
    points.push_back(static_cast<float>(centre.x() + distance), static_cast<float>(centre.y()),
                     static_cast<float>(centre.z()));  // exactly at the distance: kept
    points.labels()[points.size() - 1] = 255;
    std::vector<std::uint8_t> finite_labels, near_labels;
    for (std::size_t i = 0; i < points.size(); ++i) {
      const double x = points.x()[i], y = points.y()[i], z = points.z()[i];
      if (!std::isfinite(x) || !std::isfinite(y) || !std::isfinite(z)) continue;
      finite_labels.push_back(points.labels()[i]);
      const Eigen::Vector3d d = Eigen::Vector3d(x, y, z) - centre;
      if (d.squaredNorm() <= distance * distance) near_labels.push_back(points.labels()[i]);
    }
    const std::size_t before = points.size();
    EXPECT_EQ(points.remove_non_finite(), before - finite_labels.size());
    EXPECT_EQ(std::vector<std::uint8_t>(points.labels().begin(), points.labels().end()), finite_labels);
    EXPECT_EQ(points.remove_farther_than(centre, distance), finite_labels.size() - near_labels.size());
    EXPECT_EQ(std::vector<std::uint8_t>(points.labels().begin(), points.labels().end()), near_labels);
    EXPECT_EQ(points.labels().back(), 255);
    // Nothing left to remove: both return 0 and change nothing.
    const std::vector<float> xs(points.x().begin(), points.x().end());
    EXPECT_EQ(points.remove_non_finite(), 0u);
    EXPECT_EQ(points.remove_farther_than(centre, distance), 0u);
    EXPECT_EQ(std::vector<float>(points.x().begin(), points.x().end()), xs);
  }
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
