#include "engine/pipeline/run_outputs.hpp"

#include <algorithm>

#include "engine/core/class_colors.hpp"
#include "engine/core/version.hpp"
#include "engine/io/atomic_file.hpp"
#include "engine/io/point_cloud_file.hpp"
#include "engine/io/run_folder.hpp"
#include "engine/io/sha256.hpp"
#include "engine/metric/map_file.hpp"
#include "engine/metric/octomap_color_export.hpp"
#include "engine/metric/octomap_export.hpp"
#include "engine/metric/voxel_cloud.hpp"
#include "engine/pipeline/mapper_config_json.hpp"
#include "engine/pipeline/mapper_file.hpp"
#include "engine/pipeline/run_summary.hpp"
#include "engine/segments/segment_files.hpp"
#include "engine/topo/graph_files.hpp"
#include "engine/topo/ros_map_files.hpp"

namespace sarmap::pipeline {

namespace fs = std::filesystem;

nlohmann::ordered_json input_record(const fs::path& input) {
  nlohmann::ordered_json record;
  record["path"] = fs::absolute(input).string();
  const fs::path defining = fs::is_directory(input) ? input / "sequence.json" : input;
  record["sha256"] = fs::is_regular_file(defining) ? nlohmann::ordered_json(digest_file(defining).sha256)
                                                   : nlohmann::ordered_json(nullptr);
  return record;
}

const std::vector<std::string>& run_output_names() {
  static const std::vector<std::string> names{
      "map.sarmap",    "map.bt",       "map.ot",       "voxels.ply",    "semantic_points.ply",
      "segments.json", "segments.ply", "graph.json",   "graph.graphml", "graph.ply",
      "grid.pgm",      "grid.yaml",    "profile.json", "summary.json"};
  return names;
}

void write_run(const Mapper& mapper, RunFolderWriter& folder, const RunRecord& record) {
  const metric::MetricMap& map = mapper.metric_map();
  metric::save_map(map, folder.path_of("map.sarmap"));
  metric::write_octomap_bt(map, folder.path_of("map.bt"));
  metric::write_octomap_ot(map, folder.path_of("map.ot"));
  metric::write_voxel_cloud(map, folder.path_of("voxels.ply"));
  std::vector<std::string> outputs = run_output_names();
  if (record.voxel_cubes) {
    metric::write_voxel_cubes(map, folder.path_of("voxel_cubes.ply"));
    outputs.insert(std::find(outputs.begin(), outputs.end(), "voxels.ply") + 1, "voxel_cubes.ply");
  }
  {
    PointBuffer semantic = mapper.semantic_points();  // a copy: the colours are for the file only
    // Classes that came after their scan, or changed since, are the map's now.
    if (mapper.classifier().labels_arrive_late()) mapper.classifier().relabel(semantic);
    paint_class_colors(semantic);
    write_point_cloud(folder.path_of("semantic_points.ply"), semantic);
  }
  segments::write_segments_json(folder.path_of("segments.json"), mapper.segment_map());
  segments::write_segments_ply(folder.path_of("segments.ply"), mapper.segment_map());
  const topo::TopoMap& topo = mapper.topo_map();
  topo::write_graph_json(folder.path_of("graph.json"), topo);
  topo::write_graph_graphml(folder.path_of("graph.graphml"), topo);
  topo::write_graph_ply(folder.path_of("graph.ply"), topo);
  topo::write_ros_map(topo.grid().grid, folder.folder(), "grid");
  {
    AtomicFileWriter w(folder.path_of("profile.json"));
    w.write(mapper.profile().json() + "\n");
    w.commit();
  }
  {
    AtomicFileWriter w(folder.path_of(kRunSummaryName));
    w.write(run_summary_json(mapper).dump(2) + "\n");
    w.commit();
  }
  if (record.mapper_state) {
    save_mapper_file(folder.path_of(kMapperFileName), mapper);
    outputs.emplace_back(kMapperFileName);
  }

  nlohmann::ordered_json manifest;
  manifest["version"] = kRunManifestVersion;
  manifest["sarmap_version"] = kVersion;
  manifest["input"] = record.input;
  // Simulated input only: the arena the sequence was rendered from, which
  // eval holds the --arena it is given to (engine/eval/run_evaluation.hpp).
  if (!record.arena_sha256.empty()) manifest["arena_sha256"] = record.arena_sha256;
  manifest["layout"] = record.layout;
  manifest["scans"] = record.scans;
  manifest["scans_skipped"] = record.scans_skipped;
  // Every setting of the Mapper, for `sarmap run --config OUT/manifest.json`.
  manifest["config"] = config_to_json(mapper.config());
  folder.commit(manifest, outputs);
}

}  // namespace sarmap::pipeline
