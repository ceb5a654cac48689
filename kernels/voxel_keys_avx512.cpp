// The voxel-key kernel compiled for AVX512 (flags in kernels/CMakeLists.txt).
#include "kernels/voxel_keys_body.hpp"

namespace sarmap::kernels::detail {

void voxel_keys_avx512(const float* x, const float* y, const float* z, std::size_t count, double inv_resolution,
                       double max_coordinate, std::uint64_t* keys) {
  voxel_keys_impl<xsimd::avx512bw>(x, y, z, count, inv_resolution, max_coordinate, keys);
}

}  // namespace sarmap::kernels::detail
