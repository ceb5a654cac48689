// `sarmap merge RUN... --out DIR [--transform RUN=x,y,z,yaw_deg]...
// [--keep-state] [--quiet]`: one run folder from the maps of several runs
// mapped with `sarmap run --keep-state` (robots in one building, or the parts
// of one sequence), merged as Mapper::merge merges: the first run's frame is
// the merged map's, and a run whose map frame differs by a known transform
// is carried into it first (finding that transform is out of scope).
#include <cmath>
#include <cstdio>
#include <filesystem>
#include <map>
#include <memory>
#include <string>
#include <vector>

#include <Eigen/Geometry>
#include <nlohmann/json.hpp>

#include "engine/core/degrees.hpp"
#include "engine/core/error.hpp"
#include "engine/io/json_fields.hpp"
#include "engine/io/run_folder.hpp"
#include "engine/pipeline/mapper_file.hpp"
#include "engine/pipeline/run_outputs.hpp"
#include "tools/sarmap/commands.hpp"
#include "tools/sarmap/number_checks.hpp"

namespace sarmap::cli {
namespace {

namespace fs = std::filesystem;
using Json = nlohmann::ordered_json;

struct MergeArgs {
  std::vector<std::string> runs;
  std::string out;
  std::vector<std::string> transforms;  // RUN=x,y,z,yaw_deg
  bool keep_state = false;
  bool quiet = false;
};

struct Transform {
  double x = 0, y = 0, z = 0, yaw_deg = 0;
  Pose pose() const {
    const Eigen::Matrix3d yaw = Eigen::AngleAxisd(yaw_deg * kDeg, Eigen::Vector3d::UnitZ()).toRotationMatrix();
    return Pose(yaw, Eigen::Vector3d(x, y, z), "--transform");
  }
};

// A run named on the command line by the text given, or by the same folder.
bool same_run(const std::string& named, const std::string& run) {
  if (named == run) return true;
  std::error_code error;
  const fs::path a = fs::weakly_canonical(named, error);
  if (error) return false;
  const fs::path b = fs::weakly_canonical(run, error);
  return !error && a == b;
}

// Each run's transform into the first run's frame (identity when not given).
std::vector<Transform> parse_transforms(const MergeArgs& a) {
  std::vector<Transform> transforms(a.runs.size());
  std::vector<bool> given(a.runs.size(), false);
  for (const std::string& text : a.transforms) {
    const std::size_t equals = text.rfind('=');
    if (equals == std::string::npos || equals == 0) {
      throw Error(ErrorCode::InvalidArgument, "merge: --transform must be RUN=x,y,z,yaw_deg, got '" + text + "'");
    }
    const std::string run = text.substr(0, equals);
    const auto numbers = finite_number_list(text.substr(equals + 1), 4);
    if (!numbers) {
      throw Error(ErrorCode::InvalidArgument,
                  "merge: --transform " + run + "= must be four finite numbers x,y,z,yaw_deg, got '" +
                      text.substr(equals + 1) + "'");
    }
    std::size_t index = a.runs.size();
    for (std::size_t i = 0; i < a.runs.size() && index == a.runs.size(); ++i) {
      if (same_run(run, a.runs[i])) index = i;
    }
    if (index == a.runs.size()) {
      throw Error(ErrorCode::InvalidArgument, "merge: --transform names " + run + ", which is not one of the runs");
    }
    if (given[index]) throw Error(ErrorCode::InvalidArgument, "merge: two --transform options for " + run);
    given[index] = true;
    transforms[index] = {(*numbers)[0], (*numbers)[1], (*numbers)[2], (*numbers)[3]};
  }
  return transforms;
}

// A run folder's manifest after checking the folder is whole and holds a
// saved Mapper.
Json checked_manifest(const std::string& run) {
  if (!fs::is_directory(run)) throw Error(ErrorCode::Io, "merge: " + run + " is not a run folder");
  verify_run_folder(run);
  if (!fs::exists(fs::path(run) / pipeline::kMapperFileName)) {
    throw Error(ErrorCode::InvalidArgument, "merge: " + run + " holds no " + pipeline::kMapperFileName +
                                                ": map it with `sarmap run --keep-state` to merge it");
  }
  return json_fields::read_file(fs::path(run) / kRunManifestName);
}

std::size_t count_of(const Json& manifest, const char* key) {
  const auto it = manifest.find(key);
  return it != manifest.end() && it->is_number_unsigned() ? it->get<std::size_t>() : 0;
}

void run_merge(const MergeArgs& a) {
  if (a.runs.size() < 2) throw Error(ErrorCode::InvalidArgument, "merge: give two or more runs");
  for (const std::string& run : a.runs) {
    if (same_run(a.out, run)) {
      throw Error(ErrorCode::InvalidArgument, "merge: --out " + a.out + " is one of the runs; write elsewhere");
    }
  }
  const std::vector<Transform> transforms = parse_transforms(a);
  // Every run is checked before any is loaded or the output touched.
  std::vector<Json> manifests;
  for (const std::string& run : a.runs) manifests.push_back(checked_manifest(run));

  std::unique_ptr<pipeline::Mapper> merged;
  pipeline::RunRecord record;
  record.layout = "merged";
  record.input = Json{{"path", nullptr}, {"sha256", nullptr}, {"runs", Json::array()}};
  std::string arena = manifests.front().value("arena_sha256", std::string());
  for (std::size_t i = 0; i < a.runs.size(); ++i) {
    // One saved Mapper in memory at a time besides the merged one.
    const std::unique_ptr<pipeline::Mapper> part = pipeline::load_mapper_file(fs::path(a.runs[i]) / pipeline::kMapperFileName);
    if (!merged) merged = std::make_unique<pipeline::Mapper>(part->config(), part->sensor());
    const Transform& t = transforms[i];
    const pipeline::MapperMergeCounts counts = merged->merge(*part, t.pose());
    if (!a.quiet) {
      std::printf("merged %s: %zu blocks added, %zu merged (%zu voxels both knew), %zu kept points added\n",
                  a.runs[i].c_str(), counts.metric.blocks_added, counts.metric.blocks_merged,
                  counts.metric.voxels_in_both, counts.semantic_points_added);
    }
    const Json& m = manifests[i];
    record.input["runs"].push_back(Json{{"run", fs::absolute(a.runs[i]).lexically_normal().string()},
                                        {"input", m.value("input", Json())},
                                        {"layout", m.value("layout", Json())},
                                        {"scans", count_of(m, "scans")},
                                        {"transform", Json{{"x", t.x}, {"y", t.y}, {"z", t.z}, {"yaw_deg", t.yaw_deg}}}});
    record.scans += count_of(m, "scans");
    record.scans_skipped += count_of(m, "scans_skipped");
    if (m.value("arena_sha256", std::string()) != arena) arena.clear();
  }
  record.arena_sha256 = arena;
  record.mapper_state = a.keep_state;
  RunFolderWriter folder(a.out);
  pipeline::write_run(*merged, folder, record);
  if (!a.quiet) {
    std::printf("%zu runs, %zu scans -> %zu segments, written to %s\n", a.runs.size(), record.scans,
                merged->segment_map().size(), a.out.c_str());
  }
}

}  // namespace

void add_merge_command(CLI::App& app) {
  auto a = std::make_shared<MergeArgs>();
  CLI::App* cmd = app.add_subcommand(
      "merge", "Merge the maps of runs written with `sarmap run --keep-state` into one run folder");
  cmd->add_option("RUN", a->runs, "Run folders, two or more; the first one's map frame is the merged map's")
      ->required();
  cmd->add_option("--out", a->out, "Output folder (a new run folder)")->required();
  cmd->add_option("--transform", a->transforms,
                  "RUN=x,y,z,yaw_deg: carry RUN's map frame into the first run's by this yaw (degrees, about "
                  "z) then translation (metres); repeat for several runs. Kept points and segments move "
                  "exactly; the voxels are resampled (exact for whole voxels and quarter turns)");
  cmd->add_flag("--keep-state", a->keep_state, "Also write mapper.state, so the merged run can be merged again");
  cmd->add_flag("--quiet", a->quiet, "No summary");
  cmd->callback([a] { run_merge(*a); });
}

}  // namespace sarmap::cli
