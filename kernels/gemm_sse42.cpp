// The GEMM kernels compiled for SSE4.2 (the build baseline).
#include "kernels/gemm_body.hpp"

namespace sarmap::kernels::detail {

void gemm_rows_sse42(const GemmArgs& args, std::size_t begin, std::size_t end) {
  gemm_rows_impl<xsimd::sse4_2>(args, begin, end);
}

void gemm_column_max_sse42(const GemmArgs& args, std::size_t begin, std::size_t end, float* colmax) {
  gemm_column_max_impl<xsimd::sse4_2>(args, begin, end, colmax);
}

}  // namespace sarmap::kernels::detail
