// grid.pgm + grid.yaml as ROS map_server reads them: the exact bytes written,
// round trips, what the reader accepts from other writers (comments, quotes,
// negate, its own thresholds), and the errors it gives for bad files.
#include "engine/topo/ros_map_files.hpp"

#include <gtest/gtest.h>

#include <unistd.h>
#include <filesystem>
#include <functional>
#include <random>
#include <string>

#include "engine/core/error.hpp"
#include "tests/file_bytes.hpp"

namespace sarmap::topo {
namespace {

using test::slurp;
using test::spit;

class RosMapFiles : public ::testing::Test {
 protected:
  void SetUp() override {
    // Unique per process: ctest runs test processes in parallel.
    folder_ = std::filesystem::temp_directory_path() / ("sarmap_ros_map_test_" + std::to_string(::getpid()));
    std::filesystem::remove_all(folder_);
    std::filesystem::create_directories(folder_);
  }
  void TearDown() override { std::filesystem::remove_all(folder_); }

  void expect_error(const std::function<void()>& call, ErrorCode code, const std::string& fragment) {
    try {
      call();
      ADD_FAILURE() << "no error; expected one naming '" << fragment << "'";
    } catch (const Error& e) {
      EXPECT_EQ(e.code(), code) << e.what();
      EXPECT_NE(std::string(e.what()).find(fragment), std::string::npos) << e.what();
    }
  }

