// `sarmap run INPUT --out DIR [--classifier dgcnn|geometric|labels] [--model M]`:
// builds the maps scan by scan through the pipeline's Mapper and writes every output through
// pipeline::write_run (map.sarmap, map.bt, map.ot, voxels.ply, semantic_points.ply, segments.*, graph.*,
// grid.*, profile.json, summary.json, then manifest.json; docs/formats.md), each atomically.
#include <unistd.h>

#include <algorithm>
#include <chrono>
#include <cmath>
#include <cstdio>
#include <filesystem>
#include <memory>
#include <optional>
#include <string>

#include <nlohmann/json.hpp>
#include <tbb/global_control.h>

#include "engine/core/error.hpp"
#include "engine/io/run_folder.hpp"
#include "engine/io/sha256.hpp"
#include "engine/io/scan_source.hpp"
#include "engine/pipeline/checkpoint.hpp"
#include "engine/pipeline/mapper.hpp"
#include "engine/pipeline/mapper_config_json.hpp"
#include "engine/pipeline/mapper_file.hpp"
#include "engine/pipeline/run_outputs.hpp"
#include "engine/topo/topo_map.hpp"
#include "tools/sarmap/number_checks.hpp"
#include "tools/sarmap/commands.hpp"
#include "tools/sarmap/disable_rule_option.hpp"
#include "tools/sarmap/off_switch.hpp"
#include "tools/sarmap/progress.hpp"
#include "tools/sarmap/run_command.hpp"
#include "tools/sarmap/shipped_data.hpp"
#include "tools/sarmap/skipped_scans.hpp"

