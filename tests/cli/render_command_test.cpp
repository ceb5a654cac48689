// `sarmap render` on a run of a small simulated room: the picture's layout and
// what it shows read back with libpng, a route drawn, the growth strip of the
// run's snapshots, and errors (no RUNDIR, not a run, unwritable --out) that
// leave no file behind.
#include <gtest/gtest.h>
#include <png.h>
#include <unistd.h>

#include <filesystem>
#include <fstream>
#include <string>
#include <vector>

#include "tests/cli/cli_runner.hpp"

namespace sarmap {
namespace {

namespace fs = std::filesystem;
using test::quoted;
using test::run_cli;

struct Picture {
  int width = 0, height = 0;
  std::vector<std::uint8_t> rgb;
  // Pixels of exactly this colour in the rectangle [x0, x1) x [y0, y1).
  int count(std::uint8_t r, std::uint8_t g, std::uint8_t b, int x0, int y0, int x1, int y1) const {
    int n = 0;
    for (int y = y0; y < y1; ++y) {
      for (int x = x0; x < x1; ++x) {
        const std::size_t i = 3 * (static_cast<std::size_t>(y) * static_cast<std::size_t>(width) + x);
        n += rgb[i] == r && rgb[i + 1] == g && rgb[i + 2] == b ? 1 : 0;
      }
    }
    return n;
  }
};

Picture read_png(const fs::path& path) {
  png_image image{};
  image.version = PNG_IMAGE_VERSION;
  Picture p;
  if (!png_image_begin_read_from_file(&image, path.c_str())) {
    ADD_FAILURE() << path << ": " << image.message;
    return p;
  }
  image.format = PNG_FORMAT_RGB;
  p.width = static_cast<int>(image.width);
  p.height = static_cast<int>(image.height);
  p.rgb.resize(PNG_IMAGE_SIZE(image));
  if (!png_image_finish_read(&image, nullptr, p.rgb.data(), 0, nullptr)) ADD_FAILURE() << image.message;
  return p;
}

class RenderCommand : public ::testing::Test {
 protected:
  static void SetUpTestSuite() {
    fs::remove_all(dir());
    fs::create_directories(dir());
    const fs::path arena = fs::path(SARMAP_SOURCE_DIR) / "tests" / "cli" / "data" / "room_with_door.json";
    const auto sim = run_cli(
        "simulate " + quoted(arena.string()) + " --out " + quoted((dir() / "seq").string()) + " --quiet",
        dir());
    ASSERT_EQ(sim.exit_code, 0) << sim.err;
    const auto r = run_cli("run " + quoted((dir() / "seq").string()) + " --out " + quoted(run().string()) +
                               " --classifier labels --snapshots 16,32 --quiet",
                           dir());
    ASSERT_EQ(r.exit_code, 0) << r.err;
  }
  static void TearDownTestSuite() { fs::remove_all(dir()); }
  static fs::path dir() {
    return fs::temp_directory_path() / ("sarmap_render_cli_" + std::to_string(::getpid()));
  }
  static fs::path run() { return dir() / "run"; }
  static test::CliResult render(const std::string& args) { return run_cli("render " + args, dir()); }
  // Regular files in a folder whose name starts with a dot: temporaries.
  static int hidden_files(const fs::path& folder) {
    int n = 0;
    for (const auto& e : fs::directory_iterator(folder))
      n += e.path().filename().string()[0] == '.' && e.is_regular_file();
    return n;
  }
};

constexpr int kW = 160, kH = 90, kGap = 4;

TEST_F(RenderCommand, DrawsBothMapsInThreeDAndTheTopView) {
  const fs::path out = dir() / "picture.png";
  const auto r =
      render(quoted(run().string()) + " --out " + quoted(out.string()) + " --width 160 --height 90");
  ASSERT_EQ(r.exit_code, 0) << r.err;
  EXPECT_NE(r.out.find("rendered"), std::string::npos) << r.out;
  const Picture p = read_png(out);
  ASSERT_EQ(p.width, 2 * kW + 3 * kGap);
  ASSERT_EQ(p.height, 2 * kH + 3 * kGap);
  const int panel = kW * kH;
  // Each panel shows the map: far from all white.
  const int metric_white = p.count(255, 255, 255, kGap, kGap, kGap + kW, kGap + kH);
  const int semantic_white = p.count(255, 255, 255, 2 * kGap + kW, kGap, 2 * kGap + 2 * kW, kGap + kH);
  const int top_x = (p.width - kW) / 2, top_y = 2 * kGap + kH;
  const int top_white = p.count(255, 255, 255, top_x, top_y, top_x + kW, top_y + kH);
  EXPECT_LT(metric_white, panel * 9 / 10);
  EXPECT_LT(semantic_white, panel * 9 / 10);
  EXPECT_LT(top_white, panel * 9 / 10);
  // The two 3-D views see the same voxels from the same camera.
  EXPECT_EQ(metric_white, semantic_white);
  // The semantic view shows the floor (terrain, its top in the exact class
  // colour) and the walls; the top view's nodes are in terrain yellow too.
  EXPECT_GT(p.count(230, 200, 20, 2 * kGap + kW, kGap, 2 * kGap + 2 * kW, kGap + kH), 50);
  EXPECT_GT(p.count(230, 200, 20, top_x, top_y, top_x + kW, top_y + kH), 5);
  EXPECT_EQ(hidden_files(dir()), 0);
}

TEST_F(RenderCommand, DrawsTheRouteInTheRunFolderOrGiven) {
  const fs::path route = dir() / "route.json";
  const auto plan =
      run_cli("plan " + quoted(run().string()) + " --from 0.6,0.6,0 --to 3.4,2.4,0 --graph roadmap --out " +
                  quoted(route.string()) + " --quiet",
              dir());
  ASSERT_EQ(plan.exit_code, 0) << plan.err;
  const fs::path without = dir() / "without.png", with = dir() / "with.png";
  ASSERT_EQ(render(quoted(run().string()) + " --out " + quoted(without.string()) +
                   " --width 160 --height 90 --quiet")
                .exit_code,
            0);
  const auto r = render(quoted(run().string()) + " --out " + quoted(with.string()) +
                        " --width 160 --height 90 --quiet --path " + quoted(route.string()));
  ASSERT_EQ(r.exit_code, 0) << r.err;
  const Picture a = read_png(without), b = read_png(with);
  // The path's green appears in the top view only when a route is drawn.
  EXPECT_EQ(a.count(0, 170, 60, 0, 0, a.width, a.height), 0);
  EXPECT_GT(b.count(0, 170, 60, 0, kGap + kH, b.width, b.height), 20);
  EXPECT_EQ(b.count(0, 170, 60, 0, 0, b.width, kGap + kH), 0);
  // The same route as the run folder's path.json is drawn without --path.
  fs::copy_file(route, run() / "path.json");
  const fs::path in_folder = dir() / "in_folder.png";
  const auto f = render(quoted(run().string()) + " --out " + quoted(in_folder.string()) +
                        " --width 160 --height 90 --quiet");
  fs::remove(run() / "path.json");
  ASSERT_EQ(f.exit_code, 0) << f.err;
  EXPECT_EQ(read_png(in_folder).rgb, b.rgb);
  // A route file that is not one is an error naming it.
  const fs::path bad = dir() / "bad_route.json";
  { std::ofstream(bad) << "{\"found\": true}"; }
  const auto e = render(quoted(run().string()) + " --out " + quoted((dir() / "bad.png").string()) +
                        " --path " + quoted(bad.string()));
  EXPECT_EQ(e.exit_code, 1);
  EXPECT_NE(e.err.find("sarmap: error: "), std::string::npos) << e.err;
  EXPECT_NE(e.err.find("bad_route.json"), std::string::npos) << e.err;
  EXPECT_FALSE(fs::exists(dir() / "bad.png"));
}

TEST_F(RenderCommand, GrowthStripHasAColumnPerSnapshotAndTheRun) {
  const fs::path out = dir() / "p.png", growth = dir() / "growth.png";
  const auto r = render(quoted(run().string()) + " --out " + quoted(out.string()) + " --growth " +
                        quoted(growth.string()) + " --width 160 --height 90 --quiet");
  ASSERT_EQ(r.exit_code, 0) << r.err;
  const Picture g = read_png(growth);
  // snap_0016, snap_0032 and the run, each view at half size.
  EXPECT_EQ(g.width, 3 * (kW / 2 + kGap) + kGap);
  EXPECT_EQ(g.height, 2 * (kH / 2) + 3 * kGap);
  // The map grows: the first column shows less of it than the last.
  const int first = g.count(255, 255, 255, kGap, kGap, kGap + kW / 2, kGap + kH / 2);
  const int last_x = kGap + 2 * (kW / 2 + kGap);
  const int last = g.count(255, 255, 255, last_x, kGap, last_x + kW / 2, kGap + kH / 2);
  EXPECT_GT(first, last);
}

TEST_F(RenderCommand, ErrorsLeaveNoFileBehind) {
  auto r = render("");
  EXPECT_EQ(r.exit_code, 2);
  EXPECT_NE(r.err.find("sarmap: error: "), std::string::npos) << r.err;
  EXPECT_NE(r.err.find("RUNDIR"), std::string::npos) << r.err;

  // A folder that is not a run.
  const fs::path empty = dir() / "empty";
  fs::create_directories(empty);
  r = render(quoted(empty.string()) + " --out " + quoted((empty / "x.png").string()));
  EXPECT_EQ(r.exit_code, 1);
  EXPECT_NE(r.err.find("sarmap: error: "), std::string::npos) << r.err;
  EXPECT_NE(r.err.find("not a finished run folder"), std::string::npos) << r.err;
  EXPECT_TRUE(fs::is_empty(empty));
  r = render(quoted((dir() / "no_such_run").string()));
  EXPECT_EQ(r.exit_code, 1);
  EXPECT_NE(r.err.find("no_such_run"), std::string::npos) << r.err;

  // An --out whose folder does not exist, and one that is a folder.
  r = render(quoted(run().string()) + " --out " + quoted((dir() / "missing" / "x.png").string()) +
             " --width 32 --height 32");
  EXPECT_EQ(r.exit_code, 1);
  EXPECT_NE(r.err.find("sarmap: error: "), std::string::npos) << r.err;
  EXPECT_NE(r.err.find("does not exist"), std::string::npos) << r.err;
  EXPECT_FALSE(fs::exists(dir() / "missing"));
  fs::create_directories(dir() / "taken.png");
  r = render(quoted(run().string()) + " --out " + quoted((dir() / "taken.png").string()) +
             " --width 32 --height 32");
  EXPECT_EQ(r.exit_code, 1);
  EXPECT_NE(r.err.find("sarmap: error: "), std::string::npos) << r.err;
  EXPECT_NE(r.err.find("is a folder"), std::string::npos) << r.err;
  EXPECT_TRUE(fs::is_directory(dir() / "taken.png"));
  EXPECT_EQ(hidden_files(dir()), 0);

  // Sizes a picture cannot have are usage errors.
  r = render(quoted(run().string()) + " --width 0");
  EXPECT_EQ(r.exit_code, 2);
  EXPECT_NE(r.err.find("--width"), std::string::npos) << r.err;
}

}  // namespace
}  // namespace sarmap
