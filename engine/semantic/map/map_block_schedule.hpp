// Which blocks of the accumulated map the network should (re)classify. The
// map's ground plane is tiled by the model's square blocks (overlapping by
// the stride, on a grid fixed at the world origin); each block lists the map
// points in it and is ready once it holds min_points and has grown by
// `growth` since it was last classified, or once it stops growing with
// points no classification has seen, so a surface seen again and again costs
// a few classifications, not one per scan.
#pragma once

#include <cstddef>
#include <cstdint>
#include <map>
#include <span>
#include <vector>

#include "engine/core/point_buffer.hpp"
#include "engine/core/state_stream.hpp"

namespace sarmap {

struct MapBlockSettings {
  double block_size = 1.0;       // metres, the model's
  double stride = 0.75;          // metres between block origins, in (block_size / 16, block_size]
  std::size_t min_points = 100;  // sparser blocks wait
  double growth = 0.25;          // classified again once grown by this fraction of the last count
  // ... and by at least this many points: each classification costs the
  // same whatever the block holds, so a sparse block is not classified again
  // for every few points (a LiDAR's far blocks grow a little every scan).
  std::size_t min_new_points = 0;
  // Also classify a block again when it holds points its last classification
  // did not see and has stopped growing (no new point in the last call), so
  // that no point waits for a growth that may never come. A block classified
  // before needs min_new_points unseen points for this too: until then its
  // unseen points borrow their neighbours' classes.
  bool classify_when_quiet = true;
};

struct MapBlock {
  long long i = 0, j = 0;               // origin (i * stride, j * stride)
  std::vector<std::uint32_t> points;    // map points in the block, in arrival order
  std::size_t classified_points = 0;    // points.size() when last classified; 0: never
  std::uint32_t classifications = 0;
  std::vector<std::uint8_t> scores;     // the last classification's quantised scores, classified_points x classes
};

class MapBlockSchedule {
 public:
  // Throws sarmap::Error (InvalidArgument) for a non-positive block size, a
  // stride outside (block_size / 16, block_size], a growth below 0.
  explicit MapBlockSchedule(const MapBlockSettings& settings);

  const MapBlockSettings& settings() const { return settings_; }
  std::size_t block_count() const { return blocks_.size(); }

  // Puts each of `added` (indices into map_points) into the blocks holding it.
  void add_points(const PointBuffer& map_points, std::span<const std::uint32_t> added);
  // The blocks ready to classify, in (j, i) order. The pointers stay valid
  // until the next add_points(). Call once per scan, after add_points().
  std::vector<MapBlock*> ready();
  // Every block holding points no classification has seen, with at least
  // min_points, in (j, i) order: what is left to do when the scans end.
  std::vector<MapBlock*> unfinished();
  // Of the blocks holding (x, y) that have min_points and points no
  // classification has seen, the one whose centre is nearest (the first in
  // (j, i) order on a tie), or nullptr: the block to classify for a map
  // point that has waited too long for its class. Valid as ready()'s.
  MapBlock* most_central_unfinished(double x, double y);
  // Block (i, j), or nullptr when no point has reached it.
  const MapBlock* find(long long i, long long j) const;

  // Follows LabelledPointMap::keep_only: points renumbered, forgotten ones
  // (kNoPoint) left out of their blocks with their scores (`classes` per
  // classified point), blocks left empty removed.
  void renumber(const std::vector<std::uint32_t>& renumbered, std::size_t classes);

  // Bytes held by the blocks' point lists and scores.
  std::size_t memory_bytes() const;

  void save_state(StateWriter& out) const;
  void load_state(StateReader& in);
  // Whether every block's points are below `points` and its scores hold
  // `classes` per classified point (a check after loading).
  bool consistent_with(std::size_t points, std::size_t classes) const;

 private:
  // Holds points no classification has seen: any, if it was never
  // classified; else at least min_new_points (and at least one).
  bool has_enough_unseen(const MapBlock& block) const;
  bool is_ready(const MapBlock& block) const;
  // Holds min_points and points no classification has seen.
  bool is_unfinished(const MapBlock& block) const;

  MapBlockSettings settings_;
  std::map<std::pair<long long, long long>, MapBlock> blocks_;  // key (j, i)
  std::vector<std::pair<long long, long long>> touched_;        // grown since the last ready(), unsorted
  std::vector<std::pair<long long, long long>> waiting_;        // holding unseen points, not ready at the last ready(); sorted
};

}  // namespace sarmap
