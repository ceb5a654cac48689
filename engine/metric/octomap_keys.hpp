// What the .bt and .ot exports share: OctoMap's 16-bit key range and the
// Morton order that makes every octree subtree one contiguous run of sorted
// voxels, so both writers walk a sorted array instead of building a tree.
#pragma once

#include <cstdint>
#include <sstream>
#include <string_view>

#include "engine/core/error.hpp"
#include "engine/metric/voxel_key.hpp"

namespace sarmap::metric::octomap_keys {

inline constexpr int kTreeDepth = 16;
inline constexpr std::int32_t kKeyOffset = 32768;  // OctoMap's tree_max_val

// Interleaves 16-bit keys so that bits 3b..3b+2 hold child index
// (x + 2y + 4z) at the level that splits on key bit b, as OctoMap's computeChildIdx.
inline std::uint64_t morton(std::uint32_t x, std::uint32_t y, std::uint32_t z) {
  std::uint64_t m = 0;
  for (int b = 0; b < kTreeDepth; ++b) {
    m |= std::uint64_t{(x >> b) & 1u} << (3 * b);
    m |= std::uint64_t{(y >> b) & 1u} << (3 * b + 1);
    m |= std::uint64_t{(z >> b) & 1u} << (3 * b + 2);
  }
  return m;
}

// The Morton code of a voxel's OctoMap key. Throws sarmap::Error (OutOfRange)
// when the voxel lies outside the 16-bit key range (voxel index in
// [-32768, 32767], i.e. +-32768 x resolution metres), naming the format, the
// axis and the extent.
inline std::uint64_t morton_of(const VoxelKey& k, double resolution, std::string_view format) {
  const std::int32_t c[3] = {k.x, k.y, k.z};
  static constexpr const char* kAxis[3] = {"x", "y", "z"};
  for (int a = 0; a < 3; ++a) {
    if (c[a] < -kKeyOffset || c[a] >= kKeyOffset) {
      std::ostringstream msg;
      msg << format << " export: the map reaches voxel index " << c[a] << " on " << kAxis[a] << " ("
          << (c[a] + 0.5) * resolution << " m); OctoMap's 16-bit keys hold voxel indices [-32768, 32767], "
          << "i.e. +-" << kKeyOffset * resolution << " m at resolution " << resolution
          << " m; export a smaller map or use a coarser resolution";
      throw Error(ErrorCode::OutOfRange, msg.str());
    }
  }
  return morton(static_cast<std::uint32_t>(k.x + kKeyOffset), static_cast<std::uint32_t>(k.y + kKeyOffset),
                static_cast<std::uint32_t>(k.z + kKeyOffset));
}

}  // namespace sarmap::metric::octomap_keys
