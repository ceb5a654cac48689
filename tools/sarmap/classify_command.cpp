// `sarmap classify --raw-block BLOCK.npy --model M.safetensors --logits OUT.npy`:
// runs the DGCNN on one prepared (N, C) float32 block, no preprocessing, and
// writes the (N, classes) logits. This is how sarmap is compared with any
// other implementation of the network (tools/python/dgcnn_reference.py run).
// `sarmap classify INPUT --model M --out OUT.ply`: labels a PLY/PCD cloud or
// frame --frame N of a sequence folder (world frame) with DgcnnClassifier and
// the rule chain, or with the geometric baseline (`--classifier geometric`):
// a scan, or an accumulated map such as a run's semantic_points.ply, so that
// both classifiers can be compared on the same map points.
#include <algorithm>
#include <cstddef>
#include <cstdint>
#include <cmath>
#include <cstdio>
#include <memory>
#include <optional>
#include <string>
#include <vector>

#include <tbb/global_control.h>

#include "engine/core/error.hpp"
#include "engine/io/npy.hpp"
#include "engine/io/point_cloud_file.hpp"
#include "engine/io/scan_source.hpp"
#include "engine/semantic/dgcnn/dgcnn_classifier.hpp"
#include "engine/semantic/dgcnn/dgcnn_model.hpp"
#include "engine/semantic/geometric/geometric_classifier.hpp"
#include "engine/semantic/rules/rule_chain.hpp"
#include "engine/pipeline/point_classifier.hpp"
#include "kernels/simd_level.hpp"
#include "tools/sarmap/number_checks.hpp"
#include "tools/sarmap/commands.hpp"
#include "tools/sarmap/disable_rule_option.hpp"
#include "tools/sarmap/sequence_input_options.hpp"
#include "tools/sarmap/shipped_data.hpp"

