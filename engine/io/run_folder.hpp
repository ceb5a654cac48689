// An output folder written as one set, whole or absent. manifest.json is the
// set's commit record: a writer removes the old manifest before it writes
// anything, writes every output atomically, and writes the manifest last with
// each output's size and SHA-256; a reader trusts the folder only when the
// manifest is there and every file it lists matches it (docs/formats.md,
// "manifest.json"). So a run killed in its write phase, a full disk, or two
// runs into one folder leave a folder that readers refuse, never a mix.
#pragma once

#include <cstdint>
#include <filesystem>
#include <string>
#include <string_view>
#include <vector>

#include <nlohmann/json.hpp>

namespace sarmap {

// Version 2 (2026-11-27) dropped "settings", which repeated part of "config".
inline constexpr int kRunManifestVersion = 2;
inline constexpr std::string_view kRunManifestName = "manifest.json";

class RunFolderWriter {
 public:
  // Creates `folder` if needed and prepares it for a new set. Throws
  // sarmap::Error naming the folder when it is a filesystem root, holds files
  // but no earlier run, is being written by another process (its lock), or
  // takes no files. Removes temporaries left by processes that are gone and
  // the old manifest.json.
  explicit RunFolderWriter(std::filesystem::path folder);
  ~RunFolderWriter();
  RunFolderWriter(const RunFolderWriter&) = delete;
  RunFolderWriter& operator=(const RunFolderWriter&) = delete;

  const std::filesystem::path& folder() const { return folder_; }
  std::filesystem::path path_of(std::string_view name) const { return folder_ / name; }

  // Writes manifest.json last: `manifest` with "outputs" set to each named
  // file's {"name", "bytes", "sha256"}. Throws when a named file is missing.
  void commit(nlohmann::ordered_json manifest, const std::vector<std::string>& outputs);

 private:
  std::filesystem::path folder_;
  int lock_fd_ = -1;
};

// Removes the temporaries AtomicFileWriter left in `folder` for processes
// that are gone (killed while writing); others' are left alone.
void remove_stale_temporaries(const std::filesystem::path& folder);

// Checks a folder written by RunFolderWriter: manifest.json must exist and
// every output it lists must have its recorded size and SHA-256. Files the
// manifest does not list (a plan, a rendering) are not checked. Throws
// sarmap::Error (InvalidData) naming the file that does not match.
void verify_run_folder(const std::filesystem::path& folder);

}  // namespace sarmap
