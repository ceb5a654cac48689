// Tests of engine/sim/random_arena.hpp: arenas differ per seed, repeat for a
// seed, follow the NIST-like recipe, keep elements apart and let the
// trajectory see the ramps; the sensor choice changes the sensor only.
#include "engine/sim/random_arena.hpp"

#include <gtest/gtest.h>

#include <cmath>

#include "engine/sim/ground_truth_grid.hpp"
#include "engine/sim/simulator.hpp"

namespace sarmap::sim {
namespace {

struct Footprint {
  Eigen::Vector2d center;
  double radius;
};

Footprint footprint(const ArenaElement& e) {
  if (const auto* r = std::get_if<InclinedRampSpec>(&e.shape)) return {r->center, 0.5 * std::hypot(r->length, r->width)};
  if (const auto* f = std::get_if<FlatRampSpec>(&e.shape)) return {f->center, 0.5 * f->size.norm()};
  const auto& b = std::get<BoxSpec>(e.shape);
  return {b.center.head<2>(), 0.5 * b.size.head<2>().norm()};
}

double distance_to_wall(const Eigen::Vector2d& p, const WallSpec& w) {
  const Eigen::Vector2d d = w.to - w.from;
  const double u = std::clamp((p - w.from).dot(d) / d.squaredNorm(), 0.0, 1.0);
  return (p - (w.from + u * d)).norm();
}

TEST(RandomArena, SeedsGiveDifferentValidArenas) {
  std::vector<std::string> texts;
  for (std::uint64_t seed : {1u, 2u, 3u, 4u}) {
    SCOPED_TRACE(seed);
    texts.push_back(random_arena_json(seed));
    EXPECT_EQ(random_arena_json(seed), texts.back());
    const Arena a = random_arena(seed);
    EXPECT_EQ(a.name, "random-" + std::to_string(seed));
    EXPECT_TRUE(a.floor);
    int inclined = 0, flat = 0, walls = 0;
    std::vector<Footprint> features;
    std::vector<WallSpec> wall_specs;
    for (const ArenaElement& e : a.elements) {
      if (const auto* w = std::get_if<WallSpec>(&e.shape)) {
        ++walls;
        wall_specs.push_back(*w);
        continue;
      }
      if (const auto* r = std::get_if<InclinedRampSpec>(&e.shape)) {
        ++inclined;
        EXPECT_GE(r->angle_deg, 10);
        EXPECT_LE(r->angle_deg, 25);
      }
      if (const auto* f = std::get_if<FlatRampSpec>(&e.shape)) {
        ++flat;
        EXPECT_GE(f->height, 0.1);
        EXPECT_LE(f->height, 0.4);
      }
      features.push_back(footprint(e));
    }
    EXPECT_GE(walls, 6);  // four outer walls and interior ones
    EXPECT_GE(inclined, 1);
    EXPECT_LE(inclined, 4);
    EXPECT_GE(flat, 1);
    EXPECT_LE(flat, 3);
    // No two features overlap, none touches a wall.
    for (std::size_t i = 0; i < features.size(); ++i) {
      for (std::size_t k = i + 1; k < features.size(); ++k) {
        EXPECT_GT((features[i].center - features[k].center).norm(), features[i].radius + features[k].radius);
      }
      for (const WallSpec& w : wall_specs) {
        EXPECT_GT(distance_to_wall(features[i].center, w), features[i].radius + 0.05);
      }
    }
    // The trajectory keeps off walls and features.
    for (const Eigen::Vector2d& p : a.trajectory.waypoints) {
      EXPECT_TRUE(p.x() > 0 && p.y() > 0 && p.x() < a.bounds_max.x() && p.y() < a.bounds_max.y());
      for (const WallSpec& w : wall_specs) EXPECT_GT(distance_to_wall(p, w), 0.3);
      for (const Footprint& f : features) EXPECT_GT((p - f.center).norm(), f.radius + 0.3);
    }
  }
  for (std::size_t i = 0; i < texts.size(); ++i) {
    for (std::size_t k = i + 1; k < texts.size(); ++k) EXPECT_NE(texts[i], texts[k]);
  }
}

TEST(RandomArena, TrajectorySeesEveryRampClass) {
  const Arena a = random_arena(42);
  const Simulator sim(a, {.noise = false});
  const GroundTruthGrid g = voxelize_arena(sim, {.resolution = 0.1, .frame_stride = 6, .ray_stride = 12});
  const auto seen = g.occupied_per_class(true);
  EXPECT_GT(seen[static_cast<std::size_t>(ClassId::InclinedRamp)], 5u);
  EXPECT_GT(seen[static_cast<std::size_t>(ClassId::FlatRamp)], 5u);
  EXPECT_GT(seen[static_cast<std::size_t>(ClassId::Wall)], 50u);
  EXPECT_GT(seen[static_cast<std::size_t>(ClassId::Terrain)], 50u);
}

// The default sensor is the depth camera random arenas had before the choice:
// the text is pinned by its SHA-256 (taken from `sarmap simulate --random 17
// --write-arena` before the sensor options existed), so the sequences stay
// byte for byte what they were.
TEST(RandomArena, DefaultSensorKeepsTheDescription) {
  EXPECT_EQ(random_arena(17).sha256, "74cf334adf237aed554876650bf537076cc63b3a284467be186cb260bd8d0727");
  EXPECT_EQ(random_arena_json(17, RandomSensor{}), random_arena_json(17));
  const Arena a = random_arena(17);
  EXPECT_EQ(a.sensor.type, SensorType::DepthCamera);
  EXPECT_EQ(a.sensor.intrinsics.width, 320);
  EXPECT_DOUBLE_EQ(a.sensor.intrinsics.fx, 277);
  EXPECT_DOUBLE_EQ(a.sensor.max_range, 5.0);
}

TEST(RandomArena, LidarSensorKeepsLayoutAndPath) {
  RandomSensor lidar;
  lidar.type = SensorType::Lidar;
  lidar.rings = 32;
  lidar.samples = 900;
  lidar.vertical_fov_min_deg = -30;
  lidar.vertical_fov_max_deg = 10;
  lidar.max_range = 20;
  lidar.height = 0.8;
  const Arena a = random_arena(17, lidar);
  const Arena depth = random_arena(17);
  EXPECT_EQ(a.sensor.type, SensorType::Lidar);
  EXPECT_EQ(a.sensor.rings, 32);
  EXPECT_EQ(a.sensor.horizontal_samples, 900);
  EXPECT_DOUBLE_EQ(a.sensor.vertical_fov_min_deg, -30);
  EXPECT_DOUBLE_EQ(a.sensor.vertical_fov_max_deg, 10);
  EXPECT_DOUBLE_EQ(a.sensor.min_range, 0.4);
  EXPECT_DOUBLE_EQ(a.sensor.max_range, 20);
  EXPECT_DOUBLE_EQ(a.trajectory.height, 0.8);
  EXPECT_DOUBLE_EQ(a.trajectory.pitch_deg, 0);  // a LiDAR is mounted level unless asked
  EXPECT_EQ(a.elements.size(), depth.elements.size());
  EXPECT_EQ(a.trajectory.frames, depth.trajectory.frames);
  ASSERT_EQ(a.trajectory.waypoints.size(), depth.trajectory.waypoints.size());
  for (std::size_t i = 0; i < a.trajectory.waypoints.size(); ++i) {
    EXPECT_EQ(a.trajectory.waypoints[i], depth.trajectory.waypoints[i]);
  }
}

TEST(RandomArena, DepthCameraSizeKeepsTheFieldOfView) {
  RandomSensor camera;
  camera.width = 640;
  camera.image_height = 480;
  camera.pitch_deg = -15;
  camera.min_range = 0.5;
  camera.max_range = 8;
  const Arena a = random_arena(17, camera);
  EXPECT_EQ(a.sensor.intrinsics.width, 640);
  EXPECT_EQ(a.sensor.intrinsics.height, 480);
  EXPECT_DOUBLE_EQ(a.sensor.intrinsics.fx, 554);
  EXPECT_DOUBLE_EQ(a.sensor.intrinsics.fy, 554);
  EXPECT_DOUBLE_EQ(a.sensor.intrinsics.cx, 320);
  EXPECT_DOUBLE_EQ(a.sensor.intrinsics.cy, 240);
  EXPECT_DOUBLE_EQ(a.sensor.min_range, 0.5);
  EXPECT_DOUBLE_EQ(a.sensor.max_range, 8);
  EXPECT_DOUBLE_EQ(a.trajectory.pitch_deg, -15);
  EXPECT_EQ(a.sensor.noise.kind, NoiseKind::Kinect);
}

}  // namespace
}  // namespace sarmap::sim
