// `sarmap eval` segment figures on a real run: the tiny arena simulated
// noise-free, built by `sarmap run --classifier labels`, its segments.json
// scored against the arena's faces, in --json and in the table.
#include <gtest/gtest.h>

#include <nlohmann/json.hpp>

#include "engine/io/run_folder.hpp"
#include "tests/sim/run_cli.hpp"

namespace sarmap::eval {
namespace {

TEST(SegmentEvalCli, FiguresOfASimulatedRun) {
  const auto dir = testing::scratch_dir("segment_eval_cli");
  const std::string arena = SARMAP_SOURCE_DIR "/tests/cli/data/tiny_arena.json";
  const std::string seq = (dir / "seq").string(), run = (dir / "run").string();
  auto r = testing::run_cli("simulate " + arena + " --out " + seq + " --quiet", dir);
  ASSERT_EQ(r.exit_code, 0) << r.err;
  r = testing::run_cli("run " + seq + " --out " + run + " --classifier labels --quiet", dir);
  ASSERT_EQ(r.exit_code, 0) << r.err;
  r = testing::run_cli("eval --arena " + arena + " --run " + run + " --json", dir);
  ASSERT_EQ(r.exit_code, 0) << r.err;
  const auto j = nlohmann::json::parse(r.out);
  EXPECT_EQ(j.at("files").at("segments.json").get<bool>(), true);
  const auto& s = j.at("segments");
  // The floor, the wall's two faces and the platform's top.
  EXPECT_EQ(s.at("counted").get<int>(), 4);
  EXPECT_GE(s.at("segment_count").get<int>(), 1);
  EXPECT_GE(s.at("matched").get<int>(), 1);
  EXPECT_LE(s.at("missed").get<int>(), s.at("seen").get<int>());
  ASSERT_FALSE(s.at("max_normal_error_deg").is_null());
  // Noise-free points: the planes are right to well under a degree and a centimetre.
  EXPECT_LT(s.at("max_normal_error_deg").get<double>(), 1.0);
  EXPECT_LT(s.at("max_offset_error_m").get<double>(), 0.01);
  std::size_t counted = 0;
  for (const auto& f : s.at("faces")) counted += f.at("counted").get<bool>();
  EXPECT_EQ(counted, 4u);

  r = testing::run_cli("eval --arena " + arena + " --run " + run, dir);
  ASSERT_EQ(r.exit_code, 0) << r.err;
  EXPECT_NE(r.out.find("planar segments:"), std::string::npos) << r.out;
  EXPECT_NE(r.out.find("platform_top"), std::string::npos) << r.out;

  // segments.json gone from a finished run: the folder is no longer the set
  // its manifest lists, and eval refuses it naming the file.
  std::filesystem::remove(dir / "run" / "segments.json");
  r = testing::run_cli("eval --arena " + arena + " --run " + run, dir);
  EXPECT_EQ(r.exit_code, 1);
  EXPECT_NE(r.err.find("segments.json: listed in manifest.json but missing"), std::string::npos) << r.err;

  // A set that never had segments.json: a note, no figures.
  RunFolderWriter(dir / "run").commit(nlohmann::ordered_json::object(), {"map.sarmap", "semantic_points.ply"});
  r = testing::run_cli("eval --arena " + arena + " --run " + run + " --json", dir);
  ASSERT_EQ(r.exit_code, 0) << r.err;
  const auto k = nlohmann::json::parse(r.out);
  EXPECT_FALSE(k.contains("segments"));
  EXPECT_NE(k.at("notes").dump().find("segments.json absent"), std::string::npos) << k.at("notes");
  std::filesystem::remove_all(dir);
}

}  // namespace
}  // namespace sarmap::eval
