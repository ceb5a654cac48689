// The buffers one DGCNN forward pass works in, kept between blocks so that
// after the first block of a given size no memory is allocated.
#pragma once

#include <cstddef>
#include <cstdint>

#include "engine/semantic/dgcnn/repeated_rows.hpp"
#include "kernels/aligned_buffer.hpp"
#include "kernels/knn.hpp"

namespace sarmap {

struct DgcnnWorkspace {
  kernels::KnnWorkspace knn;
  kernels::AlignedBuffer<std::uint32_t> visit_order;  // n: the points in spatial order, for every kNN
  kernels::AlignedBuffer<std::uint64_t> order_keys;   // 2n: scratch of spatial_order()
  kernels::AlignedBuffer<std::uint32_t> neighbours;  // n x k
  kernels::AlignedBuffer<float> edge_terms;         // n x 2E: [a | b] of an EdgeConv
  kernels::AlignedBuffer<float> local;              // n x (E1 + E2 + E3): [x1 | x2 | x3]
  kernels::AlignedBuffer<float> global;             // emb
  kernels::AlignedBuffer<float> head_bias;          // conv7's bias plus its global share
  kernels::AlignedBuffer<float> head1;              // n x H1
  kernels::AlignedBuffer<float> head2;              // n x H2
  RepeatedRows repeated;                            // the block's distinct rows, when some repeat
  kernels::AlignedBuffer<float> distinct_logits;    // distinct rows x classes

  // Bytes held by every buffer: a forward pass's working set besides the
  // weights (benchmarks report it per block size).
  std::size_t bytes() const {
    return knn.bytes() + visit_order.capacity_bytes() + order_keys.capacity_bytes() +
           neighbours.capacity_bytes() + edge_terms.capacity_bytes() + local.capacity_bytes() +
           global.capacity_bytes() + head_bias.capacity_bytes() + head1.capacity_bytes() + head2.capacity_bytes() +
           repeated.bytes() + distinct_logits.capacity_bytes();
  }
};

// Wall-clock seconds of each stage of the last forward pass (benchmarks).
struct DgcnnStageTimes {
  double knn[3] = {0, 0, 0};
  double edge_conv[3] = {0, 0, 0};
  double global = 0;  // conv6 + max over points
  double head = 0;    // conv7, conv8, conv9
};

}  // namespace sarmap
