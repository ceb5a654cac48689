// The .bt export read back by Debian's liboctomap, voxel by voxel, and the
// map itself against OctoMap's own insertPointCloud on the same scans.
#include "engine/metric/octomap_export.hpp"

#include <gtest/gtest.h>
#include <octomap/OcTree.h>
#include <unistd.h>

#include <filesystem>
#include <sstream>

#include "engine/core/error.hpp"
#include "engine/metric/ray_integrator.hpp"
#include "tests/metric/synthetic_room.hpp"

namespace sarmap::metric {
namespace {

constexpr std::int32_t kOctomapKeyOffset = 32768;

octomap::OcTreeKey octo_key(const VoxelKey& k) {
  return octomap::OcTreeKey(static_cast<octomap::key_type>(k.x + kOctomapKeyOffset), static_cast<octomap::key_type>(k.y + kOctomapKeyOffset),
                            static_cast<octomap::key_type>(k.z + kOctomapKeyOffset));
}
VoxelKey our_key(const octomap::OcTreeKey& k) { return {k[0] - kOctomapKeyOffset, k[1] - kOctomapKeyOffset, k[2] - kOctomapKeyOffset}; }

// Every known voxel of one map has the same state in the other, both ways.
void expect_same_states(const MetricMap& map, const octomap::OcTree& tree) {
  std::size_t checked = 0;
  map.blocks().for_each_block([&](const BlockKey& bk, const MetricMap::Blocks::Block& block) {
    for (int l = 0; l < kBlockVoxels; ++l) {
      if (!block.known(l)) continue;
      const VoxelKey k = voxel_of(bk, l);
      const octomap::OcTreeNode* node = tree.search(octo_key(k));
      ASSERT_NE(node, nullptr);
      EXPECT_EQ(tree.isNodeOccupied(node), map.state(k) == VoxelState::Occupied);
      ++checked;
    }
  });
  std::size_t leaves = 0;
  for (auto it = tree.begin_leafs(), end = tree.end_leafs(); it != end; ++it) {
    const int size = static_cast<int>(std::lround(it.getSize() / tree.getResolution()));
    const VoxelKey lo = our_key(it.getIndexKey());
    // A pruned leaf stands for size^3 voxels, all in the leaf's state.
    for (int z = 0; z < size; ++z)
      for (int y = 0; y < size; ++y)
        for (int x = 0; x < size; ++x) {
          const VoxelState s = map.state({lo.x + x, lo.y + y, lo.z + z});
          EXPECT_EQ(s, tree.isNodeOccupied(*it) ? VoxelState::Occupied : VoxelState::Free);
          ++leaves;
        }
  }
  EXPECT_EQ(leaves, checked);
}

MetricMap room_map(double res, int frames, int w, int h) {
  MetricMap map(settings_at_resolution(res));
  RayIntegrator integrator;
  testing::SyntheticRoom room;
  for (int f = 0; f < frames; ++f) {
    const auto scan = room.frame(f, frames, w, h);
    integrator.integrate(map, scan.points, scan.origin);
  }
  return map;
}

TEST(OctomapExport, OctomapReadsTheFileBackVoxelByVoxel) {
  const MetricMap map = room_map(0.1, 4, 64, 48);
  std::size_t nodes = 0;
  const std::string bytes = octomap_binary(map, &nodes);
  std::istringstream in(bytes);
  octomap::OcTree tree(0.1);
  ASSERT_TRUE(tree.readBinary(in));
  EXPECT_DOUBLE_EQ(tree.getResolution(), 0.1);
  EXPECT_EQ(tree.size(), nodes);
  expect_same_states(map, tree);

  // Through a file as well, and pruning kept it smaller than one node per voxel.
  const auto path = std::filesystem::temp_directory_path() / ("sarmap_bt_" + std::to_string(::getpid()) + ".bt");
  write_octomap_bt(map, path);
  octomap::OcTree from_file(0.1);
  ASSERT_TRUE(from_file.readBinary(path.string()));
  EXPECT_EQ(from_file.size(), nodes);
  EXPECT_LT(from_file.getNumLeafNodes(), map.counts().known);
  std::filesystem::remove(path);
}

TEST(OctomapExport, PrunesAFullUniformBlockToOneLeaf) {
  MetricMap map(settings_at_resolution(0.05));
  for (int l = 0; l < kBlockVoxels; ++l)
    map.blocks().set_voxel(voxel_of(BlockKey{0, 0, 0}, l), {map.occupancy().max(), {}});
  std::istringstream in(octomap_binary(map));
  octomap::OcTree tree(0.05);
  ASSERT_TRUE(tree.readBinary(in));
  EXPECT_EQ(tree.getNumLeafNodes(), 1u);
  expect_same_states(map, tree);
}

TEST(OctomapExport, EmptyMapAndMapsBeyondSixteenBitKeys) {
  MetricMap empty(settings_at_resolution(0.05));
  std::istringstream in(octomap_binary(empty));
  octomap::OcTree tree(0.05);
  EXPECT_TRUE(tree.readBinary(in));
  EXPECT_EQ(tree.size(), 0u);

  MetricMap far(settings_at_resolution(0.01));
  // Voxel 40000 at 0.01 m is 400 m away: beyond OctoMap's +-327.68 m at this resolution.
  far.blocks().set_voxel(voxel_of(block_of(VoxelKey{40000, 0, 0}), 0), {100, {}});
  try {
    octomap_binary(far);
    FAIL() << "expected an error";
  } catch (const Error& e) {
    EXPECT_EQ(e.code(), ErrorCode::OutOfRange);
    EXPECT_NE(std::string(e.what()).find("16-bit"), std::string::npos);
  }
}

TEST(OctomapAgreement, SameScansGiveTheSameStatesOnNinetyNinePercent) {
  for (const double res : {0.05, 0.1}) {
    const int frames = 8;
    MetricMap map(settings_at_resolution(res));
    RayIntegrator integrator;
    octomap::OcTree tree(res);
    testing::SyntheticRoom room;
    for (int f = 0; f < frames; ++f) {
      const auto scan = room.frame(f, frames, 80, 60);
      integrator.integrate(map, scan.points, scan.origin);
      octomap::Pointcloud cloud;
      for (std::size_t i = 0; i < scan.points.size(); ++i) {
        cloud.push_back(scan.points.x()[i], scan.points.y()[i], scan.points.z()[i]);
      }
      const octomap::point3d origin(static_cast<float>(scan.origin.x()), static_cast<float>(scan.origin.y()),
                                    static_cast<float>(scan.origin.z()));
      tree.insertPointCloud(cloud, origin, -1.0, false, true);
    }
    std::size_t either = 0, agree = 0;
    map.blocks().for_each_block([&](const BlockKey& bk, const MetricMap::Blocks::Block& block) {
      for (int l = 0; l < kBlockVoxels; ++l) {
        if (!block.known(l)) continue;
        const VoxelKey k = voxel_of(bk, l);
        const octomap::OcTreeNode* node = tree.search(octo_key(k));
        ++either;
        if (node && tree.isNodeOccupied(node) == (map.state(k) == VoxelState::Occupied)) ++agree;
      }
    });
    for (auto it = tree.begin_leafs(), end = tree.end_leafs(); it != end; ++it) {
      if (map.state(our_key(it.getKey())) == VoxelState::Unknown) ++either;  // known only to OctoMap
    }
    ASSERT_GT(either, 10000u);
    const double agreement = static_cast<double>(agree) / static_cast<double>(either);
    // Measured 0.9992 at 0.05 m and 0.9971 at 0.10 m (2026-11-26); the
    // thresholds sit just under, so a regression shows.
    EXPECT_GE(agreement, res < 0.075 ? 0.998 : 0.995) << "resolution " << res << ": " << agree << " of " << either;
    std::printf("agreement with OctoMap at %.2f m: %.4f (%zu voxels)\n", res, agreement, either);
  }
}

}  // namespace
}  // namespace sarmap::metric
