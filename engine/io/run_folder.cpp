#include "engine/io/run_folder.hpp"

#include <cerrno>
#include <csignal>
#include <cstring>
#include <fcntl.h>
#include <fstream>
#include <sys/file.h>
#include <unistd.h>

#include "engine/core/error.hpp"
#include "engine/io/atomic_file.hpp"
#include "engine/io/sha256.hpp"

namespace sarmap {
namespace fs = std::filesystem;

namespace {

constexpr std::string_view kLockName = ".sarmap.lock";

// Names that show a folder already holds a sarmap run, so writing into it
// replaces that run rather than mixing outputs into someone's other files.
bool holds_a_run(const fs::path& folder) {
  for (const std::string_view name : {kRunManifestName, std::string_view("map.sarmap"), kLockName}) {
    if (fs::exists(folder / name)) return true;
  }
  return false;
}

bool is_empty_folder(const fs::path& folder) { return fs::directory_iterator(folder) == fs::directory_iterator(); }

// AtomicFileWriter names its temporaries ".NAME.tmp.PID.RANDOM"; returns PID, or -1.
long temporary_owner(const std::string& name) {
  if (name.empty() || name[0] != '.') return -1;
  const std::size_t tmp = name.rfind(".tmp.");
  if (tmp == std::string::npos) return -1;
  const std::size_t pid_start = tmp + 5;
  const std::size_t pid_end = name.find('.', pid_start);
  if (pid_end == std::string::npos || pid_end == pid_start) return -1;
  long pid = 0;
  for (std::size_t i = pid_start; i < pid_end; ++i) {
    if (name[i] < '0' || name[i] > '9' || pid > 100'000'000) return -1;
    pid = pid * 10 + (name[i] - '0');
  }
  return pid;
}

bool process_is_gone(long pid) { return ::kill(static_cast<pid_t>(pid), 0) != 0 && errno == ESRCH; }

std::string read_lock_owner(int fd) {
  char text[32] = {};
  const ssize_t got = ::pread(fd, text, sizeof text - 1, 0);
  return got > 0 ? std::string(text, static_cast<std::size_t>(got)) : std::string("unknown");
}

using Json = nlohmann::ordered_json;

Json read_manifest(const fs::path& folder) {
  const fs::path path = folder / kRunManifestName;
  std::ifstream in(path);
  if (!in) {
    throw Error(ErrorCode::InvalidData, folder.string() +
                                            ": no manifest.json, so its outputs are not a whole set (the run that "
                                            "wrote them failed or was stopped, or another is writing): run again");
  }
  Json manifest = Json::parse(in, nullptr, false);
  if (manifest.is_discarded() || !manifest.is_object()) {
    throw Error(ErrorCode::InvalidData, path.string() + ": not a JSON object");
  }
  const bool listed = manifest.contains("outputs") && manifest["outputs"].is_array();
  if (!listed || (!manifest["outputs"].empty() && !manifest["outputs"][0].is_object())) {
    throw Error(ErrorCode::InvalidData, path.string() +
                                            ": lists no outputs with sizes and hashes (written by a sarmap older "
                                            "than manifest version 1): run again");
  }
  return manifest;
}

}  // namespace

void remove_stale_temporaries(const fs::path& folder) {
  for (const fs::directory_entry& entry : fs::directory_iterator(folder)) {
    const long pid = temporary_owner(entry.path().filename().string());
    if (pid > 0 && entry.is_regular_file() && process_is_gone(pid)) {
      std::error_code ignored;
      fs::remove(entry.path(), ignored);
    }
  }
}

RunFolderWriter::RunFolderWriter(fs::path folder) : folder_(std::move(folder)) {
  if (folder_.empty()) throw Error(ErrorCode::InvalidArgument, "output folder: empty path");
  const fs::path absolute = fs::absolute(folder_).lexically_normal();
  if (absolute == absolute.root_path() || absolute.relative_path().empty()) {
    throw Error(ErrorCode::InvalidArgument, folder_.string() + ": a filesystem root cannot be an output folder");
  }
  if (fs::exists(folder_) && !fs::is_directory(folder_)) {
    throw Error(ErrorCode::InvalidArgument, folder_.string() + ": exists and is not a folder");
  }
  fs::create_directories(folder_);
  if (!is_empty_folder(folder_) && !holds_a_run(folder_)) {
    throw Error(ErrorCode::InvalidArgument,
                folder_.string() + ": holds other files and no earlier sarmap run (no manifest.json or "
                                   "map.sarmap); give a new or empty folder");
  }
  const fs::path lock_path = folder_ / kLockName;
  lock_fd_ = ::open(lock_path.c_str(), O_RDWR | O_CREAT | O_CLOEXEC, 0644);
  if (lock_fd_ < 0) {
    throw Error(ErrorCode::Io, lock_path.string() + ": cannot create the folder's lock: " + std::strerror(errno));
  }
  if (::flock(lock_fd_, LOCK_EX | LOCK_NB) != 0) {
    const std::string owner = read_lock_owner(lock_fd_);
    ::close(lock_fd_);
    lock_fd_ = -1;
    throw Error(ErrorCode::InvalidArgument,
                folder_.string() + ": another sarmap process (pid " + owner + ") is writing this folder");
  }
  const std::string pid = std::to_string(::getpid());
  if (::ftruncate(lock_fd_, 0) != 0 || ::pwrite(lock_fd_, pid.data(), pid.size(), 0) < 0) {
    // The pid only makes the other writer's error clearer; the lock itself holds.
  }
  remove_stale_temporaries(folder_);
  std::error_code removed;
  fs::remove(folder_ / kRunManifestName, removed);
  if (removed) {
    throw Error(ErrorCode::Io, (folder_ / kRunManifestName).string() + ": cannot remove the old manifest: " +
                                   removed.message());
  }
  // Find out now, not after the whole mapping, that the folder takes files.
  AtomicFileWriter probe(folder_ / ".sarmap_write_probe");
}

RunFolderWriter::~RunFolderWriter() {
  if (lock_fd_ >= 0) ::close(lock_fd_);  // closing releases the flock
}

void RunFolderWriter::commit(Json manifest, const std::vector<std::string>& outputs) {
  Json listed = Json::array();
  for (const std::string& name : outputs) {
    const fs::path path = folder_ / name;
    if (!fs::is_regular_file(path)) {
      throw Error(ErrorCode::Io, path.string() + ": output missing when writing the manifest");
    }
    const FileDigest digest = digest_file(path);
    listed.push_back(Json{{"name", name}, {"bytes", digest.bytes}, {"sha256", digest.sha256}});
  }
  manifest["outputs"] = std::move(listed);
  AtomicFileWriter writer(folder_ / kRunManifestName);
  writer.write(manifest.dump(2) + "\n");
  writer.commit();
}

void verify_run_folder(const fs::path& folder) {
  const Json manifest = read_manifest(folder);
  const fs::path manifest_path = folder / kRunManifestName;
  for (const Json& output : manifest["outputs"]) {
    if (!output.is_object() || !output.contains("name") || !output["name"].is_string() ||
        !output.contains("bytes") || !output["bytes"].is_number_unsigned() || !output.contains("sha256") ||
        !output["sha256"].is_string()) {
      throw Error(ErrorCode::InvalidData,
                  manifest_path.string() + ": an output entry lacks its name, bytes or sha256");
    }
    const std::string name = output["name"].get<std::string>();
    const fs::path relative(name);
    if (name.empty() || relative.is_absolute() || relative.has_parent_path()) {
      throw Error(ErrorCode::InvalidData, manifest_path.string() + ": output \"" + name +
                                              "\" is not a file name in the folder");
    }
    const fs::path path = folder / relative;
    if (!fs::is_regular_file(path)) {
      throw Error(ErrorCode::InvalidData, path.string() + ": listed in manifest.json but missing");
    }
    const auto expected_bytes = output["bytes"].get<std::uint64_t>();
    const std::uintmax_t bytes = fs::file_size(path);
    if (bytes != expected_bytes) {
      throw Error(ErrorCode::InvalidData, path.string() + ": " + std::to_string(bytes) +
                                              " bytes, manifest.json says " + std::to_string(expected_bytes) +
                                              " (written by another run or changed since)");
    }
    if (digest_file(path).sha256 != output["sha256"].get<std::string>()) {
      throw Error(ErrorCode::InvalidData, path.string() +
                                              ": its SHA-256 differs from manifest.json's (written by another run "
                                              "or changed since)");
    }
  }
}

}  // namespace sarmap
