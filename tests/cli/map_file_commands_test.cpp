// `sarmap info` and `sarmap convert` on a metric map (map.sarmap): the
// figures info prints against the MetricMap the file was saved from, each
// output format read back by the project's own readers, and damaged files
// refused with an error naming the file and the problem.
#include <gmock/gmock.h>
#include <gtest/gtest.h>

#include <array>
#include <cmath>
#include <cstddef>
#include <filesystem>
#include <fstream>
#include <string>

#include <nlohmann/json.hpp>

#include "engine/core/bounds.hpp"
#include "engine/core/classes.hpp"
#include "engine/io/point_cloud_file.hpp"
#include "engine/metric/map_file.hpp"
#include "engine/metric/octomap_color_export.hpp"
#include "engine/metric/octomap_export.hpp"
#include "engine/metric/ray_integrator.hpp"
#include "engine/metric/voxel_cloud.hpp"
#include "tests/cli/cli_runner.hpp"
#include "tests/io/scratch_folder.hpp"
#include "tests/metric/synthetic_room.hpp"

namespace sarmap {
namespace {

using test::quoted;
using test::run_cli;
using ::testing::HasSubstr;

const std::string kTinyFrame = std::string(SARMAP_TEST_DATA_DIR) + "/sequences/tiny/frame_000000.ply";

// Three frames of the synthetic room at 0.1 m: walls, floor, a box and a
// platform, so several classes are occupied.
metric::MetricMap room_map() {
  metric::MetricMap map(metric::settings_at_resolution(0.1));
  metric::RayIntegrator integrator;
  testing::SyntheticRoom room;
  for (int f = 0; f < 3; ++f) {
    const auto scan = room.frame(f, 3, 40, 30);
    integrator.integrate(map, scan.points, scan.origin);
  }
  return map;
}

// What info must report, counted here voxel by voxel through the map's own
// queries rather than through the code info uses.
struct Expected {
  metric::MapCounts counts;
  std::array<std::size_t, kClassCount> occupied_by_class{};
  Bounds occupied;  // voxel faces
  std::size_t uniform_blocks = 0;  // every voxel at one log-odds, no class evidence
};

Expected expected_of(const metric::MetricMap& map) {
  Expected e;
  e.counts = map.counts();
  const double half = 0.5 * map.resolution();
  map.blocks().for_each_block([&](const metric::BlockKey& bk, const metric::MetricMap::Blocks::Block&) {
    const metric::SemanticVoxel first = *map.blocks().voxel(metric::voxel_of(bk, 0));
    bool uniform = true;
    for (int l = 0; l < metric::kBlockVoxels; ++l) {
      const metric::SemanticVoxel v = *map.blocks().voxel(metric::voxel_of(bk, l));
      uniform = uniform && v.log_odds == first.log_odds && v.evidence == metric::ClassEvidence{};
    }
    e.uniform_blocks += uniform ? 1 : 0;
    for (int l = 0; l < metric::kBlockVoxels; ++l) {
      const metric::VoxelKey k = metric::voxel_of(bk, l);
      if (map.state(k) != metric::VoxelState::Occupied) continue;
      ++e.occupied_by_class[static_cast<std::size_t>(map.class_of(k))];
      e.occupied.extend(map.center_of(k) - Eigen::Vector3d::Constant(half));
      e.occupied.extend(map.center_of(k) + Eigen::Vector3d::Constant(half));
    }
  });
  return e;
}

std::string bytes_of(const std::filesystem::path& p) { return test::read_all(p); }

void write_bytes(const std::filesystem::path& p, const std::string& bytes) {
  std::ofstream(p, std::ios::binary).write(bytes.data(), static_cast<std::streamsize>(bytes.size()));
}

TEST(CliMapInfo, JsonFiguresMatchTheMapTheFileCameFrom) {
  test::ScratchFolder dir;
  metric::MetricMap map = room_map();
  // A whole 2 x 2 x 2 group of all-free blocks beside the room (three
  // frames leave no block of the room itself uniform).
  metric::DenseVoxels free_block;
  for (metric::SemanticVoxel& v : free_block) v = {map.occupancy().min(), {}};
  for (int i = 0; i < 8; ++i) map.blocks().assign({20 + (i & 1), 20 + ((i >> 1) & 1), i >> 2}, free_block);
  metric::save_map(map, dir / "map.sarmap");
  const Expected want = expected_of(map);
  ASSERT_GT(want.counts.occupied, 0u);
  ASSERT_GT(want.counts.free, 0u);

  const auto r = run_cli("info --json " + quoted((dir / "map.sarmap").string()), dir.path());
  ASSERT_EQ(r.exit_code, 0) << r.err;
  const auto j = nlohmann::json::parse(r.out);
  EXPECT_EQ(j.at("kind"), "metric_map");
  EXPECT_EQ(j.at("format"), "sarmap");
  EXPECT_EQ(j.at("version"), 3);
  EXPECT_DOUBLE_EQ(j.at("resolution").get<double>(), 0.1);
  EXPECT_EQ(j.at("class_fusion"), "bayesian");
  EXPECT_EQ(j.at("blocks").get<std::size_t>(), want.counts.blocks);
  ASSERT_GE(want.uniform_blocks, 8u);
  EXPECT_EQ(j.at("uniform_blocks").get<std::size_t>(), want.uniform_blocks);
  EXPECT_GE(j.at("blocks_in_uniform_groups").get<std::size_t>(), 8u);
  EXPECT_LE(j.at("blocks_in_uniform_groups").get<std::size_t>(), want.uniform_blocks);
  EXPECT_EQ(j.at("voxels").at("known").get<std::size_t>(), want.counts.known);
  EXPECT_EQ(j.at("voxels").at("free").get<std::size_t>(), want.counts.free);
  EXPECT_EQ(j.at("voxels").at("occupied").get<std::size_t>(), want.counts.occupied);
  std::size_t classes_seen = 0;
  for (const ClassInfo& c : kClassTable) {
    const std::size_t n = want.occupied_by_class[static_cast<std::size_t>(c.id)];
    EXPECT_EQ(j.at("occupied_classes").at(std::string(c.name)).get<std::size_t>(), n) << c.name;
    classes_seen += n > 0;
  }
  EXPECT_GE(classes_seen, 3u);  // the room shows walls, floor and obstacles
  const auto& occupied = j.at("bounds").at("occupied");
  for (int axis = 0; axis < 3; ++axis) {
    EXPECT_NEAR(occupied.at("min")[axis].get<double>(), want.occupied.min[axis], 1e-9) << axis;
    EXPECT_NEAR(occupied.at("max")[axis].get<double>(), want.occupied.max[axis], 1e-9) << axis;
  }
  // What is known includes what is occupied.
  const auto& known = j.at("bounds").at("known");
  for (int axis = 0; axis < 3; ++axis) {
    EXPECT_LE(known.at("min")[axis].get<double>(), want.occupied.min[axis] + 1e-9) << axis;
    EXPECT_GE(known.at("max")[axis].get<double>(), want.occupied.max[axis] - 1e-9) << axis;
  }
}

TEST(CliMapInfo, TextReportNamesResolutionCountsAndClasses) {
  test::ScratchFolder dir;
  const metric::MetricMap map = room_map();
  metric::save_map(map, dir / "room.SARMAP");  // the extension in any case
  const Expected want = expected_of(map);
  const auto r = run_cli("info " + quoted((dir / "room.SARMAP").string()), dir.path());
  ASSERT_EQ(r.exit_code, 0) << r.err;
  EXPECT_EQ(r.err, "");
  EXPECT_THAT(r.out, HasSubstr("format: sarmap metric map (version 3)\n"));
  EXPECT_THAT(r.out, HasSubstr("resolution: 0.1 m\n"));
  EXPECT_THAT(r.out, HasSubstr("blocks: " + std::to_string(want.counts.blocks) + " "));
  EXPECT_THAT(r.out, HasSubstr("voxels: " + std::to_string(want.counts.known) + " known: " +
                               std::to_string(want.counts.free) + " free, " +
                               std::to_string(want.counts.occupied) + " occupied\n"));
  std::string classes = "occupied classes:";
  for (const ClassInfo& c : kClassTable) {
    classes += " " + std::string(c.name) + " " + std::to_string(want.occupied_by_class[static_cast<std::size_t>(c.id)]);
  }
  EXPECT_THAT(r.out, HasSubstr(classes + "\n"));
  EXPECT_THAT(r.out, HasSubstr("known bounds: min ("));
  EXPECT_THAT(r.out, HasSubstr("occupied bounds: min ("));
}

// The loader's checks reach the user: a cut-short file, a file of something
// else and a flipped byte each name the file and what is wrong, exit 1.
TEST(CliMapInfo, DamagedMapFilesAreRefusedNamingFileAndProblem) {
  test::ScratchFolder dir;
  metric::save_map(room_map(), dir / "map.sarmap");
  const std::string bytes = bytes_of(dir / "map.sarmap");
  write_bytes(dir / "cut.sarmap", bytes.substr(0, bytes.size() / 2));
  write_bytes(dir / "tiny.sarmap", bytes.substr(0, 40));
  write_bytes(dir / "other.sarmap", "ply\nformat ascii 1.0\n" + bytes.substr(21));
  std::string flipped = bytes;
  flipped[bytes.size() / 2] = static_cast<char>(flipped[bytes.size() / 2] ^ 0x40);
  write_bytes(dir / "flipped.sarmap", flipped);
  const struct {
    const char* file;
    const char* problem;
  } cases[] = {{"cut.sarmap", "truncated"},
               {"tiny.sarmap", "truncated"},
               {"other.sarmap", "not a sarmap metric map"},
               {"flipped.sarmap", "checksum mismatch"}};
  for (const auto& c : cases) {
    const std::string path = (dir / c.file).string();
    const auto r = run_cli("info " + quoted(path), dir.path());
    EXPECT_EQ(r.exit_code, 1) << c.file;
    EXPECT_EQ(r.err.rfind("sarmap: error: ", 0), 0u) << r.err;
    EXPECT_THAT(r.err, HasSubstr(path)) << c.file;
    EXPECT_THAT(r.err, HasSubstr(c.problem)) << c.file;
    EXPECT_EQ(r.out, "") << c.file;
  }
}

// convert writes what sarmap run writes: the same bytes as voxels.ply's
// writer, read back by the project's readers as the map's occupied voxels
// with class, palette colour, probability and the voxel size.
TEST(CliMapConvert, PlyAndPcdHoldTheOccupiedVoxelsAsRunWritesThem) {
  test::ScratchFolder dir;
  const metric::MetricMap map = room_map();
  metric::save_map(map, dir / "map.sarmap");
  const std::string in = quoted((dir / "map.sarmap").string());
  metric::write_voxel_cloud(map, dir / "direct.ply");
  const std::size_t occupied = map.counts().occupied;
  for (const std::string name : {"v.ply", "v.pcd", "ascii.ply", "ascii.pcd"}) {
    const bool ascii = name.rfind("ascii", 0) == 0;
    const auto r = run_cli("convert " + in + " " + quoted((dir / name).string()) + (ascii ? " --ascii" : ""),
                           dir.path());
    ASSERT_EQ(r.exit_code, 0) << name << ": " << r.err;
    EXPECT_THAT(r.out, HasSubstr(std::to_string(occupied) + " occupied voxels")) << name;
    PointCloudFileInfo info;
    const PointBuffer cloud = read_point_cloud(dir / name, &info);
    EXPECT_EQ(info.encoding.find("ascii") != std::string::npos, ascii) << name;
    EXPECT_THAT(info.comments, ::testing::Contains("voxel_size 0.1")) << name;
    ASSERT_EQ(cloud.size(), occupied) << name;
    ASSERT_TRUE(cloud.has_labels() && cloud.has_colors()) << name;
    const std::size_t probability = cloud.find_score("probability");
    ASSERT_LT(probability, cloud.score_count()) << name;
    for (std::size_t i = 0; i < cloud.size(); ++i) {
      const Eigen::Vector3d p(cloud.x()[i], cloud.y()[i], cloud.z()[i]);
      ASSERT_EQ(map.state_at(p), metric::VoxelState::Occupied) << name << " point " << i;
      const ClassId id = map.class_at(p);
      EXPECT_EQ(cloud.labels()[i], static_cast<std::uint8_t>(id)) << name << " point " << i;
      EXPECT_EQ(cloud.red()[i], class_info(id).color.r) << name << " point " << i;
      EXPECT_EQ(cloud.blue()[i], class_info(id).color.b) << name << " point " << i;
      EXPECT_NEAR(cloud.score(probability)[i], map.probability_at(p), 1e-6) << name << " point " << i;
    }
  }
  EXPECT_EQ(bytes_of(dir / "v.ply"), bytes_of(dir / "direct.ply"));
  // info shows the voxel size a cloud's header carries.
  const auto info = run_cli("info " + quoted((dir / "v.ply").string()), dir.path());
  EXPECT_THAT(info.out, HasSubstr("comment: voxel_size 0.1\n"));
}

TEST(CliMapConvert, BtIsTheOctomapExportOfTheMap) {
  test::ScratchFolder dir;
  const metric::MetricMap map = room_map();
  metric::save_map(map, dir / "map.sarmap");
  const auto r = run_cli("convert --quiet " + quoted((dir / "map.sarmap").string()) + " " +
                             quoted((dir / "map.bt").string()),
                         dir.path());
  ASSERT_EQ(r.exit_code, 0) << r.err;
  EXPECT_EQ(r.out, "");
  const std::string bt = bytes_of(dir / "map.bt");
  EXPECT_EQ(bt.rfind("# Octomap OcTree binary file", 0), 0u);
  EXPECT_THAT(bt, HasSubstr("\nres 0.1"));
  // The writer tests/metric/octomap_export_test.cpp loads with liboctomap, byte for byte.
  EXPECT_EQ(bt, metric::octomap_binary(map));
}

TEST(CliMapConvert, OtIsTheColourTreeExportOfTheMap) {
  test::ScratchFolder dir;
  const metric::MetricMap map = room_map();
  metric::save_map(map, dir / "map.sarmap");
  const auto r =
      run_cli("convert " + quoted((dir / "map.sarmap").string()) + " " + quoted((dir / "map.ot").string()),
              dir.path());
  ASSERT_EQ(r.exit_code, 0) << r.err;
  EXPECT_THAT(r.out,
              HasSubstr("OctoMap colour tree of " + std::to_string(map.counts().known) + " known voxels"));
  const std::string ot = bytes_of(dir / "map.ot");
  EXPECT_EQ(ot.rfind("# Octomap OcTree file\n", 0), 0u);
  EXPECT_THAT(ot, HasSubstr("\nid ColorOcTree\n"));
  // The writer tests/metric/octomap_color_export_test.cpp loads with liboctomap, byte for byte.
  EXPECT_EQ(ot, metric::octomap_color_tree(map));
}

TEST(CliMapConvert, VoxelCubesWriteEightCornersAndSixFacesPerVoxel) {
  test::ScratchFolder dir;
  const metric::MetricMap map = room_map();
  metric::save_map(map, dir / "map.sarmap");
  const auto r = run_cli("convert --voxel-cubes " + quoted((dir / "map.sarmap").string()) + " " +
                             quoted((dir / "cubes.ply").string()),
                         dir.path());
  ASSERT_EQ(r.exit_code, 0) << r.err;
  const std::size_t occupied = map.counts().occupied;
  EXPECT_THAT(r.out, HasSubstr(std::to_string(occupied) + " occupied voxels as cubes"));
  PointCloudFileInfo info;
  const PointBuffer corners = read_point_cloud(dir / "cubes.ply", &info);
  EXPECT_EQ(corners.size(), 8 * occupied);
  EXPECT_THAT(info.comments, ::testing::Contains("voxel_size 0.1"));
  EXPECT_THAT(bytes_of(dir / "cubes.ply"), HasSubstr("element face " + std::to_string(6 * occupied) + "\n"));
  // Every corner lies on a voxel corner of the 0.1 m grid.
  for (std::size_t i = 0; i < corners.size(); ++i) {
    for (const float v : {corners.x()[i], corners.y()[i], corners.z()[i]}) {
      EXPECT_NEAR(v * 10.0f, std::round(v * 10.0f), 1e-3) << i;
    }
  }
}

TEST(CliMapConvert, RefusesWhatAMapCannotBecome) {
  test::ScratchFolder dir;
  metric::save_map(room_map(), dir / "map.sarmap");
  const std::string in = quoted((dir / "map.sarmap").string());
  const struct {
    std::string args;
    const char* says;
  } cases[] = {
      {"convert " + in + " " + quoted((dir / "out.xyz").string()),
       "converts to a .ply or .pcd cloud or an OctoMap .bt or .ot"},
      {"convert --voxel-cubes " + in + " " + quoted((dir / "out.pcd").string()),
       "--voxel-cubes writes a .ply mesh"},
      {"convert --ascii " + in + " " + quoted((dir / "out.bt").string()),
       "--ascii applies to .ply / .pcd clouds"},
      {"convert --ascii " + in + " " + quoted((dir / "out.ot").string()),
       "--ascii applies to .ply / .pcd clouds"},
      {"convert --voxel 0.2 " + in + " " + quoted((dir / "out.ply").string()), "--voxel thins point clouds"},
      {"convert --voxel-cubes " + quoted(kTinyFrame) + " " + quoted((dir / "out.ply").string()),
       "--voxel-cubes needs a metric map"},
  };
  for (const auto& c : cases) {
    const auto r = run_cli(c.args, dir.path());
    EXPECT_EQ(r.exit_code, 1) << c.args;
    EXPECT_EQ(r.err.rfind("sarmap: error: ", 0), 0u) << r.err;
    EXPECT_THAT(r.err, HasSubstr(c.says)) << c.args;
  }
  for (const char* name : {"out.xyz", "out.pcd", "out.bt", "out.ot", "out.ply"})
    EXPECT_FALSE(std::filesystem::exists(dir / name));
}

TEST(CliMapConvert, ADamagedMapIsRefusedAndNothingWritten) {
  test::ScratchFolder dir;
  metric::save_map(room_map(), dir / "map.sarmap");
  const std::string bytes = bytes_of(dir / "map.sarmap");
  write_bytes(dir / "cut.sarmap", bytes.substr(0, bytes.size() - 100));
  const std::string path = (dir / "cut.sarmap").string();
  for (const char* out : {"v.ply", "map.bt", "map.ot"}) {
    const auto r = run_cli("convert " + quoted(path) + " " + quoted((dir / out).string()), dir.path());
    EXPECT_EQ(r.exit_code, 1) << out;
    EXPECT_THAT(r.err, HasSubstr(path)) << out;
    EXPECT_THAT(r.err, HasSubstr("truncated")) << out;
    EXPECT_FALSE(std::filesystem::exists(dir / out)) << out;
  }
  const auto missing = run_cli("convert " + quoted((dir / "none.sarmap").string()) + " " +
                                   quoted((dir / "v.ply").string()),
                               dir.path());
  EXPECT_EQ(missing.exit_code, 1);
  EXPECT_THAT(missing.err, HasSubstr((dir / "none.sarmap").string() + ": no such file"));
}

}  // namespace
}  // namespace sarmap
