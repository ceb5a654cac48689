// Where `sarmap` finds its shipped model and default arena
// (tools/sarmap/shipped_data.cpp): the build-tree binary in the source tree's
// datasets/, any other copy only beside itself in ../share/sarmap/, and
// SARMAP_DATA_DIR instead of both. tests/install_package.cmake checks a real
// install.
#include <gtest/gtest.h>
#include <unistd.h>

#include <cstdlib>
#include <filesystem>
#include <string>

#include <nlohmann/json.hpp>

#include "tests/cli/cli_runner.hpp"

namespace sarmap {
namespace {

namespace fs = std::filesystem;
using test::quoted;

const fs::path kSourceDatasets = fs::path(SARMAP_SOURCE_DIR) / "datasets";
const fs::path kModel = fs::path("models") / "ramps-dgcnn.safetensors";

class ShippedData : public ::testing::Test {
 protected:
  void SetUp() override {
    ::unsetenv("SARMAP_DATA_DIR");
    fs::remove_all(dir_);
    fs::create_directories(dir_);
  }
  void TearDown() override {
    ::unsetenv("SARMAP_DATA_DIR");
    fs::remove_all(dir_);
  }
  // `sarmap run` on the two-scan sequence with the default classifier, the DGCNN without --model.
  test::CliResult run(const fs::path& binary, const std::string& out) {
    return test::run_binary(binary,
                            "run " + quoted(std::string(SARMAP_TEST_DATA_DIR) + "/sequences/tiny") +
                                " --out " + quoted((dir_ / out).string()) + " --quiet",
                            dir_);
  }
  fs::path model_used(const std::string& out) {
    const auto manifest = nlohmann::json::parse(test::read_all(dir_ / out / "manifest.json"));
    return manifest.at("config").at("classifier").at("model").get<std::string>();
  }
  // A copy of the built binary in DIR/bin/, as an install would place it.
  fs::path copied_binary() {
    fs::create_directories(dir_ / "bin");
    fs::path copy = dir_ / "bin" / "sarmap";
    fs::copy_file(SARMAP_CLI_PATH, copy);
    return copy;
  }
  fs::path dir_ = fs::temp_directory_path() / ("sarmap_shipped_data_" + std::to_string(::getpid()));
};

TEST_F(ShippedData, TheBuildTreeBinaryUsesTheSourceTree) {
  const auto r = run(SARMAP_CLI_PATH, "run");
  ASSERT_EQ(r.exit_code, 0) << r.err;
  EXPECT_TRUE(fs::equivalent(model_used("run"), kSourceDatasets / kModel));
}

TEST_F(ShippedData, ACopyLooksBesideItselfAndNeverInTheSourceTree) {
  const fs::path binary = copied_binary();
  auto r = run(binary, "run");
  EXPECT_EQ(r.exit_code, 1);
  EXPECT_NE(r.err.find("sarmap: error: the shipped models/ramps-dgcnn.safetensors was not found"),
            std::string::npos)
      << r.err;
  EXPECT_NE(r.err.find((dir_ / "share" / "sarmap" / kModel).string()), std::string::npos) << r.err;
  EXPECT_NE(r.err.find("SARMAP_DATA_DIR"), std::string::npos) << r.err;
  EXPECT_EQ(r.err.find(kSourceDatasets.string()), std::string::npos) << r.err;

  r = test::run_binary(binary, "demo --out " + quoted((dir_ / "demo").string()), dir_);
  EXPECT_EQ(r.exit_code, 1);
  EXPECT_NE(r.err.find((dir_ / "share" / "sarmap" / "arenas" / "esogu-6x4.json").string()), std::string::npos)
      << r.err;
  EXPECT_NE(r.err.find("--arena"), std::string::npos) << r.err;

  // The install layout: bin/sarmap finds ../share/sarmap/models/.
  fs::create_directories(dir_ / "share" / "sarmap" / "models");
  fs::create_symlink(kSourceDatasets / kModel, dir_ / "share" / "sarmap" / kModel);
  r = run(binary, "run2");
  ASSERT_EQ(r.exit_code, 0) << r.err;
  EXPECT_EQ(model_used("run2"), dir_ / "share" / "sarmap" / kModel);
}

TEST_F(ShippedData, SarmapDataDirIsTheOnlyPlaceLookedWhenSet) {
  ::setenv("SARMAP_DATA_DIR", (dir_ / "nowhere").c_str(), 1);
  auto r = run(SARMAP_CLI_PATH, "run");
  EXPECT_EQ(r.exit_code, 1);
  EXPECT_NE(r.err.find((dir_ / "nowhere" / kModel).string() + ", from SARMAP_DATA_DIR"), std::string::npos)
      << r.err;
  EXPECT_EQ(r.err.find(kSourceDatasets.string()), std::string::npos) << r.err;

  fs::create_directories(dir_ / "data" / "models");
  fs::create_symlink(kSourceDatasets / kModel, dir_ / "data" / kModel);
  ::setenv("SARMAP_DATA_DIR", (dir_ / "data").c_str(), 1);
  r = run(SARMAP_CLI_PATH, "run2");
  ASSERT_EQ(r.exit_code, 0) << r.err;
  EXPECT_EQ(model_used("run2"), dir_ / "data" / kModel);
}

}  // namespace
}  // namespace sarmap
