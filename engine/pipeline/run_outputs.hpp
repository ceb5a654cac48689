// A run's output folder from a Mapper: every map, the segments, the graph, the
// kept points, the profile and the summary, each written atomically, then
// manifest.json last as the set's commit record (engine/io/run_folder.hpp;
// docs/formats.md). One writer for `sarmap run`, the examples and library
// front ends.
#pragma once

#include <cstddef>
#include <filesystem>
#include <string>
#include <vector>

#include <nlohmann/json.hpp>

#include "engine/pipeline/mapper.hpp"

namespace sarmap {
class RunFolderWriter;
}

namespace sarmap::pipeline {

// What manifest.json records besides the outputs and the Mapper's config,
// and the optional outputs.
struct RunRecord {
  nlohmann::ordered_json input;  // input_record() of the sequence folder or cloud
  std::string layout;           // sarmap | tum | 7scenes | cloud
  std::string arena_sha256;     // simulated input only: the arena the sequence came from
  std::size_t scans = 0;        // scans mapped
  std::size_t scans_skipped = 0;
  // Also write voxel_cubes.ply: each occupied voxel as a cube in its class
  // colour, for viewers that know no voxels (listed after voxels.ply).
  bool voxel_cubes = false;
  // Also write mapper.state: the whole Mapper, for `sarmap merge` (listed
  // last before the manifest; engine/pipeline/mapper_file.hpp).
  bool mapper_state = false;
};

// manifest.json's "input": the absolute path and the SHA-256 of the file
// that defines the input (a single cloud, or a sarmap sequence's
// sequence.json; null for other folders).
nlohmann::ordered_json input_record(const std::filesystem::path& input);

// The files write_run always writes before the manifest, in order.
const std::vector<std::string>& run_output_names();

// Writes every output of `mapper` into `folder`, then its manifest.json
// (version, sarmap version, input, arena, layout, scans, config, outputs). The profile is written as it stands (set its wall time first).
// Throws sarmap::Error naming the file that could not be written; the folder
// then has no manifest, so readers refuse it.
void write_run(const Mapper& mapper, RunFolderWriter& folder, const RunRecord& record);

}  // namespace sarmap::pipeline
