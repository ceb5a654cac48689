// write_run: a Mapper's whole output set, written by the library as `sarmap
// run` writes it: every file there and readable, the manifest last with the
// config that made the maps, and a folder that verify_run_folder accepts;
// summary.json holds the Mapper's own figures, and add_to_run_summary adds
// to it without breaking the set.
#include "engine/pipeline/run_outputs.hpp"

#include <gtest/gtest.h>

#include <cmath>
#include <filesystem>
#include <fstream>
#include <string>
#include <vector>

#include <nlohmann/json.hpp>

#include "engine/core/error.hpp"
#include "engine/io/point_cloud_file.hpp"
#include "engine/io/run_folder.hpp"
#include "engine/metric/map_file.hpp"
#include "engine/metric/map_summary.hpp"
#include "engine/pipeline/mapper_config_json.hpp"
#include "engine/pipeline/run_summary.hpp"
#include "engine/sim/arena.hpp"
#include "engine/sim/simulator.hpp"
#include "tests/io/scratch_folder.hpp"

namespace sarmap::pipeline {
namespace {

namespace fs = std::filesystem;

nlohmann::json json_of(const fs::path& file) {
  std::ifstream in(file);
  return nlohmann::json::parse(in);
}

TEST(WriteRun, WritesEveryOutputAndTheManifestLast) {
  const sim::Arena arena = sim::load_arena(std::string(SARMAP_SOURCE_DIR) + "/datasets/arenas/esogu-6x4.json");
  const sim::Simulator simulator(arena);
  MapperConfig config;
  config.classifier.kind = pipeline::ClassifierKind::Labels;
  config.voxel = 0.1;
  Mapper mapper(config, sim::sensor_info(arena.sensor));
  for (std::size_t f = 0; f < 40; f += 8) {
    Scan scan = simulator.simulate(f);
    mapper.integrate(scan);
  }
  ASSERT_GT(mapper.segment_map().size(), 0u);

  const test::ScratchFolder scratch;
  RunRecord record;
  record.input = input_record(scratch.write("cloud.ply", "not read, only hashed"));
  record.layout = "cloud";
  record.arena_sha256 = arena.sha256;
  record.scans = 5;
  {
    RunFolderWriter folder(scratch / "run");
    write_run(mapper, folder, record);
  }
  EXPECT_NO_THROW(verify_run_folder(scratch / "run"));
  const nlohmann::json manifest = json_of(scratch / "run" / "manifest.json");
  EXPECT_EQ(manifest.at("scans"), 5);
  EXPECT_EQ(manifest.at("layout"), "cloud");
  EXPECT_EQ(manifest.at("arena_sha256"), arena.sha256);
  EXPECT_EQ(manifest.at("version"), 2);
  EXPECT_EQ(manifest.at("config"), nlohmann::json::parse(config_to_json(mapper.config()).dump()));
  ASSERT_EQ(manifest.at("outputs").size(), run_output_names().size());
  for (std::size_t i = 0; i < run_output_names().size(); ++i) {
    EXPECT_EQ(manifest.at("outputs")[i].at("name"), run_output_names()[i]);
  }
  // The files hold the Mapper's maps.
  const metric::MetricMap map = metric::load_map(scratch / "run" / "map.sarmap");
  EXPECT_EQ(map.counts().occupied, mapper.metric_map().counts().occupied);
  EXPECT_EQ(read_point_cloud(scratch / "run" / "semantic_points.ply").size(), mapper.semantic_points().size());
  EXPECT_EQ(json_of(scratch / "run" / "segments.json").at("segments").size(), mapper.segment_map().size());
  EXPECT_EQ(json_of(scratch / "run" / "profile.json").at("scans"), mapper.profile().scan_count());
}

MapperConfig labels_config() {
  MapperConfig config;
  config.classifier.kind = ClassifierKind::Labels;
  config.voxel = 0.1;
  return config;
}

// A Mapper after a few scans of the default arena, labelled with the truth.
struct MappedArena {
  sim::Arena arena = sim::load_arena(std::string(SARMAP_SOURCE_DIR) + "/datasets/arenas/esogu-6x4.json");
  Mapper mapper{labels_config(), sim::sensor_info(arena.sensor)};
  MappedArena() {
    const sim::Simulator simulator(arena);
    for (std::size_t f = 0; f < 40; f += 8) {
      Scan scan = simulator.simulate(f);
      mapper.integrate(scan);
    }
  }
};

void write_run_into(const Mapper& mapper, const fs::path& folder_path) {
  RunRecord record;
  record.layout = "sarmap";
  record.scans = mapper.profile().scan_count();
  RunFolderWriter folder(folder_path);
  write_run(mapper, folder, record);
}

TEST(WriteRun, SummaryHoldsTheMappersOwnFigures) {
  MappedArena mapped;
  Mapper& mapper = mapped.mapper;
  mapper.profile().set_wall_seconds(2.5);
  const test::ScratchFolder scratch;
  write_run_into(mapper, scratch / "run");
  EXPECT_NO_THROW(verify_run_folder(scratch / "run"));
  bool listed = false;
  const nlohmann::json manifest = json_of(scratch / "run" / "manifest.json");
  for (const auto& output : manifest.at("outputs")) {
    listed = listed || output.at("name").get<std::string>() == "summary.json";
  }
  EXPECT_TRUE(listed);

  std::ifstream summary_file(scratch / "run" / "summary.json");
  const auto summary = nlohmann::ordered_json::parse(summary_file);  // in order: the stages
  const StageProfile& profile = mapper.profile();
  EXPECT_EQ(summary.at("version"), 1);
  EXPECT_EQ(summary.at("scans"), 5);
  EXPECT_EQ(summary.at("scans_skipped"), 0);
  EXPECT_GT(profile.counter("preprocess", "points_in"), 0.0);
  EXPECT_EQ(summary.at("points_in").get<double>(), profile.counter("preprocess", "points_in"));
  EXPECT_EQ(summary.at("points_out").get<double>(), profile.counter("preprocess", "points_out"));
  EXPECT_EQ(summary.at("wall_s"), 2.5);
  EXPECT_EQ(summary.at("scans_per_second"), 2.0);
  // Every stage the profile timed, in its order, in milliseconds to the microsecond.
  std::vector<std::string> stages;
  for (const auto& [name, stage] : summary.at("stages").items()) {
    stages.push_back(name);
    EXPECT_EQ(stage.at("mean_ms").get<double>(), std::round(profile.stats(name).mean_s * 1e6) / 1e3) << name;
    EXPECT_EQ(stage.at("p95_ms").get<double>(), std::round(profile.stats(name).p95_s * 1e6) / 1e3) << name;
  }
  EXPECT_EQ(stages, profile.stage_names());
  EXPECT_GT(profile.stats("metric").mean_s, 0.0);

  const metric::MapSummary map = metric::summarize_map(mapper.metric_map());
  const nlohmann::ordered_json& metric_map = summary.at("metric_map");
  EXPECT_EQ(metric_map.at("voxel"), 0.1);
  EXPECT_EQ(metric_map.at("blocks"), map.counts.blocks);
  EXPECT_EQ(metric_map.at("known_voxels"), map.counts.known);
  EXPECT_EQ(metric_map.at("free_voxels"), map.counts.free);
  EXPECT_EQ(metric_map.at("occupied_voxels"), map.counts.occupied);
  EXPECT_EQ(metric_map.at("bytes"), mapper.metric_map().memory_bytes());
  EXPECT_FALSE(summary.contains("labelled_point_map"));  // the labels classifier keeps none
  EXPECT_GT(map.counts.occupied, 0u);
  EXPECT_EQ(summary.at("semantic_points"), mapper.semantic_points().size());
  std::size_t segments = 0;
  for (std::size_t c = 0; c < kClassCount; ++c) {
    const std::string name(kClassTable[c].name);
    EXPECT_EQ(metric_map.at("occupied_by_class").at(name), map.occupied_by_class[c]) << name;
    const std::size_t of_class = mapper.segment_map().of_class(static_cast<ClassId>(c)).size();
    EXPECT_EQ(summary.at("segments").at("by_class").at(name), of_class) << name;
    segments += of_class;
  }
  EXPECT_GT(mapper.segment_map().size(), 0u);
  EXPECT_EQ(summary.at("segments").at("count"), mapper.segment_map().size());
  EXPECT_EQ(segments, mapper.segment_map().size());
  EXPECT_EQ(summary.at("segments").at("points"), mapper.segment_map().point_count());
  EXPECT_EQ(summary.at("segments").at("bytes"), mapper.segment_map().memory_bytes());

  std::size_t nodes = 0, tree = 0;
  for (const topo::TopoNode& n : mapper.topo_map().nodes()) nodes += n.alive;
  for (const topo::TopoEdge& e : mapper.topo_map().edges()) tree += e.in_tree;
  const nlohmann::ordered_json& topo_map = summary.at("topo_map");
  EXPECT_GT(nodes, 0u);
  EXPECT_EQ(topo_map.at("nodes"), nodes);
  EXPECT_EQ(topo_map.at("roadmap_edges"), mapper.topo_map().edges().size());
  EXPECT_EQ(topo_map.at("tree_edges"), tree);
  EXPECT_EQ(topo_map.at("components"), nodes - tree);
  EXPECT_EQ(topo_map.at("bytes"), mapper.topo_map().memory_bytes());
  // The wall scene's Embree index and buffers, live while the topological map is.
  EXPECT_GT(topo_map.at("embree_bytes").get<std::size_t>(), 0u);
}

TEST(AddToRunSummary, AddsAMemberAndCommitsTheFolderAgain) {
  const MappedArena mapped;
  const test::ScratchFolder scratch;
  const fs::path run = scratch / "run";
  write_run_into(mapped.mapper, run);
  nlohmann::json summary = json_of(run / "summary.json");
  nlohmann::json manifest = json_of(run / "manifest.json");

  const nlohmann::ordered_json figures{{"voxel_f1", 0.9}, {"graph", {{"nodes", 3}}}};
  add_to_run_summary(run, "eval", figures);
  EXPECT_NO_THROW(verify_run_folder(run));
  nlohmann::json amended = json_of(run / "summary.json");
  EXPECT_EQ(amended.at("eval"), nlohmann::json::parse(figures.dump()));
  amended.erase("eval");
  EXPECT_EQ(amended, summary);  // the run's own figures as they were
  nlohmann::json recommitted = json_of(run / "manifest.json");
  for (std::size_t i = 0; i < run_output_names().size(); ++i) {
    const nlohmann::json& before = manifest.at("outputs")[i];
    const nlohmann::json& after = recommitted.at("outputs")[i];
    EXPECT_EQ(after.at("name"), before.at("name"));
    EXPECT_EQ(after.at("sha256") == before.at("sha256"),
              before.at("name").get<std::string>() != "summary.json")
        << before.at("name");
  }
  manifest.erase("outputs");
  recommitted.erase("outputs");
  EXPECT_EQ(recommitted, manifest);  // the same record

  // Nothing replaces a member, the run's or an added one; the folder stays as it was.
  const std::string before = json_of(run / "manifest.json").dump();
  EXPECT_THROW(add_to_run_summary(run, "eval", 1), Error);
  EXPECT_THROW(add_to_run_summary(run, "scans", 1), Error);
  EXPECT_EQ(json_of(run / "manifest.json").dump(), before);
  EXPECT_NO_THROW(verify_run_folder(run));

  // A folder that does not verify is refused and keeps its manifest.
  std::ofstream(run / "graph.json", std::ios::app) << " ";
  EXPECT_THROW(add_to_run_summary(run, "other", 1), Error);
  EXPECT_EQ(json_of(run / "manifest.json").dump(), before);
  EXPECT_FALSE(json_of(run / "summary.json").contains("other"));
}

}  // namespace
}  // namespace sarmap::pipeline
