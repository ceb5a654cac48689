// Loading and shape-checking the DGCNN layers (see dgcnn_weights.hpp).
#include "engine/semantic/dgcnn/dgcnn_weights.hpp"

#include <algorithm>
#include <cmath>
#include <string>

#include "engine/core/error.hpp"

namespace sarmap {
namespace {

// Trained weights (BatchNorm folded or not) are a few units at most; far
// beyond this they overflow the forward pass.
constexpr float kMaxWeight = 1e4f;

class TensorSource {
 public:
  explicit TensorSource(const SafetensorsFile& file) : file_(file) {
    for (const SafetensorsTensor& t : file.tensors()) {
      if (t.name.rfind("module.", 0) == 0) prefix_ = "module.";
    }
  }

  const SafetensorsTensor* find(const std::string& name) const { return file_.find(prefix_ + name); }

  const SafetensorsTensor& require(const std::string& name) const {
    const SafetensorsTensor* t = find(name);
    if (t == nullptr) fail(name, "missing");
    return *t;
  }

  // The tensor's values, refused when one is not finite or beyond
  // kMaxWeight: such a model writes NaN scores or labels every point alike.
  std::vector<float> floats(const std::string& name, const SafetensorsTensor& t) const {
    std::vector<float> values = file_.floats(t);
    for (std::size_t i = 0; i < values.size(); ++i) {
      if (!std::isfinite(values[i])) fail(name, "value " + std::to_string(i) + " is not finite");
      if (std::abs(values[i]) > kMaxWeight) {
        fail(name, "value " + std::to_string(i) + " (" + std::to_string(values[i]) + ") is beyond +-" +
                       std::to_string(static_cast<int>(kMaxWeight)) + ", not a trained weight");
      }
    }
    return values;
  }

  [[noreturn]] void fail(const std::string& name, const std::string& message) const {
    throw Error(ErrorCode::InvalidData, file_.source() + ": tensor '" + prefix_ + name + "': " + message);
  }

 private:
  const SafetensorsFile& file_;
  std::string prefix_;
};

std::string shape_text(const std::vector<std::size_t>& shape) {
  std::string s = "[";
  for (std::size_t i = 0; i < shape.size(); ++i) s += (i ? ", " : "") + std::to_string(shape[i]);
  return s + "]";
}

// A Conv1d / Conv2d 1x1 weight: [out, in] followed by kernel dimensions of 1.
void read_weight(const TensorSource& src, const std::string& name, ConvLayer& layer) {
  const SafetensorsTensor& t = src.require(name);
  if (t.shape.size() < 2 || t.shape.size() > 4) src.fail(name, "shape " + shape_text(t.shape) + " is not a 1x1 convolution");
  for (std::size_t d = 2; d < t.shape.size(); ++d) {
    if (t.shape[d] != 1) src.fail(name, "shape " + shape_text(t.shape) + ": only 1x1 kernels are supported");
  }
  if (t.shape[0] == 0 || t.shape[1] == 0) src.fail(name, "shape " + shape_text(t.shape) + " is empty");
  layer.out = t.shape[0];
  layer.in = t.shape[1];
  layer.weight = src.floats(name, t);
  if (std::all_of(layer.weight.begin(), layer.weight.end(), [](float v) { return v == 0.0f; })) {
    src.fail(name, "every weight is zero, not a trained layer");
  }
}

std::vector<float> read_vector(const TensorSource& src, const std::string& name, std::size_t size) {
  const SafetensorsTensor& t = src.require(name);
  if (t.shape.size() != 1 || t.shape[0] != size) {
    src.fail(name, "shape " + shape_text(t.shape) + ", expected [" + std::to_string(size) + "]");
  }
  return src.floats(name, t);
}

void read_bn(const TensorSource& src, int index, ConvLayer& layer) {
  // nn.Sequential(conv, bn, act) names it convN.1; the reference also keeps
  // the same module as bnN, so either name is accepted.
  std::string prefix = layer.name + ".1.";
  if (src.find(prefix + "weight") == nullptr && src.find("bn" + std::to_string(index) + ".weight") != nullptr) {
    prefix = "bn" + std::to_string(index) + ".";
  }
  layer.has_bn = true;
  layer.bn_gamma = read_vector(src, prefix + "weight", layer.out);
  layer.bn_beta = read_vector(src, prefix + "bias", layer.out);
  layer.bn_mean = read_vector(src, prefix + "running_mean", layer.out);
  layer.bn_var = read_vector(src, prefix + "running_var", layer.out);
  for (float v : layer.bn_var) {
    if (!(v >= 0.0f)) src.fail(prefix + "running_var", "holds a negative or NaN variance");
  }
}

void expect_in(const TensorSource& src, const ConvLayer& layer, std::size_t expected, const std::string& why) {
  if (layer.in != expected) {
    src.fail(layer.name + (layer.name == "conv9" ? ".weight" : ".0.weight"),
             "has " + std::to_string(layer.in) + " input channels, expected " + std::to_string(expected) + " (" +
                 why + "): the layer shapes do not chain");
  }
}

}  // namespace

DgcnnWeights load_dgcnn_weights(const SafetensorsFile& file) {
  const TensorSource src(file);
  DgcnnWeights w;
  for (int i = 0; i < 8; ++i) {
    ConvLayer& layer = w.conv[i];
    layer.name = "conv" + std::to_string(i + 1);
    read_weight(src, layer.name + ".0.weight", layer);
    read_bn(src, i + 1, layer);
  }
  ConvLayer& cls = w.conv[8];
  cls.name = "conv9";
  read_weight(src, "conv9.weight", cls);
  if (src.find("conv9.bias") != nullptr) cls.bias = read_vector(src, "conv9.bias", cls.out);

  const ConvLayer* c = w.conv;
  if (c[0].in % 2 != 0 || c[0].in < 6) {
    src.fail("conv1.0.weight", "has " + std::to_string(c[0].in) +
                                   " input channels; expected 2 x C with C >= 3 (edge features [x_j - x_i, x_i])");
  }
  expect_in(src, c[1], c[0].out, "conv1's outputs");
  expect_in(src, c[2], 2 * c[1].out, "2 x conv2's outputs");
  expect_in(src, c[3], c[2].out, "conv3's outputs");
  expect_in(src, c[4], 2 * c[3].out, "2 x conv4's outputs");
  const std::size_t local = c[1].out + c[3].out + c[4].out;
  expect_in(src, c[5], local, "x1 + x2 + x3 channels");
  expect_in(src, c[6], c[5].out + local, "global feature + x1 + x2 + x3");
  expect_in(src, c[7], c[6].out, "conv7's outputs");
  expect_in(src, c[8], c[7].out, "conv8's outputs");
  return w;
}

}  // namespace sarmap
