// Block membership by integer cell ranges per point; an ordered map keeps the
// block order (and so every later seed) independent of how it was built.
#include "engine/semantic/dgcnn/block_partition.hpp"

#include <algorithm>
#include <cmath>
#include <limits>
#include <map>
#include <string>
#include <utility>

#include "engine/core/error.hpp"

namespace sarmap {
std::pair<long long, long long> covering_block_range(double d, double s, double b) {
  long long last = static_cast<long long>(std::floor(d / s));
  long long first = static_cast<long long>(std::floor((d - b) / s)) + 1;
  // Guard rounding at the edges: enforce the exact interval test.
  while (first <= last && static_cast<double>(first) * s + b <= d) ++first;
  while (last >= first && static_cast<double>(last) * s > d) --last;
  return {first, last};
}

namespace {

// Cell indices i >= 0 with i*s <= d < i*s + b, as [first, last].
std::pair<long long, long long> cell_range(double d, double s, double b) {
  auto [first, last] = covering_block_range(d, s, b);
  if (first < 0) first = 0;
  return {first, last};
}

}  // namespace

BlockPartition partition_blocks(const PointBuffer& points, const BlockPartitionSettings& settings) {
  const double b = settings.block_size;
  const double s = settings.stride > 0.0 ? settings.stride : b;
  if (!(b > 0.0) || !std::isfinite(b)) {
    throw Error(ErrorCode::InvalidArgument, "partition_blocks: block_size must be a positive number, got " + std::to_string(b));
  }
  if (s < b / kMaxBlockOverlap) {
    throw Error(ErrorCode::OutOfRange, "partition_blocks: stride " + std::to_string(s) + " is below block_size " +
                                           std::to_string(b) + " / " + std::to_string(int(kMaxBlockOverlap)) +
                                           "; every point would lie in over " +
                                           std::to_string(int(kMaxBlockOverlap * kMaxBlockOverlap)) + " blocks");
  }
  if (s > b) {
    throw Error(ErrorCode::InvalidArgument, "partition_blocks: stride " + std::to_string(s) +
                                                " exceeds block_size " + std::to_string(b) + "; points between blocks would be lost");
  }
  BlockPartition result;
  const std::size_t n = points.size();
  result.covered.assign(n, 0);
  if (n == 0) return result;
  if (n > std::numeric_limits<std::uint32_t>::max()) {
    throw Error(ErrorCode::OutOfRange, "partition_blocks: more than 2^32-1 points");
  }
  double min_x = std::numeric_limits<double>::infinity(), min_y = min_x;
  for (std::size_t p = 0; p < n; ++p) {
    const double x = points.x()[p], y = points.y()[p];
    if (!std::isfinite(x) || !std::isfinite(y) || !std::isfinite(static_cast<double>(points.z()[p]))) {
      throw Error(ErrorCode::InvalidData, "partition_blocks: point " + std::to_string(p) + " has a non-finite coordinate");
    }
    min_x = std::min(min_x, x);
    min_y = std::min(min_y, y);
  }
  const double ox = std::floor(min_x / s) * s, oy = std::floor(min_y / s) * s;
  double max_x = min_x, max_y = min_y;
  for (std::size_t p = 0; p < n; ++p) {
    max_x = std::max(max_x, static_cast<double>(points.x()[p]));
    max_y = std::max(max_y, static_cast<double>(points.y()[p]));
  }
  // Cell indices must fit comfortably in long long; a scan this wide is corrupt.
  if ((max_x - ox) / s > 1e12 || (max_y - oy) / s > 1e12) {
    throw Error(ErrorCode::OutOfRange, "partition_blocks: the cloud spans more than 1e12 blocks");
  }
  std::map<std::pair<long long, long long>, std::vector<std::uint32_t>> cells;  // key (j, i)
  for (std::size_t p = 0; p < n; ++p) {
    const auto [i0, i1] = cell_range(points.x()[p] - ox, s, b);
    const auto [j0, j1] = cell_range(points.y()[p] - oy, s, b);
    for (long long j = j0; j <= j1; ++j) {
      for (long long i = i0; i <= i1; ++i) cells[{j, i}].push_back(static_cast<std::uint32_t>(p));
    }
  }
  for (auto& [key, members] : cells) {
    if (members.size() < settings.min_points) continue;
    for (std::uint32_t p : members) result.covered[p] = 1;
    Block block;
    block.origin_x = ox + static_cast<double>(key.second) * s;
    block.origin_y = oy + static_cast<double>(key.first) * s;
    block.size = b;
    block.points = std::move(members);
    result.blocks.push_back(std::move(block));
  }
  for (std::uint8_t c : result.covered) result.dropped_points += c == 0 ? 1 : 0;
  return result;
}

}  // namespace sarmap
