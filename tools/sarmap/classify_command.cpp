// `sarmap classify --raw-block BLOCK.npy --model M.safetensors --logits OUT.npy`:
// runs the DGCNN on one prepared (N, C) float32 block, no preprocessing, and
// writes the (N, classes) logits. This is how sarmap is compared with any
// other implementation of the network (tools/python/dgcnn_reference.py run).
#include <cstddef>
#include <memory>
#include <optional>
#include <string>
#include <vector>

#include <tbb/global_control.h>

#include "engine/core/error.hpp"
#include "engine/io/npy.hpp"
#include "engine/semantic/dgcnn_model.hpp"
#include "kernels/simd_level.hpp"
#include "tools/sarmap/commands.hpp"

namespace sarmap::cli {
namespace {

struct ClassifyOptions {
  std::string raw_block;
  std::string model;
  std::string logits;
  int threads = 0;
  std::string simd;
};

void run_raw_block(const ClassifyOptions& o) {
  std::unique_ptr<tbb::global_control> limit;
  if (o.threads > 0) {
    limit = std::make_unique<tbb::global_control>(tbb::global_control::max_allowed_parallelism,
                                                  static_cast<std::size_t>(o.threads));
  }
  kernels::SimdLevel level = kernels::active_simd_level();
  if (!o.simd.empty()) {
    const auto forced = kernels::simd_level_from_string(o.simd);
    if (!forced || !kernels::simd_level_supported(*forced)) {
      throw Error(ErrorCode::InvalidArgument, "--simd " + o.simd + ": not an instruction set this CPU runs "
                                              "(sse4_2, avx2, avx512)");
    }
    level = *forced;
  }
  const DgcnnModel model = DgcnnModel::load(o.model, level);
  const NpyArray block = read_npy_f32(o.raw_block);
  if (block.shape.size() != 2 || block.shape[1] != model.channels() || block.shape[0] == 0) {
    std::string shape;
    for (std::size_t d : block.shape) shape += (shape.empty() ? "" : ", ") + std::to_string(d);
    throw Error(ErrorCode::InvalidData, o.raw_block + ": shape (" + shape + "), the model expects (N, " +
                                            std::to_string(model.channels()) + ") with N >= 1");
  }
  const std::size_t n = block.shape[0];
  std::vector<float> logits(n * model.classes());
  DgcnnWorkspace workspace;
  model.forward(block.values.data(), n, logits.data(), workspace);
  const std::size_t shape[2] = {n, model.classes()};
  write_npy_f32(o.logits, shape, logits);
}

}  // namespace

void add_classify_command(CLI::App& app) {
  auto options = std::make_shared<ClassifyOptions>();
  CLI::App* cmd = app.add_subcommand("classify", "Run the DGCNN semantic network");
  cmd->add_option("--raw-block", options->raw_block,
                  "An (N, C) float32 .npy block fed to the network as it is (no preprocessing)")
      ->required()
      ->check(CLI::ExistingFile);
  cmd->add_option("--model", options->model, "The network weights (.safetensors)")->required()->check(CLI::ExistingFile);
  cmd->add_option("--logits", options->logits, "Where to write the (N, classes) float32 logits (.npy)")->required();
  cmd->add_option("--threads", options->threads, "Worker threads (default: all cores)")->check(CLI::NonNegativeNumber);
  cmd->add_option("--simd", options->simd, "Force an instruction set: sse4_2, avx2 or avx512");
  cmd->callback([options] { run_raw_block(*options); });
}

}  // namespace sarmap::cli