namespace sarmap::cli {

namespace fs = std::filesystem;

namespace {

// The CLI's validators refuse these already; RunOptions built in code (demo,
// tests) are checked the same way. !(x >= 0) so that NaN fails too.
void require_finite_non_negative(double value, const char* flag) {
  if (!(value >= 0) || !std::isfinite(value)) {
    throw Error(ErrorCode::InvalidArgument, std::string("run: ") + flag + " must be a finite number >= 0");
  }
}

// What a checkpoint must match to be continued: the whole config and the
// range the run uses (not the thread count or stage overlap: the maps do not
// depend on them), the input's layout, frame count and defining file, and
// the model's bytes.
std::string run_fingerprint(const RunOptions& o, const pipeline::Mapper& mapper, const ScanSource& source,
                            const nlohmann::ordered_json& input) {
  nlohmann::ordered_json what;
  what["max_range"] = mapper.max_range();
  what["config"] = pipeline::config_to_json(mapper.config());
  what["input_sha256"] = input["sha256"];
  what["layout"] = source.layout();
  what["frames"] = source.size();
  if (o.classifier == "dgcnn") what["model_sha256"] = digest_file(mapper.config().classifier.model).sha256;
  return sha256_hex(what.dump());
}

// The settings `sarmap run` has flags for, over `config`.
pipeline::MapperConfig apply_run_options(const RunOptions& o, pipeline::MapperConfig config) {
  config.voxel = o.voxel;
  config.max_range = o.max_range;
  config.max_point_distance = o.max_point_distance;
  config.bounds.keep_radius = o.keep_radius;
  config.bounds.max_blocks = o.max_blocks;
  config.classifier.kind = pipeline::classifier_kind_from_name(o.classifier);
  if (!o.model.empty()) config.classifier.model = o.model;
  config.classifier.dgcnn.min_points = o.min_block_points;
  config.classifier.dgcnn.stride = o.block_stride;
  config.classifier.per_scan = o.classify_per_scan;
  for (const std::string& rule : o.disabled_rules) rule_enabled(config.classifier.rules, rule) = false;
  return config;
}

// OUT/snap_NNNN for a snapshot after `scans` scans.
fs::path snapshot_folder(const fs::path& out, std::size_t scans) {
  char name[32];
  std::snprintf(name, sizeof name, "snap_%04zu", scans);
  return out / name;
}

// The scan count a folder name "snap_NNNN" stands for, or nullopt.
std::optional<std::size_t> snapshot_scans(const std::string& name) {
  if (name.size() < 9 || name.rfind("snap_", 0) != 0 || name.size() > 25) return std::nullopt;
  std::size_t scans = 0;
  for (std::size_t i = 5; i < name.size(); ++i) {
    if (name[i] < '0' || name[i] > '9') return std::nullopt;
    scans = scans * 10 + static_cast<std::size_t>(name[i] - '0');
  }
  return scans;
}

// Snapshot folders of an earlier run that this one will not write again: all
// of them, except on a resume those of the scans already mapped that this run
// asks for too.
void remove_stale_snapshots(const fs::path& out, const std::vector<std::size_t>& wanted, std::size_t scans_done) {
  for (const fs::directory_entry& entry : fs::directory_iterator(out)) {
    const std::optional<std::size_t> scans = snapshot_scans(entry.path().filename().string());
    if (!scans || !entry.is_directory() || entry.is_symlink()) continue;
    const bool kept = *scans <= scans_done && std::binary_search(wanted.begin(), wanted.end(), *scans) &&
                      snapshot_folder(out, *scans) == entry.path();
    if (!kept) fs::remove_all(entry.path());
  }
}

}  // namespace

void load_config_file(RunOptions& o, const std::function<bool(const char* flag)>& given) {
  const RunOptions defaults;
  pipeline::MapperConfig base = apply_run_options(defaults, {});
  base.semantic_points_voxel = defaults.voxel;
  pipeline::MapperConfig c = pipeline::read_config_file(o.config_file, base);
  if (!given("--voxel")) o.voxel = c.voxel;
  if (!given("--max-range")) o.max_range = c.max_range;
  if (!given("--max-point-distance")) o.max_point_distance = c.max_point_distance;
  if (!given("--keep-radius")) o.keep_radius = c.bounds.keep_radius;
  if (!given("--max-blocks")) o.max_blocks = c.bounds.max_blocks;
  if (!given("--classifier")) o.classifier = std::string(to_string(c.classifier.kind));
  if (!given("--model")) o.model = c.classifier.model;
  if (!given("--min-block-points")) o.min_block_points = c.classifier.dgcnn.min_points;
  if (!given("--block-stride")) o.block_stride = c.classifier.dgcnn.stride;
  if (!given("--classify-per-scan")) o.classify_per_scan = c.classifier.per_scan;
  o.base_config = c;
}

std::size_t default_max_blocks() {
  const long pages = ::sysconf(_SC_PHYS_PAGES), page_bytes = ::sysconf(_SC_PAGE_SIZE);
  if (pages <= 0 || page_bytes <= 0) return 0;
  // Blocks at their largest, so that the budget holds whatever they hold.
  return static_cast<std::size_t>(pages) / 2 * static_cast<std::size_t>(page_bytes) /
         metric::SemanticBlocks::kMaxBlockBytes;
}

RunSummary run_pipeline(const RunOptions& o) {
  if (o.out.empty()) throw Error(ErrorCode::InvalidArgument, "run: --out DIR is required");
  if (o.threads < 0) throw Error(ErrorCode::InvalidArgument, "run: --threads must be >= 0 (0 = all cores)");
  require_finite_non_negative(o.max_range, "--max-range");
  require_finite_non_negative(o.max_point_distance, "--max-point-distance");
  require_finite_non_negative(o.keep_radius, "--keep-radius");
  require_finite_non_negative(o.block_stride, "--block-stride");
  std::vector<std::size_t> snapshots = o.snapshots;
  std::sort(snapshots.begin(), snapshots.end());
  snapshots.erase(std::unique(snapshots.begin(), snapshots.end()), snapshots.end());
  if (!snapshots.empty() && snapshots.front() == 0) {
    throw Error(ErrorCode::InvalidArgument, "run: --snapshots takes scan counts of 1 or more");
  }
  std::unique_ptr<tbb::global_control> limit;
  if (o.threads > 0) {
    limit = std::make_unique<tbb::global_control>(tbb::global_control::max_allowed_parallelism,
                                                  static_cast<std::size_t>(o.threads));
  }
  const auto wall_start = std::chrono::steady_clock::now();
  std::unique_ptr<ScanSource> source = open_input_sequence(o.input, o.sequence);
  pipeline::MapperConfig config = apply_run_options(o, o.base_config.value_or(pipeline::MapperConfig{}));
  // Without a config file the kept points share the map's voxel.
  if (!o.base_config) config.semantic_points_voxel = o.voxel;
  if (o.classifier == "dgcnn") {
    if (config.classifier.model.empty()) config.classifier.model = shipped_ramp_model();
    if (!fs::exists(config.classifier.model)) {
      throw Error(ErrorCode::Io, "run: model file " + config.classifier.model.string() +
                                     " not found (give --model M.safetensors, or --classifier geometric for "
                                     "the baseline that needs no model)");
    }
  }
  pipeline::Mapper mapper(config, source->sensor());
  // Before the mapping: a folder that cannot take the outputs fails now, and
  // the old run's manifest goes, so the folder reads as unfinished until the
  // new manifest is written last.
  RunFolderWriter folder(o.out);

  const nlohmann::ordered_json input = pipeline::input_record(o.input);
  const std::string fingerprint = run_fingerprint(o, mapper, *source, input);
  const fs::path checkpoint_folder = o.out / ".checkpoint";
  const fs::path checkpoint = checkpoint_folder / "state.bin";
  std::size_t first_frame = 0;
  std::size_t scans = 0;
  double elapsed_before = 0;  // by the runs this one continues
  if (fs::is_directory(checkpoint_folder)) remove_stale_temporaries(checkpoint_folder);
  if (o.resume && fs::exists(checkpoint)) {
    const pipeline::CheckpointHeader header = pipeline::load_checkpoint(checkpoint, fingerprint, mapper);
    first_frame = static_cast<std::size_t>(header.next_frame);
    scans = static_cast<std::size_t>(header.scans);
    elapsed_before = header.elapsed_s;
    source->skip_to(first_frame);
    if (!o.quiet) {
      std::printf("resuming from %s: frame %zu of %zu, %zu scans mapped\n", checkpoint.string().c_str(),
                  first_frame, source->size(), scans);
    }
  } else {
    if (o.resume && !o.quiet) {
      std::printf("no checkpoint in %s: starting from the first frame\n", checkpoint_folder.string().c_str());
    }
    // Another run's checkpoint must not be continued by a later --resume.
    fs::remove_all(checkpoint_folder);
  }
  if (o.checkpoint_every > 0) fs::create_directories(checkpoint_folder);
  remove_stale_snapshots(o.out, snapshots, scans);
  auto next_snapshot = std::upper_bound(snapshots.begin(), snapshots.end(), scans);
  const auto elapsed = [&] {
    return elapsed_before + std::chrono::duration<double>(std::chrono::steady_clock::now() - wall_start).count();
  };

  ProgressLine progress("run", source->size(), !o.quiet);
  // One unreadable frame or refused scan costs that scan, not the run: both
  // leave the maps as they were (ScanSource::next, Mapper::integrate_stream).
  SkippedScans skipped(mapper.profile(), o.strict);
  // Every output as the maps stand, into `into` (the run's folder or a snapshot's).
  const auto write_outputs = [&](RunFolderWriter& into) {
    mapper.profile().set_wall_seconds(elapsed());
    pipeline::RunRecord record;
    record.input = input;
    record.layout = source->layout();
    record.arena_sha256 = source->arena_sha256();
    record.scans = scans;
    record.scans_skipped = skipped.count();
    record.voxel_cubes = o.voxel_cubes;
    record.mapper_state = o.keep_state;
    pipeline::write_run(mapper, into, record);
  };
  // The Mapper is read (a snapshot) or saved (a checkpoint) only between two
  // integrate_stream calls: each call ends at the next frame that may need
  // either, counting the scans in flight as if all of them will be mapped.
  bool input_ended = false;
  std::size_t frame = first_frame;  // the next frame to read
  std::size_t in_flight = 0;        // read, not yet done
  std::size_t chunk_start = frame;  // where this integrate_stream call began
  const auto checkpoint_due = [&] {
    return o.checkpoint_every > 0 && frame != chunk_start && frame % o.checkpoint_every == 0;
  };
  const auto read = [&](std::size_t, Scan& scan) {
    const bool snapshot_due = next_snapshot != snapshots.end() && scans + in_flight >= *next_snapshot;
    if (checkpoint_due() || snapshot_due) return false;
    ++frame;
    ++in_flight;
    if (!source->next(scan)) {
      --frame;
      --in_flight;
      input_ended = true;
      return false;
    }
    return true;
  };
  const auto done = [&](pipeline::StreamedScan& item) {
    --in_flight;
    if (item.mapped) {
      ++scans;
    } else {
      skipped.add(item.frame, item.read_failed ? "frame " + std::to_string(item.frame) : item.scan.source,
                  *item.error, /*row_open=*/false);
    }
    progress.update(item.frame + 1);
  };
  const pipeline::StageOverlap overlap = o.overlap ? pipeline::StageOverlap::On : pipeline::StageOverlap::Off;
  while (!input_ended) {
    chunk_start = frame;
    mapper.integrate_stream(frame, read, done, overlap);
    if (next_snapshot != snapshots.end() && scans == *next_snapshot) {
      RunFolderWriter snapshot(snapshot_folder(o.out, scans));
      write_outputs(snapshot);
      ++next_snapshot;
    }
    // The checkpoint holds the state between two frames, read or not.
    if (checkpoint_due()) {
      pipeline::save_checkpoint(checkpoint, {fingerprint, frame, scans, elapsed()}, mapper);
    }
  }
  progress.finish();
  if (scans == 0 && skipped.count() > 0) {
    throw Error(ErrorCode::InvalidData, "run: none of the " + std::to_string(skipped.count()) +
                                            " scans could be used; the first: " + skipped.first_error());
  }

  mapper.finish();
  write_outputs(folder);
  // The outputs are whole: nothing is left to resume.
  std::error_code ignored;
  fs::remove_all(checkpoint_folder, ignored);
  const metric::MetricMap& map = mapper.metric_map();
  const topo::TopoMap& topo = mapper.topo_map();
  RunSummary summary;
  summary.scans = scans;
  summary.counts = map.counts();
  summary.stats = mapper.metric_stats();
  summary.wall_s = mapper.profile().wall_seconds();
  if (next_snapshot != snapshots.end()) {
    std::fprintf(stderr, "sarmap: warning: no snapshot after %zu scans: the run mapped %zu\n", *next_snapshot, scans);
  }
  if (mapper.blocks_dropped() > 0) {
    // Both bounds named when both are set (the block budget always is, unless
    // 0): the Mapper does not count which one dropped a block.
    char radius[64];
    std::snprintf(radius, sizeof radius, "--keep-radius %g m", o.keep_radius);
    const std::string budget = "--max-blocks " + std::to_string(o.max_blocks);
    const std::string bounds = o.keep_radius > 0 && o.max_blocks > 0 ? std::string(radius) + " and " + budget
                               : o.keep_radius > 0                   ? std::string(radius)
                                                                     : budget;
    std::fprintf(stderr, "sarmap: warning: %zu map blocks were forgotten to keep the map within %s\n",
                 mapper.blocks_dropped(), bounds.c_str());
  }
  if (!o.quiet) {
    if (skipped.count() > 0) std::printf("%zu scans skipped (profile.json lists them)\n", skipped.count());
    std::printf("%zu scans, %zu points (%zu rejected) -> %zu occupied, %zu free voxels at %.3f m in %.2f s\n",
                scans, summary.stats.points_in, summary.stats.points_rejected, summary.counts.occupied,
                summary.counts.free, o.voxel, summary.wall_s);
    std::size_t nodes = 0, tree = 0;
    for (const topo::TopoNode& n : topo.nodes()) nodes += n.alive;
    for (const topo::TopoEdge& e : topo.edges()) tree += e.in_tree;
    std::printf("%zu segments; topological map: %zu nodes, %zu roadmap edges, %zu tree edges\n",
                mapper.segment_map().size(), nodes, topo.edges().size(), tree);
    std::string written;
    for (const std::string& name : pipeline::run_output_names()) {
      written += name + ", ";
      if (name == "voxels.ply" && o.voxel_cubes) written += "voxel_cubes.ply, ";
    }
    if (o.keep_state) written += std::string(pipeline::kMapperFileName) + ", ";
    std::printf("wrote %smanifest.json to %s\n", written.c_str(), o.out.string().c_str());
  }
  return summary;
}

void add_run_command(CLI::App& app) {
  auto o = std::make_shared<RunOptions>();
  CLI::App* cmd = app.add_subcommand("run", "Build the maps from a scan sequence");
  cmd->add_option("INPUT", o->input, "Sequence folder (sarmap, TUM, 7-Scenes) or a PLY/PCD file")->required();
  cmd->add_option("--out", o->out, "Output folder")->required();
  cmd->add_option("--config", o->config_file,
                  "A config file (docs/formats.md, run config) or a run's manifest.json, whose \"config\" "
                  "reproduces that run; the other flags given override it")
      ->check(CLI::ExistingFile);
  cmd->add_option("--voxel", o->voxel, "Metric map voxel size in metres")
      ->capture_default_str()
      ->check(finite_positive());
  cmd->add_option("--classifier", o->classifier,
                  "Where point classes come from: dgcnn (the network), geometric (normal-based baseline, "
                  "no model) or labels (the input's label property)")
      ->capture_default_str();
  cmd->add_option("--model", o->model, "DGCNN weights (default: the shipped ramp model, ramps-dgcnn.safetensors in the data folder: README, Install)");
  cmd->add_option("--min-block-points", o->min_block_points,
                  "DGCNN blocks with fewer points are not classified (their points stay unknown)")
      ->capture_default_str()
      ->check(CLI::PositiveNumber);
  cmd->add_option("--block-stride", o->block_stride,
                  "Metres between DGCNN block origins; below the block size the blocks overlap and each "
                  "point's scores are averaged over the blocks that hold it (0 = three quarters of the block size, "
                  "the default; the block size = no overlap)")
      ->capture_default_str()
      ->check(finite_non_negative());
  cmd->add_flag("--classify-per-scan", o->classify_per_scan,
                "DGCNN: classify each scan on its own (every block of every scan) instead of the accumulated "
                "map (by default the scans' points join a map thinned to one point per 2.5 cm cell, whose "
                "blocks are classified when they have grown by a quarter or stopped growing)");
  add_disable_rule_option(cmd, o->disabled_rules);
  cmd->add_option("--threads", o->threads, "Worker threads (0 = all cores)")
      ->capture_default_str()
      ->check(finite_non_negative());
  add_off_switch(cmd, "--no-overlap", o->overlap,
                 "Run every stage of a scan before the next scan starts (by default the next scan is read "
                 "and classified while the maps take this one, with the same maps; a run with --keep-radius or "
                 "--max-blocks runs in order anyway)");
  cmd->add_option("--max-range", o->max_range,
                  "Cut rays longer than this (m); 0 = the sequence's sensor max_range")
      ->capture_default_str()
      ->check(finite_non_negative());
  cmd->add_option("--keep-radius", o->keep_radius,
                  "After each scan, forget map blocks farther than this from the sensor (m); 0 = keep all")
      ->capture_default_str()
      ->check(finite_non_negative());
  cmd->add_option("--max-blocks", o->max_blocks,
                  "Keep at most this many map blocks (8^3 voxels each, about 7 KiB), forgetting the farthest from "
                  "the sensor first; 0 = no limit (the default: as many as half this machine's memory holds)")
      ->capture_default_str()
      ->check(finite_non_negative());
  cmd->add_option("--max-point-distance", o->max_point_distance,
                  "Drop points farther than this from their scan's origin (m), counted in profile.json; "
                  "0 = keep all")
      ->capture_default_str()
      ->check(finite_non_negative());
  add_sequence_input_options(cmd, o->sequence);
  cmd->add_flag("--strict", o->strict,
                "Stop at the first frame that cannot be read or scan the map refuses (by default such a scan "
                "is skipped with a warning and listed in profile.json)");
  cmd->add_option("--checkpoint-every", o->checkpoint_every,
                  "Save the whole state to OUT/.checkpoint/ after every N frames, so that --resume can continue "
                  "a run that was killed (0 = never)")
      ->capture_default_str()
      ->check(finite_non_negative());
  cmd->add_flag("--resume", o->resume,
                "Continue from OUT/.checkpoint/ (the same settings and input are required; without a checkpoint "
                "the run starts from the first frame)");
  cmd->add_option("--snapshots", o->snapshots,
                  "Also write every output after these numbers of scans, into OUT/snap_NNNN/ (e.g. 40,80,120): "
                  "the maps as they grew")
      ->delimiter(',')
      ->check(finite_non_negative());
  cmd->add_flag("--voxel-cubes", o->voxel_cubes,
                "Also write voxel_cubes.ply: every occupied voxel as a cube in its class colour, for viewers "
                "that know no voxels (as `sarmap convert --voxel-cubes`)");
  cmd->add_flag("--keep-state", o->keep_state,
                "Also write mapper.state: the whole Mapper (maps, kept points, segments, classifier memory, "
                "config and sensor), so that `sarmap merge` can merge this run with others");
  cmd->add_flag("--quiet", o->quiet, "No progress line or summary");
  cmd->callback([o, cmd] {
    if (!o->config_file.empty()) {
      load_config_file(*o, [cmd](const char* flag) { return cmd->count(flag) > 0; });
    }
    run_pipeline(*o);
  });
}

}  // namespace sarmap::cli
