#include "engine/io/sequence_writer.hpp"

#include <algorithm>
#include <cmath>
#include <cstdio>
#include <string>
#include <string_view>
#include <system_error>

#include "engine/core/error.hpp"
#include "engine/io/atomic_file.hpp"
#include "engine/io/intrinsics.hpp"
#include "engine/io/ply.hpp"
#include "engine/io/run_folder.hpp"
#include "engine/io/sha256.hpp"

namespace sarmap {
namespace {

// Checked here rather than discovered by the reader after a long simulation.
void validate_sensor(const SensorInfo& s) {
  const bool has_type = s.type != SensorType::Unknown;
  if (!has_type && (s.max_range != 0 || s.min_range != 0 || s.intrinsics)) {
    throw Error(ErrorCode::InvalidArgument,
                "SequenceWriter: a sensor range or intrinsics needs a sensor type");
  }
  if (!(s.max_range >= 0) || !(s.min_range >= 0) || (s.max_range > 0 && s.min_range >= s.max_range)) {
    throw Error(ErrorCode::InvalidArgument,
                "SequenceWriter: sensor ranges must be finite, non-negative and min_range < max_range");
  }
  if (s.intrinsics) {
    if (s.type != SensorType::DepthCamera) {
      throw Error(ErrorCode::InvalidArgument,
                  "SequenceWriter: intrinsics are only meaningful for a depth camera");
    }
    if (s.intrinsics->width <= 0 || s.intrinsics->height <= 0) {
      throw Error(ErrorCode::InvalidArgument, "SequenceWriter: intrinsics need the image width and height");
    }
    validate_intrinsics(*s.intrinsics, "SequenceWriter");
  }
}

// Whether `name` is one add() gives a frame: "frame_", six or more digits, ".ply".
bool is_frame_name(std::string_view name) {
  constexpr std::string_view prefix = "frame_", suffix = ".ply";
  if (name.size() < prefix.size() + 6 + suffix.size() || !name.starts_with(prefix) || !name.ends_with(suffix)) {
    return false;
  }
  const std::string_view digits = name.substr(prefix.size(), name.size() - prefix.size() - suffix.size());
  return std::all_of(digits.begin(), digits.end(), [](char c) { return c >= '0' && c <= '9'; });
}

void remove_file(const std::filesystem::path& path) {
  std::error_code ec;
  std::filesystem::remove(path, ec);
  if (ec) throw Error(ErrorCode::Io, path.string() + ": cannot remove: " + ec.message());
}

}  // namespace

void remove_written_sequence(const std::filesystem::path& folder) {
  std::error_code ec;
  if (!std::filesystem::is_directory(folder, ec)) return;
  remove_file(folder / "sequence.json");
  for (const std::filesystem::directory_entry& entry : std::filesystem::directory_iterator(folder)) {
    if (entry.is_regular_file() && !entry.is_symlink() && is_frame_name(entry.path().filename().string())) {
      remove_file(entry.path());
    }
  }
  remove_stale_temporaries(folder);
}

SequenceWriter::SequenceWriter(std::filesystem::path folder, SensorInfo sensor) : folder_(std::move(folder)) {
  validate_sensor(sensor);
  manifest_.points_frame = PointsFrame::World;
  manifest_.sensor = std::move(sensor);
  std::error_code ec;
  std::filesystem::create_directories(folder_, ec);
  if (ec) throw Error(ErrorCode::Io, folder_.string() + ": cannot create folder: " + ec.message());
  remove_file(folder_ / "sequence.json");
}

void SequenceWriter::add(const Scan& scan) {
  if (finished_) throw Error(ErrorCode::InvalidArgument, "SequenceWriter: add() after finish()");
  if (!scan.origin.allFinite() || !std::isfinite(scan.timestamp)) {
    throw Error(ErrorCode::InvalidArgument, "SequenceWriter: frame " +
                                                std::to_string(manifest_.frames.size()) +
                                                ": origin and timestamp must be finite");
  }
  if (!manifest_.frames.empty() && scan.timestamp < manifest_.frames.back().timestamp) {
    throw Error(ErrorCode::InvalidArgument,
                "SequenceWriter: frame " + std::to_string(manifest_.frames.size()) + ": timestamp " +
                    std::to_string(scan.timestamp) + " is earlier than the previous frame's");
  }
  char name[32];
  std::snprintf(name, sizeof name, "frame_%06zu.ply", manifest_.frames.size());
  write_ply(folder_ / name, scan.points);
  manifest_.frames.push_back({name, scan.pose, scan.origin, scan.timestamp});
}

void SequenceWriter::set_arena_sha256(std::string sha256) {
  if (finished_) throw Error(ErrorCode::InvalidArgument, "SequenceWriter: set_arena_sha256() after finish()");
  if (!is_sha256_hex(sha256)) {
    throw Error(ErrorCode::InvalidArgument,
                "SequenceWriter: arena_sha256 \"" + sha256 + "\" is not 64 lowercase hex digits");
  }
  manifest_.arena_sha256 = std::move(sha256);
}

void SequenceWriter::finish() {
  if (finished_) return;
  AtomicFileWriter out(folder_ / "sequence.json");
  out.write(sequence_manifest_json(manifest_));
  out.commit();
  finished_ = true;
}

}  // namespace sarmap
