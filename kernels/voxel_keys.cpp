#include "kernels/voxel_keys.hpp"

#include <cmath>
#include <stdexcept>

namespace sarmap::kernels {

void voxel_keys_reference(const float* x, const float* y, const float* z, std::size_t count, double inv_resolution,
                          double max_coordinate, std::uint64_t* keys) {
  for (std::size_t i = 0; i < count; ++i) {
    const double c[3] = {x[i], y[i], z[i]};
    std::uint64_t packed = 0;
    bool inside = true;
    for (int a = 0; a < 3; ++a) {
      inside = std::fabs(c[a]) <= max_coordinate;  // false for NaN
      if (!inside) break;
      const auto index = static_cast<std::int64_t>(std::floor(c[a] * inv_resolution));
      packed |= (static_cast<std::uint64_t>(index + kVoxelKeyOffset) & kVoxelKeyMask) << (kVoxelKeyBits * a);
    }
    keys[i] = inside ? packed : kRejectedVoxelKey;
  }
}

void voxel_keys(const float* x, const float* y, const float* z, std::size_t count, double inv_resolution,
                double max_coordinate, std::uint64_t* keys, SimdLevel level) {
  if (!simd_level_supported(level)) throw std::invalid_argument("voxel_keys: instruction set not supported");
  switch (level) {
    case SimdLevel::Avx512: return detail::voxel_keys_avx512(x, y, z, count, inv_resolution, max_coordinate, keys);
    case SimdLevel::Avx2: return detail::voxel_keys_avx2(x, y, z, count, inv_resolution, max_coordinate, keys);
    case SimdLevel::Sse42: break;  // two doubles per vector: the plain loop is as good
  }
  voxel_keys_reference(x, y, z, count, inv_resolution, max_coordinate, keys);
}

}  // namespace sarmap::kernels
