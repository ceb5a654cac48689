// The run pipeline as a function, shared by `sarmap run` and `sarmap demo`.
#pragma once

#include <cstddef>
#include <filesystem>
#include <functional>
#include <optional>
#include <string>
#include <vector>

#include "engine/metric/metric_map.hpp"
#include "engine/metric/ray_integrator.hpp"
#include "engine/pipeline/mapper.hpp"
#include "tools/sarmap/sequence_input_options.hpp"

namespace sarmap::cli {

// As many map blocks as half this machine's memory holds: past it the map
// forgets its farthest blocks rather than the process being killed for memory.
std::size_t default_max_blocks();

struct RunOptions {
  std::filesystem::path input;
  SequenceInputArgs sequence;
  std::filesystem::path out;
  double voxel = 0.05;
  std::string classifier = "dgcnn";  // dgcnn | geometric | labels
  std::filesystem::path model;        // dgcnn; empty: the shipped ramp model
  // dgcnn: sparser blocks are left unknown (pipeline_dgcnn_settings says why
  // it is lower than `sarmap classify`'s).
  std::size_t min_block_points = pipeline::pipeline_dgcnn_settings().min_points;
  double block_stride = 0.0;  // metres between DGCNN block origins; 0 = three quarters of the model's block size
  // dgcnn: classify each scan on its own instead of the accumulated map.
  bool classify_per_scan = false;
  // dgcnn: rules of the chain turned off (kRuleNames), over the config file's.
  std::vector<std::string> disabled_rules;
  int threads = 0;
  bool overlap = true;  // classify the next scan while the maps take this one (same maps)
  double max_range = 0.0;
  double max_point_distance = 1000.0;  // drop points farther from their scan's origin (m); 0 = keep all
  double keep_radius = 0.0;     // drop map blocks farther than this from the sensor (m); 0 = keep all
  // Keep at most this many map blocks, the farthest dropped first; 0 = no limit.
  std::size_t max_blocks = default_max_blocks();
  bool strict = false;  // a bad frame or refused scan ends the run instead of being skipped
  // Save the whole state to OUT/.checkpoint/ after every this many frames (0 = never).
  std::size_t checkpoint_every = 0;
  // Continue from OUT/.checkpoint/ when it holds a checkpoint of this run's
  // settings and input (from the first frame when there is none).
  bool resume = false;
  // Also write the whole output set after each of these numbers of scans,
  // into OUT/snap_NNNN/ (each a folder with its own manifest).
  std::vector<std::size_t> snapshots;
  // Also write voxel_cubes.ply (each occupied voxel as a coloured cube mesh).
  bool voxel_cubes = false;
  // Also write mapper.state (the whole Mapper), which `sarmap merge` reads.
  bool keep_state = false;
  bool quiet = false;
  // Every Mapper setting without a field above (segments, topo, occupancy,
  // ...), from `--config`; the fields above are applied over it.
  std::optional<pipeline::MapperConfig> base_config;
  // `--config`: a config file or a run's manifest.json (load_config_file).
  std::filesystem::path config_file;
};

// Reads o.config_file into o.base_config and takes the fields of `o` from it
// whose flags `given` says the command line did not give (so the flags
// override the file). Keys the file leaves out take `sarmap run`'s own
// defaults. Throws sarmap::Error naming the file and key.
void load_config_file(RunOptions& o, const std::function<bool(const char* flag)>& given);

struct RunSummary {
  std::size_t scans = 0;
  metric::MapCounts counts;
  metric::IntegrationStats stats;
  double wall_s = 0;
};

// Throws sarmap::Error for bad options or input.
RunSummary run_pipeline(const RunOptions& options);

}  // namespace sarmap::cli
