// `sarmap run --config`: manifest.json's "config" holds every setting and
// reproduces its run; a config file sets what no flag reaches; the flags given
// override the file; a bad file is refused naming the key, before any output.
#include <gtest/gtest.h>

#include <filesystem>
#include <string>

#include <nlohmann/json.hpp>

#include "engine/core/scan.hpp"
#include "engine/io/run_folder.hpp"
#include "engine/io/scan_source.hpp"
#include "engine/pipeline/mapper.hpp"
#include "engine/pipeline/mapper_config_json.hpp"
#include "engine/pipeline/run_outputs.hpp"
#include "tests/cli/cli_runner.hpp"
#include "tests/io/scratch_folder.hpp"
#include "tests/cli/tiny_arena.hpp"

namespace sarmap {
namespace {

namespace fs = std::filesystem;
using test::quoted;
using test::run_cli;

using testing::kTinyArena;

nlohmann::json json_of(const fs::path& file) { return nlohmann::json::parse(test::read_all(file)); }

// The SHA-256 manifest.json lists for an output.
std::string output_hash(const nlohmann::json& manifest, const std::string& name) {
  for (const auto& output : manifest.at("outputs")) {
    if (output.at("name") == name) return output.at("sha256").get<std::string>();
  }
  return "(not listed)";
}

// One simulated sequence and a plain run of it, shared by the tests.
class RunConfig : public ::testing::Test {
 protected:
  static void SetUpTestSuite() {
    scratch_ = new test::ScratchFolder();
    auto r = run_cli("simulate " + quoted(kTinyArena) + " --out " + quoted(seq().string()) + " --quiet", dir());
    ASSERT_EQ(r.exit_code, 0) << r.err;
    r = run("--voxel 0.1 --classifier labels", dir() / "plain");
    ASSERT_EQ(r.exit_code, 0) << r.err;
  }
  static void TearDownTestSuite() {
    delete scratch_;
    scratch_ = nullptr;
  }
  static const fs::path& dir() { return scratch_->path(); }
  static fs::path seq() { return dir() / "seq"; }
  static test::CliResult run(const std::string& options, const fs::path& out) {
    return run_cli("run " + quoted(seq().string()) + " --out " + quoted(out.string()) + " --quiet " + options, dir());
  }

