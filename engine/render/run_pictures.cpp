#include "engine/render/run_pictures.hpp"

#include <algorithm>
#include <cmath>
#include <optional>
#include <string>

#include "engine/core/error.hpp"
#include "engine/io/point_cloud_file.hpp"
#include "engine/io/run_folder.hpp"
#include "engine/metric/map_file.hpp"
#include "engine/metric/voxel_cloud.hpp"
#include "engine/render/camera.hpp"
#include "engine/render/voxel_views.hpp"
#include "engine/segments/segment_files.hpp"
#include "engine/topo/graph_files.hpp"

namespace sarmap::render {
namespace {

namespace fs = std::filesystem;

constexpr Rgb kFrame{200, 200, 200};
constexpr int kGap = 4;  // pixels between panels

VoxelSet voxels_of(const PointBuffer& cloud, float voxel) {
  VoxelSet set;
  set.voxel = voxel;
  set.centres.reserve(cloud.size());
  set.labels.reserve(cloud.size());
  for (std::size_t i = 0; i < cloud.size(); ++i) {
    set.centres.emplace_back(cloud.x()[i], cloud.y()[i], cloud.z()[i]);
    const auto label = cloud.has_labels() ? class_from_value(cloud.labels()[i]) : std::nullopt;
    set.labels.push_back(label.value_or(ClassId::Unknown));
  }
  return set;
}

// voxels.ply names its voxel edge in a header comment ("voxel_size 0.05").
float voxel_size_of(const PointCloudFileInfo& info, const fs::path& file) {
  for (const std::string& comment : info.comments) {
    constexpr std::string_view key = "voxel_size ";
    if (comment.rfind(key, 0) != 0) continue;
    try {
      const double size = std::stod(comment.substr(key.size()));
      if (size > 0 && std::isfinite(size)) return static_cast<float>(size);
    } catch (const std::exception&) {
    }
  }
  throw Error(ErrorCode::InvalidData, file.string() + ": no \"voxel_size\" comment in the header");
}

VoxelSet read_voxels(const fs::path& run_dir) {
  const fs::path map_file = run_dir / "map.sarmap";
  if (fs::is_regular_file(map_file)) {
    const metric::MetricMap map = metric::load_map(map_file);
    return voxels_of(metric::occupied_voxel_cloud(map), static_cast<float>(map.resolution()));
  }
  const fs::path cloud_file = run_dir / "voxels.ply";
  if (!fs::is_regular_file(cloud_file)) {
    throw Error(ErrorCode::Io, run_dir.string() + ": neither map.sarmap nor voxels.ply is there to draw");
  }
  PointCloudFileInfo info;
  const PointBuffer cloud = read_point_cloud(cloud_file, &info);
  return voxels_of(cloud, voxel_size_of(info, cloud_file));
}

void frame(RgbImage& picture, int x0, int y0, int width, int height) {
  for (int x = x0 - 1; x <= x0 + width; ++x) {
    for (const int y : {y0 - 1, y0 + height}) {
      if (picture.contains(x, y)) picture.set(x, y, kFrame);
    }
  }
  for (int y = y0 - 1; y <= y0 + height; ++y) {
    for (const int x : {x0 - 1, x0 + width}) {
      if (picture.contains(x, y)) picture.set(x, y, kFrame);
    }
  }
}

void place(RgbImage& picture, const RgbImage& panel, int x0, int y0) {
  picture.paste(panel, x0, y0);
  frame(picture, x0, y0, panel.width(), panel.height());
}

HeightRange heights_of(const Box3& box) { return {box.min.z(), box.max.z()}; }

// Before any ray is cast, so a bad size costs nothing.
void check_size(const PictureSize& size) { check_image_size(size.view_width, size.view_height); }

}  // namespace

RunContents read_run_contents(const fs::path& run_dir, const fs::path& path_file) {
  if (!fs::is_directory(run_dir)) throw Error(ErrorCode::Io, run_dir.string() + ": not a folder");
  if (!fs::is_regular_file(run_dir / "manifest.json")) {
    throw Error(
        ErrorCode::InvalidData,
        run_dir.string() + ": not a finished run folder (no manifest.json; write one with sarmap run)");
  }
  verify_run_folder(run_dir);
  RunContents run;
  run.voxels = read_voxels(run_dir);
  if (fs::is_regular_file(run_dir / "segments.json")) {
    run.overlays.segments = segments::read_segments_json(run_dir / "segments.json").segments;
  }
  if (fs::is_regular_file(run_dir / "graph.json")) {
    topo::GraphFile graph = topo::read_graph_json(run_dir / "graph.json");
    run.overlays.nodes = std::move(graph.nodes);
    run.overlays.edges = std::move(graph.edges);
  }
  const fs::path route_file = !path_file.empty() ? path_file : run_dir / "path.json";
  if (!path_file.empty() || fs::is_regular_file(route_file)) {
    const topo::Route route = topo::read_route_json(route_file);
    if (route.found) run.overlays.path = route.points;
  }
  return run;
}

RgbImage render_run_picture(const RunContents& run, const PictureSize& size) {
  check_size(size);
  const int w = size.view_width, h = size.view_height;
  const VoxelScene scene(run.voxels);
  const Box3 box = voxel_bounds(run.voxels);
  const VoxelViews views = render_voxel_views(scene, run.voxels, oblique_camera(box, w, h), heights_of(box));
  const RgbImage top = render_top_view(scene, run.voxels, top_down_camera(box, w, h), run.overlays);
  RgbImage picture(2 * w + 3 * kGap, 2 * h + 3 * kGap, kBackground);
  place(picture, views.metric, kGap, kGap);
  place(picture, views.semantic, w + 2 * kGap, kGap);
  place(picture, top, (picture.width() - w) / 2, h + 2 * kGap);
  return picture;
}

std::vector<fs::path> growth_folders(const fs::path& run_dir) {
  std::vector<fs::path> folders;
  if (fs::is_directory(run_dir)) {
    for (const fs::directory_entry& entry : fs::directory_iterator(run_dir)) {
      const std::string name = entry.path().filename().string();
      if (entry.is_directory() && name.rfind("snap_", 0) == 0) folders.push_back(entry.path());
    }
  }
  // snap_NNNN names are zero-padded, but a count past 9999 scans is longer:
  // shorter names first, then by name, is scan order.
  std::sort(folders.begin(), folders.end(), [](const fs::path& a, const fs::path& b) {
    const std::string x = a.filename().string(), y = b.filename().string();
    return x.size() != y.size() ? x.size() < y.size() : x < y;
  });
  folders.push_back(run_dir);
  return folders;
}

RgbImage render_growth_strip(std::span<const RunContents> runs, const PictureSize& size) {
  check_size(size);
  if (runs.empty()) throw Error(ErrorCode::InvalidArgument, "render_growth_strip: no runs to draw");
  const int w = size.view_width, h = size.view_height;
  const Box3 box = voxel_bounds(runs.back().voxels);
  const Camera camera = oblique_camera(box, w, h);
  const auto columns = static_cast<int>(runs.size());
  RgbImage picture(columns * (w + kGap) + kGap, 2 * h + 3 * kGap, kBackground);
  for (int i = 0; i < columns; ++i) {
    const RunContents& run = runs[static_cast<std::size_t>(i)];
    const VoxelScene scene(run.voxels);
    const VoxelViews views = render_voxel_views(scene, run.voxels, camera, heights_of(box));
    const int x = kGap + i * (w + kGap);
    place(picture, views.metric, x, kGap);
    place(picture, views.semantic, x, h + 2 * kGap);
  }
  return picture;
}

RgbImage render_run_growth(const fs::path& run_dir, const PictureSize& size) {
  std::vector<RunContents> runs;
  for (const fs::path& folder : growth_folders(run_dir)) runs.push_back(read_run_contents(folder));
  return render_growth_strip(runs, size);
}

}  // namespace sarmap::render
