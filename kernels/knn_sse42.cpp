// The kNN kernel compiled for SSE4.2 (the build baseline).
#include "kernels/knn_body.hpp"

namespace sarmap::kernels::detail {

void knn_rows_sse42(const KnnArgs& args, std::size_t begin, std::size_t end) {
  knn_rows_impl<xsimd::sse4_2>(args, begin, end);
}

}  // namespace sarmap::kernels::detail
