// Files that ship with sarmap and that commands use by default: the built-in
// default arena, the trained ramp model and the browser viewer's script. An
// installed binary finds them in the prefix's share/sarmap/ (beside its own
// bin/), so it needs no source tree.
#pragma once

#include <filesystem>
#include <string>
#include <vector>

namespace sarmap::cli {

// Where the shipped data is looked for, in order; each folder holds models/
// and arenas/ as datasets/ does.
struct DataDir {
  std::filesystem::path path;
  std::string why;  // how this place was chosen, for the error that lists them
};

// SARMAP_DATA_DIR when it is set (then the only place); otherwise
// <binary's folder>/../share/sarmap for an installed binary, or the source
// tree's datasets/ for the binary in the build tree it was built in.
std::vector<DataDir> shipped_data_dirs();

// arenas/esogu-6x4.json from the first place that has it; throws
// Error(Io) naming every place looked when none has it.
std::filesystem::path shipped_default_arena();
// models/ramps-dgcnn.safetensors (`run --classifier dgcnn` without --model),
// found and reported as shipped_default_arena is.
std::filesystem::path shipped_ramp_model();
// viewer.js, the browser viewer's script that `sarmap view` inlines, bundled
// by the build from web/viewer/ (web/CMakeLists.txt). The build-tree binary
// finds it in the build tree's share/sarmap/; otherwise found and reported as
// shipped_default_arena is, with how to build it when it is missing.
std::filesystem::path shipped_viewer_bundle();

}  // namespace sarmap::cli
