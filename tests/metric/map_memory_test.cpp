// Memory as the map and the integrator count it themselves: every block, its
// slab and rows and the table that finds them in the map's figure, the
// integrator's scratch apart from it, and a loaded map packed afresh.
#include <gtest/gtest.h>
#include <unistd.h>

#include <filesystem>

#include <tbb/task_arena.h>

#include "engine/core/state_stream.hpp"
#include "engine/metric/map_file.hpp"
#include "engine/metric/ray_integrator.hpp"
#include "tests/metric/synthetic_room.hpp"

namespace sarmap::metric {
namespace {

MetricMap room_map(RayIntegrator& integrator, int frames) {
  MetricMap map(settings_at_resolution(0.05));
  testing::SyntheticRoom room;
  for (int f = 0; f < frames; ++f) {
    const auto scan = room.frame(f, frames, 80, 60);
    integrator.integrate(map, scan.points, scan.origin);
  }
  return map;
}

TEST(MapMemory, CountsEveryBlockItsSlabItsRowsAndTheTableThatFindsThem) {
  using Blocks = MetricMap::Blocks;
  Blocks blocks;
  const std::size_t empty = blocks.memory_bytes();
  std::size_t before = empty;
  // 4096 blocks, each with a slab of log-odds (one voxel free, the rest
  // unknown) and three voxels with evidence.
  DenseVoxels voxels;
  voxels[0].log_odds = -13;
  for (int l : {1, 100, 511}) voxels[static_cast<std::size_t>(l)].evidence[2] = 9;
  for (int i = 0; i < 4096; ++i) {
    blocks.assign(BlockKey{i % 64 - 32, i / 64 - 32, 5}, voxels);
    const std::size_t now = blocks.memory_bytes();
    ASSERT_GE(now, before) << i;
    before = now;
  }
  const std::size_t held =
      4096 * (sizeof(Blocks::Block) + kBlockVoxels * sizeof(std::int8_t) + 3 * sizeof(StoredEvidence));
  const std::size_t bytes = blocks.memory_bytes();
  EXPECT_GT(bytes, held + empty);  // the key table, pages and chunk classes cost something
  // The key table is about 8 % of blocks this small (a slab of 512 bytes, three rows).
  EXPECT_LT(bytes - held, held * 10 / 100) << "more than 10 % beyond what the blocks hold";
  // By part: each holds at least what it stores, and they add up.
  const Blocks::Memory parts = blocks.memory();
  EXPECT_GE(parts.records, 4096 * sizeof(Blocks::Block));
  EXPECT_GE(parts.index, 4096 * sizeof(std::uint64_t));
  EXPECT_GE(parts.log_odds, 4096 * kBlockVoxels * sizeof(std::int8_t));
  EXPECT_GE(parts.evidence, 4096 * 4 * sizeof(StoredEvidence));  // three rows in a chunk of four
  EXPECT_EQ(parts.records + parts.index + parts.log_odds + parts.evidence + sizeof(Blocks), bytes);
}

void expect_scratch_apart_from_the_map() {
  RayIntegrator integrator;
  const std::size_t idle = integrator.scratch_bytes();
  EXPECT_GT(idle, 0u);
  testing::SyntheticRoom room;
  const auto scan = room.frame(0, 4, 160, 120);
  MetricMap map(settings_at_resolution(0.05));
  const IntegrationStats stats = integrator.integrate(map, scan.points, scan.origin);
  const std::size_t after_one = integrator.scratch_bytes();
  // It keeps at least every end voxel's key and one ray per end voxel.
  EXPECT_GE(after_one - idle, stats.end_voxels * (sizeof(VoxelKey) + 3 * sizeof(double)));
  // Kept and reused: the same scan again needs nothing more.
  MetricMap second(settings_at_resolution(0.05));
  integrator.integrate(second, scan.points, scan.origin);
  EXPECT_EQ(integrator.scratch_bytes(), after_one);
  // The map's figure does not depend on the scratch of the integrator that built it.
  RayIntegrator fresh;
  MetricMap third(settings_at_resolution(0.05));
  fresh.integrate(third, scan.points, scan.origin);
  EXPECT_EQ(third.memory_bytes(), map.memory_bytes());
  EXPECT_GT(map.memory_bytes(), map.blocks().block_count() * sizeof(MetricMap::Blocks::Block));
  // Compact: well under half of 512 dense voxels (14 bytes each) per block.
  EXPECT_LT(map.memory_bytes(), map.blocks().block_count() * sizeof(DenseVoxels) / 2);
  EXPECT_EQ(RayIntegrator(std::move(fresh)).scratch_bytes(), after_one);
  EXPECT_EQ(fresh.scratch_bytes(), 0u);  // NOLINT(bugprone-use-after-move): moved from, holds nothing
}

TEST(MapMemory, TheIntegratorsScratchIsCountedApartFromTheMap) {
  // One thread: each thread that walks rays keeps masks of its own, so with
  // more the scratch depends on which threads took part.
  tbb::task_arena one_thread(1);
  one_thread.execute([] { expect_scratch_apart_from_the_map(); });
}

// A loaded map is packed afresh: no storage given back and kept for later,
// no rows room grown into, so it allocates at most what the map saved did.
TEST(MapMemory, ALoadedMapAllocatesNoMoreThanTheSavedMap) {
  RayIntegrator integrator;
  const MetricMap map = room_map(integrator, 6);
  ASSERT_GT(map.blocks().block_count(), 100u);

  StateWriter out;
  map.save_state(out);
  MetricMap resumed(map.settings());
  StateReader in(out.bytes(), "state.bin");
  resumed.load_state(in);
  EXPECT_LE(resumed.memory_bytes(), map.memory_bytes());
  EXPECT_GT(resumed.memory_bytes(), map.memory_bytes() * 3 / 4);

  const auto dir =
      std::filesystem::temp_directory_path() / ("sarmap_map_memory_" + std::to_string(::getpid()));
  std::filesystem::create_directories(dir);
  save_map(map, dir / "m.sarmap");
  EXPECT_EQ(load_map(dir / "m.sarmap").memory_bytes(), resumed.memory_bytes());
  std::filesystem::remove_all(dir);
}

}  // namespace
}  // namespace sarmap::metric
