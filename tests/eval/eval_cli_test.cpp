// Tests of `sarmap eval` on a tiny synthetic run folder.
#include <gtest/gtest.h>

#include <nlohmann/json.hpp>

#include "engine/io/ply.hpp"
#include "engine/io/run_folder.hpp"
#include "tests/sim/run_cli.hpp"

namespace sarmap::eval {
namespace {

TEST(EvalCli, JsonFiguresOfASyntheticRun) {
  const auto dir = testing::scratch_dir("eval_cli");
  std::filesystem::create_directories(dir / "run");
  // 3 terrain right, 1 wall right, 1 flat ramp taken for terrain, 1 unlabelled.
  PointBuffer p(6);
  p.enable_labels();
  p.enable_gt_labels();
  const std::uint8_t predicted[] = {1, 1, 1, 2, 1, 0};
  const std::uint8_t truth[] = {1, 1, 1, 2, 4, 3};
  for (std::size_t i = 0; i < 6; ++i) {
    p.labels()[i] = predicted[i];
    p.gt_labels()[i] = truth[i];
  }
  {
    RunFolderWriter folder(dir / "run");
    write_ply(dir / "run" / "semantic_points.ply", p);
    folder.commit(nlohmann::ordered_json::object(), {"semantic_points.ply"});
  }
  const std::string arena = SARMAP_SOURCE_DIR "/datasets/arenas/esogu-6x4.json";
  const auto r = testing::run_cli("eval --arena " + arena + " --run " + (dir / "run").string() + " --json", dir);
  ASSERT_EQ(r.exit_code, 0) << r.err;
  const auto j = nlohmann::json::parse(r.out);
  EXPECT_DOUBLE_EQ(j.at("accuracy").get<double>(), 4.0 / 6.0);
  EXPECT_DOUBLE_EQ(j.at("per_class_iou").at("terrain").get<double>(), 3.0 / 4.0);
  EXPECT_DOUBLE_EQ(j.at("per_class_iou").at("wall").get<double>(), 1.0);
  EXPECT_DOUBLE_EQ(j.at("mean_iou").get<double>(), (0.75 + 1.0 + 0.0 + 0.0) / 4.0);
  EXPECT_EQ(j.at("arena").get<std::string>(), "esogu-6x4");
  // The table form, and a run folder that does not exist.
  const auto table = testing::run_cli("eval --arena " + arena + " --run " + (dir / "run").string(), dir);
  EXPECT_EQ(table.exit_code, 0);
  EXPECT_NE(table.out.find("mean IoU"), std::string::npos) << table.out;
  const auto missing = testing::run_cli("eval --arena " + arena + " --run " + (dir / "nope").string(), dir);
  EXPECT_EQ(missing.exit_code, 1);
  EXPECT_NE(missing.err.find("run folder not found"), std::string::npos) << missing.err;
  std::filesystem::remove_all(dir);
}

}  // namespace
}  // namespace sarmap::eval
