// The integrator's scratch key table (engine/core/flat_key_index.hpp)
// against the well-kept alternatives on the same look-up stream: the end-voxel
// dedupe of pass 1, i.e. one find-or-insert per point of a scan at 0.05 m and
// a clear between scans, over the first 16 frames of the default arena.
#include <benchmark/benchmark.h>
#include <tbb/concurrent_hash_map.h>

#include <cstdint>
#include <unordered_map>
#include <vector>

#include "bench/metric/sequence_fixture.hpp"
#include "engine/core/flat_key_index.hpp"
#include "engine/metric/voxel_key.hpp"

namespace {

constexpr std::size_t kFrames = 16;

// Packed voxel keys of every point, frame by frame.
const std::vector<std::vector<std::uint64_t>>& key_stream() {
  static std::vector<std::vector<std::uint64_t>> frames;
  if (!frames.empty()) return frames;
  const auto& scans = sarmap::bench::default_arena_sequence(320);
  for (std::size_t f = 0; f < kFrames && f < scans.size(); ++f) {
    const sarmap::PointBuffer& p = scans[f].points;
    auto& keys = frames.emplace_back();
    for (std::size_t i = 0; i < p.size(); ++i) {
      keys.push_back(sarmap::metric::pack(sarmap::metric::key_of(p.x()[i], p.y()[i], p.z()[i], 20.0)));
    }
  }
  return frames;
}

void report(benchmark::State& state, std::size_t distinct) {
  std::size_t lookups = 0;
  for (const auto& f : key_stream()) lookups += f.size();
  state.counters["lookups_per_s"] =
      benchmark::Counter(static_cast<double>(lookups * state.iterations()), benchmark::Counter::kIsRate);
  state.counters["distinct_per_scan"] = static_cast<double>(distinct) / static_cast<double>(key_stream().size());
}

void BM_FlatKeyIndex(benchmark::State& state) {
  const auto& frames = key_stream();
  sarmap::FlatKeyIndex table(65536);
  std::size_t distinct = 0;
  for (auto _ : state) {
    distinct = 0;
    for (const auto& keys : frames) {
      table.clear();
      for (std::uint64_t k : keys) benchmark::DoNotOptimize(table.find_or_insert(k));
      distinct += table.size();
    }
  }
  report(state, distinct);
}

void BM_StdUnorderedMap(benchmark::State& state) {
  const auto& frames = key_stream();
  std::unordered_map<std::uint64_t, std::uint32_t, sarmap::metric::PackedKeyHash> table;
  table.reserve(65536);
  std::size_t distinct = 0;
  for (auto _ : state) {
    distinct = 0;
    for (const auto& keys : frames) {
      table.clear();
      for (std::uint64_t k : keys) {
        benchmark::DoNotOptimize(table.try_emplace(k, static_cast<std::uint32_t>(table.size())).first->second);
      }
      distinct += table.size();
    }
  }
  report(state, distinct);
}

struct TbbKeyHash {
  static std::size_t hash(std::uint64_t k) { return static_cast<std::size_t>(sarmap::mix_key(k)); }
  static bool equal(std::uint64_t a, std::uint64_t b) { return a == b; }
};

void BM_TbbConcurrentHashMap(benchmark::State& state) {
  const auto& frames = key_stream();
  tbb::concurrent_hash_map<std::uint64_t, std::uint32_t, TbbKeyHash> table(65536);
  std::size_t distinct = 0;
  for (auto _ : state) {
    distinct = 0;
    for (const auto& keys : frames) {
      table.clear();
      std::uint32_t next = 0;
      for (std::uint64_t k : keys) {
        decltype(table)::accessor a;
        if (table.insert(a, k)) a->second = next++;
        benchmark::DoNotOptimize(a->second);
      }
      distinct += table.size();
    }
  }
  report(state, distinct);
}

BENCHMARK(BM_FlatKeyIndex)->Unit(benchmark::kMillisecond);
BENCHMARK(BM_StdUnorderedMap)->Unit(benchmark::kMillisecond);
BENCHMARK(BM_TbbConcurrentHashMap)->Unit(benchmark::kMillisecond);

}  // namespace

BENCHMARK_MAIN();
