// The benchmarks' input: an arena of datasets/arenas simulated by the sim
// library at 320 x 240 or 640 x 480 depth (the default arena: 160 frames;
// the 52 x 15 m building arena for a larger map), built once per process
// and kept in memory so only mapping is timed.
#pragma once

#include <cstddef>
#include <map>
#include <string>
#include <utility>
#include <vector>

#include "engine/core/scan.hpp"
#include "engine/sim/arena.hpp"
#include "engine/sim/simulator.hpp"

namespace sarmap::bench {

// arena_file in datasets/arenas; width = 320 or 640, the intrinsics scale with it.
inline const std::vector<Scan>& arena_sequence(const std::string& arena_file, int width) {
  static std::map<std::pair<std::string, int>, std::vector<Scan>> cache;
  auto& scans = cache[{arena_file, width}];
  if (!scans.empty()) return scans;
  sim::Arena arena = sim::load_arena(SARMAP_SOURCE_DIR "/datasets/arenas/" + arena_file);
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

inline const std::vector<Scan>& default_arena_sequence(int width) { return arena_sequence("esogu-6x4.json", width); }
inline const std::vector<Scan>& building_arena_sequence(int width) {
  return arena_sequence("building-52x15.json", width);
}

inline std::size_t total_points(const std::vector<Scan>& scans) {
  std::size_t n = 0;
  for (const Scan& s : scans) n += s.points.size();
  return n;
}

}  // namespace sarmap::bench
