// Occupied voxels as a cloud: one point per occupied voxel at its centre with
// class, palette colour and occupancy probability; written as .ply or .pcd
// with the voxel size in the header and read back by the project's readers.
#include "engine/metric/voxel_cloud.hpp"

#include <gtest/gtest.h>

#include <algorithm>
#include <array>
#include <cmath>
#include <map>
#include <string>
#include <tuple>
#include <vector>

#include "engine/core/classes.hpp"
#include "engine/core/error.hpp"
#include "engine/io/point_cloud_file.hpp"
#include "tests/io/scratch_folder.hpp"
#include "tests/metric/hand_made_map.hpp"

namespace sarmap::metric {
namespace {

using Centre = std::tuple<long, long, long>;  // voxel centre in millimetres

Centre centre_mm(float x, float y, float z) {
  return {std::lround(x * 1000.0), std::lround(y * 1000.0), std::lround(z * 1000.0)};
}

// Every occupied voxel of the map by centre, with its class, read from the map itself.
std::map<Centre, ClassId> occupied_voxels(const MetricMap& map) {
  std::map<Centre, ClassId> out;
  map.blocks().for_each_block([&](const BlockKey& bk, const MetricMap::Blocks::Block& block) {
    for (int l = 0; l < kBlockVoxels; ++l) {
      const VoxelKey k = voxel_of(bk, l);
      if (map.state(k) != VoxelState::Occupied) continue;
      const Eigen::Vector3d c = map.center_of(k);
      out[centre_mm(static_cast<float>(c.x()), static_cast<float>(c.y()), static_cast<float>(c.z()))] =
          map.class_of(k);
    }
    (void)block;
  });
  return out;
}

// The cloud holds exactly the map's occupied voxels, each with its class,
// the palette's colour and a probability above the occupied threshold.
void expect_cloud_of(const PointBuffer& cloud, const MetricMap& map) {
  const auto want = occupied_voxels(map);
  ASSERT_EQ(cloud.size(), want.size());
  ASSERT_TRUE(cloud.has_labels());
  ASSERT_TRUE(cloud.has_colors());
  const std::size_t probability = cloud.find_score("probability");
  ASSERT_LT(probability, cloud.score_count());
  std::map<Centre, ClassId> got;
  for (std::size_t i = 0; i < cloud.size(); ++i) {
    const ClassId id = static_cast<ClassId>(cloud.labels()[i]);
    got[centre_mm(cloud.x()[i], cloud.y()[i], cloud.z()[i])] = id;
    EXPECT_EQ(cloud.red()[i], class_info(id).color.r) << i;
    EXPECT_EQ(cloud.green()[i], class_info(id).color.g) << i;
    EXPECT_EQ(cloud.blue()[i], class_info(id).color.b) << i;
    const float p = cloud.score(probability)[i];
    EXPECT_GE(p, map.occupancy().settings().occupied_threshold) << i;
    EXPECT_LE(p, 1.0f) << i;
  }
  EXPECT_EQ(got, want);
}

TEST(VoxelCloud, OnePointPerOccupiedVoxelWithClassColourAndProbability) {
  const MetricMap map = testing::hand_made_map();
  const PointBuffer cloud = occupied_voxel_cloud(map);
  expect_cloud_of(cloud, map);
  std::array<std::size_t, kClassCount> by_class{};
  for (const std::uint8_t label : cloud.labels()) ++by_class[label];
  EXPECT_EQ(by_class, testing::kHandMadeOccupiedByClass);
  // Every voxel was set to the clamp maximum: the probability it stands for.
  EXPECT_FLOAT_EQ(cloud.score(cloud.find_score("probability"))[0],
                  static_cast<float>(OccupancyModel::probability(map.occupancy().max())));
}

TEST(VoxelCloud, WrittenAsPlyOrPcdWithTheVoxelSizeInTheHeader) {
  sarmap::test::ScratchFolder dir;
  const MetricMap map = testing::hand_made_map();
  for (const char* name : {"v.ply", "v.pcd"}) {
    for (const bool binary : {true, false}) {
      write_voxel_cloud(map, dir / name, binary);
      PointCloudFileInfo info;
      const PointBuffer read = read_point_cloud(dir / name, &info);
      expect_cloud_of(read, map);
      EXPECT_NE(std::find(info.comments.begin(), info.comments.end(), "voxel_size 0.1"), info.comments.end())
          << name << (binary ? " binary" : " ascii");
    }
  }
  EXPECT_THROW(write_voxel_cloud(map, dir / "v.xyz"), Error);
}

TEST(VoxelCloud, VoxelSizeCommentIsTheShortestExactDecimal) {
  EXPECT_EQ(voxel_size_comment(MetricMap(settings_at_resolution(0.05))), "voxel_size 0.05");
  EXPECT_EQ(voxel_size_comment(MetricMap(settings_at_resolution(0.125))), "voxel_size 0.125");
  EXPECT_EQ(voxel_size_comment(MetricMap(settings_at_resolution(2))), "voxel_size 2");
}

}  // namespace
}  // namespace sarmap::metric
