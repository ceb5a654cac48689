// Building the runnable DGCNN from its layers and the forward pass (see
// dgcnn_model.hpp). Data are point-major: one row of channels per point.
#include "engine/semantic/dgcnn/dgcnn_model.hpp"

#include <algorithm>
#include <chrono>
#include <cmath>
#include <string>

#include "engine/core/error.hpp"
#include "engine/semantic/dgcnn/repeated_rows.hpp"
#include "kernels/edge_conv.hpp"
#include "kernels/gemm.hpp"
#include "kernels/knn.hpp"
#include "kernels/spatial_order.hpp"

namespace sarmap {
namespace {

constexpr float kSlope = 0.2f;  // LeakyReLU(0.2) after every BN
constexpr double kBnEpsilon = 1e-5;  // PyTorch's BatchNorm default

// Weight and bias of conv followed by BN, as one affine map.
struct Folded {
  std::size_t out = 0, in = 0;
  std::vector<float> weight, bias;
};

Folded fold(const ConvLayer& c) {
  Folded f{c.out, c.in, c.weight, std::vector<float>(c.out, 0.0f)};
  for (std::size_t o = 0; o < c.out; ++o) {
    double scale = 1.0, shift = c.bias.empty() ? 0.0 : c.bias[o];
    if (c.has_bn) {
      scale = c.bn_gamma[o] / std::sqrt(static_cast<double>(c.bn_var[o]) + kBnEpsilon);
      shift = c.bn_beta[o] + scale * (shift - c.bn_mean[o]);
    }
    for (std::size_t i = 0; i < c.in; ++i) f.weight[o * c.in + i] = static_cast<float>(scale * c.weight[o * c.in + i]);
    f.bias[o] = static_cast<float>(shift);
  }
  return f;
}

// W [x_j - x_i; x_i] + b = W1 x_j + (W2 - W1) x_i + b: rows [W1; W2 - W1],
// bias [0; b], so one GEMM gives both per-point terms.
kernels::PackedMatrix split_edge(const Folded& f, kernels::SimdLevel level) {
  const std::size_t c = f.in / 2;
  std::vector<float> w(2 * f.out * c), bias(2 * f.out, 0.0f);
  for (std::size_t o = 0; o < f.out; ++o) {
    for (std::size_t i = 0; i < c; ++i) {
      const float w1 = f.weight[o * f.in + i], w2 = f.weight[o * f.in + c + i];
      w[o * c + i] = w1;
      w[(f.out + o) * c + i] = w2 - w1;
    }
    bias[f.out + o] = f.bias[o];
  }
  return kernels::PackedMatrix(w.data(), bias.data(), 2 * f.out, c, level);
}

kernels::PackedMatrix pack(const Folded& f, kernels::SimdLevel level) {
  return kernels::PackedMatrix(f.weight.data(), f.bias.data(), f.out, f.in, level);
}

using Clock = std::chrono::steady_clock;
double seconds_since(Clock::time_point t) { return std::chrono::duration<double>(Clock::now() - t).count(); }

}  // namespace

DgcnnModel DgcnnModel::load(const std::filesystem::path& path) { return load(path, kernels::active_simd_level()); }

DgcnnModel DgcnnModel::load(const std::filesystem::path& path, kernels::SimdLevel level) {
  const SafetensorsFile file = SafetensorsFile::read(path);
  return DgcnnModel(load_dgcnn_weights(file), parse_dgcnn_metadata(file.metadata(), file.source()), level);
}

DgcnnModel::DgcnnModel(const DgcnnWeights& w, DgcnnMetadata metadata, kernels::SimdLevel level)
    : metadata_(std::move(metadata)), level_(level) {
  if (!kernels::simd_level_supported(level)) {
    throw Error(ErrorCode::Unsupported, std::string("instruction set ") + std::string(kernels::to_string(level)) +
                                            " is not supported by this CPU");
  }
  channels_ = w.channels();
  classes_ = w.classes();
  emb_ = w.emb();
  if (!metadata_.classes.empty() && metadata_.classes.size() != classes_) {
    throw Error(ErrorCode::InvalidData, "model metadata sarmap.classes names " +
                                            std::to_string(metadata_.classes.size()) + " classes but conv9 has " +
                                            std::to_string(classes_) + " outputs");
  }
  if (metadata_.k > kernels::kKnnMaxK) throw Error(ErrorCode::Unsupported, "k above " + std::to_string(kernels::kKnnMaxK));

  // EdgeConv 1 and 2: split first convolution, then a second one; EdgeConv 3:
  // split convolution only (gather-max).
  const int first[3] = {0, 2, 4};
  for (int e = 0; e < 3; ++e) {
    const Folded f = fold(w.conv[first[e]]);
    EdgeLayer& layer = edge_[e];
    layer.in = f.in / 2;
    layer.hidden = f.out;
    layer.split = split_edge(f, level);
    layer.out = f.out;
    if (e < 2) {
      const Folded s = fold(w.conv[first[e] + 1]);
      if (s.in > kernels::kEdgeMaxHidden || s.out > kernels::kEdgeMaxOut) {
        throw Error(ErrorCode::Unsupported, w.conv[first[e] + 1].name + ": EdgeConv widths above " +
                                                std::to_string(kernels::kEdgeMaxHidden) + " are not supported");
      }
      layer.second = pack(s, level);
      layer.out = s.out;
    }
  }
  local_ = edge_[0].out + edge_[1].out + edge_[2].out;
  if (edge_[0].out > kernels::kKnnMaxDim || edge_[1].out > kernels::kKnnMaxDim) {
    throw Error(ErrorCode::Unsupported, "EdgeConv output widths above " + std::to_string(kernels::kKnnMaxDim) +
                                            " are not supported by the kNN kernel");
  }
  global_ = pack(fold(w.conv[5]), level);

  const Folded h1 = fold(w.conv[6]);
  head1_ = h1.out;
  head_global_.resize(head1_ * emb_);
  std::vector<float> local_cols(head1_ * local_);
  for (std::size_t o = 0; o < head1_; ++o) {
    for (std::size_t i = 0; i < emb_; ++i) head_global_[o * emb_ + i] = h1.weight[o * h1.in + i];
    for (std::size_t i = 0; i < local_; ++i) local_cols[o * local_ + i] = h1.weight[o * h1.in + emb_ + i];
  }
  head_bias_ = h1.bias;
  head_local_ = kernels::PackedMatrix(local_cols.data(), nullptr, head1_, local_, level);
  const Folded h2 = fold(w.conv[7]);
  head2_ = h2.out;
  head2_w_ = pack(h2, level);
  classifier_ = pack(fold(w.conv[8]), level);
}

void DgcnnModel::check_block(const float* block, std::size_t n) const {
  if (n == 0) throw Error(ErrorCode::InvalidArgument, "DGCNN forward: empty block");
  if (n > kMaxBlockPoints) {
    throw Error(ErrorCode::OutOfRange, "DGCNN forward: a block of " + std::to_string(n) + " points; at most " +
                                           std::to_string(kMaxBlockPoints) +
                                           " (the neighbour search grows with the square of the count)");
  }
  for (std::size_t i = 0; i < n * channels_; ++i) {
    if (!std::isfinite(block[i])) {
      throw Error(ErrorCode::InvalidData, "DGCNN input: point " + std::to_string(i / channels_) + " channel " +
                                              std::to_string(i % channels_) + " is not finite");
    }
  }
}

void DgcnnModel::forward(const float* block, std::size_t n, float* logits, DgcnnWorkspace& ws,
                         DgcnnStageTimes* times) const {
  check_block(block, n);
  const std::size_t distinct = find_repeated_rows(block, n, channels_, ws.repeated);
  if (distinct == n) {
    run(block, n, nullptr, logits, ws, times);
    return;
  }
  ws.distinct_logits.resize(distinct * classes_);
  run(ws.repeated.distinct.data(), distinct, ws.repeated.copies.data(), ws.distinct_logits.data(), ws, times);
  for (std::size_t i = 0; i < n; ++i) {
    std::copy_n(ws.distinct_logits.data() + ws.repeated.row_of.data()[i] * classes_, classes_, logits + i * classes_);
  }
}

void DgcnnModel::forward_with_copies(const float* rows, std::size_t n, const std::uint32_t* copies, float* logits,
                                     DgcnnWorkspace& ws, DgcnnStageTimes* times) const {
  check_block(rows, n);
  std::size_t total = 0;
  for (std::size_t i = 0; i < n; ++i) {
    if (copies[i] == 0) throw Error(ErrorCode::InvalidArgument, "DGCNN forward: row " + std::to_string(i) + " has no copies");
    total += copies[i];
  }
  if (total > kMaxBlockPoints) {
    throw Error(ErrorCode::OutOfRange, "DGCNN forward: rows standing for " + std::to_string(total) +
                                           " points; at most " + std::to_string(kMaxBlockPoints));
  }
  run(rows, n, copies, logits, ws, times);
}

void DgcnnModel::run(const float* block, std::size_t n, const std::uint32_t* copies, float* logits,
                     DgcnnWorkspace& ws, DgcnnStageTimes* times) const {
  const std::size_t k = metadata_.k;
  std::size_t widest = 0;
  for (const EdgeLayer& e : edge_) widest = std::max(widest, 2 * e.hidden);
  ws.neighbours.resize(n * k);
  ws.edge_terms.resize(n * widest);
  ws.local.resize(n * local_);
  ws.global.resize(global_.panel_count() * global_.panel_width());
  ws.head_bias.resize(head_local_.panel_count() * head_local_.panel_width());
  ws.head1.resize(n * head1_);
  ws.head2.resize(n * head2_);

  // Each EdgeConv reads its input rows (`in`, stride ld_in) and the kNN rows
  // (`knn_in`, dim channels) and writes its output at column `col` of local.
  const float* in = block;
  std::size_t ld_in = channels_;
  const float* knn_in = block + channels_ - 3;  // the first kNN uses the last three channels
  std::size_t knn_dim = 3;
  std::size_t col = 0;
  // Every kNN visits the points in the spatial order of the first one's xyz:
  // later layers' features are functions of the local neighbourhood, so
  // neighbours in feature space are mostly near in space too, and the kernel
  // meets them first (the neighbours do not depend on the order).
  auto order_start = Clock::now();
  ws.visit_order.resize(n);
  kernels::spatial_order(knn_in, ld_in, n, ws.order_keys, ws.visit_order.data());
  for (int e = 0; e < 3; ++e) {
    const EdgeLayer& layer = edge_[e];
    auto t0 = e == 0 ? order_start : Clock::now();
    kernels::knn(knn_in, ld_in, n, knn_dim, k, level_, ws.knn, ws.neighbours.data(), ws.visit_order.data());
    if (copies != nullptr) keep_k_nearest_copies(ws.neighbours.data(), n, k, copies);
    auto t1 = Clock::now();
    const std::size_t ld_ab = 2 * layer.hidden;
    kernels::gemm_bias_act(in, ld_in, n, layer.split, 1.0f, ws.edge_terms.data(), ld_ab);
    float* out = ws.local.data() + col;
    const float* a = ws.edge_terms.data();
    const float* b = a + layer.hidden;
    if (e < 2) {
      kernels::edge_conv_max(a, b, ld_ab, n, layer.hidden, ws.neighbours.data(), k, kSlope, layer.second, kSlope, out,
                             local_);
    } else {
      kernels::gather_max(a, b, ld_ab, n, layer.hidden, ws.neighbours.data(), k, kSlope, level_, out, local_);
    }
    if (times != nullptr) {
      times->knn[e] = std::chrono::duration<double>(t1 - t0).count();
      times->edge_conv[e] = seconds_since(t1);
    }
    in = knn_in = out;
    ld_in = local_;
    knn_dim = layer.out;
    col += layer.out;
  }

  auto t0 = Clock::now();
  // Global feature: max over points commutes with the monotone bias + LeakyReLU.
  float* global = ws.global.data();
  kernels::gemm_column_max(ws.local.data(), local_, n, global_, global);
  for (std::size_t o = 0; o < emb_; ++o) {
    const float v = global[o] + global_.bias()[o];
    global[o] = v >= 0.0f ? v : kSlope * v;
  }
  if (times != nullptr) times->global = seconds_since(t0);

  t0 = Clock::now();
  // conv7 on [global, x1, x2, x3]: the global columns give one bias per block.
  float* bias = ws.head_bias.data();
  for (std::size_t o = 0; o < head1_; ++o) {
    double sum = head_bias_[o];
    const float* row = head_global_.data() + o * emb_;
    for (std::size_t i = 0; i < emb_; ++i) sum += static_cast<double>(row[i]) * global[i];
    bias[o] = static_cast<float>(sum);
  }
  kernels::gemm_bias_act(ws.local.data(), local_, n, head_local_, bias, kSlope, ws.head1.data(), head1_);
  kernels::gemm_bias_act(ws.head1.data(), head1_, n, head2_w_, kSlope, ws.head2.data(), head2_);
  kernels::gemm_bias_act(ws.head2.data(), head2_, n, classifier_, 1.0f, logits, classes_);
  if (times != nullptr) times->head = seconds_since(t0);
}

double DgcnnModel::flops(std::size_t n) const {
  const double N = static_cast<double>(n), K = static_cast<double>(metadata_.k);
  double total = 0.0;
  std::size_t knn_dim = 3;
  for (int e = 0; e < 3; ++e) {
    const EdgeLayer& l = edge_[e];
    total += 2.0 * N * N * static_cast<double>(knn_dim);                             // distances
    total += 2.0 * N * static_cast<double>(l.in) * 2.0 * static_cast<double>(l.hidden);  // split GEMM
    total += N * K * static_cast<double>(l.hidden);                                   // gather-add / max
    if (e < 2) total += 2.0 * N * K * static_cast<double>(l.hidden) * static_cast<double>(l.out);
    knn_dim = l.out;
  }
  total += 2.0 * N * static_cast<double>(local_) * static_cast<double>(emb_);
  total += 2.0 * static_cast<double>(emb_) * static_cast<double>(head1_);
  total += 2.0 * N * static_cast<double>(local_) * static_cast<double>(head1_);
  total += 2.0 * N * static_cast<double>(head1_) * static_cast<double>(head2_);
  total += 2.0 * N * static_cast<double>(head2_) * static_cast<double>(classes_);
  return total;
}

}  // namespace sarmap
