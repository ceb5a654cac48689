// The .sarmap file: exact round trip, and corrupt or truncated files rejected
// with a message naming the problem.
#include "engine/metric/map_file.hpp"

#include <gtest/gtest.h>
#include <zlib.h>
#include <unistd.h>

#include <algorithm>
#include <array>
#include <cmath>
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

// Appends v little-endian in n bytes.
void put_le(std::string& out, std::uint64_t v, int n) {
  for (int i = 0; i < n; ++i) out.push_back(static_cast<char>((v >> (8 * i)) & 0xff));
}
// Replaces the trailing CRC-32 by that of the bytes before it.
void reseal(std::string& file) {
  const std::uint32_t crc = static_cast<std::uint32_t>(
      crc32(0, reinterpret_cast<const Bytef*>(file.data()), static_cast<uInt>(file.size() - 4)));
  for (int i = 0; i < 4; ++i) file[file.size() - 4 + i] = static_cast<char>((crc >> (8 * i)) & 0xff);
}
// The map as an earlier version wrote it, in that version's units (log-odds
// in 1/1024 nat within the clamp range of the day, Bayesian evidence in
// 1/256 nat): version 1 every voxel, version 2 compactly. The 96-byte header
// is `compact`'s (a version 3 file of the same map) with the version's
// number, layout and 14-byte payload.
std::string legacy_file(const MetricMap& map, const std::string& compact, int version) {
  std::string file = compact.substr(0, 96);
  file[8] = static_cast<char>(version);
  file[21] = static_cast<char>(version);  // payload layout, after magic, version, resolution and fusion
  file[22] = 14;
  file[23] = 0;
  const OccupancySettings& occ = map.settings().occupancy;
  const auto wide = [](double p) { return std::lround(std::log(p / (1 - p)) * 1024.0); };
  const auto put_log_odds = [&](std::int16_t v) {
    const long old = v == kUnknownLogOdds ? v : std::clamp<long>(v * 32L, wide(occ.clamp_min), wide(occ.clamp_max));
    put_le(file, static_cast<std::uint16_t>(old), 2);
  };
  const bool bayesian = map.settings().fusion.fusion == ClassFusion::Bayesian;
  const auto put_evidence = [&](const ClassEvidence& e) {
    for (std::int16_t v : e) put_le(file, static_cast<std::uint16_t>(bayesian ? std::lround(v * 256.0 / 6.0) : v), 2);
  };
  for (const BlockKey& k : map.blocks().sorted_block_keys()) {
    for (std::int32_t c : {k.x, k.y, k.z}) put_le(file, static_cast<std::uint32_t>(c), 4);
    const DenseVoxels voxels = map.blocks().find(k)->dense();
    if (version == 1) {
      for (const SemanticVoxel& v : voxels) {
        put_log_odds(v.log_odds);
        put_evidence(v.evidence);
      }
      continue;
    }
    const bool uniform = std::all_of(voxels.begin(), voxels.end(),
                                     [&](const SemanticVoxel& v) { return v.log_odds == voxels[0].log_odds; });
    put_le(file, uniform ? 0 : 1, 1);
    for (int l = 0; l < (uniform ? 1 : kBlockVoxels); ++l) put_log_odds(voxels[static_cast<std::size_t>(l)].log_odds);
    std::array<std::uint64_t, kBlockVoxels / 64> mask{};
    for (int l = 0; l < kBlockVoxels; ++l) {
      if (!no_evidence(voxels[static_cast<std::size_t>(l)].evidence)) mask[l >> 6] |= std::uint64_t{1} << (l & 63);
    }
    for (std::uint64_t word : mask) put_le(file, word, 8);
    for (const SemanticVoxel& v : voxels) {
      if (!no_evidence(v.evidence)) put_evidence(v.evidence);
    }
  }
  file.append(4, '\0');
  reseal(file);
  return file;
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

// Version 3 stores a block's log-odds once when all 512 agree and evidence
// only where a voxel holds some, a byte per value; version 1 and 2 files
// (two bytes per value, in the units of their day) load to the same map.
TEST_F(MapFileTest, EarlierVersionsLoadToTheSameMap) {
  for (const ClassFusion fusion : {ClassFusion::Bayesian, ClassFusion::Histogram}) {
    const MetricMap map = room_map(fusion);
    save_map(map, dir_ / "m.sarmap");
    const std::string compact = bytes_of(dir_ / "m.sarmap");
    ASSERT_EQ(compact[8], 3);
    EXPECT_EQ(read_map_file(dir_ / "m.sarmap").version, 3u);
    for (const int version : {1, 2}) {
      const std::string old = legacy_file(map, compact, version);
      EXPECT_LT(compact.size() * (version == 1 ? 6 : 1), old.size()) << "version 3 should be smaller";
      write_bytes(dir_ / "old.sarmap", old);
      const MetricMap back = load_map(dir_ / "old.sarmap");
      EXPECT_EQ(read_map_file(dir_ / "old.sarmap").version, static_cast<std::uint32_t>(version));
      ASSERT_EQ(back.blocks().sorted_block_keys(), map.blocks().sorted_block_keys());
      for (const BlockKey& k : map.blocks().sorted_block_keys()) {
        const DenseVoxels ours = map.blocks().find(k)->dense(), read = back.blocks().find(k)->dense();
        EXPECT_EQ(std::memcmp(read.data(), ours.data(), sizeof(ours)), 0) << "version " << version;
      }
      // Saved again, it is written as version 3, byte for byte as the map itself.
      save_map(back, dir_ / "again.sarmap");
      EXPECT_EQ(bytes_of(dir_ / "again.sarmap"), compact);
    }
  }
}

// A block's bytes follow its values: uniform occupancy is one value, a
// voxel's evidence a row only where it is not all zero.
TEST_F(MapFileTest, CompactBlocksStoreWhatTheVoxelsHold) {
  MetricMap map(settings_at_resolution(0.1));
  DenseVoxels all_free;
  for (SemanticVoxel& v : all_free) v.log_odds = map.occupancy().min();
  map.blocks().assign({0, 0, 0}, all_free);
  DenseVoxels mixed = all_free;
  mixed[5].log_odds = map.occupancy().max();
  mixed[5].evidence = {0, 0, 7, 0, 0, 0};
  mixed[511].evidence = {1, 0, 0, 0, 0, -3};
  map.blocks().assign({1, 0, 0}, mixed);
  save_map(map, dir_ / "m.sarmap");
  const std::string file = bytes_of(dir_ / "m.sarmap");
  // Header, uniform block (key, kind, one value, mask), block with two rows, CRC.
  EXPECT_EQ(file.size(), 96u + (12 + 1 + 1 + 64) + (12 + 1 + 512 + 64 + 2 * 6) + 4);
  const MetricMap back = load_map(dir_ / "m.sarmap");
  for (const BlockKey& k : {BlockKey{0, 0, 0}, BlockKey{1, 0, 0}}) {
    const DenseVoxels ours = map.blocks().find(k)->dense(), read = back.blocks().find(k)->dense();
    EXPECT_EQ(std::memcmp(read.data(), ours.data(), sizeof(ours)), 0);
  }
  // A row of zeros where the mask says evidence is held (voxel 511's, the
  // file's last row) is refused, not read as a second way to say "none".
  std::string zero_row = file;
  zero_row.replace(zero_row.size() - 4 - 6, 6, std::string(6, '\0'));
  reseal(zero_row);
  write_bytes(dir_ / "bad.sarmap", zero_row);
  EXPECT_NE(load_error(dir_ / "bad.sarmap").find("voxel 511 of block (1, 0, 0) has an all-zero evidence row"),
            std::string::npos)
      << load_error(dir_ / "bad.sarmap");
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
  reseal(far);
  write_bytes(bad, far);
  EXPECT_NE(load_error(bad).find("(-2147483648, "), std::string::npos) << load_error(bad);
  EXPECT_NE(load_error(bad).find("beyond the map limits"), std::string::npos) << load_error(bad);

  // Behind a valid checksum: an occupancy kind that does not exist (the
  // first block's, after its key), trailing bytes, more blocks than fit.
  std::string kind = good;
  kind[108] = 7;
  reseal(kind);
  write_bytes(bad, kind);
  EXPECT_NE(load_error(bad).find("unknown block occupancy kind 7"), std::string::npos) << load_error(bad);
  std::string trailing = good;
  trailing.insert(trailing.size() - 4, "xx");
  reseal(trailing);
  write_bytes(bad, trailing);
  EXPECT_NE(load_error(bad).find("trailing bytes"), std::string::npos) << load_error(bad);
  std::string many = good;
  many[95] = 0x10;  // the block count's top byte
  reseal(many);
  write_bytes(bad, many);
  EXPECT_NE(load_error(bad).find("hold at most"), std::string::npos) << load_error(bad);
  // A version 1 header with version 3's compact blocks.
  std::string layout = good;
  layout[8] = 1;
  reseal(layout);
  write_bytes(bad, layout);
  EXPECT_NE(load_error(bad).find("version 1 expects layout 1"), std::string::npos) << load_error(bad);

  EXPECT_NE(load_error(dir_ / "missing.sarmap").find("cannot open"), std::string::npos);
  // Every message names the file.
  EXPECT_NE(load_error(bad).find("bad.sarmap"), std::string::npos);
}

}  // namespace
}  // namespace sarmap::metric
