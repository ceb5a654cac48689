// Finds the shipped model and default arena: in SARMAP_DATA_DIR, or beside the
// binary in ../share/sarmap/, or in the source tree for the build-tree binary.
#include "tools/sarmap/shipped_data.hpp"

#include <cstdlib>
#include <system_error>

#include "engine/core/error.hpp"

namespace sarmap::cli {

namespace fs = std::filesystem;

namespace {

// Set by CMake (tools/sarmap/CMakeLists.txt): the source tree, the folder the
// build writes this binary into, and share/sarmap relative to bin/ in the
// install layout.
constexpr const char* kSourceDir = SARMAP_SOURCE_DIR;
constexpr const char* kBuildTreeBinaryDir = SARMAP_BUILD_TREE_BINARY_DIR;
constexpr const char* kInstalledDataFromBinary = SARMAP_INSTALLED_DATA_FROM_BINARY;

fs::path find_shipped(const fs::path& relative, const std::string& what_instead) {
  const std::vector<DataDir> dirs = shipped_data_dirs();
  std::string looked;
  for (const DataDir& dir : dirs) {
    if (dir.path.empty()) {  // no place to look: say why
      looked += (looked.empty() ? "" : "; ") + dir.why;
      continue;
    }
    fs::path file = dir.path / relative;
    std::error_code ec;
    if (fs::is_regular_file(file, ec)) return file;
    looked += (looked.empty() ? "" : "; ") + file.string() + ", " + dir.why;
  }
  throw Error(ErrorCode::Io, "the shipped " + relative.string() + " was not found (looked for " + looked +
                                 "). " + what_instead +
                                 ", or point SARMAP_DATA_DIR at a folder holding models/ and arenas/");
}

}  // namespace

std::vector<DataDir> shipped_data_dirs() {
  if (const char* env = std::getenv("SARMAP_DATA_DIR"); env != nullptr && *env != '\0') {
    return {{env, "from SARMAP_DATA_DIR"}};
  }
  std::error_code ec;
  const fs::path binary = fs::read_symlink("/proc/self/exe", ec);
  if (ec) return {{fs::path(), "no place beside the binary (/proc/self/exe could not be read)"}};
  // Only the binary the build wrote may use the source tree: a copy or an
  // installed binary must not depend on where it was built.
  if (fs::equivalent(binary.parent_path(), kBuildTreeBinaryDir, ec)) {
    return {{fs::path(kSourceDir) / "datasets", "in the source tree of this build-tree binary"}};
  }
  return {{(binary.parent_path() / kInstalledDataFromBinary).lexically_normal(),
           "beside the binary " + binary.string()}};
}

fs::path shipped_default_arena() {
  return find_shipped(fs::path("arenas") / "esogu-6x4.json", "Give --arena A.json");
}

fs::path shipped_ramp_model() {
  return find_shipped(fs::path("models") / "ramps-dgcnn.safetensors",
                      "Give --model M.safetensors (or --classifier geometric, which needs no model)");
}

}  // namespace sarmap::cli
