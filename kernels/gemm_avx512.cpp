// The GEMM kernels compiled for AVX-512 (built with -mavx512f -mavx512dq -mavx512vl -mavx512bw).
#include "kernels/gemm_body.hpp"

namespace sarmap::kernels::detail {

void gemm_rows_avx512(const GemmArgs& args, std::size_t begin, std::size_t end) {
  gemm_rows_impl<xsimd::avx512bw>(args, begin, end);
}

void gemm_column_max_avx512(const GemmArgs& args, std::size_t begin, std::size_t end, float* colmax) {
  gemm_column_max_impl<xsimd::avx512bw>(args, begin, end, colmax);
}

}  // namespace sarmap::kernels::detail
