// The EdgeConv kernels compiled for SSE4.2 (the build baseline).
#include "kernels/edge_conv_body.hpp"

namespace sarmap::kernels::detail {

void edge_conv_points_sse42(const EdgeConvArgs& args, std::size_t begin, std::size_t end) {
  edge_conv_points_impl<xsimd::sse4_2>(args, begin, end);
}

void gather_max_points_sse42(const EdgeConvArgs& args, std::size_t begin, std::size_t end) {
  gather_max_points_impl<xsimd::sse4_2>(args, begin, end);
}

}  // namespace sarmap::kernels::detail
