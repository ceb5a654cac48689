// The kNN kernel compiled for AVX2 + FMA (built with -mavx2 -mfma).
#include "kernels/knn_body.hpp"

namespace sarmap::kernels::detail {

void knn_rows_avx2(const KnnArgs& args, std::size_t begin, std::size_t end) {
  knn_rows_impl<xsimd::fma3<xsimd::avx2>>(args, begin, end);
}

}  // namespace sarmap::kernels::detail