  std::filesystem::path folder_;
};

bool same_grid(const PlanningGrid& a, const PlanningGrid& b) {
  return a.width() == b.width() && a.height() == b.height() && a.resolution() == b.resolution() &&
         a.origin() == b.origin() && std::equal(a.cells().begin(), a.cells().end(), b.cells().begin());
}

TEST_F(RosMapFiles, WritesMapSaversBytesWithTheTopRowFirst) {
  // Row y = 0 (lowest): free, occupied, unknown; row y = 1: occupied, free, free.
  PlanningGrid grid(3, 2, 0.05, Eigen::Vector2d(-2.5, 1.0), CellState::Free);
  grid.set({1, 0}, CellState::Occupied);
  grid.set({2, 0}, CellState::Unknown);
  grid.set({0, 1}, CellState::Occupied);
  const RosMapPaths paths = write_ros_map(grid, folder_);
  EXPECT_EQ(paths.image, folder_ / "grid.pgm");
  EXPECT_EQ(paths.yaml, folder_ / "grid.yaml");
  EXPECT_EQ(slurp(paths.image),
            std::string("P5\n3 2\n255\n") + std::string("\x00\xFE\xFE", 3) + std::string("\xFE\x00\xCD", 3));
  EXPECT_EQ(slurp(paths.image).size(), 11u + 6u);
  EXPECT_EQ(slurp(paths.yaml),
            "image: grid.pgm\n"
            "resolution: 0.05\n"
            "origin: [-2.5, 1.0, 0.0]\n"
            "negate: 0\n"
            "occupied_thresh: 0.65\n"
            "free_thresh: 0.196\n");
  // No temporary files left beside them.
  EXPECT_EQ(
      std::distance(std::filesystem::directory_iterator(folder_), std::filesystem::directory_iterator()), 2);
}

TEST_F(RosMapFiles, RoundTripsRandomGridsExactly) {
  std::mt19937 random(4);
  std::uniform_real_distribution<double> unit(-50.0, 50.0);
  for (int round = 0; round < 20; ++round) {
    PlanningGrid grid(1 + static_cast<int>(random() % 90), 1 + static_cast<int>(random() % 60),
                      0.01 + std::abs(unit(random)) / 100.0, Eigen::Vector2d(unit(random), unit(random)));
    for (CellState& c : grid.cells()) c = static_cast<CellState>(random() % 3);
    const RosMapPaths paths = write_ros_map(grid, folder_, "map_" + std::to_string(round));
    EXPECT_TRUE(same_grid(read_ros_map(paths.yaml), grid)) << "round " << round;
  }
}

TEST_F(RosMapFiles, ReadsWhatOtherWritersProduce) {
  // A header with comments, CR LF and quoted values in the YAML, a key this
  // reader does not know, its own thresholds and negate: 1 (dark = free).
  const std::string pgm =
      std::string("P5\n# CREATOR: someone else\n2 # width\n1\n# depth next\n200\n") + "\x10\xC0";
  spit(folder_ / "other image.pgm", pgm);
  spit(folder_ / "other.yaml",
       "# a map\r\n"
       "image: \"other image.pgm\"  # beside this file\r\n"
       "mode: trinary\r\n"
       "resolution: 0.1\r\n"
       "origin: [ 1.5 , -2 , 0 ]\r\n"
       "negate: 1\r\n"
       "occupied_thresh: 0.5\r\n"
       "free_thresh: 0.2\r\n"
       "extra_key: 7\r\n");
  const PlanningGrid grid = read_ros_map(folder_ / "other.yaml");
  EXPECT_EQ(grid.width(), 2);
  EXPECT_EQ(grid.height(), 1);
  EXPECT_EQ(grid.resolution(), 0.1);
  EXPECT_EQ(grid.origin(), Eigen::Vector2d(1.5, -2.0));
  // negate 1: occupancy = value / maxval: 16/200 = 0.08 < 0.2 free, 192/200 = 0.96 > 0.5 occupied.
  EXPECT_EQ(grid.at({0, 0}), CellState::Free);
  EXPECT_EQ(grid.at({1, 0}), CellState::Occupied);
}

TEST_F(RosMapFiles, ClassifiesPixelsAsMapServerDoes) {
  // With negate 0 and the usual thresholds: occupied up to 89, free from 206 (205 is unknown).
  std::string pixels;
  for (const int v : {0, 89, 90, 204, 205, 206, 254, 255}) pixels += static_cast<char>(v);
  spit(folder_ / "levels.pgm", "P5 8 1 255\n" + pixels);
  spit(folder_ / "levels.yaml",
       "image: levels.pgm\nresolution: 1\norigin: [0, 0, 0]\nnegate: 0\noccupied_thresh: 0.65\nfree_thresh: "
       "0.196\n");
  const PlanningGrid grid = read_ros_map(folder_ / "levels.yaml");
  const std::vector<CellState> expected{CellState::Occupied, CellState::Occupied, CellState::Unknown,
                                        CellState::Unknown,  CellState::Unknown,  CellState::Free,
                                        CellState::Free,     CellState::Free};
  EXPECT_TRUE(std::equal(expected.begin(), expected.end(), grid.cells().begin()));
}

TEST_F(RosMapFiles, RefusesBadYaml) {
  const PlanningGrid grid(2, 2, 0.1, Eigen::Vector2d::Zero(), CellState::Free);
  const RosMapPaths paths = write_ros_map(grid, folder_);
  const std::string good = slurp(paths.yaml);
  const auto with = [&](const std::string& from, const std::string& to) {
    std::string text = good;
    text.replace(text.find(from), from.size(), to);
    spit(paths.yaml, text);
  };
  const auto read = [&] { read_ros_map(paths.yaml); };
  with("resolution: 0.1\n", "");
  expect_error(read, ErrorCode::Parse, "missing the key 'resolution'");
  with("resolution: 0.1", "resolution: fine");
  expect_error(read, ErrorCode::Parse, "grid.yaml:2: resolution: 'fine' is not a finite number");
  with("resolution: 0.1", "resolution: -0.1");
  expect_error(read, ErrorCode::Parse, "resolution must be > 0");
  with("origin: [0.0, 0.0, 0.0]", "origin: [0.0, 0.0]");
  expect_error(read, ErrorCode::Parse, "grid.yaml:3: origin: expected three numbers");
  with("origin: [0.0, 0.0, 0.0]", "origin: 0.0");
  expect_error(read, ErrorCode::Parse, "origin: expected [x, y, yaw]");
  with("origin: [0.0, 0.0, 0.0]", "origin: [0.0, 0.0, 1.57]");
  expect_error(read, ErrorCode::Unsupported, "rotated maps are not supported");
  with("negate: 0", "negate: 2");
  expect_error(read, ErrorCode::Parse, "negate: expected 0 or 1");
  with("free_thresh: 0.196", "free_thresh: 0.7");
  expect_error(read, ErrorCode::Parse, "free_thresh <= occupied_thresh");
  with("negate: 0", "negate: 0\nmode: scale");
  expect_error(read, ErrorCode::Unsupported, "mode 'scale': only trinary maps are read");
  with("negate: 0", "negate: 0\nnegate: 0");
  expect_error(read, ErrorCode::Parse, "grid.yaml:5: 'negate' is given twice");
  with("negate: 0", "negate 0");
  expect_error(read, ErrorCode::Parse, "grid.yaml:4: expected 'key: value'");
  with("image: grid.pgm", "image: missing.pgm");
  expect_error(read, ErrorCode::Io, "missing.pgm");
  std::filesystem::remove(paths.yaml);
  expect_error(read, ErrorCode::Io, "grid.yaml");
}

TEST_F(RosMapFiles, RefusesBadPgm) {
  const PlanningGrid grid(3, 2, 0.1, Eigen::Vector2d::Zero(), CellState::Free);
  const RosMapPaths paths = write_ros_map(grid, folder_);
  const std::string good = slurp(paths.image);
  const auto read = [&] { read_ros_map(paths.yaml); };
  spit(paths.image, good.substr(0, good.size() - 1));
  expect_error(read, ErrorCode::Parse,
               "grid.pgm (byte offset 11): the PGM holds 5 bytes of pixels, 3 x 2 needs 6");
  spit(paths.image, good + "x");
  expect_error(read, ErrorCode::Parse, "holds 7 bytes of pixels");
  spit(paths.image, "P2\n3 2\n255\n254 254 254 254 254 254\n");
  expect_error(read, ErrorCode::Unsupported, "only binary 8-bit PGM (P5) is read");
  spit(paths.image, "P5\n3 2\n65535\n" + std::string(12, '\0'));
  expect_error(read, ErrorCode::Unsupported, "16-bit");
  spit(paths.image, "P5\n3 x\n255\n" + std::string(6, '\0'));
  expect_error(read, ErrorCode::Parse, "expected the height in the PGM header");
  spit(paths.image, "P5\n0 2\n255\n");
  expect_error(read, ErrorCode::Parse, "a PGM of 0 x 2 pixels");
  spit(paths.image, "GIF89a");
  expect_error(read, ErrorCode::Parse, "not a PGM file");
  spit(paths.image, "P5\n3 2\n255");
  expect_error(read, ErrorCode::Parse, "expected one whitespace byte after the PGM's maximum value");
}

TEST_F(RosMapFiles, RefusesStemsThatWouldNeedQuotingOrLeaveTheFolder) {
  const PlanningGrid grid(2, 2, 0.1, Eigen::Vector2d::Zero());
  for (const char* stem : {"", "..", "a/b", "a b", "a:b", "#x"}) {
    expect_error([&] { write_ros_map(grid, folder_, stem); }, ErrorCode::InvalidArgument, "file stem");
  }
  expect_error([&] { write_ros_map(grid, folder_ / "no such folder"); }, ErrorCode::Io, "no such folder");
}

}  // namespace
}  // namespace sarmap::topo
