#include "engine/semantic/map/map_block_schedule.hpp"

#include <algorithm>
#include <cmath>
#include <iterator>
#include <string>

#include "engine/core/error.hpp"
#include "engine/semantic/dgcnn/block_partition.hpp"

namespace sarmap {

MapBlockSchedule::MapBlockSchedule(const MapBlockSettings& settings) : settings_(settings) {
  const double b = settings.block_size, s = settings.stride;
  if (!(b > 0.0) || !std::isfinite(b)) {
    throw Error(ErrorCode::InvalidArgument, "map blocks: block size must be a positive number, got " + std::to_string(b));
  }
  if (!(s >= b / kMaxBlockOverlap) || s > b) {
    throw Error(ErrorCode::InvalidArgument, "map blocks: stride " + std::to_string(s) + " must lie in [block size / " +
                                                std::to_string(int(kMaxBlockOverlap)) + ", block size " +
                                                std::to_string(b) + "]");
  }
  if (!(settings.growth >= 0.0) || !std::isfinite(settings.growth)) {
    throw Error(ErrorCode::InvalidArgument, "map blocks: growth must be a number >= 0, got " +
                                                std::to_string(settings.growth));
  }
}

void MapBlockSchedule::add_points(const PointBuffer& map_points, std::span<const std::uint32_t> added) {
  const double b = settings_.block_size, s = settings_.stride;
  for (const std::uint32_t p : added) {
    const auto [i0, i1] = covering_block_range(map_points.x()[p], s, b);
    const auto [j0, j1] = covering_block_range(map_points.y()[p], s, b);
    for (long long j = j0; j <= j1; ++j) {
      for (long long i = i0; i <= i1; ++i) {
        auto [it, fresh] = blocks_.try_emplace({j, i});
        if (fresh) {
          it->second.i = i;
          it->second.j = j;
        }
        it->second.points.push_back(p);
        touched_.push_back({j, i});
      }
    }
  }
}

bool MapBlockSchedule::has_enough_unseen(const MapBlock& block) const {
  const std::size_t unseen = block.points.size() - block.classified_points;
  return unseen > 0 && (block.classified_points == 0 || unseen >= settings_.min_new_points);
}

bool MapBlockSchedule::is_unfinished(const MapBlock& block) const {
  return block.points.size() > block.classified_points && block.points.size() >= settings_.min_points;
}

bool MapBlockSchedule::is_ready(const MapBlock& block) const {
  const std::size_t n = block.points.size();
  if (n < settings_.min_points) return false;
  if (block.classified_points == 0) return true;
  return static_cast<double>(n) >= (1.0 + settings_.growth) * static_cast<double>(block.classified_points) &&
         has_enough_unseen(block);
}

std::vector<MapBlock*> MapBlockSchedule::ready() {
  std::sort(touched_.begin(), touched_.end());
  touched_.erase(std::unique(touched_.begin(), touched_.end()), touched_.end());
  // Ready: grown enough (only a block touched now can be), or holding points
  // no classification has seen and not grown this time (the sensor has
  // moved on: its view of the block is as full as it will be for now).
  std::vector<std::pair<long long, long long>> keys;
  std::set_union(touched_.begin(), touched_.end(), waiting_.begin(), waiting_.end(), std::back_inserter(keys));
  std::vector<MapBlock*> result;
  std::vector<std::pair<long long, long long>> waiting;
  for (const auto& key : keys) {
    MapBlock& block = blocks_.at(key);
    const bool grew = std::binary_search(touched_.begin(), touched_.end(), key);
    const bool quiet = !grew && settings_.classify_when_quiet && block.points.size() >= settings_.min_points &&
                       has_enough_unseen(block);
    if ((grew && is_ready(block)) || quiet) {
      result.push_back(&block);
    } else if (is_unfinished(block)) {
      waiting.push_back(key);
    }
  }
  touched_.clear();
  waiting_ = std::move(waiting);
  return result;
}

std::vector<MapBlock*> MapBlockSchedule::unfinished() {
  std::vector<MapBlock*> result;
  for (auto& [key, block] : blocks_) {
    if (is_unfinished(block)) {
      result.push_back(&block);
    }
  }
  touched_.clear();
  waiting_.clear();
  return result;
}

MapBlock* MapBlockSchedule::most_central_unfinished(double x, double y) {
  const double b = settings_.block_size, s = settings_.stride;
  const auto [i0, i1] = covering_block_range(x, s, b);
  const auto [j0, j1] = covering_block_range(y, s, b);
  MapBlock* best = nullptr;
  double best_distance = 0.0;
  for (long long j = j0; j <= j1; ++j) {
    for (long long i = i0; i <= i1; ++i) {
      const auto it = blocks_.find({j, i});
      if (it == blocks_.end()) continue;
      MapBlock& block = it->second;
      if (!is_unfinished(block)) continue;
      const double dx = x - (static_cast<double>(i) * s + 0.5 * b), dy = y - (static_cast<double>(j) * s + 0.5 * b);
      const double distance = dx * dx + dy * dy;
      if (!best || distance < best_distance) {
        best = &block;
        best_distance = distance;
      }
    }
  }
  return best;
}

const MapBlock* MapBlockSchedule::find(long long i, long long j) const {
  const auto it = blocks_.find({j, i});
  return it == blocks_.end() ? nullptr : &it->second;
}

void MapBlockSchedule::renumber(const std::vector<std::uint32_t>& renumbered, std::size_t classes) {
  constexpr std::uint32_t kGone = 0xffffffffu;
  for (auto it = blocks_.begin(); it != blocks_.end();) {
    MapBlock& block = it->second;
    std::vector<std::uint32_t> points;
    std::vector<std::uint8_t> scores;
    std::size_t classified = 0;
    for (std::size_t k = 0; k < block.points.size(); ++k) {
      const std::uint32_t p = renumbered[block.points[k]];
      if (p == kGone) continue;
      points.push_back(p);
      if (k < block.classified_points) {
        scores.insert(scores.end(), block.scores.begin() + static_cast<std::ptrdiff_t>(k * classes),
                      block.scores.begin() + static_cast<std::ptrdiff_t>((k + 1) * classes));
        ++classified;
      }
    }
    if (points.empty()) {
      it = blocks_.erase(it);
      continue;
    }
    block.points = std::move(points);
    block.scores = std::move(scores);
    block.classified_points = classified;
    ++it;
  }
  std::erase_if(waiting_, [&](const auto& key) { return !blocks_.count(key); });
  std::erase_if(touched_, [&](const auto& key) { return !blocks_.count(key); });
}

std::size_t MapBlockSchedule::memory_bytes() const {
  std::size_t bytes = 0;
  for (const auto& [key, block] : blocks_) {
    bytes += sizeof(MapBlock) + 4 * sizeof(void*) + block.points.capacity() * sizeof(std::uint32_t) +
             block.scores.capacity();
  }
  return bytes;
}

void MapBlockSchedule::save_state(StateWriter& out) const {
  out.tag("MBLK");
  out.put<std::uint64_t>(blocks_.size());
  for (const auto& [key, block] : blocks_) {
    out.put(block.i);
    out.put(block.j);
    out.put_vector(block.points);
    out.put<std::uint64_t>(block.classified_points);
    out.put(block.classifications);
    out.put_vector(block.scores);
  }
  std::vector<long long> flat;
  for (const auto& [j, i] : waiting_) {
    flat.push_back(j);
    flat.push_back(i);
  }
  out.put_vector(flat);
}

void MapBlockSchedule::load_state(StateReader& in) {
  in.expect_tag("MBLK");
  const std::size_t count = in.get_count(3 * sizeof(std::uint64_t));
  std::map<std::pair<long long, long long>, MapBlock> blocks;
  for (std::size_t b = 0; b < count; ++b) {
    MapBlock block;
    block.i = in.get<long long>();
    block.j = in.get<long long>();
    block.points = in.get_vector<std::uint32_t>();
    block.classified_points = in.get<std::uint64_t>();
    block.classifications = in.get<std::uint32_t>();
    block.scores = in.get_vector<std::uint8_t>();
    if (block.classified_points > block.points.size()) in.fail("a map block classified more points than it holds");
    if (!blocks.emplace(std::make_pair(block.j, block.i), std::move(block)).second) in.fail("a map block twice");
  }
  const std::vector<long long> flat = in.get_vector<long long>();
  if (flat.size() % 2 != 0) in.fail("the waiting map blocks' keys are cut short");
  std::vector<std::pair<long long, long long>> waiting;
  for (std::size_t k = 0; k < flat.size(); k += 2) waiting.emplace_back(flat[k], flat[k + 1]);
  for (const auto& key : waiting) {
    if (!blocks.count(key)) in.fail("a waiting map block that does not exist");
  }
  if (!std::is_sorted(waiting.begin(), waiting.end())) in.fail("the waiting map blocks are out of order");
  blocks_ = std::move(blocks);
  waiting_ = std::move(waiting);
  touched_.clear();
}

bool MapBlockSchedule::consistent_with(std::size_t points, std::size_t classes) const {
  for (const auto& [key, block] : blocks_) {
    if (block.scores.size() != block.classified_points * classes) return false;
    for (const std::uint32_t p : block.points) {
      if (p >= points) return false;
    }
  }
  return true;
}

}  // namespace sarmap
