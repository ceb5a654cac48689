// Integer voxel and block coordinates of the metric map, and the limits that
// keep them exact: voxel index = floor(coordinate / resolution), the same grid
// as OctoMap's (whose key is that index + 32768), so the two maps' voxels coincide.
#pragma once

#include <cmath>
#include <cstdint>
#include <functional>

#include "engine/core/flat_key_index.hpp"

namespace sarmap::metric {

// Blocks are 8 x 8 x 8 voxels; a voxel's index inside its block is x + 8y + 64z.
inline constexpr int kBlockShift = 3;
inline constexpr int kBlockEdge = 1 << kBlockShift;
inline constexpr int kBlockVoxels = kBlockEdge * kBlockEdge * kBlockEdge;

// Points and sensor origins farther than this from the map origin on any
// axis are rejected (counted, never wrapped).
inline constexpr double kMaxCoordinate = 10000.0;
// 10 km at the finest resolution is 1e6 voxels, below 2^20: every voxel index
// fits 21 signed bits, so a key packs into one 64-bit word without loss.
inline constexpr double kMinResolution = 0.01;
inline constexpr double kMaxResolution = 100.0;
inline constexpr int kPackBits = 21;
inline constexpr std::int64_t kPackOffset = std::int64_t{1} << (kPackBits - 1);
inline constexpr std::uint64_t kPackMask = (std::uint64_t{1} << kPackBits) - 1;

struct VoxelKey {
  std::int32_t x = 0, y = 0, z = 0;
  friend bool operator==(const VoxelKey&, const VoxelKey&) = default;
};

// Block coordinates: voxel index >> 3 (floor division, also for negatives).
struct BlockKey {
  std::int32_t x = 0, y = 0, z = 0;
  friend bool operator==(const BlockKey&, const BlockKey&) = default;
};

inline BlockKey block_of(const VoxelKey& v) {
  return {v.x >> kBlockShift, v.y >> kBlockShift, v.z >> kBlockShift};
}
// Index of a voxel inside its block.
inline int local_index(const VoxelKey& v) {
  return (v.x & (kBlockEdge - 1)) | ((v.y & (kBlockEdge - 1)) << kBlockShift) |
         ((v.z & (kBlockEdge - 1)) << (2 * kBlockShift));
}
inline VoxelKey voxel_of(const BlockKey& b, int local) {
  return {(b.x << kBlockShift) | (local & (kBlockEdge - 1)),
          (b.y << kBlockShift) | ((local >> kBlockShift) & (kBlockEdge - 1)),
          (b.z << kBlockShift) | ((local >> (2 * kBlockShift)) & (kBlockEdge - 1))};
}

// One 64-bit word per key (3 x 21 bits); order of packed words is not spatial.
inline std::uint64_t pack(std::int32_t x, std::int32_t y, std::int32_t z) {
  return (static_cast<std::uint64_t>(x + kPackOffset) & kPackMask) |
         ((static_cast<std::uint64_t>(y + kPackOffset) & kPackMask) << kPackBits) |
         ((static_cast<std::uint64_t>(z + kPackOffset) & kPackMask) << (2 * kPackBits));
}
inline std::uint64_t pack(const VoxelKey& v) { return pack(v.x, v.y, v.z); }
inline std::uint64_t pack(const BlockKey& b) { return pack(b.x, b.y, b.z); }
inline VoxelKey unpack_voxel(std::uint64_t word) {
  return {static_cast<std::int32_t>(static_cast<std::int64_t>(word & kPackMask) - kPackOffset),
          static_cast<std::int32_t>(static_cast<std::int64_t>((word >> kPackBits) & kPackMask) - kPackOffset),
          static_cast<std::int32_t>(static_cast<std::int64_t>((word >> (2 * kPackBits)) & kPackMask) -
                                    kPackOffset)};
}
inline BlockKey unpack_block(std::uint64_t word) {
  return {static_cast<std::int32_t>(static_cast<std::int64_t>(word & kPackMask) - kPackOffset),
          static_cast<std::int32_t>(static_cast<std::int64_t>((word >> kPackBits) & kPackMask) - kPackOffset),
          static_cast<std::int32_t>(static_cast<std::int64_t>((word >> (2 * kPackBits)) & kPackMask) -
                                    kPackOffset)};
}

struct PackedKeyHash {
  std::size_t operator()(std::uint64_t word) const { return static_cast<std::size_t>(mix_key(word)); }
};

// True when every coordinate is finite and within kMaxCoordinate.
inline bool within_map_limits(double x, double y, double z) {
  return std::fabs(x) <= kMaxCoordinate && std::fabs(y) <= kMaxCoordinate &&
         std::fabs(z) <= kMaxCoordinate;  // false for NaN as well
}

// Voxel containing a point; the caller has checked within_map_limits.
inline VoxelKey key_of(double x, double y, double z, double inv_resolution) {
  return {static_cast<std::int32_t>(std::floor(x * inv_resolution)),
          static_cast<std::int32_t>(std::floor(y * inv_resolution)),
          static_cast<std::int32_t>(std::floor(z * inv_resolution))};
}

}  // namespace sarmap::metric
