// write_run: a Mapper's whole output set, written by the library as `sarmap
// run` writes it: every file there and readable, the manifest last with the
// config that made the maps, and a folder that verify_run_folder accepts.
#include "engine/pipeline/run_outputs.hpp"

#include <gtest/gtest.h>

#include <filesystem>
#include <fstream>
#include <string>

#include <nlohmann/json.hpp>

#include "engine/io/point_cloud_file.hpp"
#include "engine/io/run_folder.hpp"
#include "engine/metric/map_file.hpp"
#include "engine/pipeline/mapper_config_json.hpp"
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
  EXPECT_FALSE(manifest.contains("settings"));  // none given
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

}  // namespace
}  // namespace sarmap::pipeline
