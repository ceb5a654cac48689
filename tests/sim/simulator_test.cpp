// Tests of engine/sim/simulator.hpp, ground_height.hpp, trajectory.hpp and
// sensor_rays.hpp: points lie on the surfaces they hit, carry the surface's
// class, follow the noise model, and do not depend on the thread count.
#include "engine/sim/simulator.hpp"

#include <gtest/gtest.h>
#include <tbb/task_arena.h>

#include <cmath>
#include <cstring>
#include <numbers>
#include <set>

#include "engine/core/degrees.hpp"
#include "engine/io/scan_source.hpp"
#include "engine/sim/arena_mesh.hpp"
#include "engine/sim/ground_height.hpp"
#include "engine/sim/ray_noise.hpp"
#include "engine/sim/trajectory.hpp"
#include "tests/sim/run_cli.hpp"
#include "tests/sim/test_arenas.hpp"

namespace sarmap::sim {
namespace {

using nlohmann::json;

// An arena seen from one explicit pose: body at `position`, heading yaw, pitch.
json one_pose(const Eigen::Vector3d& position, double yaw_deg, double pitch_deg, bool depth_camera = true) {
  Eigen::Matrix3d r = body_rotation(yaw_deg * kDeg, pitch_deg);
  if (depth_camera) r = r * optical_to_body();
  return {{"poses", {testing::pose_json(r, position)}}};
}

TEST(Simulator, FloorAndWallPointsLieOnTheirPlanes) {
  json j = testing::base_arena_json();
  j["elements"] = json::parse(R"([{"type": "wall", "from": [3, 0], "to": [3, 4], "height": 1.2, "thickness": 0.2}])");
  j["trajectory"] = one_pose({1, 2, 0.6}, 0, -20);
  j["sensor"]["width"] = 64;
  j["sensor"]["height"] = 48;
  j["sensor"]["cx"] = 32;
  j["sensor"]["cy"] = 24;
  j["sensor"]["fx"] = 40;
  j["sensor"]["fy"] = 40;
  const Simulator sim(testing::parse_test_arena(j));
  ASSERT_EQ(sim.frame_count(), 1u);
  const Scan scan = sim.simulate(0);
  ASSERT_TRUE(scan.points.has_labels());
  EXPECT_TRUE(scan.origin.isApprox(Eigen::Vector3d(1, 2, 0.6)));
  std::size_t walls = 0, floors = 0;
  for (std::size_t i = 0; i < scan.points.size(); ++i) {
    const auto label = static_cast<ClassId>(scan.points.labels()[i]);
    if (label == ClassId::Wall) {
      ++walls;
      EXPECT_NEAR(scan.points.x()[i], 2.9, 1e-5);
    } else {
      ASSERT_EQ(label, ClassId::Terrain);
      ++floors;
      EXPECT_NEAR(scan.points.z()[i], 0.0, 1e-5);
    }
  }
  EXPECT_GT(walls, 100u);
  EXPECT_GT(floors, 100u);
  // Looking down 20 degrees from 0.6 m with a 1.9 m deep wall ahead, every
  // pixel sees something within range.
  EXPECT_EQ(scan.points.size(), 64u * 48u);
}

TEST(Simulator, RayOnInclinedRampReturnsAnalyticDistance) {
  ArenaElement ramp;
  ramp.shape = InclinedRampSpec{{2, 2}, 2.0, 1.0, 20, 0};
  ramp.label = ClassId::InclinedRamp;
  std::vector<ClassedMesh> meshes{element_mesh(ramp)};
  const geometry::TriangleScene scene(meshes);
  const double tan20 = std::tan(20 * kDeg);
  // Straight down onto the slope, 1.5 m from its low edge.
  auto hit = scene.intersect({2.5f, 2.0f, 3.0f}, {0, 0, -1}, 0, 100);
  ASSERT_TRUE(hit.hit);
  EXPECT_EQ(hit.label, ClassId::InclinedRamp);
  EXPECT_NEAR(hit.t, 3.0 - 1.5 * tan20, 1e-5);
  // Horizontally into the slope from the low side at 0.2 m.
  hit = scene.intersect({0.0f, 2.0f, 0.2f}, {1, 0, 0}, 0, 100);
  ASSERT_TRUE(hit.hit);
  EXPECT_NEAR(hit.t, 1.0 + 0.2 / tan20, 1e-5);
  // Into the vertical back face from behind.
  hit = scene.intersect({5.0f, 2.0f, 0.2f}, {-1, 0, 0}, 0, 100);
  ASSERT_TRUE(hit.hit);
  EXPECT_NEAR(hit.t, 2.0, 1e-5);
  // Above the high end: a miss.
  EXPECT_FALSE(scene.intersect({5.0f, 2.0f, 1.0f}, {-1, 0, 0}, 0, 100).hit);
  // The ground under the slope for the trajectory.
  EXPECT_NEAR(ground_height(scene, 2.5, 2.0, 3.0), 1.5 * tan20, 1e-5);
}

TEST(Simulator, EveryElementTypeGivesItsClass) {
  json j = testing::base_arena_json();
  j["bounds"]["max"] = {6, 6, 4};
  j["elements"] = json::parse(R"([
    {"type": "wall", "from": [0.5, 0.5], "to": [0.5, 5.5], "height": 1.2, "thickness": 0.2},
    {"type": "inclined_ramp", "center": [2, 1.5], "length": 1.2, "width": 1.0, "angle_deg": 15},
    {"type": "flat_ramp", "center": [4, 1.5], "size": [1.2, 1.0], "height": 0.3},
    {"type": "box", "center": [2, 4, 0.3], "size": [0.6, 0.6, 0.6], "yaw_deg": 30, "label": "other"},
    {"type": "mesh", "path": "data/unit_square.obj", "position": [3.5, 3.5, 0], "label": "wall"}
  ])");
  j["trajectory"] = one_pose({3, 3, 4.0}, 0, -89);
  j["sensor"] = json::parse(R"({"type": "depth_camera", "width": 120, "height": 120, "fx": 25, "fy": 25,
                                "cx": 60, "cy": 60, "min_range": 0.1, "max_range": 10, "noise": "none"})");
  const Arena arena = testing::parse_test_arena(j, SARMAP_SOURCE_DIR "/tests/sim");
  const Simulator sim(arena);
  // Straight down onto each element: its own class.
  const std::vector<std::pair<Eigen::Vector2f, ClassId>> probes = {
      {{0.5f, 3.0f}, ClassId::Wall},   {{2.0f, 1.5f}, ClassId::InclinedRamp}, {{4.0f, 1.5f}, ClassId::FlatRamp},
      {{2.0f, 4.0f}, ClassId::Other},  {{4.0f, 4.0f}, ClassId::Wall},         {{5.0f, 5.8f}, ClassId::Terrain}};
  for (const auto& [xy, label] : probes) {
    const auto hit = sim.scene().intersect({xy.x(), xy.y(), 3.5f}, {0, 0, -1}, 0, 10);
    ASSERT_TRUE(hit.hit);
    EXPECT_EQ(hit.label, label) << xy.transpose();
  }
  // And every class reaches the simulated points.
  const Scan scan = sim.simulate(0);
  std::set<int> labels(scan.points.labels().begin(), scan.points.labels().end());
  EXPECT_EQ(labels, (std::set<int>{1, 2, 3, 4, 5}));
}

