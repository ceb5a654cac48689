// libFuzzer target: the DGCNN model loader (engine/semantic/dgcnn/): a
// safetensors file parsed from memory, its layers checked to chain
// (load_dgcnn_weights), its sarmap.* metadata (parse_dgcnn_metadata), the
// packed model (what DgcnnModel::load builds) and, when it loads, one forward
// pass over a small fixed block, so a model that loads but cannot run is found.
#include <cstddef>
#include <cstdint>
#include <vector>

#include "engine/core/error.hpp"
#include "engine/io/safetensors.hpp"
#include "engine/semantic/dgcnn/dgcnn_metadata.hpp"
#include "engine/semantic/dgcnn/dgcnn_model.hpp"
#include "engine/semantic/dgcnn/dgcnn_weights.hpp"
#include "engine/semantic/dgcnn/dgcnn_workspace.hpp"
#include "fuzz/fuzz_support.hpp"
#include "kernels/simd_level.hpp"

extern "C" int LLVMFuzzerTestOneInput(const std::uint8_t* data, std::size_t size) {
  try {
    const sarmap::SafetensorsFile file =
        sarmap::SafetensorsFile::parse(std::vector<std::uint8_t>(data, data + size), "fuzz.safetensors");
    const sarmap::DgcnnWeights weights = sarmap::load_dgcnn_weights(file);
    sarmap::DgcnnMetadata metadata = sarmap::parse_dgcnn_metadata(file.metadata(), file.source());
    const sarmap::DgcnnModel model(weights, std::move(metadata), sarmap::kernels::active_simd_level());

    // 48 points spread over a unit cube (a fixed pattern: the model is what is fuzzed).
    constexpr std::size_t kPoints = 48;
    std::vector<float> block(kPoints * model.channels());
    for (std::size_t i = 0; i < block.size(); ++i) block[i] = static_cast<float>((i * 7919) % 101) / 100.0f;
    std::vector<float> logits(kPoints * model.classes());
    sarmap::DgcnnWorkspace workspace;
    model.forward(block.data(), kPoints, logits.data(), workspace);
  } catch (const sarmap::Error& e) {
    sarmap::fuzz::refused(e);
    // A malformed or unusable model refused with a message: the expected outcome.
  }
  return 0;
}
