// Splits a scan into square xy blocks (the DGCNN's unit of work), possibly
// overlapping, and drops blocks too sparse to classify.
#pragma once

#include <cstddef>
#include <cstdint>
#include <utility>
#include <vector>

#include "engine/core/point_buffer.hpp"

namespace sarmap {

// A stride below block_size / kMaxBlockOverlap is refused: each point would
// lie in more than kMaxBlockOverlap^2 blocks and the work would grow with it.
inline constexpr double kMaxBlockOverlap = 16.0;

struct BlockPartitionSettings {
  double block_size = 1.0;    // metres
  double stride = 0.0;        // metres between block origins; <= 0 means block_size
  std::size_t min_points = 500;
};

struct Block {
  double origin_x = 0.0, origin_y = 0.0;  // lower corner of the cell
  double size = 1.0;                      // side of the cell, metres
  std::vector<std::uint32_t> points;      // indices into the cloud, ascending
};

struct BlockPartition {
  std::vector<Block> blocks;         // kept blocks, ordered by (row, column)
  std::size_t dropped_points = 0;    // points that fall only in dropped blocks
  std::vector<std::uint8_t> covered; // per point: 1 when in at least one kept block
};

// The indices i of the blocks [i*stride, i*stride + block_size) that hold
// coordinate d, as [first, last] (one axis; a grid fixed at 0). The one
// definition of block membership, for scans and for the accumulated map.
std::pair<long long, long long> covering_block_range(double d, double stride, double block_size);

// Block (i, j) covers [ox + i*stride, ox + i*stride + block_size) in x (same in y),
// with ox = floor(min x / stride) * stride so the grid is fixed in the world frame.
// Throws sarmap::Error on non-positive sizes, stride > block_size (points would be
// lost between blocks), stride < block_size / kMaxBlockOverlap, or non-finite coordinates.
BlockPartition partition_blocks(const PointBuffer& points, const BlockPartitionSettings& settings);

}  // namespace sarmap