namespace sarmap::cli {
namespace {

struct ClassifyOptions {
  std::string classifier = "dgcnn";
  std::string input;
  std::size_t frame = 0;
  SequenceInputArgs sequence;
  std::string out;
  double stride = 0.0;
  // As `sarmap run`'s (pipeline_dgcnn_settings says why it is below the network's own 500).
  std::size_t min_points = pipeline::pipeline_dgcnn_settings().min_points;
  std::uint64_t seed = 1;
  std::vector<std::string> disabled_rules;
  std::string raw_block;
  std::string model;  // empty: the shipped ramp model
  std::string logits;
  int threads = 0;
  std::string simd;
  bool quiet = false;
};

std::unique_ptr<tbb::global_control> thread_limit(const ClassifyOptions& o) {
  if (o.threads <= 0) return nullptr;
  return std::make_unique<tbb::global_control>(tbb::global_control::max_allowed_parallelism,
                                               static_cast<std::size_t>(o.threads));
}

kernels::SimdLevel chosen_level(const ClassifyOptions& o) {
  kernels::SimdLevel level = kernels::active_simd_level();
  if (!o.simd.empty()) {
    const auto forced = kernels::simd_level_from_string(o.simd);
    if (!forced || !kernels::simd_level_supported(*forced)) {
      throw Error(ErrorCode::InvalidArgument, "--simd " + o.simd + ": not an instruction set this CPU runs "
                                              "(sse4_2, avx2, avx512)");
    }
    level = *forced;
  }
  return level;
}

void run_raw_block(const ClassifyOptions& o) {
  const auto limit = thread_limit(o);
  if (o.logits.empty()) throw Error(ErrorCode::InvalidArgument, "classify --raw-block needs --logits OUT.npy");
  const DgcnnModel model = DgcnnModel::load(o.model, chosen_level(o));
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

// Frame o.frame of the input, its labels (if any) kept as gt_label.
PointBuffer read_input(const ClassifyOptions& o) {
  const std::unique_ptr<ScanSource> source = open_input_sequence(o.input, o.sequence);
  if (o.frame >= source->size()) {
    throw Error(ErrorCode::InvalidArgument, o.input + ": --frame " + std::to_string(o.frame) + " but the sequence has " +
                                                std::to_string(source->size()) + " frames");
  }
  Scan scan;
  for (std::size_t i = 0; i <= o.frame; ++i) {
    if (!source->next(scan)) throw Error(ErrorCode::Io, o.input + ": frame " + std::to_string(i) + " could not be read");
  }
  PointBuffer& points = scan.points;
  if (points.has_labels()) {  // keep the input's labels as ground truth beside the prediction
    points.enable_gt_labels();
    std::copy(points.labels().begin(), points.labels().end(), points.gt_labels().begin());
  }
  return std::move(points);
}

void check_output(const ClassifyOptions& o) {
  if (o.out.empty()) throw Error(ErrorCode::InvalidArgument, "classify INPUT needs --out OUT.ply|OUT.pcd");
  point_cloud_format_of(o.out);  // reject an unknown output extension before the work
}

void run_cloud_geometric(const ClassifyOptions& o) {
  const auto limit = thread_limit(o);
  check_output(o);
  const GeometricClassifier classifier(pipeline::ClassifierConfig{}.geometric);  // `sarmap run`'s settings
  PointBuffer points = read_input(o);
  const GeometricClassifyStats stats = classifier.classify(points);
  write_point_cloud(o.out, points);
  if (o.quiet) return;
  std::printf("classified %zu points with the geometric baseline; %zu without a surface normal\n", points.size(),
              stats.without_normal);
}

void run_cloud(const ClassifyOptions& o) {
  const auto limit = thread_limit(o);
  check_output(o);
  if (!(o.stride >= 0) || !std::isfinite(o.stride)) {
    throw Error(ErrorCode::InvalidArgument, "classify: --block-stride must be a finite number >= 0");
  }
  const DgcnnModel model = DgcnnModel::load(o.model, chosen_level(o));
  DgcnnClassifierSettings settings;
  settings.stride = o.stride;
  settings.min_points = o.min_points;
  settings.seed = o.seed;
  const DgcnnClassifier classifier(model, settings);
  RuleChainSettings rule_settings;
  for (const std::string& rule : o.disabled_rules) rule_enabled(rule_settings, rule) = false;
  RuleChain rules(rule_settings);  // this frame's ramp decks only
  PointBuffer points = read_input(o);
  const DgcnnClassifyStats stats = classifier.classify(points);
  const RuleChanges changes = rules.apply(points);
  write_point_cloud(o.out, points);
  if (o.quiet) return;
  std::string changed;
  for (std::size_t r = 0; r < kRuleCount; ++r) {
    changed += (r == 0 ? "" : ", ") + std::string(kRuleNames[r]) + " " + std::to_string(changes.changed[r]);
  }
  std::printf("classified %zu points in %zu blocks; %zu points only in blocks under %zu points labelled unknown; "
              "labels changed by rule: %s\n",
              points.size(), stats.blocks, stats.dropped_points, o.min_points, changed.c_str());
}

}  // namespace

void add_classify_command(CLI::App& app) {
  auto options = std::make_shared<ClassifyOptions>();
  CLI::App* cmd = app.add_subcommand("classify", "Label a cloud with the DGCNN semantic network (or the geometric baseline)");
  cmd->add_option("input", options->input, "A PLY/PCD cloud or a sequence folder to label")->check(CLI::ExistingPath);
  cmd->add_option("--frame", options->frame, "Frame of a sequence folder (default 0)")->check(finite_non_negative());
  add_sequence_input_options(cmd, options->sequence);
  cmd->add_option("--classifier", options->classifier,
                  "dgcnn (the network and its rules) or geometric (the normal- and height-based baseline, no model; "
                  "the DGCNN's options do not apply)")
      ->check(CLI::IsMember({"dgcnn", "geometric"}))
      ->capture_default_str();
  cmd->add_option("--out", options->out, "Labelled cloud to write (.ply or .pcd): label, gt_label, per-class scores");
  // The same names and defaults as `sarmap run`'s; --stride and --min-points
  // are the names these options had before.
  cmd->add_option("--block-stride,--stride", options->stride,
                  "Metres between block origins (default 0: three quarters of the block size)")
      ->check(finite_non_negative());
  cmd->add_option("--min-block-points,--min-points", options->min_points, "Blocks with fewer points are dropped")
      ->capture_default_str()
      ->check(finite_positive());
  cmd->add_option("--seed", options->seed, "Sampling seed (default 1)")->check(finite_non_negative());
  add_disable_rule_option(cmd, options->disabled_rules);
  cmd->add_option("--raw-block", options->raw_block,
                  "An (N, C) float32 .npy block fed to the network as it is (no preprocessing)")
      ->check(CLI::ExistingFile);
  cmd->add_option("--model", options->model,
                  "The network weights (.safetensors; default: the shipped ramp model, as `sarmap run`)")
      ->check(CLI::ExistingFile);
  cmd->add_option("--logits", options->logits, "With --raw-block: where to write the (N, classes) float32 logits (.npy)");
  cmd->add_option("--threads", options->threads, "Worker threads (default: all cores)")->check(CLI::NonNegativeNumber);
  cmd->add_option("--simd", options->simd, "Force an instruction set: sse4_2, avx2 or avx512");
  cmd->add_flag("--quiet", options->quiet, "No summary line (the labels go to --out or --logits)");
  cmd->callback([options, cmd] {
    if (options->raw_block.empty() == options->input.empty()) {
      throw Error(ErrorCode::InvalidArgument, "classify: give either INPUT (a cloud or sequence) or --raw-block BLOCK.npy");
    }
    if (options->classifier == "geometric") {
      for (const char* dgcnn_only : {"--raw-block", "--model", "--logits", "--block-stride", "--min-block-points",
                                     "--seed", "--disable-rule", "--simd"}) {
        if (cmd->count(dgcnn_only) > 0) {
          throw Error(ErrorCode::InvalidArgument,
                      std::string("classify: ") + dgcnn_only + " is a DGCNN option; --classifier geometric needs none");
        }
      }
      run_cloud_geometric(*options);
      return;
    }
    if (options->model.empty()) options->model = shipped_ramp_model().string();
    if (options->raw_block.empty()) {
      run_cloud(*options);
    } else {
      run_raw_block(*options);
    }
  });
}

}  // namespace sarmap::cli
