// The EdgeConv kernels compiled for AVX2 + FMA (built with -mavx2 -mfma).
#include "kernels/edge_conv_body.hpp"

namespace sarmap::kernels::detail {

void edge_conv_points_avx2(const EdgeConvArgs& args, std::size_t begin, std::size_t end) {
  edge_conv_points_impl<xsimd::fma3<xsimd::avx2>>(args, begin, end);
}

void gather_max_points_avx2(const EdgeConvArgs& args, std::size_t begin, std::size_t end) {
  gather_max_points_impl<xsimd::fma3<xsimd::avx2>>(args, begin, end);
}

}  // namespace sarmap::kernels::detail
