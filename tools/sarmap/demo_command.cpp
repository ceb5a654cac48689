// `sarmap demo`: the whole pipeline on the built-in default arena in one
// command: simulate it (cached), `sarmap run` on the sequence, `sarmap eval`
// on the run (its headline figures added to the run's summary.json), a route
// between the arena's eval points and pictures of the maps (`sarmap render`),
// then a short summary of figures and where the outputs are.
#include <chrono>
#include <cstdint>
#include <cstdio>
#include <filesystem>
#include <memory>
#include <string>
#include <vector>

#include "engine/core/error.hpp"
#include "engine/eval/run_evaluation.hpp"
#include "engine/io/atomic_file.hpp"
#include "engine/pipeline/run_summary.hpp"
#include "engine/render/png_file.hpp"
#include "engine/render/run_pictures.hpp"
#include "engine/topo/graph_files.hpp"
#include "engine/sim/arena.hpp"
#include "engine/sim/simulator.hpp"
#include "tools/sarmap/number_checks.hpp"
#include "tools/sarmap/commands.hpp"
#include "tools/sarmap/demo_sequence_cache.hpp"
#include "tools/sarmap/progress.hpp"
#include "tools/sarmap/run_command.hpp"
#include "tools/sarmap/run_route.hpp"
#include "tools/sarmap/shipped_data.hpp"

