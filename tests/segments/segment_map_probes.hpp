// What the segment tests read of a SegmentMap beyond its public segments:
// its saved state as bytes, and how many points wait unassigned.
#pragma once

#include <cstddef>
#include <string>

#include "engine/core/state_stream.hpp"
#include "engine/segments/segment_map.hpp"

namespace sarmap::segments::testing {

inline std::string state_of(const SegmentMap& map) {
  StateWriter out;
  map.save_state(out);
  return out.bytes();
}

inline std::size_t pending_total(const SegmentMap& map) {
  std::size_t total = 0;
  for (std::size_t c : map.pending_counts()) total += c;
  return total;
}

}  // namespace sarmap::segments::testing
