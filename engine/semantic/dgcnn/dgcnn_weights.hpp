// The raw layers of a DGCNN_semseg network as stored in a safetensors file
// with the reference PyTorch state_dict names (conv1.0.weight, conv1.1.*, ...,
// conv9.weight; a "module." prefix and duplicate bnN.* entries accepted),
// checked to chain: every width comes from the tensor shapes.
#pragma once

#include <cstddef>
#include <string>
#include <vector>

#include "engine/io/safetensors.hpp"

namespace sarmap {

// A 1x1 convolution, optionally followed by BatchNorm (inference statistics).
struct ConvLayer {
  std::string name;           // "conv3"
  std::size_t out = 0, in = 0;
  std::vector<float> weight;  // out x in, row-major
  std::vector<float> bias;    // out values, or empty
  bool has_bn = false;
  std::vector<float> bn_gamma, bn_beta, bn_mean, bn_var;  // out values each
};

struct DgcnnWeights {
  // conv1..conv5: the EdgeConv layers; conv6: local -> emb; conv7, conv8: the
  // head; conv9: the classifier (no BN).
  ConvLayer conv[9];
  std::size_t channels() const { return conv[0].in / 2; }  // input channels per point
  std::size_t classes() const { return conv[8].out; }
  std::size_t emb() const { return conv[5].out; }
};

// Reads every layer, with errors naming the file and the tensor: missing
// tensor, wrong dtype, wrong rank, a shape that does not chain.
DgcnnWeights load_dgcnn_weights(const SafetensorsFile& file);

}  // namespace sarmap
