// `sarmap convert IN OUT`: PLY <-> PCD (binary, or --ascii), and a scan
// sequence into one merged cloud (every frame in the world frame, appended)
// or into a sarmap sequence folder. --voxel SIZE keeps only the first point
// that falls in each cube of that size, to thin merged clouds. A metric map
// (map.sarmap) converts to its occupied voxels as a cloud (.ply / .pcd, as
// voxels.ply), as cubes (--voxel-cubes, .ply) or to an OctoMap tree (.bt,
// or .ot: a ColorOcTree with log-odds and class colours).
#include <cctype>
#include <cmath>
#include <cstdint>
#include <cstdio>
#include <filesystem>
#include <memory>
#include <optional>
#include <string>
#include <string_view>
#include <unordered_set>
#include <vector>

#include "engine/core/error.hpp"
#include "engine/io/point_cloud_file.hpp"
#include "engine/io/scan_source.hpp"
#include "engine/io/sequence_writer.hpp"
#include "engine/metric/map_file.hpp"
#include "engine/metric/octomap_color_export.hpp"
#include "engine/metric/octomap_export.hpp"
#include "engine/metric/voxel_cloud.hpp"
#include "tools/sarmap/commands.hpp"
#include "tools/sarmap/number_checks.hpp"
#include "tools/sarmap/progress.hpp"
#include "tools/sarmap/sequence_input_options.hpp"

namespace sarmap::cli {
namespace {

struct ConvertArgs {
  std::string in;
  std::string out;
  bool ascii = false;
  double voxel = 0.0;
  bool voxel_cubes = false;
  bool quiet = false;
  SequenceInputArgs sequence;
};

// Remembers which voxels hold a point already, across every frame added.
class VoxelThinning {
 public:
  explicit VoxelThinning(double size) : size_(size) {}

  // Keeps the points whose voxel is new.
  PointBuffer thin(const PointBuffer& points) {
    std::vector<std::uint32_t> keep;
    keep.reserve(points.size());
    for (std::size_t i = 0; i < points.size(); ++i) {
      if (occupied_.insert(key(points.x()[i], points.y()[i], points.z()[i])).second) {
        keep.push_back(static_cast<std::uint32_t>(i));
      }
    }
    return points.select(keep);
  }

 private:
  // 21 bits per axis: +-2^20 voxels around the origin (10 km at 1 cm).
  static constexpr double kLimit = 1 << 20;

  std::uint64_t key(float x, float y, float z) const {
    const double c[3] = {std::floor(x / size_), std::floor(y / size_), std::floor(z / size_)};
    std::uint64_t k = 0;
    for (const double v : c) {
      if (!(v >= -kLimit && v < kLimit)) {
        throw Error(ErrorCode::OutOfRange,
                    "convert: --voxel " + std::to_string(size_) + ": point (" + std::to_string(x) + ", " +
                        std::to_string(y) + ", " + std::to_string(z) +
                        ") is more than 2^20 voxels from the origin; use larger voxels");
      }
      k = (k << 21) | static_cast<std::uint64_t>(static_cast<std::int64_t>(v) + (1 << 20));
    }
    return k;
  }