  static test::ScratchFolder* scratch_;
};

test::ScratchFolder* RunConfig::scratch_ = nullptr;

TEST_F(RunConfig, TheManifestsConfigReproducesTheRun) {
  const nlohmann::json plain = json_of(dir() / "plain" / "manifest.json");
  const nlohmann::json& config = plain.at("config");
  EXPECT_EQ(config.at("version"), 1);
  EXPECT_EQ(config.at("voxel"), 0.1);
  EXPECT_EQ(config.at("classifier").at("kind"), "labels");
  EXPECT_TRUE(config.at("segments").contains("min_points"));
  EXPECT_TRUE(config.at("topo").contains("node_spacing"));

  const auto r = run("--config " + quoted((dir() / "plain" / "manifest.json").string()), dir() / "again");
  ASSERT_EQ(r.exit_code, 0) << r.err;
  const nlohmann::json again = json_of(dir() / "again" / "manifest.json");
  EXPECT_EQ(again.at("config"), config);
  for (const char* name : {"map.sarmap", "voxels.ply", "semantic_points.ply", "segments.json", "graph.json"}) {
    EXPECT_EQ(output_hash(again, name), output_hash(plain, name)) << name;
  }
  // The run had something to reproduce.
  EXPECT_FALSE(json_of(dir() / "plain" / "segments.json").at("segments").empty());
}

// The library's run API (a Mapper from the manifest's config, write_run)
// writes what the CLI wrote, byte for byte (the profile's timings aside).
TEST_F(RunConfig, TheLibrarysRunApiWritesWhatTheCliWrote) {
  const fs::path manifest_file = dir() / "plain" / "manifest.json";
  const pipeline::MapperConfig config = pipeline::read_config_file(manifest_file);
  const std::unique_ptr<ScanSource> source = open_scan_sequence(seq());
  pipeline::Mapper mapper(config, source->sensor());
  Scan scan;
  std::size_t scans = 0;
  while (source->next(scan)) {
    mapper.integrate(scan);
    ++scans;
  }
  pipeline::RunRecord record;
  record.input = pipeline::input_record(seq());
  record.layout = source->layout();
  record.arena_sha256 = source->arena_sha256();
  record.scans = scans;
  {
    RunFolderWriter folder(dir() / "library");
    pipeline::write_run(mapper, folder, record);
  }
  const nlohmann::json cli = json_of(manifest_file);
  const nlohmann::json library = json_of(dir() / "library" / "manifest.json");
  EXPECT_EQ(library.at("config"), cli.at("config"));
  EXPECT_EQ(library.at("input"), cli.at("input"));
  EXPECT_EQ(library.at("arena_sha256"), cli.at("arena_sha256"));
  EXPECT_EQ(library.at("scans"), cli.at("scans"));
  for (const std::string& name : pipeline::run_output_names()) {
    if (name != "profile.json" && name != "summary.json") {  // they hold timings
      EXPECT_EQ(output_hash(library, name), output_hash(cli, name)) << name;
    }
  }
}

TEST_F(RunConfig, FlagsGivenOverrideTheFile) {
  const auto r = run("--config " + quoted((dir() / "plain" / "manifest.json").string()) +
                         " --voxel 0.2 --max-blocks 5000",
                     dir() / "override");
  ASSERT_EQ(r.exit_code, 0) << r.err;
  const nlohmann::json config = json_of(dir() / "override" / "manifest.json").at("config");
  EXPECT_EQ(config.at("voxel"), 0.2);
  EXPECT_EQ(config.at("bounds").at("max_blocks"), 5000);
  EXPECT_EQ(config.at("classifier").at("kind"), "labels");  // from the file
}

TEST_F(RunConfig, AFileSetsWhatNoFlagReachesAndLeavesTheRestAtRunsDefaults) {
  const fs::path file = scratch_->write("config.json", R"({"voxel": 0.1, "classifier": {"kind": "labels"},
      "segments": {"min_points": 1000}, "topo": {"node_spacing": 1.25}})");
  const auto r = run("--config " + quoted(file.string()), dir() / "file");
  ASSERT_EQ(r.exit_code, 0) << r.err;
  const nlohmann::json config = json_of(dir() / "file" / "manifest.json").at("config");
  EXPECT_EQ(config.at("segments").at("min_points"), 1000);
  EXPECT_EQ(config.at("topo").at("node_spacing"), 1.25);
  // What the file leaves out is as in a run without it (the block budget
  // sized to this machine, the pipeline's 100-point DGCNN blocks).
  const nlohmann::json plain = json_of(dir() / "plain" / "manifest.json").at("config");
  EXPECT_EQ(config.at("bounds"), plain.at("bounds"));
  EXPECT_EQ(config.at("classifier").at("dgcnn").at("min_points"), 100);
  // The setting took effect: only surfaces of 1,000 points or more are segments.
  const nlohmann::json segments = json_of(dir() / "file" / "segments.json").at("segments");
  ASSERT_FALSE(segments.empty());
  EXPECT_LT(segments.size(), json_of(dir() / "plain" / "segments.json").at("segments").size());
  for (const auto& s : segments) EXPECT_GE(s.at("inliers").get<int>(), 1000);
}

TEST_F(RunConfig, ABadFileIsRefusedNamingTheKeyBeforeAnyOutput) {
  const fs::path file = scratch_->write("bad.json", R"({"segments": {"min_pointz": 3}})");
  auto r = run("--config " + quoted(file.string()), dir() / "bad");
  EXPECT_EQ(r.exit_code, 1);
  EXPECT_NE(r.err.find("sarmap: error: " + file.string() + ": segments.min_pointz: unknown key"), std::string::npos)
      << r.err;
  EXPECT_FALSE(fs::exists(dir() / "bad"));
  r = run("--config " + quoted((dir() / "missing.json").string()), dir() / "bad");
  EXPECT_EQ(r.exit_code, 2) << r.err;  // a usage error: CLI11 checks the file exists
}

}  // namespace
}  // namespace sarmap
