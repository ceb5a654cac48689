// Pictures of what a run wrote (`sarmap render`, `sarmap demo`): the run's
// folder read into voxels and overlays, and the panels composed into one
// picture (metric and semantic 3-D views side by side, the top view below),
// or a strip of snapshots showing the map grow.
#pragma once

#include <filesystem>
#include <span>
#include <vector>

#include "engine/render/rgb_image.hpp"
#include "engine/render/top_view.hpp"
#include "engine/render/voxel_scene.hpp"

namespace sarmap::render {

struct RunContents {
  VoxelSet voxels;
  MapOverlays overlays;
};

// Reads a folder `sarmap run` wrote, after checking it against its manifest
// (verify_run_folder): the occupied voxels of map.sarmap (or, without it, of
// voxels.ply), segments.json and graph.json when present, and the route in
// `path_file` when not empty, else in the folder's path.json when present
// (`sarmap plan RUNDIR --out RUNDIR/path.json`). Throws sarmap::Error naming
// the folder or file: a folder that is not a finished run, a bad file.
RunContents read_run_contents(const std::filesystem::path& run_dir,
                              const std::filesystem::path& path_file = {});

// The size of each panel; the picture is two panels wide and two high.
struct PictureSize {
  int view_width = 1280;
  int view_height = 720;
};

// Top row: the metric view, then the semantic view (oblique_camera of the
// voxels' box); bottom row: the top view with the overlays, centred. Panels
// are separated by a thin grey frame.
RgbImage render_run_picture(const RunContents& run, const PictureSize& size = {});

// The folders a growth strip shows: the run's snap_NNNN folders in scan
// order, then the run itself.
std::vector<std::filesystem::path> growth_folders(const std::filesystem::path& run_dir);

// One column per run, in the order given (a run's snapshots, then the run):
// its metric view above its semantic view, every view from the camera that
// frames the last run, so the map is seen to grow in one place.
RgbImage render_growth_strip(std::span<const RunContents> runs, const PictureSize& size = {640, 360});

// render_growth_strip of the growth_folders of a run folder.
RgbImage render_run_growth(const std::filesystem::path& run_dir, const PictureSize& size = {640, 360});

}  // namespace sarmap::render
