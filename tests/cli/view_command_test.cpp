// `sarmap view` without a browser: the page it writes holds every layer of a
// small run with the counts of the run's own files (voxel positions decoded
// back from base64), thins layers to --max-points, draws a planned path and
// the sensor's path when there are ones, keeps a "</script" in its script from
// ending the page, and refuses a missing folder, a folder that is no run and a
// missing viewer script with a `sarmap: error:` that says what to do. The
// viewer's script comes from a stand-in SARMAP_DATA_DIR, so no npm is needed;
// tests/viewer/view_test.mjs opens the real page in Chromium.
#include <gtest/gtest.h>
#include <unistd.h>

#include <cstdlib>
#include <cstring>
#include <filesystem>
#include <fstream>
#include <string>
#include <vector>

#include <nlohmann/json.hpp>

#include "engine/io/point_cloud_file.hpp"
#include "tests/cli/cli_runner.hpp"

namespace sarmap {
namespace {

namespace fs = std::filesystem;
using test::quoted;
using test::run_cli;

// A stand-in for the bundled viewer, with the one string a page must not
// carry unescaped inside a <script> element.
constexpr const char* kStandInScript = "window.standIn = '</script><b>';\n";

std::vector<unsigned char> from_base64(const std::string& text) {
  std::vector<unsigned char> out;
  std::uint32_t word = 0;
  int bits = 0;
  for (const char c : text) {
    const char* at = std::strchr("ABCDEFGHIJKLMNOPQRSTUVWXYZabcdefghijklmnopqrstuvwxyz0123456789+/", c);
    if (c == '=' || at == nullptr) break;
    word = (word << 6) | static_cast<std::uint32_t>(
                             at - "ABCDEFGHIJKLMNOPQRSTUVWXYZabcdefghijklmnopqrstuvwxyz0123456789+/");
    bits += 6;
    if (bits >= 8) {
      bits -= 8;
      out.push_back(static_cast<unsigned char>((word >> bits) & 0xff));
    }
  }
  return out;
}

std::vector<float> floats_of(const std::string& text) {
  const std::vector<unsigned char> bytes = from_base64(text);
  std::vector<float> values(bytes.size() / sizeof(float));
  std::memcpy(values.data(), bytes.data(), values.size() * sizeof(float));
  return values;
}

std::size_t occurrences(const std::string& text, const std::string& what) {
  std::size_t n = 0;
  for (std::size_t at = text.find(what); at != std::string::npos; at = text.find(what, at + 1)) ++n;
  return n;
}

class ViewCommand : public ::testing::Test {
 protected:
  static void SetUpTestSuite() {
    fs::remove_all(dir());
    fs::create_directories(data_dir());
    std::ofstream(data_dir() / "viewer.js") << kStandInScript;
    const fs::path arena = fs::path(SARMAP_SOURCE_DIR) / "tests" / "cli" / "data" / "room_with_door.json";
    const auto sim = run_cli("simulate " + quoted(arena.string()) + " --out " + quoted(sequence().string()) +
                                 " --frames 16 --quiet",
                             dir());
    ASSERT_EQ(sim.exit_code, 0) << sim.err;
    const auto r = run_cli("run " + quoted(sequence().string()) + " --out " + quoted(run().string()) +
                               " --classifier labels --quiet",
                           dir());
    ASSERT_EQ(r.exit_code, 0) << r.err;
  }
  static void TearDownTestSuite() { fs::remove_all(dir()); }
  void SetUp() override { ::setenv("SARMAP_DATA_DIR", data_dir().c_str(), 1); }
  void TearDown() override { ::unsetenv("SARMAP_DATA_DIR"); }

  static fs::path dir() {
    return fs::temp_directory_path() / ("sarmap_view_cli_" + std::to_string(::getpid()));
  }
  static fs::path data_dir() { return dir() / "share"; }
  static fs::path sequence() { return dir() / "sequence"; }
  static fs::path run() { return dir() / "run"; }
  static test::CliResult view(const std::string& args) { return run_cli("view " + args, dir()); }