  double size_;
  std::unordered_set<std::uint64_t> occupied_;
};

bool has_extension(const std::filesystem::path& path, std::string_view wanted) {
  std::string ext = path.extension().string();
  for (char& c : ext) c = static_cast<char>(std::tolower(static_cast<unsigned char>(c)));
  return ext == wanted;
}

bool is_cloud_path(const std::filesystem::path& path) {
  return has_extension(path, ".ply") || has_extension(path, ".pcd");
}

// The occupied voxels of a map.sarmap, written by the same code as sarmap
// run's voxels.ply, map.bt and map.ot.
void convert_map(const ConvertArgs& a) {
  const std::filesystem::path out(a.out);
  const bool bt = has_extension(out, ".bt");
  const bool ot = has_extension(out, ".ot");
  if (a.voxel > 0) {
    throw Error(ErrorCode::InvalidArgument,
                "convert: --voxel thins point clouds; a metric map's voxels are its own (see sarmap run --voxel)");
  }
  if (a.voxel_cubes ? !has_extension(out, ".ply") : !(bt || ot || is_cloud_path(out))) {
    throw Error(ErrorCode::InvalidArgument,
                "convert: " + a.out +
                    (a.voxel_cubes
                         ? ": --voxel-cubes writes a .ply mesh"
                         : ": a metric map converts to a .ply or .pcd cloud or an OctoMap .bt or .ot file"));
  }
  if (a.ascii && (bt || ot || a.voxel_cubes)) {
    throw Error(ErrorCode::InvalidArgument, "convert: --ascii applies to .ply / .pcd clouds only");
  }
  const metric::MetricMap map = metric::load_map(a.in);
  const metric::MapCounts counts = map.counts();
  if (bt) {
    metric::write_octomap_bt(map, out);
    if (!a.quiet) std::printf("%s: OctoMap tree of %zu known voxels\n", a.out.c_str(), counts.known);
  } else if (ot) {
    metric::write_octomap_ot(map, out);
    if (!a.quiet) std::printf("%s: OctoMap colour tree of %zu known voxels\n", a.out.c_str(), counts.known);
  } else if (a.voxel_cubes) {
    metric::write_voxel_cubes(map, out);
    if (!a.quiet) std::printf("%s: %zu occupied voxels as cubes\n", a.out.c_str(), counts.occupied);
  } else {
    metric::write_voxel_cloud(map, out, !a.ascii);
    if (!a.quiet) std::printf("%s: %zu occupied voxels\n", a.out.c_str(), counts.occupied);
  }
}

void run_convert(const ConvertArgs& a) {
  if (a.voxel != 0 && !(a.voxel > 0 && std::isfinite(a.voxel))) {
    throw Error(ErrorCode::InvalidArgument, "convert: --voxel must be a positive size in metres");
  }
  PointCloudWriteOptions write_options;
  write_options.binary = !a.ascii;
  std::optional<VoxelThinning> thinning;
  if (a.voxel > 0) thinning.emplace(a.voxel);
  const std::filesystem::path in(a.in), out(a.out);

  if (metric::is_map_file_path(in) && !std::filesystem::is_directory(in)) {
    convert_map(a);
    return;
  }
  if (a.voxel_cubes) {
    throw Error(ErrorCode::InvalidArgument, "convert: --voxel-cubes needs a metric map (.sarmap) as input");
  }
  if (std::filesystem::is_regular_file(in) && in.filename() != "sequence.json" && !is_bag_path(in)) {
    if (!is_cloud_path(out)) {
      throw Error(ErrorCode::InvalidArgument,
                  "convert: " + a.out + ": a cloud converts to a .ply or .pcd file");
    }
    PointBuffer points = read_point_cloud(in, nullptr, a.sequence.options().limits);
    if (thinning) points = thinning->thin(points);
    write_point_cloud(out, points, write_options);
    if (!a.quiet) std::printf("%s: %zu points\n", a.out.c_str(), points.size());
    return;
  }

  std::error_code ec;
  if (std::filesystem::equivalent(in, out, ec)) {
    throw Error(ErrorCode::InvalidArgument, "convert: " + a.out + " is the input sequence itself");
  }
  const std::unique_ptr<ScanSource> source = open_input_sequence(in, a.sequence);
  ProgressLine progress("convert", source->size(), !a.quiet);
  Scan scan;
  std::size_t frames = 0;
  if (is_cloud_path(out)) {
    PointBuffer merged;
    while (source->next(scan)) {
      merged.append(thinning ? thinning->thin(scan.points) : scan.points);
      progress.update(++frames);
    }
    write_point_cloud(out, merged, write_options);
    progress.finish();
    if (!a.quiet) std::printf("%s: %zu points from %zu frames\n", a.out.c_str(), merged.size(), frames);
    return;
  }
  if (a.ascii) throw Error(ErrorCode::InvalidArgument, "convert: --ascii applies to .ply / .pcd output only");
  SequenceWriter writer(out, source->sensor());
  // Thinned or not, the frames still show the arena they were simulated in.
  if (const std::string arena = source->arena_sha256(); !arena.empty()) writer.set_arena_sha256(arena);
  std::size_t points = 0;
  while (source->next(scan)) {
    if (thinning) scan.points = thinning->thin(scan.points);
    points += scan.points.size();
    writer.add(scan);
    progress.update(++frames);
  }
  writer.finish();
  progress.finish();
  if (!a.quiet) std::printf("%s: sarmap sequence, %zu frames, %zu points\n", a.out.c_str(), frames, points);
}

}  // namespace

void add_convert_command(CLI::App& app) {
  auto args = std::make_shared<ConvertArgs>();
  CLI::App* cmd = app.add_subcommand(
      "convert",
      "Convert PLY <-> PCD, a scan sequence into one merged cloud (OUT.ply / OUT.pcd) or a sarmap "
      "sequence folder (OUT without extension), or a metric map (map.sarmap) into its occupied voxels "
      "(OUT.ply / OUT.pcd, cubes with --voxel-cubes) or an OctoMap tree (OUT.bt, or OUT.ot in class "
      "colours)");
  cmd->add_option("in", args->in,
                  "PLY / PCD file, sequence folder (sarmap, TUM RGB-D, 7-Scenes) or metric map (.sarmap)")
      ->required();
  cmd->add_option("out", args->out,
                  "Output .ply / .pcd file, .bt / .ot (from a map), or a folder for a sarmap sequence")
      ->required();
  cmd->add_flag("--ascii", args->ascii, "Write ASCII PLY / PCD instead of binary");
  cmd->add_option("--voxel", args->voxel, "Keep only the first point in each voxel of this size (metres)")
      ->check(finite_positive());
  cmd->add_flag("--voxel-cubes", args->voxel_cubes,
                "From a metric map: each occupied voxel as a cube mesh (8 vertices, 6 faces, class colour) in OUT.ply");
  add_sequence_input_options(cmd, args->sequence);
  cmd->add_flag("--quiet", args->quiet, "No progress line or summary");
  cmd->callback([args] { run_convert(*args); });
}

}  // namespace sarmap::cli
