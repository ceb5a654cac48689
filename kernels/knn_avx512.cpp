// The kNN kernel compiled for AVX-512 (built with -mavx512f -mavx512dq -mavx512vl -mavx512bw).
#include "kernels/knn_body.hpp"

namespace sarmap::kernels::detail {

void knn_rows_avx512(const KnnArgs& args, std::size_t begin, std::size_t end) {
  knn_rows_impl<xsimd::avx512bw>(args, begin, end);
}

}  // namespace sarmap::kernels::detail
