// Tests of engine/eval/confusion_matrix.hpp on a matrix worked out by hand.
#include "engine/eval/confusion_matrix.hpp"

#include <gtest/gtest.h>

namespace sarmap::eval {
namespace {

// terrain->terrain 5, terrain->wall 1, wall->wall 3, wall->unknown 1,
// inclined->inclined 2, inclined->flat 1, other->terrain 1.
ConfusionMatrix example() {
  ConfusionMatrix m;
  m.add(ClassId::Terrain, ClassId::Terrain, 5);
  m.add(ClassId::Terrain, ClassId::Wall);
  m.add(ClassId::Wall, ClassId::Wall, 3);
  m.add(ClassId::Wall, ClassId::Unknown);
  m.add(ClassId::InclinedRamp, ClassId::InclinedRamp, 2);
  m.add(ClassId::InclinedRamp, ClassId::FlatRamp);
  m.add(ClassId::Other, ClassId::Terrain);
  return m;
}

TEST(ConfusionMatrix, HandComputedFigures) {
  const ConfusionMatrix m = example();
  EXPECT_EQ(m.total(), 14u);
  EXPECT_EQ(m.count(ClassId::Wall, ClassId::Unknown), 1u);
  EXPECT_EQ(m.truth_total(ClassId::Terrain), 6u);
  EXPECT_EQ(m.predicted_total(ClassId::Terrain), 6u);
  EXPECT_DOUBLE_EQ(*m.accuracy(), 10.0 / 14.0);
  EXPECT_DOUBLE_EQ(*m.iou(ClassId::Terrain), 5.0 / 7.0);        // 5 / (6 + 6 - 5)
  EXPECT_DOUBLE_EQ(*m.iou(ClassId::Wall), 3.0 / 5.0);           // 3 / (4 + 4 - 3)
  EXPECT_DOUBLE_EQ(*m.iou(ClassId::InclinedRamp), 2.0 / 3.0);   // 2 / (3 + 2 - 2)
  EXPECT_DOUBLE_EQ(*m.iou(ClassId::FlatRamp), 0.0);             // predicted once, never true
  EXPECT_DOUBLE_EQ(*m.iou(ClassId::Other), 0.0);
  EXPECT_DOUBLE_EQ(*m.mean_iou(), (5.0 / 7.0 + 3.0 / 5.0 + 2.0 / 3.0 + 0.0) / 4.0);
  EXPECT_DOUBLE_EQ(*m.precision(ClassId::Wall), 3.0 / 4.0);
  EXPECT_DOUBLE_EQ(*m.recall(ClassId::Wall), 3.0 / 4.0);
  EXPECT_DOUBLE_EQ(*m.recall(ClassId::InclinedRamp), 2.0 / 3.0);
  EXPECT_FALSE(m.recall(ClassId::FlatRamp).has_value());
  EXPECT_FALSE(m.precision(ClassId::Other).has_value());
}

TEST(ConfusionMatrix, UndefinedFiguresAndMerge) {
  ConfusionMatrix empty;
  EXPECT_FALSE(empty.accuracy().has_value());
  EXPECT_FALSE(empty.iou(ClassId::Wall).has_value());
  EXPECT_FALSE(empty.mean_iou().has_value());
  // Only terrain is defined: the mean is its IoU alone.
  ConfusionMatrix terrain;
  terrain.add(ClassId::Terrain, ClassId::Terrain, 3);
  terrain.add(ClassId::Terrain, ClassId::Unknown, 1);
  EXPECT_DOUBLE_EQ(*terrain.mean_iou(), 0.75);
  EXPECT_DOUBLE_EQ(*terrain.accuracy(), 0.75);
  // An unknown prediction is wrong even against an unknown truth.
  ConfusionMatrix unknown;
  unknown.add(ClassId::Unknown, ClassId::Unknown);
  EXPECT_DOUBLE_EQ(*unknown.accuracy(), 0.0);
  ConfusionMatrix twice = example();
  twice.merge(example());
  EXPECT_EQ(twice.total(), 28u);
  EXPECT_DOUBLE_EQ(*twice.iou(ClassId::Wall), 3.0 / 5.0);
  const std::array<ClassId, 2> some{ClassId::Wall, ClassId::InclinedRamp};
  EXPECT_DOUBLE_EQ(*twice.mean_iou(some), (3.0 / 5.0 + 2.0 / 3.0) / 2.0);
}

}  // namespace
}  // namespace sarmap::eval
