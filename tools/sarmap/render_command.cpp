// `sarmap render RUNDIR [--out PNG] [--width W --height H] [--path path.json]
// [--growth PNG]`: pictures of a run without a browser, ray-cast on the CPU
// (engine/render): the metric and semantic maps side by side in 3-D and the
// top view with segments, graph and path; with --growth, a strip of the
// run's snapshots showing the map grow.
#include <chrono>
#include <cstdio>
#include <filesystem>
#include <memory>
#include <string>
#include <utility>

#include "engine/core/error.hpp"
#include "engine/render/png_file.hpp"
#include "engine/render/run_pictures.hpp"
#include "tools/sarmap/commands.hpp"

namespace sarmap::cli {
namespace {

namespace fs = std::filesystem;

struct RenderArgs {
  std::string run;
  std::string out;  // empty: RUNDIR/render.png
  std::string path;
  std::string growth;
  int width = 1280;
  int height = 720;
  bool quiet = false;
};

void run_render(const RenderArgs& a) {
  const auto start = std::chrono::steady_clock::now();
  const fs::path run = a.run;
  const fs::path out = a.out.empty() ? run / "render.png" : fs::path(a.out);
  // Refused before any drawing, naming the option, rather than by the
  // atomic writer after it.
  for (const auto& [flag, file] : {std::pair{"--out", out}, {"--growth", fs::path(a.growth)}}) {
    if (file.empty()) continue;
    const fs::path folder = file.parent_path().empty() ? fs::path(".") : file.parent_path();
    if (!fs::is_directory(folder)) {
      throw Error(ErrorCode::Io, std::string("render: ") + flag + " " + file.string() + ": folder " +
                                     folder.string() + " does not exist");
    }
    if (fs::is_directory(file)) {
      throw Error(ErrorCode::Io, std::string("render: ") + flag + " " + file.string() + " is a folder");
    }
  }
  const render::PictureSize size{a.width, a.height};
  // Everything is read and drawn before the first file is written, and each
  // file is written atomically: an error leaves no half picture.
  const render::RgbImage picture = render::render_run_picture(render::read_run_contents(run, a.path), size);
  render::RgbImage growth;
  if (!a.growth.empty()) growth = render::render_run_growth(run, {a.width / 2, a.height / 2});
  render::write_png(picture, out);
  if (!a.growth.empty()) render::write_png(growth, a.growth);
  if (a.quiet) return;
  const double seconds = std::chrono::duration<double>(std::chrono::steady_clock::now() - start).count();
  std::printf("rendered %s (%d x %d)%s in %.2f s\n", out.string().c_str(), picture.width(), picture.height(),
              a.growth.empty() ? "" : (" and " + a.growth).c_str(), seconds);
}

}  // namespace

void add_render_command(CLI::App& app) {
  auto args = std::make_shared<RenderArgs>();
  CLI::App* cmd = app.add_subcommand("render",
                                     "Draw a run's maps into a PNG: metric and semantic in 3-D, and a top "
                                     "view with segments, graph and path");
  cmd->add_option("RUNDIR", args->run, "Folder written by `sarmap run`")->required();
  cmd->add_option("--out", args->out, "The picture (PNG; default RUNDIR/render.png)");
  cmd->add_option("--width", args->width, "Width of each view in pixels")
      ->capture_default_str()
      ->check(CLI::Range(16, render::kMaxImageSide / 2));
  cmd->add_option("--height", args->height, "Height of each view in pixels")
      ->capture_default_str()
      ->check(CLI::Range(16, render::kMaxImageSide / 2));
  cmd->add_option("--path", args->path,
                  "A route to draw (sarmap plan --out); default RUNDIR/path.json when present");
  cmd->add_option(
      "--growth", args->growth,
      "Also a PNG strip of the run's snap_NNNN folders and the run (sarmap run --snapshots), at half size");
  cmd->add_flag("--quiet", args->quiet, "Print nothing");
  cmd->callback([args] { run_render(*args); });
}

}  // namespace sarmap::cli