TEST(Simulator, LidarRangesInASquareRoom) {
  json j = testing::base_arena_json();
  j["elements"] = json::parse(R"([
    {"type": "wall", "from": [0, 0], "to": [4, 0], "height": 1.2, "thickness": 0.2},
    {"type": "wall", "from": [4, 0], "to": [4, 4], "height": 1.2, "thickness": 0.2},
    {"type": "wall", "from": [4, 4], "to": [0, 4], "height": 1.2, "thickness": 0.2},
    {"type": "wall", "from": [0, 4], "to": [0, 0], "height": 1.2, "thickness": 0.2}
  ])");
  j["trajectory"] = one_pose({2, 2, 0.5}, 30, 0, false);
  j["sensor"] = json::parse(R"({"type": "lidar", "rings": 1, "horizontal_samples": 360,
                                "vertical_fov_deg": [0, 0], "min_range": 0.1, "max_range": 10})");
  const Simulator sim(testing::parse_test_arena(j));
  const Scan scan = sim.simulate(0);
  ASSERT_EQ(scan.points.size(), 360u);
  for (std::size_t i = 0; i < scan.points.size(); ++i) {
    EXPECT_EQ(scan.points.labels()[i], static_cast<int>(ClassId::Wall));
    const double dx = scan.points.x()[i] - 2.0, dy = scan.points.y()[i] - 2.0;
    // The inner faces are 1.9 m from the centre.
    EXPECT_NEAR(std::max(std::abs(dx), std::abs(dy)), 1.9, 1e-5);
    EXPECT_NEAR(scan.points.z()[i], 0.5, 1e-5);
  }
  // Ray 0 looks along the body's x, which the pose turned by 30 degrees.
  const double a = std::atan2(scan.points.y()[0] - 2.0, scan.points.x()[0] - 2.0);
  EXPECT_NEAR(a, 30 * kDeg, 1e-5);
}

