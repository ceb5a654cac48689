// The benchmark's input: the default arena simulated by the sim library (160
// frames of 320 x 240 depth, or 640 x 480), built once per process and kept
// in memory so only mapping is timed.
#pragma once

#include <cstddef>
#include <map>
#include <vector>

#include "engine/core/scan.hpp"
#include "engine/sim/arena.hpp"
#include "engine/sim/simulator.hpp"

namespace sarmap::bench {

// width = 320 or 640; the intrinsics scale with it.
inline const std::vector<Scan>& default_arena_sequence(int width) {
  static std::map<int, std::vector<Scan>> cache;
  auto& scans = cache[width];
  if (!scans.empty()) return scans;
  sim::Arena arena = sim::load_arena(SARMAP_SOURCE_DIR "/datasets/arenas/esogu-6x4.json");
  const double scale = static_cast<double>(width) / arena.sensor.intrinsics.width;
  auto& k = arena.sensor.intrinsics;
  k.width = width;
  k.height = static_cast<int>(k.height * scale);
  k.fx *= scale;
  k.fy *= scale;
  k.cx *= scale;
  k.cy *= scale;
  const sim::Simulator simulator(arena);
  for (std::size_t f = 0; f < simulator.frame_count(); ++f) scans.push_back(simulator.simulate(f));
  return scans;
}

inline std::size_t total_points(const std::vector<Scan>& scans) {
  std::size_t n = 0;
  for (const Scan& s : scans) n += s.points.size();
  return n;
}

}  // namespace sarmap::bench
