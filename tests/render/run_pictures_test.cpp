// Tests of engine/render/run_pictures.hpp on folders made here: the voxels
// read from voxels.ply when a folder has no map.sarmap, the overlays a
// folder lacks left out, the panels' layout, and folders that are not runs.
#include "engine/render/run_pictures.hpp"

#include <gtest/gtest.h>
#include <unistd.h>

#include <filesystem>
#include <string>

#include "engine/core/error.hpp"
#include "engine/core/point_buffer.hpp"
#include "engine/io/point_cloud_file.hpp"
#include "engine/io/run_folder.hpp"
#include "engine/render/voxel_views.hpp"

namespace sarmap::render {
namespace {

namespace fs = std::filesystem;

class RunPictures : public ::testing::Test {
 protected:
  void SetUp() override {
    dir_ = fs::temp_directory_path() / ("sarmap_run_pictures_" + std::to_string(::getpid()));
    fs::remove_all(dir_);
  }
  void TearDown() override { fs::remove_all(dir_); }

  // A run folder holding only voxels.ply: a 10 x 10 floor of 0.1 m terrain
  // voxels with one wall voxel on it, committed with its manifest.
  void write_voxels_only_run(const std::vector<std::string>& comments = {"voxel_size 0.1"}) {
    RunFolderWriter writer(dir_);
    PointBuffer cloud;
    cloud.enable_labels();
    for (int x = 0; x < 10; ++x) {
      for (int y = 0; y < 10; ++y) {
        cloud.push_back(0.05f + 0.1f * x, 0.05f + 0.1f * y, 0.05f);
        cloud.labels().back() = static_cast<std::uint8_t>(ClassId::Terrain);
      }
    }
    cloud.push_back(0.55f, 0.55f, 0.15f);
    cloud.labels().back() = static_cast<std::uint8_t>(ClassId::Wall);
    PointCloudWriteOptions options;
    options.comments = comments;
    write_point_cloud(writer.path_of("voxels.ply"), cloud, options);
    writer.commit({{"version", 1}}, {"voxels.ply"});
  }
  fs::path dir_;
};

TEST_F(RunPictures, ReadsVoxelsPlyWhenTheRunHasNoMapFile) {
  write_voxels_only_run();
  const RunContents run = read_run_contents(dir_);
  EXPECT_FLOAT_EQ(run.voxels.voxel, 0.1f);
  ASSERT_EQ(run.voxels.centres.size(), 101u);
  EXPECT_EQ(run.voxels.labels.back(), ClassId::Wall);
  EXPECT_TRUE(run.overlays.segments.empty());
  EXPECT_TRUE(run.overlays.nodes.empty());
  EXPECT_TRUE(run.overlays.path.empty());

  const RgbImage picture = render_run_picture(run, {64, 48});
  ASSERT_EQ(picture.width(), 2 * 64 + 12);
  ASSERT_EQ(picture.height(), 2 * 48 + 12);
  // The top view, centred in the bottom row: the wall voxel at the floor's
  // centre in washed-out red, the floor around it in washed-out yellow.
  const Rgb centre = picture.at(picture.width() / 2, 4 + 48 + 4 + 24);
  EXPECT_GT(centre.r, centre.g);
  EXPECT_GT(centre.r, centre.b);
  const Rgb floor = picture.at(picture.width() / 2 - 12, 4 + 48 + 4 + 24);
  EXPECT_GT(floor.g, floor.b);
}

TEST_F(RunPictures, FoldersThatAreNotRunsAreRefused) {
  EXPECT_THROW(read_run_contents(dir_), Error);  // absent
  fs::create_directories(dir_);
  try {
    read_run_contents(dir_);
    FAIL() << "accepted";
  } catch (const Error& e) {
    EXPECT_NE(std::string(e.what()).find("not a finished run folder"), std::string::npos) << e.what();
  }
  fs::remove_all(dir_);
  write_voxels_only_run({});  // voxels.ply without its voxel size
  try {
    read_run_contents(dir_);
    FAIL() << "accepted";
  } catch (const Error& e) {
    EXPECT_NE(std::string(e.what()).find("voxel_size"), std::string::npos) << e.what();
  }
}

TEST_F(RunPictures, TheGrowthStripIsAColumnPerRun) {
  write_voxels_only_run();
  const RunContents run = read_run_contents(dir_);
  const std::vector<RunContents> runs{run, run, run};
  const RgbImage strip = render_growth_strip(runs, {40, 30});
  EXPECT_EQ(strip.width(), 3 * (40 + 4) + 4);
  EXPECT_EQ(strip.height(), 2 * 30 + 12);
  EXPECT_THROW(render_growth_strip({}, {40, 30}), Error);
  EXPECT_EQ(growth_folders(dir_), std::vector<fs::path>{dir_});
}

}  // namespace
}  // namespace sarmap::render
