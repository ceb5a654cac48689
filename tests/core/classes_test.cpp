#include "engine/core/classes.hpp"

#include <gtest/gtest.h>

namespace sarmap {
namespace {

TEST(Classes, TableIsIndexedById) {
  for (std::size_t i = 0; i < kClassCount; ++i) {
    EXPECT_EQ(static_cast<std::size_t>(kClassTable[i].id), i);
    EXPECT_EQ(class_from_name(kClassTable[i].name), kClassTable[i].id);
  }
  EXPECT_EQ(class_info(ClassId::InclinedRamp).name, "inclined_ramp");
  EXPECT_FALSE(class_from_name("ramp").has_value());
  EXPECT_FALSE(class_from_value(6).has_value());
  EXPECT_EQ(class_from_value(2), ClassId::Wall);
}

TEST(Classes, ColoursFollowThePapers) {
  const Rgb terrain = class_info(ClassId::Terrain).color;  // yellow
  EXPECT_GT(terrain.r, 150);
  EXPECT_GT(terrain.g, 150);
  EXPECT_LT(terrain.b, 100);
  const Rgb wall = class_info(ClassId::Wall).color;  // red
  EXPECT_GT(wall.r, 150);
  EXPECT_LT(wall.g, 100);
  const Rgb inclined = class_info(ClassId::InclinedRamp).color;  // blue
  EXPECT_GT(inclined.b, 150);
  EXPECT_LT(inclined.r, 100);
  const Rgb flat = class_info(ClassId::FlatRamp).color;  // pink / purple
  EXPECT_GT(flat.r, 150);
  EXPECT_GT(flat.b, 150);
  const Rgb other = class_info(ClassId::Other).color;  // grey
  EXPECT_EQ(other.r, other.g);
  EXPECT_EQ(other.g, other.b);
}

}  // namespace
}  // namespace sarmap
