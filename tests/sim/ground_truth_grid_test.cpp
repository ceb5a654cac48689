// Tests of engine/sim/ground_truth_grid.hpp against voxel counts, areas and
// visibility worked out by hand.
#include "engine/sim/ground_truth_grid.hpp"

#include <gtest/gtest.h>
#include <map>
#include <tbb/task_arena.h>

#include "engine/core/error.hpp"
#include "engine/sim/ground_height.hpp"
#include "engine/sim/simulator.hpp"
#include "engine/sim/trajectory.hpp"
#include "tests/sim/test_arenas.hpp"

namespace sarmap::sim {
namespace {

using nlohmann::json;

// A 1 x 1 m floor and a floating 0.4 m cube spanning 0.3..0.7 on every axis,
// at 0.25 m voxels: the cube's faces fill the 2 x 2 x 2 voxels 1..2; the
// floor lies on the face z = 0 and so fills the layers z = -1 and z = 0.
json box_arena() {
  json j = testing::base_arena_json();
  j["bounds"] = {{"min", {0, 0, 0}}, {"max", {1, 1, 1}}};
  j["elements"] = json::parse(R"([{"type": "box", "center": [0.5, 0.5, 0.5], "size": [0.4, 0.4, 0.4]}])");
  return j;
}

double total_area(const GroundTruthGrid& g) {
  double sum = 0;
  for (const auto& [key, v] : g.occupied) {
    for (double a : v.area) sum += a;
  }
  return sum;
}

TEST(GroundTruthGrid, BoxArenaMatchesAnalyticCounts) {
  const Arena arena = testing::parse_test_arena(box_arena());
  const GroundTruthGrid g = voxelize_arena(arena, {.resolution = 0.25, .compute_free = false});
  EXPECT_EQ(g.occupied.size(), 40u);
  const auto per_class = g.occupied_per_class();
  EXPECT_EQ(per_class[static_cast<std::size_t>(ClassId::Terrain)], 32u);
  EXPECT_EQ(per_class[static_cast<std::size_t>(ClassId::Other)], 8u);
  std::map<int, int> layers;
  for (const auto& [key, v] : g.occupied) ++layers[key.z];
  EXPECT_EQ(layers, (std::map<int, int>{{-1, 16}, {0, 16}, {1, 4}, {2, 4}}));
  // Each cube voxel holds a quarter of three faces; each floor voxel half of
  // its 0.25 m square (the other half is across the face z = 0).
  for (int x = 1; x <= 2; ++x) {
    for (int y = 1; y <= 2; ++y) {
      for (int z = 1; z <= 2; ++z) {
        const OccupiedVoxel& v = g.occupied.at({x, y, z});
        EXPECT_NEAR(v.area[static_cast<std::size_t>(ClassId::Other)], 3 * 0.2 * 0.2, 1e-6);  // float vertices
        EXPECT_EQ(v.label, ClassId::Other);
      }
    }
  }
  EXPECT_NEAR(g.occupied.at({3, 0, -1}).area[static_cast<std::size_t>(ClassId::Terrain)], 0.5 * 0.0625, 1e-12);
  EXPECT_EQ(g.label({0, 0, 0}), ClassId::Terrain);
  EXPECT_EQ(g.label({0, 0, 3}), ClassId::Unknown);
  EXPECT_NEAR(total_area(g), 1.0 + 6 * 0.16, 1e-6);
  EXPECT_TRUE(g.free.empty());
  EXPECT_EQ(g.bounds_min, (VoxelKey{0, 0, 0}));
  EXPECT_EQ(g.bounds_max, (VoxelKey{3, 3, 3}));
}

TEST(GroundTruthGrid, DominantClassWinsBySurfaceArea) {
  // A thin wall (faces at x = 1.03 and 1.07) on the floor: a bottom voxel
  // holds half of 0.1 x 0.1 m of floor (the floor lies on the face z = 0)
  // against two 0.1 x 0.1 m wall faces.
  json j = testing::base_arena_json();
  j["elements"] = json::parse(R"([{"type": "wall", "from": [1.05, 0.52], "to": [1.05, 1.48], "height": 1.0,
                                   "thickness": 0.04}])");
  const GroundTruthGrid g = voxelize_arena(testing::parse_test_arena(j), {.resolution = 0.1, .compute_free = false});
  const OccupiedVoxel& v = g.occupied.at({10, 7, 0});
  EXPECT_NEAR(v.area[static_cast<std::size_t>(ClassId::Wall)], 2 * 0.1 * 0.1 + 0.0, 1e-6);
  EXPECT_NEAR(v.area[static_cast<std::size_t>(ClassId::Terrain)], 0.5 * 0.1 * 0.1, 1e-6);
  EXPECT_EQ(v.label, ClassId::Wall);
  EXPECT_EQ(g.label({12, 7, 0}), ClassId::Terrain);
  EXPECT_EQ(g.label({10, 7, 9}), ClassId::Wall);  // the top face too
}