  // The page's data: the JSON of its <script id="sarmap-data"> element.
  static nlohmann::json page_data(const fs::path& page) {
    const std::string html = test::read_all(page);
    const std::string open = "<script id=\"sarmap-data\" type=\"application/json\">";
    const std::size_t start = html.find(open);
    EXPECT_NE(start, std::string::npos);
    const std::size_t end = html.find("</script>", start);
    return nlohmann::json::parse(html.substr(start + open.size(), end - start - open.size()));
  }
};

TEST_F(ViewCommand, WritesOnePageWithEveryLayerOfTheRun) {
  const auto r = view(quoted(run().string()));
  ASSERT_EQ(r.exit_code, 0) << r.err;
  EXPECT_NE(r.out.find("wrote " + (run() / "view.html").string()), std::string::npos) << r.out;
  const std::string html = test::read_all(run() / "view.html");
  EXPECT_EQ(html.rfind("<!doctype html>", 0), 0u);
  // The script is inlined whole, its "</script" escaped: the page's only closers are its two own.
  EXPECT_NE(html.find("window.standIn = '<\\/script><b>';"), std::string::npos);
  EXPECT_EQ(occurrences(html, "</script>"), 2u);

  const nlohmann::json data = page_data(run() / "view.html");
  const nlohmann::json& layers = data.at("layers");
  for (const char* name : {"points", "voxels", "free", "segments", "nodes", "edges", "trajectory"}) {
    ASSERT_TRUE(layers.contains(name)) << name;
    EXPECT_GT(layers[name].at("count").get<std::size_t>(), 0u) << name;
  }
  EXPECT_FALSE(layers.contains("path"));  // the run has no plan

  PointCloudFileInfo info;
  const PointBuffer voxels = read_point_cloud(run() / "voxels.ply", &info);
  EXPECT_EQ(layers["voxels"]["count"], voxels.size());
  EXPECT_EQ(layers["voxels"]["total"], voxels.size());
  EXPECT_DOUBLE_EQ(layers["voxels"]["size"].get<double>(), 0.05);
  const std::vector<float> positions = floats_of(layers["voxels"]["positions"]);
  ASSERT_EQ(positions.size(), 3 * voxels.size());
  for (const std::size_t i : {std::size_t{0}, voxels.size() / 2, voxels.size() - 1}) {
    EXPECT_EQ(positions[3 * i], voxels.x()[i]);
    EXPECT_EQ(positions[3 * i + 1], voxels.y()[i]);
    EXPECT_EQ(positions[3 * i + 2], voxels.z()[i]);
  }
  EXPECT_EQ(layers["points"]["count"], read_point_cloud(run() / "semantic_points.ply").size());
  const auto segments = nlohmann::json::parse(test::read_all(run() / "segments.json"));
  EXPECT_EQ(layers["segments"]["count"], segments["segments"].size());
  const auto graph = nlohmann::json::parse(test::read_all(run() / "graph.json"));
  EXPECT_EQ(layers["nodes"]["count"], graph["nodes"].size());
  EXPECT_EQ(layers["edges"]["count"], graph["links"].size());
  EXPECT_EQ(layers["trajectory"]["count"], 16u);
  EXPECT_EQ(data.at("classes").size(), 6u);

  // Written atomically: no temporary is left beside it.
  for (const auto& entry : fs::directory_iterator(run())) {
    EXPECT_EQ(entry.path().filename().string().find(".tmp."), std::string::npos) << entry.path();
  }
}

TEST_F(ViewCommand, ThinsLayersToMaxPoints) {
  const fs::path page = dir() / "thin.html";
  const auto r = view(quoted(run().string()) + " --max-points 100 --out " + quoted(page.string()));
  ASSERT_EQ(r.exit_code, 0) << r.err;
  const nlohmann::json layers = page_data(page).at("layers");
  for (const char* name : {"points", "voxels"}) {
    EXPECT_EQ(layers[name]["count"], 100u) << name;
    EXPECT_GT(layers[name]["total"].get<std::size_t>(), 100u) << name;
  }
  // Free voxels are thinned on a coarser lattice, so they may fall below the budget.
  EXPECT_GT(layers["free"]["count"].get<std::size_t>(), 0u);
  EXPECT_LE(layers["free"]["count"].get<std::size_t>(), 100u);
  EXPECT_GT(layers["free"]["stride"].get<int>(), 1);
  EXPECT_EQ(floats_of(layers["voxels"]["positions"]).size(), 300u);
  EXPECT_NE(r.out.find("voxels 100 of "), std::string::npos) << r.out;
}

TEST_F(ViewCommand, QuietPrintsNothing) {
  fs::rename(sequence(), dir() / "sequence-moved");  // a note would be printed too
  const fs::path page = dir() / "quiet.html";
  const auto r = view(quoted(run().string()) + " --quiet --out " + quoted(page.string()));
  fs::rename(dir() / "sequence-moved", sequence());
  ASSERT_EQ(r.exit_code, 0) << r.err;
  EXPECT_EQ(r.out, "");
  EXPECT_EQ(r.err, "");
  EXPECT_TRUE(fs::exists(page));
}

TEST_F(ViewCommand, DrawsAPlannedPath) {
  const fs::path path_file = dir() / "path.json";
  std::ofstream(path_file) << R"({"found": true, "graph": "roadmap", "algorithm": "dijkstra", "length": 2.0,
                                  "points": [[0.6, 0.6, 0], [1.6, 0.6, 0], [2.6, 0.6, 0]], "nodes": [0, 1]})";
  const fs::path page = dir() / "path.html";
  auto r = view(quoted(run().string()) + " --path " + quoted(path_file.string()) + " --out " +
                quoted(page.string()));
  ASSERT_EQ(r.exit_code, 0) << r.err;
  const nlohmann::json path = page_data(page).at("layers").at("path");
  EXPECT_EQ(path["count"], 3u);
  EXPECT_EQ(path["graph"], "roadmap");