Arena noisy_wall_arena(const char* noise, double dropout) {
  json j = testing::base_arena_json();
  j["elements"] = json::parse(R"([{"type": "wall", "from": [3, 0], "to": [3, 4], "height": 2, "thickness": 0.2}])");
  j["trajectory"] = one_pose({1, 2, 1.0}, 0, 0);
  j["sensor"] = json::parse(R"({"type": "depth_camera", "width": 200, "height": 100, "fx": 400, "fy": 400,
                                "cx": 100, "cy": 50, "min_range": 0.1, "max_range": 6})");
  j["sensor"]["noise"] = noise;
  if (std::string(noise) == "gaussian") j["sensor"]["sigma"] = 0.01;
  if (dropout > 0) j["sensor"]["dropout"] = dropout;
  return testing::parse_test_arena(j);
}

TEST(Simulator, KinectNoiseFollowsTheDepthModel) {
  // A fronto-parallel wall at depth 1.9 m: each point's x error is the depth error.
  const Simulator sim(noisy_wall_arena("kinect", 0), {.seed = 7});
  const Scan scan = sim.simulate(0);
  ASSERT_EQ(scan.points.size(), 20000u);
  double sum = 0, sum2 = 0;
  for (float x : scan.points.x()) {
    const double e = x - 2.9;
    sum += e;
    sum2 += e * e;
  }
  const double n = static_cast<double>(scan.points.size());
  const double mean = sum / n, sd = std::sqrt(sum2 / n - mean * mean);
  EXPECT_NEAR(mean, 0.0, 4 * kinect_sigma(1.9) / std::sqrt(n) + 1e-6);
  EXPECT_NEAR(sd, kinect_sigma(1.9), 0.03 * kinect_sigma(1.9));
  // The noise moves points along their pixel's ray: y and z stay on it.
  const auto& rays = sim.rays().directions;
  for (std::size_t i = 0; i < 50; ++i) {
    const double depth = scan.points.x()[i] - 1.0;
    EXPECT_NEAR(scan.points.y()[i], 2.0 - rays[i].x() * depth, 1e-5);
  }
}

TEST(Simulator, GaussianNoiseAndDropout) {
  const Simulator sim(noisy_wall_arena("gaussian", 0.25), {.seed = 3});
  const Scan scan = sim.simulate(0);
  const double kept = static_cast<double>(scan.points.size()) / 20000.0;
  EXPECT_NEAR(kept, 0.75, 0.015);
  double sum2 = 0;
  for (float x : scan.points.x()) sum2 += (x - 2.9) * (x - 2.9);
  EXPECT_NEAR(std::sqrt(sum2 / static_cast<double>(scan.points.size())), 0.01, 0.0005);
  // Turning noise off gives the exact surface.
  const Simulator exact(noisy_wall_arena("gaussian", 0.25), {.seed = 3, .noise = false});
  const Scan clean = exact.simulate(0);
  EXPECT_EQ(clean.points.size(), 20000u);
  for (float x : clean.points.x()) ASSERT_NEAR(x, 2.9, 1e-5);
}

Arena default_arena_with_dropout() {
  Arena a = load_arena(SARMAP_SOURCE_DIR "/datasets/arenas/esogu-6x4.json");
  a.sensor.noise.dropout = 0.1;
  return a;
}

bool identical(const Scan& a, const Scan& b) {
  const auto& p = a.points;
  const auto& q = b.points;
  if (p.size() != q.size()) return false;
  for (std::size_t i = 0; i < p.size(); ++i) {
    if (std::memcmp(&p.x()[i], &q.x()[i], sizeof(float)) != 0 || std::memcmp(&p.y()[i], &q.y()[i], sizeof(float)) != 0 ||
        std::memcmp(&p.z()[i], &q.z()[i], sizeof(float)) != 0 || p.labels()[i] != q.labels()[i]) {
      return false;
    }
  }
  return true;
}

TEST(Simulator, BitIdenticalOnOneAndTwoThreads) {
  const Simulator sim(default_arena_with_dropout(), {.seed = 11});
  Scan one, two;
  tbb::task_arena(1).execute([&] { one = sim.simulate(40); });
  tbb::task_arena(2).execute([&] { two = sim.simulate(40); });
  ASSERT_GT(one.points.size(), 10000u);
  EXPECT_TRUE(identical(one, two));
  // The seed matters; the same seed repeats.
  const Simulator other(default_arena_with_dropout(), {.seed = 12});
  EXPECT_FALSE(identical(one, other.simulate(40)));
  EXPECT_TRUE(identical(one, sim.simulate(40)));
}

