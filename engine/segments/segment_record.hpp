// The segment map's record of one segment, private to the segment map: apart
// from segment_map.cpp only so that segment_map_state.cpp can save it whole.
#pragma once

#include <cstddef>
#include <cstdint>
#include <vector>

#include <Eigen/Core>

#include "engine/core/bounds.hpp"
#include "engine/segments/plane_moments.hpp"
#include "engine/segments/segment.hpp"
#include "engine/segments/segment_map.hpp"

namespace sarmap::segments {

// merged_into_ per id: the survivor's id, or one of these.
inline constexpr std::int64_t kAlive = -1;
inline constexpr std::int64_t kDissolved = -2;

// A segment with what it takes to grow it: running sums, its points and outline.
struct SegmentMap::Record {
  Segment view;
  bool alive = true;
  PlaneMoments moments;
  // Sum of (sensor origin - point) over points seen from a known origin: the
  // side a wall was seen from.
  Eigen::Vector3d view_sum = Eigen::Vector3d::Zero();
  // Point indices; entries that left (owner no longer this id) linger until compacted.
  std::vector<std::uint32_t> members;
  std::size_t stale = 0;
  // The last outline's corner points plus the points joined since: the next
  // outline is their convex hull, without revisiting every member.
  std::vector<Eigen::Vector3f> outline;
  Bounds box;
  bool changed = false;
  std::vector<std::uint32_t> left;  // points detached during this call
  std::size_t lost_since_rebuild = 0;  // points that left for good since the last repair
};

}  // namespace sarmap::segments
