// The .ot export read back by Debian's liboctomap (AbstractOcTree::read, as
// octovis opens a file): every known voxel at its place with its log-odds,
// state and class colour, both ways, on random maps and at the key limits.
#include "engine/metric/octomap_color_export.hpp"

#include <gtest/gtest.h>
#include <octomap/AbstractOcTree.h>
#include <octomap/ColorOcTree.h>
#include <unistd.h>

#include <cmath>
#include <filesystem>
#include <memory>
#include <random>
#include <sstream>

#include "engine/core/error.hpp"
#include "engine/metric/ray_integrator.hpp"
#include "tests/metric/hand_made_map.hpp"
#include "tests/metric/synthetic_room.hpp"

namespace sarmap::metric {
namespace {

constexpr std::int32_t kOffset = 32768;

std::unique_ptr<octomap::ColorOcTree> read_tree(const std::string& bytes) {
  std::istringstream in(bytes);
  std::unique_ptr<octomap::AbstractOcTree> tree(octomap::AbstractOcTree::read(in));
  if (!tree) return nullptr;
  auto* color_tree = dynamic_cast<octomap::ColorOcTree*>(tree.get());
  if (!color_tree) return nullptr;
  tree.release();
  return std::unique_ptr<octomap::ColorOcTree>(color_tree);
}

Rgb expected_color(const MetricMap& map, const SemanticVoxel& v) {
  if (map.occupancy().state(v.log_odds) != VoxelState::Occupied) return {255, 255, 255};
  return class_info(LabelFusion::dominant(v.evidence)).color;
}

// Every voxel under every leaf of the tree is a known voxel of the map, at the
// same place, with the same log-odds, state and colour; and the tree holds as
// many voxels as the map knows.
void expect_same_map(const MetricMap& map, const octomap::ColorOcTree& tree) {
  ASSERT_DOUBLE_EQ(tree.getResolution(), map.resolution());
  const double res = map.resolution();
  std::size_t voxels = 0;
  for (auto it = tree.begin_leafs(), end = tree.end_leafs(); it != end; ++it) {
    const int size = static_cast<int>(std::lround(it.getSize() / res));
    const octomap::OcTreeKey lo = it.getIndexKey();
    for (int z = 0; z < size; ++z)
      for (int y = 0; y < size; ++y)
        for (int x = 0; x < size; ++x) {
          const octomap::OcTreeKey key(static_cast<octomap::key_type>(lo[0] + x),
                                       static_cast<octomap::key_type>(lo[1] + y),
                                       static_cast<octomap::key_type>(lo[2] + z));
          // Position: OctoMap's voxel centre falls in sarmap's voxel and is its centre.
          const Eigen::Vector3d centre(tree.keyToCoord(key[0]), tree.keyToCoord(key[1]),
                                       tree.keyToCoord(key[2]));
          const std::optional<VoxelKey> ours = map.key_at(centre);
          ASSERT_TRUE(ours.has_value());
          EXPECT_EQ(*ours, (VoxelKey{key[0] - kOffset, key[1] - kOffset, key[2] - kOffset}));
          EXPECT_NEAR((centre - map.center_of(*ours)).norm(), 0.0, 1e-9 * res);
          const std::optional<SemanticVoxel> v = map.blocks().voxel(*ours);
          ASSERT_TRUE(v.has_value());
          ASSERT_TRUE(v->known());
          EXPECT_EQ(it->getLogOdds(), static_cast<float>(v->log_odds / kLogOddsScale));
          EXPECT_EQ(tree.isNodeOccupied(*it), map.state(*ours) == VoxelState::Occupied);
          EXPECT_NEAR(it->getOccupancy(), OccupancyModel::probability(v->log_odds), 1e-4);
          const Rgb want = expected_color(map, *v);
          const octomap::ColorOcTreeNode::Color got = it->getColor();
          EXPECT_EQ(got.r, want.r);
          EXPECT_EQ(got.g, want.g);
          EXPECT_EQ(got.b, want.b);
          ++voxels;
        }
  }
  EXPECT_EQ(voxels, map.counts().known);
}

// Inner nodes already hold what OctoMap would compute for them, so
// recomputing changes nothing.
void expect_inner_nodes_as_octomap_computes(octomap::ColorOcTree& tree) {
  if (tree.getRoot() == nullptr) return;
  const float log_odds = tree.getRoot()->getLogOdds();
  const octomap::ColorOcTreeNode::Color color = tree.getRoot()->getColor();
  tree.updateInnerOccupancy();
  EXPECT_EQ(tree.getRoot()->getLogOdds(), log_odds);
  EXPECT_EQ(tree.getRoot()->getColor(), color);
}

void set_voxel(MetricMap& map, const VoxelKey& k, std::int16_t log_odds, ClassId cls) {
  SemanticVoxel v{log_odds, {}};
  if (cls != ClassId::Unknown) v.evidence[static_cast<std::size_t>(cls)] = 120;
  map.blocks().set_voxel(k, v);
}

TEST(OctomapColorExport, HandMadeMapReadsBackVoxelByVoxel) {
  const MetricMap map = testing::hand_made_map();
  std::size_t nodes = 0;
  const std::string bytes = octomap_color_tree(map, &nodes);
  auto tree = read_tree(bytes);
  ASSERT_NE(tree, nullptr);
  EXPECT_EQ(tree->size(), nodes);
  expect_same_map(map, *tree);
  expect_inner_nodes_as_octomap_computes(*tree);
}

TEST(OctomapColorExport, RandomMapsReadBackVoxelByVoxel) {
  std::mt19937 rng(31);
  const double resolutions[] = {0.01, 0.05, 0.1, 0.25};
  for (int trial = 0; trial < 12; ++trial) {
    MetricMap map(settings_at_resolution(resolutions[trial % 4]));
    const OccupancyModel& occ = map.occupancy();
    std::uniform_int_distribution<int> coord(-20, 19), log_odds(occ.min(), occ.max()), cls(0, 5);
    const int count = std::uniform_int_distribution<int>(1, 400)(rng);
    for (int i = 0; i < count; ++i) {
      // Some voxels exactly on the threshold, which both call occupied.
      const auto lo = static_cast<std::int16_t>(i % 17 == 0 ? occ.threshold() : log_odds(rng));
      set_voxel(map, {coord(rng), coord(rng), coord(rng)}, lo, static_cast<ClassId>(cls(rng)));
    }
    SCOPED_TRACE("trial " + std::to_string(trial));
    auto tree = read_tree(octomap_color_tree(map));
    ASSERT_NE(tree, nullptr);
    expect_same_map(map, *tree);
    expect_inner_nodes_as_octomap_computes(*tree);
  }
}

TEST(OctomapColorExport, AFullUniformBlockIsOneLeafButColoursAreNeverMerged) {
  MetricMap map(settings_at_resolution(0.05));
  // Voxels -8..-1 on every axis: one full octree node of 8^3, negative coordinates.
  for (int z = -8; z < 0; ++z)
    for (int y = -8; y < 0; ++y)
      for (int x = -8; x < 0; ++x) set_voxel(map, {x, y, z}, map.occupancy().max(), ClassId::Wall);
  auto tree = read_tree(octomap_color_tree(map));
  ASSERT_NE(tree, nullptr);
  EXPECT_EQ(tree->getNumLeafNodes(), 1u);
  expect_same_map(map, *tree);

  // One voxel of another class (same log-odds): no longer one leaf, and each keeps its colour.
  set_voxel(map, {-1, -1, -1}, map.occupancy().max(), ClassId::InclinedRamp);
  tree = read_tree(octomap_color_tree(map));
  ASSERT_NE(tree, nullptr);
  EXPECT_GT(tree->getNumLeafNodes(), 1u);
  expect_same_map(map, *tree);
  expect_inner_nodes_as_octomap_computes(*tree);
}

TEST(OctomapColorExport, IntegratedRoomThroughAFile) {
  MetricMap map(settings_at_resolution(0.1));
  RayIntegrator integrator;
  testing::SyntheticRoom room;
  for (int f = 0; f < 3; ++f) {
    const auto scan = room.frame(f, 3, 48, 36);
    integrator.integrate(map, scan.points, scan.origin);
  }
  const auto path =
      std::filesystem::temp_directory_path() / ("sarmap_ot_" + std::to_string(::getpid()) + ".ot");
  write_octomap_ot(map, path);
  std::unique_ptr<octomap::AbstractOcTree> read(octomap::AbstractOcTree::read(path.string()));
  std::filesystem::remove(path);
  ASSERT_NE(read, nullptr);
  auto* tree = dynamic_cast<octomap::ColorOcTree*>(read.get());
  ASSERT_NE(tree, nullptr);
  expect_same_map(map, *tree);
}

TEST(OctomapColorExport, EmptyMapIsAnEmptyTree) {
  MetricMap empty(settings_at_resolution(0.05));
  std::size_t nodes = 1;
  auto tree = read_tree(octomap_color_tree(empty, &nodes));
  ASSERT_NE(tree, nullptr);
  EXPECT_EQ(nodes, 0u);
  EXPECT_EQ(tree->size(), 0u);
}

TEST(OctomapColorExport, VoxelsAtTheKeyLimitsAndBeyond) {
  // At 0.01 m OctoMap's keys reach voxel indices -32768 and 32767 (+-327.68 m),
  // inside sarmap's +-10 km: both corners of the key cube are exported.
  MetricMap map(settings_at_resolution(0.01));
  set_voxel(map, {-32768, -32768, -32768}, map.occupancy().max(), ClassId::Terrain);
  set_voxel(map, {32767, 32767, 32767}, map.occupancy().max(), ClassId::FlatRamp);
  set_voxel(map, {-32768, 32767, 0}, map.occupancy().min(), ClassId::Unknown);
  auto tree = read_tree(octomap_color_tree(map));
  ASSERT_NE(tree, nullptr);
  expect_same_map(map, *tree);

  set_voxel(map, {32768, 0, 0}, map.occupancy().max(), ClassId::Wall);
  try {
    octomap_color_tree(map);
    FAIL() << "expected an error";
  } catch (const Error& e) {
    EXPECT_EQ(e.code(), ErrorCode::OutOfRange);
    EXPECT_NE(std::string(e.what()).find(".ot export"), std::string::npos);
    EXPECT_NE(std::string(e.what()).find("16-bit"), std::string::npos);
  }
}

}  // namespace
}  // namespace sarmap::metric
