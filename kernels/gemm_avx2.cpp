// The GEMM kernels compiled for AVX2 + FMA (built with -mavx2 -mfma).
#include "kernels/gemm_body.hpp"

namespace sarmap::kernels::detail {

void gemm_rows_avx2(const GemmArgs& args, std::size_t begin, std::size_t end) {
  gemm_rows_impl<xsimd::fma3<xsimd::avx2>>(args, begin, end);
}

void gemm_column_max_avx2(const GemmArgs& args, std::size_t begin, std::size_t end, float* colmax) {
  gemm_column_max_impl<xsimd::fma3<xsimd::avx2>>(args, begin, end, colmax);
}

}  // namespace sarmap::kernels::detail
