// The ray-marking kernel compiled for AVX2 (built with -mavx2 -mfma).
#include "kernels/ray_marking_body.hpp"

namespace sarmap::kernels::detail {

std::size_t mark_ray_cells_avx2(const double start[3], const double* ends, std::size_t count,
                              const BlockMaskSink& sink) {
  return mark_ray_cells_impl<xsimd::avx2>(start, ends, count, sink);
}

std::size_t mark_ray_cells_dense_avx2(const double start[3], const double* ends, std::size_t count,
                                      const DenseMaskGrid& grid) {
  return mark_ray_cells_dense_impl<xsimd::avx2>(start, ends, count, grid);
}

std::size_t mark_ray_pieces_dense_avx2(const double start[3], const RayPieces& pieces,
                                       const DenseMaskGrid& grid) {
  return mark_ray_pieces_dense_impl<xsimd::avx2>(start, pieces, grid);
}

}  // namespace sarmap::kernels::detail
