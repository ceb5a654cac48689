// Finds the shipped model, default arena and viewer script: in SARMAP_DATA_DIR,
// or beside the binary in ../share/sarmap/, or in the source tree (the build
// tree for the generated viewer script) for the build-tree binary.
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
// Where the build writes the viewer's bundle (web/CMakeLists.txt): generated,
// so the build-tree binary finds it in the build tree, not in datasets/.
constexpr const char* kBuildTreeDataDir = SARMAP_BUILD_TREE_DATA_DIR;

// The first of `dirs` that holds `relative`; `hint` ends the error listing
// every place looked.
fs::path find_in(const std::vector<DataDir>& dirs, const fs::path& relative, const std::string& hint) {
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
  throw Error(ErrorCode::Io,
              "the shipped " + relative.string() + " was not found (looked for " + looked + "). " + hint);
}

fs::path find_shipped(const fs::path& relative, const std::string& what_instead) {
  return find_in(shipped_data_dirs(), relative,
                 what_instead + ", or point SARMAP_DATA_DIR at a folder holding models/ and arenas/");
}

bool is_build_tree_binary(const fs::path& binary) {
  std::error_code ec;
  return fs::equivalent(binary.parent_path(), kBuildTreeBinaryDir, ec);
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
  if (is_build_tree_binary(binary)) {
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

fs::path shipped_viewer_bundle() {
  std::vector<DataDir> dirs = shipped_data_dirs();
  std::error_code ec;
  const char* env = std::getenv("SARMAP_DATA_DIR");
  if ((env == nullptr || *env == '\0') && is_build_tree_binary(fs::read_symlink("/proc/self/exe", ec))) {
    dirs = {{kBuildTreeDataDir, "built for this build-tree binary"}};
  }
  return find_in(
      dirs, "viewer.js",
      "The build bundles it from web/viewer/ once web/node_modules exists: run tools/install-deps.sh "
      "(it runs npm ci in web/), then cmake --build again (and cmake --install for an installed sarmap)");
}

}  // namespace sarmap::cli
