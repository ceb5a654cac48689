#include "engine/core/class_colors.hpp"

#include <gtest/gtest.h>

#include "engine/core/classes.hpp"
#include "engine/core/error.hpp"

namespace sarmap {
namespace {

TEST(ClassColors, EachPointTakesItsClassColourFromTheTable) {
  PointBuffer points;
  points.enable_labels();
  for (std::size_t c = 0; c < kClassCount; ++c) {
    points.push_back(static_cast<float>(c), 0, 0);
    points.labels()[c] = static_cast<std::uint8_t>(c);
  }
  points.push_back(9, 0, 0);
  points.labels()[kClassCount] = 200;  // no class: painted as unknown
  paint_class_colors(points);
  ASSERT_TRUE(points.has_colors());
  for (std::size_t i = 0; i < points.size(); ++i) {
    const Rgb want = class_info(i < kClassCount ? static_cast<ClassId>(i) : ClassId::Unknown).color;
    EXPECT_EQ(points.red()[i], want.r) << i;
    EXPECT_EQ(points.green()[i], want.g) << i;
    EXPECT_EQ(points.blue()[i], want.b) << i;
  }
}

TEST(ClassColors, OverwritesColoursAPointAlreadyHad) {
  PointBuffer points;
  points.enable_labels();
  points.enable_colors();
  points.push_back(0, 0, 0);
  points.labels()[0] = static_cast<std::uint8_t>(ClassId::Wall);
  points.red()[0] = points.green()[0] = points.blue()[0] = 7;
  paint_class_colors(points);
  EXPECT_EQ(points.red()[0], class_info(ClassId::Wall).color.r);
  EXPECT_EQ(points.green()[0], class_info(ClassId::Wall).color.g);
}

TEST(ClassColors, PointsWithoutLabelsAreRefused) {
  PointBuffer points;
  points.push_back(0, 0, 0);
  EXPECT_THROW(paint_class_colors(points), Error);
}

}  // namespace
}  // namespace sarmap