TEST(Simulator, PacketAndSingleRaysAgree) {
  const Arena arena = load_arena(SARMAP_SOURCE_DIR "/datasets/arenas/esogu-6x4.json");
  const Simulator packet(arena, {.batch_mode = RayBatchMode::Packet16});
  const Simulator single(arena, {.batch_mode = RayBatchMode::Single});
  const std::size_t n = packet.rays().directions.size();
  for (std::size_t frame : {0u, 77u}) {
    std::vector<float> t1(n), t2(n);
    std::vector<std::uint8_t> l1(n), l2(n);
    packet.cast_frame(frame, t1, l1);
    single.cast_frame(frame, t2, l2);
    std::size_t hits = 0;
    for (std::size_t i = 0; i < n; ++i) {
      ASSERT_EQ(std::isfinite(t1[i]), std::isfinite(t2[i])) << i;
      if (!std::isfinite(t1[i])) continue;
      ++hits;
      ASSERT_NEAR(t1[i], t2[i], 1e-5) << i;
      ASSERT_EQ(l1[i], l2[i]) << i;
    }
    EXPECT_GT(hits, n / 2);
  }
}

// A simulated sequence names the arena it came from, so runs of it can too.
TEST(Simulator, SequenceRecordsTheArenasHash) {
  const auto dir = sarmap::testing::scratch_dir("simulator_arena_hash");
  Arena arena = testing::parse_test_arena(testing::base_arena_json());
  ASSERT_EQ(arena.sha256.size(), 64u);
  write_simulated_sequence(Simulator(arena), dir / "seq", 1);
  EXPECT_EQ(open_scan_sequence(dir / "seq")->arena_sha256(), arena.sha256);
  arena.sha256.clear();  // built in code: nothing to record
  write_simulated_sequence(Simulator(arena), dir / "seq", 1);
  EXPECT_EQ(open_scan_sequence(dir / "seq")->arena_sha256(), "");
  std::filesystem::remove_all(dir);
}

TEST(Trajectory, EvenlySpacedPosesAboveTheGround) {
  json j = testing::base_arena_json();
  j["elements"] = json::parse(R"([{"type": "flat_ramp", "center": [2, 1], "size": [1, 1], "height": 0.3}])");
  j["trajectory"] = json::parse(R"({"waypoints": [[0.5, 1], [3.5, 1], [3.5, 3]], "height": 0.5, "frames": 11,
                                    "pitch_deg": -10})");
  const Simulator sim(testing::parse_test_arena(j));
  const auto& poses = sim.poses();
  ASSERT_EQ(poses.size(), 11u);
  // Path length 5 m: a pose every 0.5 m. The height above the ground comes
  // from a single-precision ray cast down onto the floor, so it is exact only
  // to float rounding, which differs between Embree's AVX2 and AVX-512
  // kernels (exact on an AVX-512 machine, not on an AVX2-only one).
  EXPECT_TRUE(poses[0].translation().isApprox(Eigen::Vector3d(0.5, 1, 0.5), 1e-6));
  EXPECT_TRUE(poses[3].translation().isApprox(Eigen::Vector3d(2.0, 1, 0.8), 1e-6));  // over the platform
  EXPECT_TRUE(poses[6].translation().isApprox(Eigen::Vector3d(3.5, 1, 0.5), 1e-6));  // on the corner waypoint
  EXPECT_TRUE(poses[10].translation().isApprox(Eigen::Vector3d(3.5, 3, 0.5), 1e-6));
  // The optical axis looks along the travel, 10 degrees down.
  const Eigen::Vector3d axis0 = poses[0].rotation() * Eigen::Vector3d::UnitZ();
  EXPECT_TRUE(axis0.isApprox(Eigen::Vector3d(std::cos(10 * kDeg), 0, -std::sin(10 * kDeg)), 1e-9));
  // From the corner on, it looks along the next segment (+y); image x points right (-x world).
  const Eigen::Matrix3d& r6 = poses[6].rotation();
  EXPECT_TRUE((r6 * Eigen::Vector3d::UnitZ()).isApprox(Eigen::Vector3d(0, std::cos(10 * kDeg), -std::sin(10 * kDeg)), 1e-9));
  EXPECT_TRUE((r6 * Eigen::Vector3d::UnitX()).isApprox(Eigen::Vector3d(1, 0, 0), 1e-9));
}

}  // namespace
}  // namespace sarmap::sim