namespace sarmap::cli {
namespace {

namespace fs = std::filesystem;

struct DemoArgs {
  std::string out = "out/demo";
  std::string arena;  // empty: the built-in default arena
  std::uint64_t seed = 0;
  int threads = 0;
  std::string classifier = "dgcnn";
  std::string model;  // empty: the shipped ramp model
  bool classify_per_scan = false;
  std::vector<std::size_t> snapshots;  // as sarmap run's; also draws growth.png
  bool quiet = false;
};

double seconds_since(std::chrono::steady_clock::time_point t) {
  return std::chrono::duration<double>(std::chrono::steady_clock::now() - t).count();
}

std::string percent(const std::optional<double>& v) {
  if (!v) return "n/a";
  char text[32];
  std::snprintf(text, sizeof text, "%.1f%%", 100.0 * *v);
  return text;
}

// Simulates into `sequence` unless the cache stamp says it is already there.
// Returns whether it simulated.
bool simulate_if_needed(const sim::Arena& arena, const fs::path& arena_file, const DemoArgs& a,
                        const fs::path& sequence, const fs::path& stamp_file) {
  const std::string stamp = sequence_stamp(arena_file, arena, a.seed);
  if (cached_sequence_matches(sequence, stamp_file, stamp)) return false;
  // The stamp goes first and comes back last, so an interrupted simulation is never taken for a cached one.
  fs::remove(stamp_file);
  fs::remove_all(sequence);
  sim::SimulationOptions options;
  options.seed = a.seed;
  const sim::Simulator simulator(arena, options);
  ProgressLine progress("simulate", simulator.frame_count(), !a.quiet);
  sim::write_simulated_sequence(simulator, sequence, 0,
                                [&progress](std::size_t frame, std::size_t) { progress.update(frame + 1); });
  progress.finish();
  write_sequence_stamp(stamp_file, stamp);
  return true;
}

// The first of the arena's eval pairs with a route on the roadmap, written
// as the run's path.json (as `sarmap plan --out` would) for its picture to
// show; nothing when no pair has one.
void write_demo_route(const sim::Arena& arena, const fs::path& run_dir) {
  for (const auto& [from, to] : arena.eval_pairs) {
    const topo::Route route =
        plan_on_run(run_dir, from, to, topo::RouteGraph::Roadmap, topo::RouteSearch::AStar);
    if (!route.found) continue;
    topo::write_route_json(run_dir / "path.json", route);
    return;
  }
}

// render.png (the maps in 3-D and from above, docs/formats.md) and, with
// snapshots, growth.png; both beside the run's outputs, outside its manifest.
void write_demo_pictures(const sim::Arena& arena, const fs::path& run_dir, bool growth) {
  fs::remove(run_dir / "path.json");  // an earlier demo's, planned on another map
  write_demo_route(arena, run_dir);
  render::write_png(render::render_run_picture(render::read_run_contents(run_dir)), run_dir / "render.png");
  if (growth) {
    render::write_png(render::render_run_growth(run_dir), run_dir / "growth.png");
  } else {
    fs::remove(run_dir / "growth.png");  // an earlier demo's, of snapshots this run no longer has
  }
}

void run_demo(const DemoArgs& a) {
  const auto start = std::chrono::steady_clock::now();
  const fs::path arena_file = a.arena.empty() ? shipped_default_arena() : fs::path(a.arena);
  const fs::path out = a.out;
  if (out.empty()) throw Error(ErrorCode::InvalidArgument, "demo: --out DIR must not be empty");
  const sim::Arena arena = sim::load_arena(arena_file);
  fs::create_directories(out);
  const fs::path sequence = out / "sequence";
  const fs::path run_dir = out / "run";

  if (!a.quiet) std::printf("sarmap demo: arena %s (%s)\n", arena.name.c_str(), arena_file.string().c_str());
  std::fflush(stdout);
  const auto sim_start = std::chrono::steady_clock::now();
  const bool simulated = simulate_if_needed(arena, arena_file, a, sequence, out / "sequence.stamp");
  const double sim_s = seconds_since(sim_start);

  RunOptions run;
  run.input = sequence;
  run.out = run_dir;
  run.threads = a.threads;
  run.classifier = a.classifier;
  run.model = a.model;
  run.classify_per_scan = a.classify_per_scan;
  run.snapshots = a.snapshots;
  run.quiet = true;  // the demo prints its own summary
  const RunSummary summary = run_pipeline(run);

  const auto eval_start = std::chrono::steady_clock::now();
  const eval::RunEvaluation evaluation = eval::evaluate_run(arena, run_dir);
  {
    AtomicFileWriter writer(out / "eval.json");
    writer.write(eval::format_json(evaluation));
    writer.commit();
  }
  // Into the run's own summary too; the folder is committed again, so it
  // still verifies (docs/formats.md, "summary.json").
  pipeline::add_to_run_summary(run_dir, "eval", eval::summary_json(evaluation));
  const double eval_s = seconds_since(eval_start);

  const auto pictures_start = std::chrono::steady_clock::now();
  write_demo_pictures(arena, run_dir, !a.snapshots.empty());
  const double pictures_s = seconds_since(pictures_start);

  std::printf("sequence  %s: %s in %.1f s\n", sequence.string().c_str(),
              simulated ? "simulated now" : "cached (stamp matches), simulation skipped", sim_s);
  std::printf(
      "run       %zu scans, %zu points in %.2f s wall: %.1f scans/s, %.2f M points/s\n", summary.scans,
      summary.stats.points_in, summary.wall_s,
      summary.wall_s > 0 ? static_cast<double>(summary.scans) / summary.wall_s : 0.0,
      summary.wall_s > 0 ? static_cast<double>(summary.stats.points_in) / summary.wall_s * 1e-6 : 0.0);
  std::printf("map       %.3f m voxels: %zu occupied, %zu free\n", run.voxel, summary.counts.occupied,
              summary.counts.free);
  if (evaluation.voxels) {
    const eval::VoxelScores& v = *evaluation.voxels;
    std::printf("voxels    precision %s, recall %s, F1 %s (within one voxel: %s, %s, %s)\n",
                percent(v.precision()).c_str(), percent(v.recall()).c_str(), percent(v.f1()).c_str(),
                percent(v.precision_within_1()).c_str(), percent(v.recall_within_1()).c_str(),
                percent(v.f1_within_1()).c_str());
    std::printf("          free accuracy %s, free precision %s, class accuracy of occupied voxels %s\n",
                percent(v.free_accuracy()).c_str(), percent(v.free_precision()).c_str(),
                percent(v.class_accuracy()).c_str());
  }
  if (evaluation.points) {
    std::printf("points    accuracy %s, mean IoU %s over %zu classified points (classifier: %s)\n",
                percent(evaluation.points->confusion.accuracy()).c_str(),
                percent(evaluation.points->confusion.mean_iou()).c_str(), evaluation.points->scored,
                run.classifier.c_str());
  }
  if (evaluation.segments) {
    std::printf("segments  %s\n", eval::segment_scores_summary(*evaluation.segments).c_str());
  }
  if (evaluation.graph) {
    std::printf("graph     %s\n", eval::graph_scores_summary(*evaluation.graph).c_str());
  }
  std::printf("eval      %.1f s; figures in %s (sarmap eval --json), headline figures in %s\n", eval_s,
              (out / "eval.json").string().c_str(), (run_dir / "summary.json").string().c_str());
  std::printf(
      "outputs   %s: map.sarmap, map.bt, map.ot, voxels.ply, semantic_points.ply, segments.json, "
      "segments.ply, graph.json, graph.graphml, graph.ply, grid.pgm, grid.yaml, manifest.json, profile.json, "
      "summary.json\n",
      run_dir.string().c_str());
  std::printf("pictures  %s%s%s in %.1f s (sarmap render)\n", (run_dir / "render.png").string().c_str(),
              a.snapshots.empty() ? "" : ", ",
              a.snapshots.empty() ? "" : (run_dir / "growth.png").string().c_str(), pictures_s);
  std::printf("total     %.1f s\n", seconds_since(start));
}

}  // namespace

void add_demo_command(CLI::App& app) {
  auto args = std::make_shared<DemoArgs>();
  CLI::App* cmd = app.add_subcommand(
      "demo", "Simulate the default arena (cached), build its maps, score them and print a summary");
  cmd->add_option("--out", args->out, "Output folder (sequence/, run/, eval.json)")->capture_default_str();
  cmd->add_option("--arena", args->arena, "Arena description instead of the shipped default arena (esogu-6x4.json in the data folder: README, Install)");
  cmd->add_option("--seed", args->seed, "Seed of the simulated sensor noise")
      ->capture_default_str()
      ->check(finite_non_negative());
  cmd->add_option("--threads", args->threads, "Worker threads (0 = all cores)")
      ->capture_default_str()
      ->check(finite_non_negative());
  cmd->add_option("--classifier", args->classifier, "dgcnn, geometric or labels (as for sarmap run)")
      ->capture_default_str();
  cmd->add_option("--model", args->model, "DGCNN weights instead of the shipped ramp model (ramps-dgcnn.safetensors in the data folder: README, Install)");
  cmd->add_flag("--classify-per-scan", args->classify_per_scan,
                "DGCNN: classify each scan on its own instead of the accumulated map (as for sarmap run)");
  cmd->add_option("--snapshots", args->snapshots,
                  "Also write the outputs after these numbers of scans (run/snap_NNNN/, as sarmap run's) and "
                  "run/growth.png, the map growing")
      ->delimiter(',')
      ->check(finite_non_negative());
  cmd->add_flag("--quiet", args->quiet, "No progress lines; the summary is still printed");
  cmd->callback([args] { run_demo(*args); });
}

}  // namespace sarmap::cli
