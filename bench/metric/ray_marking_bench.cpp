// The free-space walk of ray integration alone (kernels/ray_marking.hpp):
// the scalar reference (one ray at a time, also the SSE4.2 path) against the
// AVX2 and AVX-512 kernels (one ray per lane), marking into blocks found
// through a hash table (BM_RayMarking) and into a dense grid of blocks over
// the frame's box, as the integrator does when the box is small enough
// (BM_RayMarkingDense, grid cleared per frame inside the timing); 1 thread,
// same rays: the first 16 frames of the default arena at 0.05 m, one ray to
// the centre of every distinct end voxel per frame, as the integrator casts them.
#include <benchmark/benchmark.h>

#include <array>
#include <cstdint>
#include <vector>

#include "bench/metric/sequence_fixture.hpp"
#include "engine/core/flat_key_index.hpp"
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
    sarmap::FlatKeyIndex seen(65536);
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
  sarmap::FlatKeyIndex blocks{4096};
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

// Runs mark_frame(frame, reference, level) over the frames, which returns
// the cells visited. Arg: -1 for the scalar reference, else the SimdLevel.
template <class MarkFrame>
void run_ray_marking(benchmark::State& state, MarkFrame&& mark_frame) {
  const bool reference = state.range(0) < 0;
  const auto level = static_cast<sarmap::kernels::SimdLevel>(reference ? 0 : state.range(0));
  if (!reference && !sarmap::kernels::simd_level_supported(level)) {
    state.SkipWithError("not supported by this CPU");
    return;
  }
  const auto& frames = frame_rays();
  std::size_t visits = 0;
  for (auto _ : state) {
    visits = 0;
    for (const FrameRays& f : frames) visits += mark_frame(f, reference, level);
  }
  state.counters["voxel_visits_per_s"] =
      benchmark::Counter(static_cast<double>(visits), benchmark::Counter::kIsIterationInvariantRate);
  state.SetLabel(reference ? "reference" : std::string(sarmap::kernels::to_string(level)));
}

void BM_RayMarking(benchmark::State& state) {
  Masks masks;
  run_ray_marking(state, [&](const FrameRays& f, bool reference, sarmap::kernels::SimdLevel level) {
    masks.blocks.clear();
    masks.words.clear();
    const sarmap::kernels::BlockMaskSink sink{&Masks::block_index, &masks, &masks.base};
    const std::size_t count = f.ends.size() / 3;
    return reference ? sarmap::kernels::mark_ray_cells_reference(f.origin.data(), f.ends.data(), count, sink)
                     : sarmap::kernels::mark_ray_cells(f.origin.data(), f.ends.data(), count, sink, level);
  });
}

void BM_RayMarkingDense(benchmark::State& state) {
  std::vector<std::uint64_t> words;
  run_ray_marking(state, [&](const FrameRays& f, bool reference, sarmap::kernels::SimdLevel level) {
    const std::size_t count = f.ends.size() / 3;
    sarmap::kernels::DenseMaskGrid grid = sarmap::kernels::dense_grid_covering(f.origin.data(), f.ends.data(), count);
    words.assign(sarmap::kernels::dense_grid_blocks(grid) * sarmap::kernels::kMarkBlockWords, 0);
    grid.words = words.data();
    return reference ? sarmap::kernels::mark_ray_cells_dense_reference(f.origin.data(), f.ends.data(), count, grid)
                     : sarmap::kernels::mark_ray_cells_dense(f.origin.data(), f.ends.data(), count, grid, level);
  });
}
BENCHMARK(BM_RayMarkingDense)->ArgName("level")->Arg(-1)->Arg(1)->Arg(2)->Unit(benchmark::kMillisecond)->UseRealTime();

BENCHMARK(BM_RayMarking)->ArgName("level")->Arg(-1)->Arg(1)->Arg(2)->Unit(benchmark::kMillisecond)->UseRealTime();

}  // namespace

BENCHMARK_MAIN();
