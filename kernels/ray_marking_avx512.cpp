// The ray-marking kernel compiled for AVX512 (built with -mavx512f -mavx512dq -mavx512vl -mavx512bw).
#include "kernels/ray_marking_body.hpp"

namespace sarmap::kernels::detail {

std::size_t mark_ray_cells_avx512(const double start[3], const double* ends, std::size_t count,
                              const BlockMaskSink& sink) {
  return mark_ray_cells_impl<xsimd::avx512bw>(start, ends, count, sink);
}

std::size_t mark_ray_cells_dense_avx512(const double start[3], const double* ends, std::size_t count,
                                      const DenseMaskGrid& grid) {
  return mark_ray_cells_dense_impl<xsimd::avx512bw>(start, ends, count, grid);
}

std::size_t mark_ray_pieces_dense_avx512(const double start[3], const RayPieces& pieces,
                                         const DenseMaskGrid& grid) {
  return mark_ray_pieces_dense_impl<xsimd::avx512bw>(start, pieces, grid);
}

}  // namespace sarmap::kernels::detail