  std::ofstream(path_file)
      << R"({"found": false, "reason": "unreachable", "graph": "tree", "algorithm": "dijkstra",
                                  "length": 0, "points": [], "nodes": []})";
  r = view(quoted(run().string()) + " --path " + quoted(path_file.string()) + " --out " +
           quoted(page.string()));
  ASSERT_EQ(r.exit_code, 0) << r.err;
  EXPECT_FALSE(page_data(page).at("layers").contains("path"));
  EXPECT_NE(r.out.find("holds no path"), std::string::npos) << r.out;
}

TEST_F(ViewCommand, ABadPathFileLeavesTheOldPageAlone) {
  const fs::path page = dir() / "kept.html";
  ASSERT_EQ(view(quoted(run().string()) + " --out " + quoted(page.string())).exit_code, 0);
  const std::string before = test::read_all(page);
  const fs::path bad = dir() / "bad_path.json";
  std::ofstream(bad) << R"({"found": true, "points": [[1, 2]]})";
  const auto r =
      view(quoted(run().string()) + " --path " + quoted(bad.string()) + " --out " + quoted(page.string()));
  EXPECT_EQ(r.exit_code, 1);
  EXPECT_EQ(r.err.rfind("sarmap: error: ", 0), 0u) << r.err;
  EXPECT_NE(r.err.find(bad.string()), std::string::npos) << r.err;
  EXPECT_EQ(test::read_all(page), before);
}

TEST_F(ViewCommand, LeavesOutTheTrajectoryWhenTheInputIsGone) {
  fs::rename(sequence(), dir() / "sequence-moved");
  const fs::path page = dir() / "no_input.html";
  const auto r = view(quoted(run().string()) + " --out " + quoted(page.string()));
  fs::rename(dir() / "sequence-moved", sequence());
  ASSERT_EQ(r.exit_code, 0) << r.err;
  EXPECT_FALSE(page_data(page).at("layers").contains("trajectory"));
  EXPECT_NE(r.out.find("is gone"), std::string::npos) << r.out;
}

TEST_F(ViewCommand, RefusesWhatIsNoRunFolder) {
  auto r = view(quoted((dir() / "missing").string()));
  EXPECT_EQ(r.exit_code, 1);
  EXPECT_EQ(r.err.rfind("sarmap: error: view: ", 0), 0u) << r.err;
  EXPECT_NE(r.err.find("not found"), std::string::npos) << r.err;

  r = view(quoted((run() / "voxels.ply").string()));
  EXPECT_EQ(r.exit_code, 1);
  EXPECT_NE(r.err.find("is not a folder written by sarmap run"), std::string::npos) << r.err;

  const fs::path empty = dir() / "empty";
  fs::create_directories(empty);
  std::ofstream(empty / "notes.txt") << "not a run\n";
  r = view(quoted(empty.string()));
  EXPECT_EQ(r.exit_code, 1);
  EXPECT_EQ(r.err.rfind("sarmap: error: ", 0), 0u) << r.err;
  EXPECT_NE(r.err.find("manifest.json"), std::string::npos) << r.err;
  EXPECT_FALSE(fs::exists(empty / "view.html"));

  r = view(quoted(run().string()) + " --max-points 0");
  EXPECT_EQ(r.exit_code, 2);  // a value the option refuses is a usage error
  EXPECT_NE(r.err.find("--max-points"), std::string::npos) << r.err;
}

TEST_F(ViewCommand, AMissingViewerScriptSaysHowToBuildIt) {
  const fs::path nowhere = dir() / "no-viewer";
  fs::create_directories(nowhere);
  ::setenv("SARMAP_DATA_DIR", nowhere.c_str(), 1);
  const auto r = view(quoted(run().string()) + " --out " + quoted((dir() / "never.html").string()));
  EXPECT_EQ(r.exit_code, 1);
  EXPECT_EQ(r.err.rfind("sarmap: error: ", 0), 0u) << r.err;
  EXPECT_NE(r.err.find((nowhere / "viewer.js").string()), std::string::npos) << r.err;
  EXPECT_NE(r.err.find("tools/install-deps.sh"), std::string::npos) << r.err;
  EXPECT_FALSE(fs::exists(dir() / "never.html"));
}

}  // namespace
}  // namespace sarmap