TEST(GroundTruthGrid, ClippingConservesAreaOfTiltedSurfaces) {
  // Yawed ramps and boxes cut across voxels in every direction; the pieces
  // must add up to the surface they came from.
  const Arena arena = load_arena(SARMAP_SOURCE_DIR "/datasets/arenas/esogu-6x4.json");
  double expected = 0;
  for (const ClassedMesh& m : arena_meshes(arena)) {
    for (std::size_t t = 0; t < m.indices.size(); t += 3) {
      const Eigen::Vector3d a = m.vertices[m.indices[t]].cast<double>();
      const Eigen::Vector3d b = m.vertices[m.indices[t + 1]].cast<double>();
      const Eigen::Vector3d c = m.vertices[m.indices[t + 2]].cast<double>();
      expected += 0.5 * (b - a).cross(c - a).norm();
    }
  }
  OccupiedVoxelMap map;
  ArenaElement box;
  box.shape = BoxSpec{{1.03, 2.17, 0.4}, {0.7, 0.5, 0.3}, 37};
  const ClassedMesh tilted = element_mesh(box);
  add_surface_voxels(tilted, 0.05, map);
  double sum = 0;
  for (const auto& [k, v] : map) sum += v.area[static_cast<std::size_t>(ClassId::Other)];
  EXPECT_NEAR(sum, 2 * (0.7 * 0.5 + 0.7 * 0.3 + 0.5 * 0.3), 1e-6);
  const GroundTruthGrid g = voxelize_arena(arena, {.resolution = 0.05, .compute_free = false});
  EXPECT_NEAR(total_area(g), expected, 1e-6 * expected);
}

// One pixel looking straight down from (0.125, 0.125, 0.875) over the box
// arena's floor: the ray crosses voxels z = 3, 2, 1 and ends in the floor's.
TEST(GroundTruthGrid, FreeVoxelsAreThoseARayCrosses) {
  json j = box_arena();
  j["trajectory"] = {{"poses", {testing::pose_json(Eigen::Vector3d(1, -1, -1).asDiagonal(), {0.125, 0.125, 0.875})}}};
  j["sensor"] = json::parse(R"({"type": "depth_camera", "width": 1, "height": 1, "fx": 1, "fy": 1, "cx": 0,
                                "cy": 0, "min_range": 0.1, "max_range": 5})");
  const GroundTruthGrid g = voxelize_arena(testing::parse_test_arena(j), {.resolution = 0.25});
  EXPECT_EQ(g.free, (VoxelSet{{0, 0, 1}, {0, 0, 2}, {0, 0, 3}}));
  EXPECT_EQ(g.state({0, 0, 2}), GroundTruthGrid::State::Free);
  EXPECT_EQ(g.state({0, 0, 0}), GroundTruthGrid::State::Occupied);
  EXPECT_EQ(g.state({1, 0, 2}), GroundTruthGrid::State::Unknown);
  // The floor lies on the face z = 0: the voxels on both sides saw the hit.
  EXPECT_TRUE(g.occupied.at({0, 0, 0}).observed);
  EXPECT_TRUE(g.occupied.at({0, 0, -1}).observed);
  EXPECT_EQ(g.occupied_per_class(true)[static_cast<std::size_t>(ClassId::Terrain)], 2u);
  EXPECT_EQ(g.occupied_per_class(true)[static_cast<std::size_t>(ClassId::Other)], 0u);
}

TEST(GroundTruthGrid, FreeVoxelsOfTheDefaultArenaAreSoundAndThreadIndependent) {
  const Arena arena = load_arena(SARMAP_SOURCE_DIR "/datasets/arenas/esogu-6x4.json");
  const Simulator sim(arena, {.noise = false});
  const GroundTruthOptions options{.resolution = 0.1, .frame_stride = 40, .ray_stride = 4};
  GroundTruthGrid one, two;
  tbb::task_arena(1).execute([&] { one = voxelize_arena(sim, options); });
  tbb::task_arena(2).execute([&] { two = voxelize_arena(sim, options); });
  EXPECT_EQ(one.free, two.free);
  ASSERT_GT(one.free.size(), 1000u);
  std::size_t observed = 0;
  for (const auto& [k, v] : one.occupied) {
    observed += v.observed;
    EXPECT_EQ(v.observed, two.occupied.at(k).observed);
  }
  EXPECT_GT(observed, 100u);
  for (const VoxelKey& k : one.free) {
    ASSERT_FALSE(one.occupied.count(k));
    ASSERT_TRUE(k.x >= 0 && k.y >= 0 && k.z >= 0 && k.x < 60 && k.y < 40 && k.z < 24);
    // Free space is above the floor and never inside a ramp: its centre sits
    // above the surface under it.
    const Eigen::Vector3d c = voxel_center(k, 0.1);
    ASSERT_GT(c.z(), ground_height(sim.scene(), c.x(), c.y(), 2.4)) << c.transpose();
  }
  // Every observed voxel sits where a noise-free point of those frames lands.
  const Simulator exact(arena, {.noise = false});
  const Scan scan = exact.simulate(0);
  std::size_t found = 0;
  for (std::size_t i = 0; i < scan.points.size(); i += 97) {
    const VoxelKey k = voxel_key_of({scan.points.x()[i], scan.points.y()[i], scan.points.z()[i]}, 0.1);
    found += one.occupied.count(k);
  }
  EXPECT_GT(found, scan.points.size() / 97 * 9 / 10);
}

TEST(GroundTruthGrid, RejectsBadOptions) {
  const Arena arena = testing::parse_test_arena(box_arena());
  EXPECT_THROW(voxelize_arena(arena, {.resolution = 0}), Error);
  EXPECT_THROW(voxelize_arena(arena, {.resolution = 0.1, .ray_stride = 0}), Error);
  EXPECT_THROW(voxelize_arena(arena, {.resolution = 1e-9}), Error);
}

}  // namespace
}  // namespace sarmap::sim
