// The .sarmap file: exact round trip, and corrupt or truncated files rejected
// with a message naming the problem.
#include "engine/metric/map_file.hpp"

#include <gtest/gtest.h>
#include <zlib.h>
#include <unistd.h>

#include <cstring>
#include <filesystem>
#include <fstream>
#include <iterator>

#include "engine/core/error.hpp"
#include "engine/metric/ray_integrator.hpp"
#include "tests/metric/synthetic_room.hpp"

namespace sarmap::metric {
namespace {

namespace fs = std::filesystem;

class MapFileTest : public ::testing::Test {
 protected:
  void SetUp() override {
    dir_ = fs::temp_directory_path() / ("sarmap_map_file_test_" + std::to_string(::getpid()));
    fs::create_directories(dir_);
  }
  void TearDown() override { fs::remove_all(dir_); }
  fs::path dir_;
};

MetricMap room_map(ClassFusion fusion) {
  MetricMapSettings s = settings_at_resolution(0.1);
  s.fusion.fusion = fusion;
  s.occupancy.prob_hit = 0.75;
  MetricMap map(s);
  RayIntegrator integrator;
  testing::SyntheticRoom room;
  for (int f = 0; f < 3; ++f) {
    const auto scan = room.frame(f, 3, 40, 30);
    integrator.integrate(map, scan.points, scan.origin);
  }
  return map;
}

std::string bytes_of(const fs::path& p) {
  std::ifstream in(p, std::ios::binary);
  return {std::istreambuf_iterator<char>(in), std::istreambuf_iterator<char>()};
}
void write_bytes(const fs::path& p, const std::string& b) {
  std::ofstream(p, std::ios::binary).write(b.data(), static_cast<std::streamsize>(b.size()));
}
std::string load_error(const fs::path& p) {
  try {
    load_map(p);
  } catch (const Error& e) {
    return e.what();
  }
  return "";
}

TEST(MapFilePath, IsTheSarmapExtensionInAnyCase) {
  EXPECT_TRUE(is_map_file_path("run/map.sarmap"));
  EXPECT_TRUE(is_map_file_path("MAP.SarMap"));
  EXPECT_FALSE(is_map_file_path("run/map.bt"));
  EXPECT_FALSE(is_map_file_path("sarmap"));
  EXPECT_FALSE(is_map_file_path("map.sarmap.tmp"));
}

TEST_F(MapFileTest, RoundTripIsExact) {
  for (const ClassFusion fusion : {ClassFusion::Bayesian, ClassFusion::Histogram}) {
    const MetricMap map = room_map(fusion);
    save_map(map, dir_ / "m.sarmap");
    const MetricMap back = load_map(dir_ / "m.sarmap");
    EXPECT_EQ(back.resolution(), map.resolution());
    EXPECT_EQ(back.settings().fusion.fusion, fusion);
    EXPECT_EQ(back.occupancy().hit(), map.occupancy().hit());
    ASSERT_EQ(back.blocks().sorted_block_keys(), map.blocks().sorted_block_keys());
    for (const BlockKey& k : map.blocks().sorted_block_keys()) {
      const DenseVoxels ours = map.blocks().find(k)->dense(), read = back.blocks().find(k)->dense();
      EXPECT_EQ(std::memcmp(read.data(), ours.data(), sizeof(ours)), 0);
    }
    // Saving the loaded map gives the same bytes.
    save_map(back, dir_ / "again.sarmap");
    EXPECT_EQ(bytes_of(dir_ / "m.sarmap"), bytes_of(dir_ / "again.sarmap"));
  }
}

TEST_F(MapFileTest, CorruptAndTruncatedFilesNameTheProblem) {
  save_map(room_map(ClassFusion::Bayesian), dir_ / "m.sarmap");
  const std::string good = bytes_of(dir_ / "m.sarmap");
  const fs::path bad = dir_ / "bad.sarmap";

  write_bytes(bad, good.substr(0, good.size() - 100));
  EXPECT_NE(load_error(bad).find("truncated"), std::string::npos) << load_error(bad);
  write_bytes(bad, good.substr(0, 20));
  EXPECT_NE(load_error(bad).find("truncated"), std::string::npos) << load_error(bad);

  std::string flipped = good;
  flipped[good.size() / 2] ^= 0x10;
  write_bytes(bad, flipped);
  EXPECT_NE(load_error(bad).find("checksum mismatch"), std::string::npos) << load_error(bad);

  std::string magic = good;
  magic[0] = 'X';
  write_bytes(bad, magic);
  EXPECT_NE(load_error(bad).find("magic"), std::string::npos);

  std::string version = good;
  version[8] = 9;
  write_bytes(bad, version);
  EXPECT_NE(load_error(bad).find("unsupported version 9"), std::string::npos);

  // A block key at INT32_MIN behind a valid checksum: refused as beyond the
  // map's limits (the first block's x sits right after the 96-byte header).
  std::string far = good;
  const char int_min[4] = {0, 0, 0, static_cast<char>(0x80)};
  far.replace(96, 4, int_min, 4);
  const std::uint32_t crc = static_cast<std::uint32_t>(
      crc32(0, reinterpret_cast<const Bytef*>(far.data()), static_cast<uInt>(far.size() - 4)));
  for (int i = 0; i < 4; ++i) far[far.size() - 4 + i] = static_cast<char>((crc >> (8 * i)) & 0xff);
  write_bytes(bad, far);
  EXPECT_NE(load_error(bad).find("(-2147483648, "), std::string::npos) << load_error(bad);
  EXPECT_NE(load_error(bad).find("beyond the map limits"), std::string::npos) << load_error(bad);

  EXPECT_NE(load_error(dir_ / "missing.sarmap").find("cannot open"), std::string::npos);
  // Every message names the file.
  EXPECT_NE(load_error(bad).find("bad.sarmap"), std::string::npos);
}

}  // namespace
}  // namespace sarmap::metric
