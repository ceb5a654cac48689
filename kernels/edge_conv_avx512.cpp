// The EdgeConv kernels compiled for AVX-512 (built with -mavx512f -mavx512dq -mavx512vl -mavx512bw).
#include "kernels/edge_conv_body.hpp"

namespace sarmap::kernels::detail {

void edge_conv_points_avx512(const EdgeConvArgs& args, std::size_t begin, std::size_t end) {
  edge_conv_points_impl<xsimd::avx512bw>(args, begin, end);
}

void gather_max_points_avx512(const EdgeConvArgs& args, std::size_t begin, std::size_t end) {
  gather_max_points_impl<xsimd::avx512bw>(args, begin, end);
}

}  // namespace sarmap::kernels::detail
