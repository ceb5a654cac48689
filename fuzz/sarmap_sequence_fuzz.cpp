// libFuzzer target: sarmap's sequence folder index, sequence.json
// (engine/io/sarmap_sequence_manifest.hpp, parse_sequence_manifest from
// memory), then the folder opened as a scan source (open_sarmap_sequence) and
// its first frames read: the frame paths, poses and sensor-frame transforms the
// manifest names. The folder holds two small PLY frames, frame_000000.ply and
// frame_000001.ply (those of tests/data/sequences/tiny).
#include <cstddef>
#include <cstdint>

#include "engine/core/error.hpp"
#include "engine/core/scan.hpp"
#include "engine/io/sarmap_sequence.hpp"
#include "engine/io/sarmap_sequence_manifest.hpp"
#include "fuzz/fuzz_support.hpp"

namespace {

constexpr const char* kFrame0 =
    "ply\nformat ascii 1.0\nelement vertex 3\nproperty float x\nproperty float y\nproperty float z\n"
    "property uchar label\nend_header\n0 0 1 1\n1 0 1 2\n0 1 1 2\n";
constexpr const char* kFrame1 =
    "ply\nformat ascii 1.0\nelement vertex 2\nproperty float x\nproperty float y\nproperty float z\n"
    "property uchar label\nend_header\n0 0 2 1\n0.5 0.5 2 3\n";

const std::filesystem::path& sequence_folder() {
  static const std::filesystem::path folder = [] {
    const std::filesystem::path dir = sarmap::fuzz::scratch() / "sequence";
    std::filesystem::create_directories(dir);
    sarmap::fuzz::write_file(dir / "frame_000000.ply", kFrame0);
    sarmap::fuzz::write_file(dir / "frame_000001.ply", kFrame1);
    return dir;
  }();
  return folder;
}

}  // namespace

extern "C" int LLVMFuzzerTestOneInput(const std::uint8_t* data, std::size_t size) {
  const std::string_view text = sarmap::fuzz::as_text(data, size);
  try {
    (void)sarmap::parse_sequence_manifest(text, "fuzz/sequence.json");
  } catch (const sarmap::Error& e) {
    sarmap::fuzz::refused(e);  // refused with a message: the expected outcome
    return 0;
  }
  // Only a manifest that parses is worth a folder: it must open and read, or be refused.
  sarmap::fuzz::write_file(sequence_folder() / "sequence.json", text);
  try {
    const auto source = sarmap::open_sarmap_sequence(sequence_folder());
    sarmap::Scan scan;
    for (int i = 0; i < 4 && source->next(scan); ++i) {
    }
  } catch (const sarmap::Error& e) {
    sarmap::fuzz::refused(e);
    // A frame refused with a message: also expected.
  }
  return 0;
}
