// `sarmap info` and `sarmap convert` on a metric map (map.sarmap): the
// figures info prints against the MetricMap the file was saved from, each
// output format read back by the project's own readers, and damaged files
// refused with an error naming the file and the problem.
#include <gmock/gmock.h>
#include <gtest/gtest.h>

#include <array>
#include <cstddef>
#include <filesystem>
#include <fstream>
#include <string>

#include <nlohmann/json.hpp>

#include "engine/core/bounds.hpp"
#include "engine/core/classes.hpp"
#include "engine/metric/map_file.hpp"
#include "engine/metric/ray_integrator.hpp"
#include "tests/cli/cli_runner.hpp"
#include "tests/io/scratch_folder.hpp"
#include "tests/metric/synthetic_room.hpp"

namespace sarmap {
namespace {

using test::quoted;
using test::run_cli;
using ::testing::HasSubstr;

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
};

Expected expected_of(const metric::MetricMap& map) {
  Expected e;
  e.counts = map.counts();
  const double half = 0.5 * map.resolution();
  map.blocks().for_each_block([&](const metric::BlockKey& bk, const metric::MetricMap::Blocks::Block&) {
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
  const metric::MetricMap map = room_map();
  metric::save_map(map, dir / "map.sarmap");
  const Expected want = expected_of(map);
  ASSERT_GT(want.counts.occupied, 0u);
  ASSERT_GT(want.counts.free, 0u);

  const auto r = run_cli("info --json " + quoted((dir / "map.sarmap").string()), dir.path());
  ASSERT_EQ(r.exit_code, 0) << r.err;
  const auto j = nlohmann::json::parse(r.out);
  EXPECT_EQ(j.at("kind"), "metric_map");
  EXPECT_EQ(j.at("format"), "sarmap");
  EXPECT_EQ(j.at("version"), 1);
  EXPECT_DOUBLE_EQ(j.at("resolution").get<double>(), 0.1);
  EXPECT_EQ(j.at("class_fusion"), "bayesian");
  EXPECT_EQ(j.at("blocks").get<std::size_t>(), want.counts.blocks);
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
  EXPECT_THAT(r.out, HasSubstr("format: sarmap metric map (version 1)\n"));
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

}  // namespace
}  // namespace sarmap
