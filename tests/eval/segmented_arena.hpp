// The segment stage run on an arena's simulated scans, labelled with the
// ground truth (what `sarmap run --classifier labels` feeds it), and scored
// against the arena's faces: the harness of the arena-level segment tests.
#pragma once

#include <cstddef>
#include <vector>

#include "engine/eval/segment_scores.hpp"
#include "engine/segments/segment_map.hpp"
#include "engine/sim/ground_truth_grid.hpp"
#include "engine/sim/simulator.hpp"

namespace sarmap::eval::testing {

struct SegmentedArena {
  segments::SegmentMap map;
  std::vector<segments::Segment> segments;
  SegmentScores scores;
};

// Every `frame_stride`-th frame of the arena's trajectory, with its own noise
// model, into a segment map of default settings; faces count as seen by the
// same frames (every second ray is plenty at 5 cm voxels).
inline SegmentedArena segment_arena(const sim::Arena& arena, std::size_t frame_stride) {
  SegmentedArena out;
  const sim::Simulator simulator(arena);
  for (std::size_t f = 0; f < simulator.frame_count(); f += frame_stride) {
    Scan scan = simulator.simulate(f);
    scan.points.remove_non_finite();
    out.map.integrate(scan.points, scan.origin);
  }
  for (const segments::Segment* s : out.map.segments()) out.segments.push_back(*s);
  sim::GroundTruthOptions truth;
  truth.resolution = 0.05;
  truth.frame_stride = frame_stride;
  truth.ray_stride = 2;
  out.scores = score_segments(arena, sim::voxelize_arena(simulator, truth), out.segments);
  return out;
}

}  // namespace sarmap::eval::testing
