#include "small_cloud_generator.hpp"

#include <cmath>

#include "engine/core/classes.hpp"
#include "test_random.hpp"

namespace sarmap::test {
namespace {

void add(PointBuffer& points, float x, float y, float z, ClassId label) {
  points.push_back(x, y, z);
  const std::size_t i = points.size() - 1;
  const Rgb color = class_info(label).color;
  points.red()[i] = color.r;
  points.green()[i] = color.g;
  points.blue()[i] = color.b;
  points.labels()[i] = static_cast<std::uint8_t>(label);
}

}  // namespace

PointBuffer make_small_arena_cloud() {
  Random random(20240611);
  PointBuffer points;
  points.enable_colors();
  points.enable_labels();
  auto noise = [&random] { return random.uniform(-0.005f, 0.005f); };
  // Floor: 4 m x 4 m at z = 0.
  for (int i = 0; i < 1500; ++i) {
    add(points, random.uniform(0.0f, 4.0f), random.uniform(0.0f, 4.0f), noise(), ClassId::Terrain);
  }
  // Wall: the plane x = 4, 2 m high.
  for (int i = 0; i < 1000; ++i) {
    add(points, 4.0f + noise(), random.uniform(0.0f, 4.0f), random.uniform(0.0f, 2.0f), ClassId::Wall);
  }
  // Ramp: 1 m wide, rising 15 degrees along y from (1, 1, 0) for 2 m.
  const float slope = std::tan(15.0f * 3.14159265f / 180.0f);
  for (int i = 0; i < 800; ++i) {
    const float x = random.uniform(1.0f, 2.0f);
    const float run = random.uniform(0.0f, 2.0f);
    add(points, x, 1.0f + run, run * slope + noise(), ClassId::InclinedRamp);
  }
  return points;
}

}  // namespace sarmap::test
