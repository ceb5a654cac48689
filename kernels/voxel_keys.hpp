// The voxel of every point as one packed 64-bit key: the first step of ray
// integration (end-voxel dedupe), vectorised because it runs once per point
// and its floors and conversions were much of that pass. A key packs
// floor(coordinate * inv_resolution) per axis into 21 bits each (x lowest,
// offset by 2^20); a point with a coordinate beyond +-max_coordinate or not
// finite gets kRejectedVoxelKey instead, which no voxel packs to. The
// vector versions compute exactly the reference's keys (same double
// arithmetic: the float is widened, multiplied, floored).
#pragma once

#include <cstddef>
#include <cstdint>

#include "kernels/simd_level.hpp"

namespace sarmap::kernels {

inline constexpr int kVoxelKeyBits = 21;
inline constexpr std::int64_t kVoxelKeyOffset = std::int64_t{1} << (kVoxelKeyBits - 1);
inline constexpr std::uint64_t kVoxelKeyMask = (std::uint64_t{1} << kVoxelKeyBits) - 1;
// Packed keys use the low 63 bits, so the all-ones word is never a voxel.
inline constexpr std::uint64_t kRejectedVoxelKey = ~std::uint64_t{0};

// Writes keys[i] for i < count. The caller guarantees that max_coordinate *
// inv_resolution < 2^20 (every accepted point's index fits its 21 bits).
void voxel_keys(const float* x, const float* y, const float* z, std::size_t count, double inv_resolution,
                double max_coordinate, std::uint64_t* keys, SimdLevel level);

// One point at a time: the definition, and the SSE4.2 path.
void voxel_keys_reference(const float* x, const float* y, const float* z, std::size_t count, double inv_resolution,
                          double max_coordinate, std::uint64_t* keys);

namespace detail {
void voxel_keys_avx2(const float* x, const float* y, const float* z, std::size_t count, double inv_resolution,
                     double max_coordinate, std::uint64_t* keys);
void voxel_keys_avx512(const float* x, const float* y, const float* z, std::size_t count, double inv_resolution,
                       double max_coordinate, std::uint64_t* keys);
}  // namespace detail

}  // namespace sarmap::kernels
