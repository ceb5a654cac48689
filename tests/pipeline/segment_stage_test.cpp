// The segment stage as the Mapper runs it: its range limit follows the
// sensor (a depth camera's noise grows with the square of the range, a
// LiDAR's does not).
#include "engine/pipeline/mapper.hpp"

#include <gtest/gtest.h>

namespace sarmap::pipeline {
namespace {

// A 10 x 10 m floor of labelled points seen from 1 m above its corner: most lie beyond 3 m.
Scan far_floor() {
  Scan scan;
  scan.points.enable_labels();
  for (double x = 0; x <= 10; x += 0.05) {
    for (double y = 0; y <= 10; y += 0.05) {
      scan.points.push_back(static_cast<float>(x), static_cast<float>(y), 0);
      scan.points.labels()[scan.points.size() - 1] = static_cast<std::uint8_t>(ClassId::Terrain);
    }
  }
  scan.origin = {0, 0, 1};
  return scan;
}

double far_points(SensorType type) {
  MapperConfig config;
  config.classifier.kind = pipeline::ClassifierKind::Labels;
  SensorInfo sensor;
  sensor.type = type;
  Mapper mapper(config, sensor);
  Scan scan = far_floor();
  mapper.integrate(scan);
  EXPECT_EQ(mapper.segment_map().of_class(ClassId::Terrain).size(), 1u);
  return mapper.profile().counter("segment", "points_far");
}

TEST(SegmentStage, RangeLimitForDepthCamerasNotForLidars) {
  EXPECT_GT(far_points(SensorType::DepthCamera), 30000.0);
  EXPECT_EQ(far_points(SensorType::Lidar), 0.0);
}

}  // namespace
}  // namespace sarmap::pipeline
