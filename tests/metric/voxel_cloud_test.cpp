// Occupied voxels as a cloud: one point per occupied voxel at its centre with
// class, palette colour and occupancy probability; written as .ply or .pcd
// with the voxel size in the header and read back by the project's readers;
// and as a mesh of coloured cubes.
#include "engine/metric/voxel_cloud.hpp"

#include <gtest/gtest.h>

#include <algorithm>
#include <array>
#include <cmath>
#include <cstring>
#include <map>
#include <set>
#include <string>
#include <tuple>
#include <vector>

#include <Eigen/Geometry>

#include "engine/core/classes.hpp"
#include "engine/core/error.hpp"
#include "engine/io/point_cloud_file.hpp"
#include "tests/file_bytes.hpp"
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

// Cubes: 8 corners per occupied voxel in its class colour, 6 quads facing
// outwards, the voxel size in the header; the point reader opens the file.
TEST(VoxelCubes, EightCornersAndSixOutwardQuadsPerOccupiedVoxel) {
  sarmap::test::ScratchFolder dir;
  const MetricMap map = testing::hand_made_map();
  const PointBuffer centres = occupied_voxel_cloud(map);
  ASSERT_EQ(centres.size(), 13u);
  write_voxel_cubes(map, dir / "cubes.ply");

  PointCloudFileInfo info;
  const PointBuffer corners = read_point_cloud(dir / "cubes.ply", &info);
  EXPECT_EQ(info.comments, (std::vector<std::string>{"written by sarmap", "voxel_size 0.1"}));
  ASSERT_EQ(corners.size(), 8 * centres.size());
  ASSERT_TRUE(corners.has_colors());
  for (std::size_t v = 0; v < centres.size(); ++v) {
    const Rgb want = class_info(static_cast<ClassId>(centres.labels()[v])).color;
    for (std::size_t c = 0; c < 8; ++c) {
      const std::size_t i = 8 * v + c;
      // Each corner half a voxel from the centre on every axis, all eight distinct.
      EXPECT_NEAR(std::abs(corners.x()[i] - centres.x()[v]), 0.05, 1e-6) << i;
      EXPECT_NEAR(std::abs(corners.y()[i] - centres.y()[v]), 0.05, 1e-6) << i;
      EXPECT_NEAR(std::abs(corners.z()[i] - centres.z()[v]), 0.05, 1e-6) << i;
      EXPECT_EQ(corners.x()[i] > centres.x()[v], (c & 1) != 0) << i;
      EXPECT_EQ(corners.y()[i] > centres.y()[v], (c & 2) != 0) << i;
      EXPECT_EQ(corners.z()[i] > centres.z()[v], (c & 4) != 0) << i;
      EXPECT_EQ(corners.red()[i], want.r) << i;
      EXPECT_EQ(corners.green()[i], want.g) << i;
      EXPECT_EQ(corners.blue()[i], want.b) << i;
    }
  }

  // The faces, read from the binary body: after the vertices (x y z float,
  // red green blue uchar), one uchar count and four int indices each.
  const std::string bytes = sarmap::test::slurp(dir / "cubes.ply");
  ASSERT_NE(bytes.find("element face 78\nproperty list uchar int vertex_indices\n"), std::string::npos);
  std::size_t at = bytes.find("end_header\n") + 11 + corners.size() * 15;
  ASSERT_EQ(bytes.size() - at, 78u * 17);
  for (std::size_t v = 0; v < centres.size(); ++v) {
    const Eigen::Vector3d centre(centres.x()[v], centres.y()[v], centres.z()[v]);
    std::set<std::tuple<int, int, int>> directions;
    for (int f = 0; f < 6; ++f, at += 17) {
      ASSERT_EQ(bytes[at], 4);
      std::int32_t index[4];
      std::memcpy(index, bytes.data() + at + 1, sizeof index);
      Eigen::Vector3d p[4], normal = Eigen::Vector3d::Zero(), middle = Eigen::Vector3d::Zero();
      for (int k = 0; k < 4; ++k) {
        ASSERT_GE(index[k], static_cast<std::int32_t>(8 * v));  // the face uses its own cube's corners
        ASSERT_LT(index[k], static_cast<std::int32_t>(8 * v + 8));
        p[k] = {corners.x()[index[k]], corners.y()[index[k]], corners.z()[index[k]]};
        middle += p[k] / 4;
      }
      for (int k = 0; k < 4; ++k) normal += p[k].cross(p[(k + 1) % 4]);  // Newell: area-weighted normal
      EXPECT_NEAR(normal.norm(), 2 * 0.01, 1e-6) << "a square face of 0.1 m sides, voxel " << v << " face " << f;
      const Eigen::Vector3d out = middle - centre;
      EXPECT_NEAR(out.norm(), 0.05, 1e-6) << v << " " << f;
      EXPECT_GT(normal.dot(out), 0) << "face " << f << " of voxel " << v << " faces inwards";
      directions.insert({static_cast<int>(std::lround(out.x() / 0.05)), static_cast<int>(std::lround(out.y() / 0.05)),
                         static_cast<int>(std::lround(out.z() / 0.05))});
    }
    EXPECT_EQ(directions.size(), 6u) << "voxel " << v << " lacks a side";
  }
}

TEST(VoxelCubes, OnlyAsPly) {
  sarmap::test::ScratchFolder dir;
  EXPECT_THROW(write_voxel_cubes(testing::hand_made_map(), dir / "cubes.pcd"), Error);
  EXPECT_FALSE(std::filesystem::exists(dir / "cubes.pcd"));
}

}  // namespace
}  // namespace sarmap::metric
