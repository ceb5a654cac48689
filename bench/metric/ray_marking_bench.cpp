// The free-space walk of ray integration alone (kernels/ray_marking.hpp):
// the scalar reference (one ray at a time, also the SSE4.2 path) against the
// AVX2 and AVX-512 kernels (one ray per lane), marking into blocks found
// through a hash table (BM_RayMarking) and into a dense grid of blocks over
// the frame's box, as the integrator does when the box is small enough
// (BM_RayMarkingDense, grid cleared per frame inside the timing); 1 thread,
// same rays: the first 16 frames of the default arena at 0.05 m, one ray to
// the centre of every distinct end voxel per frame, as the integrator casts them.
#include <benchmark/benchmark.h>

#include <algorithm>
#include <array>
#include <cmath>
#include <cstdint>
#include <vector>

#include "bench/metric/sequence_fixture.hpp"
#include "engine/metric/flat_key_index.hpp"
#include "engine/metric/voxel_key.hpp"
#include "kernels/ray_marking.hpp"

namespace {

constexpr std::size_t kFrames = 16;
constexpr double kInvResolution = 20.0;  // 0.05 m voxels

struct FrameRays {
  std::array<double, 3> origin;
  std::vector<double> ends;  // xyz per ray, voxel units
};

const std::vector<FrameRays>& frame_rays() {
  static std::vector<FrameRays> frames;
  if (!frames.empty()) return frames;
  const auto& scans = sarmap::bench::default_arena_sequence(320);
  for (std::size_t f = 0; f < kFrames && f < scans.size(); ++f) {
    const sarmap::PointBuffer& p = scans[f].points;
    FrameRays& rays = frames.emplace_back();
    rays.origin = {scans[f].origin.x() * kInvResolution, scans[f].origin.y() * kInvResolution,
                   scans[f].origin.z() * kInvResolution};
    sarmap::metric::FlatKeyIndex seen(65536);
    for (std::size_t i = 0; i < p.size(); ++i) {
      const auto key = sarmap::metric::key_of(p.x()[i], p.y()[i], p.z()[i], kInvResolution);
      if (seen.find_or_insert(sarmap::metric::pack(key)) + 1 != seen.size()) continue;
      rays.ends.insert(rays.ends.end(), {key.x + 0.5, key.y + 0.5, key.z + 0.5});
    }
  }
  return frames;
}

// The integrator's per-thread sink, reduced: a key index and 8 words per block.
struct Masks {
  sarmap::metric::FlatKeyIndex blocks{4096};
  std::vector<std::uint64_t> words;
  std::uint64_t* base = nullptr;
  static std::uint32_t block_index(void* self, std::int32_t bx, std::int32_t by, std::int32_t bz) {
    auto& m = *static_cast<Masks*>(self);
    const std::uint32_t b = m.blocks.find_or_insert(sarmap::metric::pack(bx, by, bz));
    if (b * sarmap::kernels::kMarkBlockWords == m.words.size()) {
      m.words.resize(m.words.size() + sarmap::kernels::kMarkBlockWords, 0);
      m.base = m.words.data();
    }
    return b;
  }
};

// Arg: -1 for the scalar reference, else the SimdLevel.
void BM_RayMarking(benchmark::State& state) {
  const bool reference = state.range(0) < 0;
  const auto level = static_cast<sarmap::kernels::SimdLevel>(reference ? 0 : state.range(0));
  if (!reference && !sarmap::kernels::simd_level_supported(level)) {
    state.SkipWithError("not supported by this CPU");
    return;
  }
  const auto& frames = frame_rays();
  Masks masks;
  std::size_t visits = 0;
  for (auto _ : state) {
    visits = 0;
    for (const FrameRays& f : frames) {
      masks.blocks.clear();
      masks.words.clear();
      const sarmap::kernels::BlockMaskSink sink{&Masks::block_index, &masks, &masks.base};
      visits += reference ? sarmap::kernels::mark_ray_cells_reference(f.origin.data(), f.ends.data(), f.ends.size() / 3, sink)
                          : sarmap::kernels::mark_ray_cells(f.origin.data(), f.ends.data(), f.ends.size() / 3, sink, level);
    }
  }
  state.counters["voxel_visits_per_s"] =
      benchmark::Counter(static_cast<double>(visits), benchmark::Counter::kIsIterationInvariantRate);
  state.SetLabel(reference ? "reference" : std::string(sarmap::kernels::to_string(level)));
}

// Arg: -1 for the scalar reference, else the SimdLevel.
void BM_RayMarkingDense(benchmark::State& state) {
  const bool reference = state.range(0) < 0;
  const auto level = static_cast<sarmap::kernels::SimdLevel>(reference ? 0 : state.range(0));
  if (!reference && !sarmap::kernels::simd_level_supported(level)) {
    state.SkipWithError("not supported by this CPU");
    return;
  }
  const auto& frames = frame_rays();
  std::vector<std::uint64_t> words;
  std::size_t visits = 0;
  for (auto _ : state) {
    visits = 0;
    for (const FrameRays& f : frames) {
      // The box of the origin's and the ends' blocks.
      sarmap::kernels::DenseMaskGrid grid{};
      std::size_t blocks = 1;
      for (int i = 0; i < 3; ++i) {
        double lo = f.origin[i], hi = f.origin[i];
        for (std::size_t r = i; r < f.ends.size(); r += 3) lo = std::min(lo, f.ends[r]), hi = std::max(hi, f.ends[r]);
        grid.first_block[i] = static_cast<std::int32_t>(std::floor(lo)) >> sarmap::kernels::kMarkBlockShift;
        grid.blocks[i] =
            (static_cast<std::int32_t>(std::floor(hi)) >> sarmap::kernels::kMarkBlockShift) - grid.first_block[i] + 1;
        blocks *= static_cast<std::size_t>(grid.blocks[i]);
      }
      words.assign(blocks * sarmap::kernels::kMarkBlockWords, 0);
      grid.words = words.data();
      const std::size_t count = f.ends.size() / 3;
      visits += reference ? sarmap::kernels::mark_ray_cells_dense_reference(f.origin.data(), f.ends.data(), count, grid)
                          : sarmap::kernels::mark_ray_cells_dense(f.origin.data(), f.ends.data(), count, grid, level);
    }
  }
  state.counters["voxel_visits_per_s"] =
      benchmark::Counter(static_cast<double>(visits), benchmark::Counter::kIsIterationInvariantRate);
  state.SetLabel(reference ? "reference" : std::string(sarmap::kernels::to_string(level)));
}
BENCHMARK(BM_RayMarkingDense)->ArgName("level")->Arg(-1)->Arg(1)->Arg(2)->Unit(benchmark::kMillisecond)->UseRealTime();

BENCHMARK(BM_RayMarking)->ArgName("level")->Arg(-1)->Arg(1)->Arg(2)->Unit(benchmark::kMillisecond)->UseRealTime();

}  // namespace

BENCHMARK_MAIN();
