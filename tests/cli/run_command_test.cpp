// `sarmap run` end to end on the tiny committed sequence: every output exists
// and parses, profile.json has the documented shape, and bad input is refused;
// and on a TUM folder, which needs the shared --intrinsics option.
#include <gtest/gtest.h>
#include <unistd.h>

#include <algorithm>
#include <cmath>
#include <filesystem>
#include <fstream>
#include <set>
#include <string>
#include <vector>

#include <nlohmann/json.hpp>

#include "engine/core/classes.hpp"
#include "engine/io/point_cloud_file.hpp"
#include "engine/io/run_folder.hpp"
#include "engine/io/sha256.hpp"
#include "engine/metric/map_file.hpp"
#include "engine/metric/octomap_color_export.hpp"
#include "tests/cli/cli_runner.hpp"
#include "tests/io/png_test_writer.hpp"
#include "tests/release_only.hpp"

namespace sarmap {
namespace {

namespace fs = std::filesystem;
using test::quoted;
using test::run_cli;

class RunCommand : public ::testing::Test {
 protected:
  void SetUp() override {
    dir_ = fs::temp_directory_path() / ("sarmap_run_cli_" + std::to_string(::getpid()));
    fs::remove_all(dir_);
    fs::create_directories(dir_);
  }
  void TearDown() override { fs::remove_all(dir_); }
  // `sarmap run` of the input with the small test network.
  test::CliResult run_dgcnn(const std::string& extra, const fs::path& out) const {
    const std::string model = std::string(SARMAP_TEST_DATA_DIR) + "/dgcnn/model_c6.safetensors";
    return run_cli("run " + quoted(input_.string()) + " --out " + quoted(out.string()) + " --voxel 0.1 --model " +
                       quoted(model) + " --quiet --min-block-points 1" + extra,
                   dir_);
  }
  static nlohmann::json json_of(const fs::path& file) { return nlohmann::json::parse(test::read_all(file)); }
  fs::path dir_;
  const fs::path input_ = fs::path(SARMAP_TEST_DATA_DIR) / "sequences" / "tiny";
};

TEST_F(RunCommand, WritesEveryOutput) {
  const fs::path out = dir_ / "run";
  const auto r =
      run_cli("run " + quoted(input_.string()) + " --out " + quoted(out.string()) + " --voxel 0.1 --classifier labels",
              dir_);
  ASSERT_EQ(r.exit_code, 0) << r.err;
  EXPECT_NE(r.out.find("2 scans, 5 points"), std::string::npos) << r.out;

  const metric::MetricMap map = metric::load_map(out / "map.sarmap");
  EXPECT_DOUBLE_EQ(map.resolution(), 0.1);
  EXPECT_GT(map.counts().occupied, 0u);
  EXPECT_EQ(test::read_all(out / "map.bt").rfind("# Octomap OcTree binary file", 0), 0u);
  EXPECT_EQ(test::read_all(out / "map.ot"), metric::octomap_color_tree(map));
  EXPECT_EQ(read_point_cloud(out / "voxels.ply").size(), map.counts().occupied);
  const PointBuffer semantic = read_point_cloud(out / "semantic_points.ply");
  EXPECT_TRUE(semantic.has_labels());
  EXPECT_TRUE(semantic.has_gt_labels());
  EXPECT_EQ(semantic.size(), 5u);  // 3 + 2 points, each in its own 0.1 m voxel

  const auto manifest = nlohmann::json::parse(test::read_all(out / "manifest.json"));
  EXPECT_EQ(manifest.at("version").get<int>(), 2);
  EXPECT_EQ(fs::path(manifest.at("input").at("path").get<std::string>()), fs::absolute(input_));
  EXPECT_EQ(manifest.at("input").at("sha256").get<std::string>(), sha256_hex(test::read_all(input_ / "sequence.json")));
  EXPECT_EQ(manifest.at("scans").get<int>(), 2);
  EXPECT_EQ(manifest.at("scans_skipped").get<int>(), 0);
  // Every output, with its size and hash; the manifest itself comes last and is not listed.
  std::vector<std::string> listed;
  for (const auto& output : manifest.at("outputs")) {
    const std::string name = output.at("name").get<std::string>();
    listed.push_back(name);
    EXPECT_EQ(output.at("bytes").get<std::uintmax_t>(), fs::file_size(out / name)) << name;
    EXPECT_EQ(output.at("sha256").get<std::string>(), sha256_hex(test::read_all(out / name))) << name;
  }
  EXPECT_EQ(listed,
            (std::vector<std::string>{"map.sarmap", "map.bt", "map.ot", "voxels.ply", "semantic_points.ply",
                                      "segments.json", "segments.ply", "graph.json", "graph.graphml",
                                      "graph.ply", "grid.pgm", "grid.yaml", "profile.json", "summary.json"}));
  EXPECT_NO_THROW(verify_run_folder(out));
  EXPECT_EQ(manifest.at("config").at("classifier").at("kind").get<std::string>(), "labels");

  const auto profile = nlohmann::ordered_json::parse(test::read_all(out / "profile.json"));
  EXPECT_EQ(profile.at("version").get<int>(), 1);
  EXPECT_EQ(profile.at("units").get<std::string>(), "s");
  EXPECT_EQ(profile.at("scans").get<int>(), 2);
  const double wall = profile.at("wall_s").get<double>();
  EXPECT_GT(wall, 0.0);
  EXPECT_NEAR(profile.at("scans_per_second").get<double>(), 2.0 / wall, 1e-9 * (2.0 / wall));
  // Stages in the order a scan goes through them.
  std::vector<std::string> stages;
  for (const auto& [name, stage] : profile.at("stages").items()) {
    stages.push_back(name);
    for (const char* key : {"total_s", "mean_s", "p50_s", "p95_s", "max_s"}) {
      ASSERT_TRUE(stage.contains(key)) << name << " lacks " << key;
      EXPECT_GE(stage.at(key).get<double>(), 0.0) << name << "." << key;
    }
    EXPECT_LE(stage.at("p50_s").get<double>(), stage.at("max_s").get<double>()) << name;
  }
  EXPECT_EQ(stages, (std::vector<std::string>{"read", "preprocess", "classify", "metric", "segment", "topo",
                                              "semantic_points"}));
  const auto& pre = profile.at("stages").at("preprocess");
  EXPECT_EQ(pre.at("points_in").get<double>(), 5.0);
  EXPECT_EQ(pre.at("points_out").get<double>(), 5.0);
  const auto& classify = profile.at("stages").at("classify");
  EXPECT_EQ(classify.at("points").get<double>(), 5.0);
  EXPECT_EQ(classify.at("unlabelled").get<double>(), 0.0);
  const auto& metric = profile.at("stages").at("metric");
  EXPECT_EQ(metric.at("points_in").get<double>(), 5.0);
  EXPECT_GT(metric.at("rays").get<double>(), 0.0);
  EXPECT_GT(metric.at("voxel_visits").get<double>(), 0.0);
  EXPECT_GT(metric.at("voxels_updated").get<double>(), 0.0);
  EXPECT_EQ(metric.at("scans_hashed_walk").get<double>(), 0.0);  // two small scans: the dense grid
  ASSERT_EQ(profile.at("per_scan").size(), 2u);
  std::vector<std::string> row;
  for (const auto& [name, value] : profile.at("per_scan").at(0).items()) row.push_back(name);
  EXPECT_EQ(row, (std::vector<std::string>{"read_s", "preprocess_s", "classify_s", "metric_s", "segment_s", "topo_s",
                                           "semantic_points_s", "latency_s", "metric_map_bytes",
                                           "metric_integrator_scratch_bytes", "segment_bytes", "topo_bytes",
                                           "topo_embree_bytes", "semantic_points_bytes"}));
  // A scan's latency covers at least its own stages.
  for (const auto& scan : profile.at("per_scan")) {
    double stages_s = 0;
    for (const auto& [name, value] : scan.items()) {
      if (name != "latency_s" && name.size() > 2 && name.compare(name.size() - 2, 2, "_s") == 0) {
        stages_s += value.get<double>();
      }
    }
    EXPECT_GE(scan.at("latency_s").get<double>(), stages_s * 0.999);
  }
  // The map's bytes after the last scan are summary.json's, and what the map counts itself.
  EXPECT_EQ(metric.at("map_bytes").get<double>(),
            profile.at("per_scan").at(1).at("metric_map_bytes").get<double>());
  EXPECT_GE(metric.at("map_bytes_max").get<double>(), metric.at("map_bytes").get<double>());
  EXPECT_GT(metric.at("integrator_scratch_bytes").get<double>(), 0.0);
  const auto& segment = profile.at("stages").at("segment");
  for (const char* key : {"points_in", "planes_found", "created", "merged"}) EXPECT_TRUE(segment.contains(key)) << key;
  // Five points are too few for a plane: the files exist and hold no segment.
  EXPECT_EQ(json_of(out / "segments.json").at("segments").size(), 0u);
  EXPECT_TRUE(fs::exists(out / "segments.ply"));
  // No segment, no node: an empty graph in each format, and a grid of what was seen.
  EXPECT_EQ(json_of(out / "graph.json").at("nodes").size(), 0u);
  for (const char* f : {"graph.graphml", "graph.ply", "grid.pgm", "grid.yaml"}) EXPECT_TRUE(fs::exists(out / f)) << f;

  // summary.json: the same run's figures as profile.json and the maps have them.
  const auto summary = nlohmann::ordered_json::parse(test::read_all(out / "summary.json"));
  EXPECT_EQ(summary.at("version").get<int>(), 1);
  EXPECT_EQ(summary.at("scans").get<int>(), 2);
  EXPECT_EQ(summary.at("points_in").get<int>(), 5);
  EXPECT_EQ(summary.at("points_out").get<int>(), 5);
  EXPECT_EQ(summary.at("wall_s"), profile.at("wall_s"));
  EXPECT_EQ(summary.at("scans_per_second"), profile.at("scans_per_second"));
  std::vector<std::string> summary_stages;
  for (const auto& [name, stage] : summary.at("stages").items()) {
    summary_stages.push_back(name);
    const auto& timed = profile.at("stages").at(name);
    EXPECT_EQ(stage.at("mean_ms").get<double>(), std::round(timed.at("mean_s").get<double>() * 1e6) / 1e3);
    EXPECT_EQ(stage.at("p95_ms").get<double>(), std::round(timed.at("p95_s").get<double>() * 1e6) / 1e3);
  }
  EXPECT_EQ(summary_stages, stages);
  EXPECT_EQ(summary.at("latency").at("p95_ms").get<double>(),
            std::round(profile.at("latency").at("p95_s").get<double>() * 1e6) / 1e3);
  EXPECT_EQ(summary.at("metric_map").at("occupied_voxels").get<std::size_t>(), map.counts().occupied);
  EXPECT_EQ(summary.at("metric_map").at("free_voxels").get<std::size_t>(), map.counts().free);
  // The map read back from map.sarmap is packed afresh: at most what the run's map allocates.
  EXPECT_EQ(summary.at("metric_map").at("bytes").get<double>(),
            profile.at("stages").at("metric").at("map_bytes"));
  EXPECT_GE(summary.at("metric_map").at("bytes").get<std::size_t>(), map.memory_bytes());
  EXPECT_EQ(summary.at("semantic_points").get<std::size_t>(), 5u);
  // The kept points' bytes, beside the map's: the run's after its last scan.
  EXPECT_EQ(profile.at("stages").at("semantic_points").at("points_kept").get<double>(), 5.0);
  EXPECT_EQ(summary.at("semantic_points_bytes").get<double>(),
            profile.at("stages").at("semantic_points").at("bytes").get<double>());
  EXPECT_EQ(summary.at("segments").at("count").get<int>(), 0);
  EXPECT_EQ(summary.at("topo_map").at("nodes").get<int>(), 0);
  // The segment and topological maps' bytes beside the metric map's: the
  // run's after its last scan, as profile.json has them.
  EXPECT_EQ(summary.at("segments").at("points").get<int>(), 5);
  EXPECT_EQ(summary.at("segments").at("bytes").get<double>(),
            profile.at("stages").at("segment").at("bytes").get<double>());
  EXPECT_GT(summary.at("segments").at("bytes").get<double>(), 0.0);
  EXPECT_EQ(summary.at("topo_map").at("bytes").get<double>(), profile.at("stages").at("topo").at("bytes").get<double>());
  EXPECT_GT(summary.at("topo_map").at("bytes").get<double>(), 0.0);
}

// semantic_points.ply and voxels.ply carry red, green and blue from the one
// class table, point by point, as the segment and graph files do; voxels.ply
// also its voxel size and each voxel's occupancy probability.
TEST_F(RunCommand, PointsAndVoxelsAreColouredByClass) {
  const fs::path out = dir_ / "run";
  const auto r = run_cli("run " + quoted(input_.string()) + " --out " + quoted(out.string()) +
                             " --voxel 0.1 --classifier labels --quiet",
                         dir_);
  ASSERT_EQ(r.exit_code, 0) << r.err;
  for (const char* file : {"semantic_points.ply", "voxels.ply"}) {
    const PointBuffer points = read_point_cloud(out / file);
    ASSERT_TRUE(points.has_colors()) << file;
    ASSERT_TRUE(points.has_labels()) << file;
    std::set<int> classes;
    for (std::size_t i = 0; i < points.size(); ++i) {
      classes.insert(points.labels()[i]);
      const Rgb want = class_info(static_cast<ClassId>(points.labels()[i])).color;
      EXPECT_EQ(points.red()[i], want.r) << file << " point " << i;
      EXPECT_EQ(points.green()[i], want.g) << file << " point " << i;
      EXPECT_EQ(points.blue()[i], want.b) << file << " point " << i;
    }
    // The tiny sequence's labels: terrain, wall and inclined ramp, so the colours differ.
    EXPECT_EQ(classes, (std::set<int>{1, 2, 3})) << file;
  }
  // voxels.ply names its voxel size, which points alone cannot tell.
  PointCloudFileInfo info;
  const PointBuffer voxels = read_point_cloud(out / "voxels.ply", &info);
  EXPECT_EQ(info.comments, (std::vector<std::string>{"written by sarmap", "voxel_size 0.1"}));
  EXPECT_LT(voxels.find_score("probability"), voxels.score_count());
}

// --voxel-cubes adds voxel_cubes.ply, a mesh of 8 corners and 6 faces per
// occupied voxel, listed in the manifest after voxels.ply; without it there is none.
TEST_F(RunCommand, VoxelCubesAreWrittenAndListedOnlyWhenAsked) {
  for (const bool cubes : {true, false}) {
    const fs::path out = dir_ / (cubes ? "cubes" : "plain");
    const auto r = run_cli("run " + quoted(input_.string()) + " --out " + quoted(out.string()) +
                               " --voxel 0.1 --classifier labels --quiet" + (cubes ? " --voxel-cubes" : ""),
                           dir_);
    ASSERT_EQ(r.exit_code, 0) << r.err;
    const nlohmann::json manifest = json_of(out / "manifest.json");
    std::vector<std::string> listed;
    for (const auto& output : manifest.at("outputs")) listed.push_back(output.at("name").get<std::string>());
    EXPECT_EQ(fs::exists(out / "voxel_cubes.ply"), cubes);
    EXPECT_EQ(std::find(listed.begin(), listed.end(), "voxel_cubes.ply") != listed.end(), cubes);
    if (!cubes) continue;
    EXPECT_EQ(listed[4], "voxel_cubes.ply");  // after map.sarmap, map.bt, map.ot, voxels.ply
    const std::size_t occupied = metric::load_map(out / "map.sarmap").counts().occupied;
    ASSERT_GT(occupied, 0u);
    EXPECT_EQ(read_point_cloud(out / "voxel_cubes.ply").size(), 8 * occupied);
    EXPECT_NE(test::read_all(out / "voxel_cubes.ply").find("element face " + std::to_string(6 * occupied) + "\n"),
              std::string::npos);
    EXPECT_NO_THROW(verify_run_folder(out));
  }
}

TEST_F(RunCommand, MissingInputIsAnError) {
  const fs::path missing = dir_ / "no_such_sequence";
  const auto r =
      run_cli("run " + quoted(missing.string()) + " --out " + quoted((dir_ / "run").string()), dir_);
  EXPECT_EQ(r.exit_code, 1);
  EXPECT_NE(r.err.find("no_such_sequence"), std::string::npos) << r.err;
  EXPECT_FALSE(fs::exists(dir_ / "run" / "map.sarmap"));
}

TEST_F(RunCommand, AnOutputFolderThatCannotBeMadeIsAnErrorNotACrash) {
  std::ofstream(dir_ / "a_file") << "not a folder";
  const auto r = run_cli("run " + quoted(input_.string()) + " --out " + quoted((dir_ / "a_file" / "run").string()) +
                             " --classifier labels --quiet",
                         dir_);
  EXPECT_EQ(r.exit_code, 1);
  EXPECT_EQ(r.err.rfind("sarmap: error: ", 0), 0u) << r.err;
  EXPECT_NE(r.err.find("a_file"), std::string::npos) << r.err;
  EXPECT_EQ(r.err.find("internal error"), std::string::npos) << r.err;
}

TEST_F(RunCommand, UnknownClassifierIsAnError) {
  const auto r = run_cli(
      "run " + quoted(input_.string()) + " --out " + quoted((dir_ / "run").string()) + " --classifier oracle",
      dir_);
  EXPECT_EQ(r.exit_code, 1);
  EXPECT_NE(r.err.find("oracle"), std::string::npos) << r.err;
  EXPECT_NE(r.err.find("geometric"), std::string::npos) << r.err;  // the message lists the choices
  EXPECT_FALSE(fs::exists(dir_ / "run" / "map.sarmap"));
}

TEST_F(RunCommand, MissingModelIsAnErrorThatNamesTheFile) {
  const fs::path model = dir_ / "no_such_model.safetensors";
  const auto r = run_cli("run " + quoted(input_.string()) + " --out " + quoted((dir_ / "run").string()) +
                             " --model " + quoted(model.string()),
                         dir_);
  EXPECT_EQ(r.exit_code, 1);
  EXPECT_NE(r.err.find("no_such_model.safetensors"), std::string::npos) << r.err;
  EXPECT_FALSE(fs::exists(dir_ / "run" / "map.sarmap"));
}

TEST_F(RunCommand, GeometricBaselineNeedsNoModel) {
  const fs::path out = dir_ / "run";
  const auto r = run_cli("run " + quoted(input_.string()) + " --out " + quoted(out.string()) +
                             " --voxel 0.1 --classifier geometric --model /nonexistent.safetensors --quiet",
                         dir_);
  ASSERT_EQ(r.exit_code, 0) << r.err;
  const auto manifest = nlohmann::json::parse(test::read_all(out / "manifest.json"));
  EXPECT_EQ(manifest.at("config").at("classifier").at("kind").get<std::string>(), "geometric");
  EXPECT_FALSE(manifest.contains("settings"));  // manifest version 2: the config alone
  EXPECT_EQ(manifest.at("version").get<int>(), 2);
  const PointBuffer semantic = read_point_cloud(out / "semantic_points.ply");
  EXPECT_EQ(semantic.size(), 5u);
  EXPECT_TRUE(semantic.has_gt_labels());  // the input's labels are kept as ground truth
}

// The DGCNN with a given model; --min-block-points decides whether the tiny
// frames' blocks (3 and 2 points) are classified or left unknown.
TEST_F(RunCommand, DgcnnClassifiesBlocksWithEnoughPoints) {
  RELEASE_ONLY();  // three DGCNN runs: over half a minute under ASan, for option plumbing
  const std::string model = std::string(SARMAP_TEST_DATA_DIR) + "/dgcnn/model_c6.safetensors";
  const auto run = [&](const std::string& extra, const fs::path& out) {
    return run_cli("run " + quoted(input_.string()) + " --out " + quoted(out.string()) + " --voxel 0.1 --model " +
                       quoted(model) + " --quiet" + extra,
                   dir_);
  };
  auto r = run("", dir_ / "default");
  ASSERT_EQ(r.exit_code, 0) << r.err;
  auto profile = nlohmann::json::parse(test::read_all(dir_ / "default" / "profile.json"));
  EXPECT_EQ(profile.at("stages").at("classify").at("blocks").get<double>(), 0.0);
  EXPECT_EQ(profile.at("stages").at("classify").at("unlabelled").get<double>(), 5.0);
  auto manifest = nlohmann::json::parse(test::read_all(dir_ / "default" / "manifest.json"));
  EXPECT_EQ(manifest.at("config").at("classifier").at("kind").get<std::string>(), "dgcnn");
  EXPECT_EQ(manifest.at("config").at("classifier").at("dgcnn").at("min_points").get<int>(), 100);

  r = run(" --min-block-points 1", dir_ / "every_block");
  ASSERT_EQ(r.exit_code, 0) << r.err;
  profile = nlohmann::json::parse(test::read_all(dir_ / "every_block" / "profile.json"));
  EXPECT_GE(profile.at("stages").at("classify").at("blocks").get<double>(), 2.0);
  EXPECT_EQ(profile.at("stages").at("classify").at("unlabelled").get<double>(), 0.0);
  const PointBuffer semantic = read_point_cloud(dir_ / "every_block" / "semantic_points.ply");
  EXPECT_EQ(semantic.score_count(), 4u);  // the fixture model's classes
  for (std::uint8_t label : semantic.labels()) EXPECT_NE(label, 0);

  r = run(" --min-block-points 0", dir_ / "zero");
  EXPECT_NE(r.exit_code, 0);
  EXPECT_NE(r.err.find("--min-block-points"), std::string::npos) << r.err;
}

// Overlapping blocks: with a stride of half the block each point lies in up
// to four blocks, so more blocks run than with the default quarter overlap, every point still
// gets a class, and the manifest records the stride. A stride above the block
// size would leave gaps and is refused by name.
TEST_F(RunCommand, DgcnnBlockStrideOverlapsBlocks) {
  RELEASE_ONLY();  // five DGCNN runs: over two minutes under ASan, for option plumbing
  const auto run = [&](const std::string& extra, const fs::path& out) { return run_dgcnn(extra, out); };
  const auto blocks = [&](const fs::path& out) {
    return json_of(out / "profile.json").at("stages").at("classify").at("blocks").get<double>();
  };
  auto r = run("", dir_ / "plain");
  ASSERT_EQ(r.exit_code, 0) << r.err;
  r = run(" --block-stride 0.5", dir_ / "overlap");
  ASSERT_EQ(r.exit_code, 0) << r.err;
  EXPECT_GT(blocks(dir_ / "overlap"), blocks(dir_ / "plain"));
  const auto manifest = nlohmann::json::parse(test::read_all(dir_ / "overlap" / "manifest.json"));
  EXPECT_DOUBLE_EQ(manifest.at("config").at("classifier").at("dgcnn").at("stride").get<double>(), 0.5);
  // Keep the cloud in a variable: a range-for over a temporary's span would
  // read freed memory (ASan caught exactly that here once).
  const PointBuffer classified = read_point_cloud(dir_ / "overlap" / "semantic_points.ply");
  ASSERT_TRUE(classified.has_labels());
  for (std::uint8_t label : classified.labels()) EXPECT_NE(label, 0);

  r = run(" --block-stride 2", dir_ / "gaps");
  EXPECT_NE(r.exit_code, 0);
  EXPECT_NE(r.err.find("stride"), std::string::npos) << r.err;
  r = run(" --block-stride -1", dir_ / "negative");
  EXPECT_NE(r.exit_code, 0);
  EXPECT_NE(r.err.find("--block-stride"), std::string::npos) << r.err;
}

// The rules after the network (engine/semantic/rules/rule_chain.hpp) are on
// by default and `--disable-rule NAME` turns each off: the manifest records
// which, and the profile counts what each changed (nothing when off). An
// unknown name is a usage error naming the rules. (What they change is
// tested on exact geometry in tests/semantic; this input is too small.)
TEST_F(RunCommand, DisabledRulesAreRecordedAndCounted) {
  RELEASE_ONLY();  // DGCNN runs: a minute and a half under ASan, for option plumbing
  auto r = run_dgcnn("", dir_ / "all");
  ASSERT_EQ(r.exit_code, 0) << r.err;
  r = run_dgcnn(" --disable-rule ramp_veto --disable-rule wall_bands --disable-rule ramp_sides --disable-rule wall_feet",
                dir_ / "none");
  ASSERT_EQ(r.exit_code, 0) << r.err;
  r = run_dgcnn(" --disable-rule wall_feet", dir_ / "no-feet");
  ASSERT_EQ(r.exit_code, 0) << r.err;
  const auto enabled = [&](const char* run, const char* rule) {
    const auto classifier = json_of(dir_ / run / "manifest.json").at("config").at("classifier");
    // The veto's settings sit with the network's, where config files had them before the chain.
    const auto& group = std::string(rule) == "ramp_veto" ? classifier.at("dgcnn").at(rule) : classifier.at(rule);
    return group.at("enabled").get<bool>();
  };
  for (const char* rule : {"ramp_veto", "wall_bands", "ramp_sides", "wall_feet"}) {
    EXPECT_TRUE(enabled("all", rule)) << rule;
    EXPECT_FALSE(enabled("none", rule)) << rule;
    EXPECT_EQ(enabled("no-feet", rule), std::string(rule) != "wall_feet") << rule;
    for (const char* run : {"all", "none", "no-feet"}) {
      const auto classify = json_of(dir_ / run / "profile.json").at("stages").at("classify");
      ASSERT_TRUE(classify.contains(rule)) << run << " " << rule;
      if (!enabled(run, rule)) {
        EXPECT_EQ(classify.at(rule).get<double>(), 0.0) << run << " " << rule;
      }
    }
  }
  r = run_dgcnn(" --disable-rule wall_legs", dir_ / "unknown");
  EXPECT_EQ(r.exit_code, 2);
  EXPECT_NE(r.err.find("wall_legs"), std::string::npos) << r.err;
  EXPECT_NE(r.err.find("ramp_sides"), std::string::npos) << r.err;
  EXPECT_FALSE(fs::exists(dir_ / "unknown" / "manifest.json"));
}

// Map bounds from the command line: the saved map holds no more blocks than
// allowed, the profile counts what was dropped, the manifest records the
// settings, and a negative radius is refused by name.
TEST_F(RunCommand, MapBoundsLimitTheSavedMap) {
  const auto run = [&](const std::string& extra, const fs::path& out) {
    return run_cli("run " + quoted(input_.string()) + " --out " + quoted(out.string()) +
                       " --voxel 0.05 --classifier labels --quiet" + extra,
                   dir_);
  };
  auto r = run("", dir_ / "all");
  ASSERT_EQ(r.exit_code, 0) << r.err;
  const std::size_t all_blocks = metric::load_map(dir_ / "all" / "map.sarmap").blocks().block_count();
  ASSERT_GT(all_blocks, 4u);
  const std::size_t budget = all_blocks / 2;
  r = run(" --max-blocks " + std::to_string(budget) + " --keep-radius 50", dir_ / "bounded");
  ASSERT_EQ(r.exit_code, 0) << r.err;
  EXPECT_NE(r.err.find("within --keep-radius 50 m and --max-blocks " + std::to_string(budget) + "\n"),
            std::string::npos)
      << r.err;
  EXPECT_LE(metric::load_map(dir_ / "bounded" / "map.sarmap").blocks().block_count(), budget);
  const auto profile = nlohmann::json::parse(test::read_all(dir_ / "bounded" / "profile.json"));
  EXPECT_GT(profile.at("stages").at("metric").at("blocks_dropped").get<double>(), 0.0);
  const auto manifest = nlohmann::json::parse(test::read_all(dir_ / "bounded" / "manifest.json"));
  EXPECT_EQ(manifest.at("config").at("bounds").at("max_blocks").get<std::size_t>(), budget);
  EXPECT_DOUBLE_EQ(manifest.at("config").at("bounds").at("keep_radius").get<double>(), 50.0);

  // A radius alone: the warning names it (and the default budget, which bounds the map too).
  r = run(" --keep-radius 0.5", dir_ / "radius");
  ASSERT_EQ(r.exit_code, 0) << r.err;
  EXPECT_NE(r.err.find("within --keep-radius 0.5 m and --max-blocks "), std::string::npos) << r.err;
  r = run(" --keep-radius 0.5 --max-blocks 0", dir_ / "radius_only");
  ASSERT_EQ(r.exit_code, 0) << r.err;
  EXPECT_NE(r.err.find("within --keep-radius 0.5 m\n"), std::string::npos) << r.err;

  r = run(" --keep-radius -2", dir_ / "negative");
  EXPECT_NE(r.exit_code, 0);
  EXPECT_NE(r.err.find("--keep-radius"), std::string::npos) << r.err;
  // NaN, infinity and negative numbers name their flag too (CLI11 lets NaN
  // past its own NonNegativeNumber, and takes -1 for an unsigned as 2^64 - 1).
  for (const char* flag : {"--keep-radius", "--max-range", "--block-stride", "--max-point-distance", "--voxel",
                           "--max-blocks", "--threads", "--max-time-difference"}) {
    for (const char* value : {"nan", "inf", "-1"}) {
      r = run(std::string(" ") + flag + " " + value, dir_ / "not_finite");
      EXPECT_NE(r.exit_code, 0) << flag << " " << value;
      EXPECT_NE(r.err.find(flag), std::string::npos) << r.err;
      EXPECT_NE(r.err.find("must be a finite number"), std::string::npos) << r.err;
    }
  }
  EXPECT_FALSE(fs::exists(dir_ / "not_finite"));  // refused before anything is written
}

TEST_F(RunCommand, TumFolderIsReadWithTheIntrinsicsOption) {
  fs::create_directories(dir_ / "tum/depth");
  for (int f = 0; f < 2; ++f) {
    test::write_png_gray16(dir_ / ("tum/depth/" + std::to_string(f) + ".png"), 2, 2, {5000, 0, 10000, 5000});
  }
  auto write = [this](const std::string& name, const std::string& text) {
    std::ofstream(dir_ / name) << text;
    return dir_ / name;
  };
  write("tum/depth.txt", "1.00 depth/0.png\n1.10 depth/1.png\n");
  write("tum/groundtruth.txt", "1.00 0 0 0 0 0 0 1\n1.10 1 0 0 0 0 0 1\n");
  const fs::path k = write("k.txt", "100 0 0.5\n0 100 0.5\n0 0 1\n");
  const std::string run = "run " + quoted((dir_ / "tum").string()) + " --out " + quoted((dir_ / "out").string());
  auto r = run_cli(run + " --quiet", dir_);
  EXPECT_NE(r.exit_code, 0);
  EXPECT_NE(r.err.find("--intrinsics"), std::string::npos) << r.err;
  // With intrinsics the frames are read; they carry no labels, so the labels
  // classifier stops at the first scan, naming it; the baseline maps them.
  r = run_cli(run + " --quiet --classifier labels --intrinsics " + quoted(k.string()), dir_);
  EXPECT_NE(r.exit_code, 0);
  EXPECT_EQ(r.err.find("--intrinsics"), std::string::npos) << r.err;
  EXPECT_NE(r.err.find("depth/0.png): the input has no label property"), std::string::npos) << r.err;
  r = run_cli(run + " --quiet --classifier geometric --intrinsics " + quoted(k.string()), dir_);
  EXPECT_EQ(r.exit_code, 0) << r.err;
  EXPECT_FALSE(read_point_cloud(dir_ / "out" / "semantic_points.ply").has_gt_labels());
}

}  // namespace
}  // namespace sarmap
