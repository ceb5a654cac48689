// libFuzzer target: the arena description, datasets/arenas/*.json
// (engine/sim/arena.hpp, parse_arena from memory), then the triangles of every
// element it accepted (arena_meshes), the first thing simulate and eval do with
// an arena. Mesh paths resolve against a scratch folder holding one small OBJ,
// square.obj, so mesh elements can load.
#include <cstddef>
#include <cstdint>

#include "engine/core/error.hpp"
#include "engine/sim/arena.hpp"
#include "engine/sim/arena_mesh.hpp"
#include "fuzz/fuzz_support.hpp"

namespace {

const std::filesystem::path& mesh_folder() {
  static const std::filesystem::path folder = [] {
    const std::filesystem::path dir = sarmap::fuzz::scratch() / "arena";
    std::filesystem::create_directories(dir);
    sarmap::fuzz::write_file(dir / "square.obj",
                             "v 0 0 0.5\nv 1 0 0.5\nv 1 1 0.5\nv 0 1 0.5\nf 1 2 3\nf 1 3 4\n");
    return dir;
  }();
  return folder;
}

}  // namespace

extern "C" int LLVMFuzzerTestOneInput(const std::uint8_t* data, std::size_t size) {
  try {
    const sarmap::sim::Arena arena =
        sarmap::sim::parse_arena(sarmap::fuzz::as_text(data, size), "fuzz.json", mesh_folder());
    (void)sarmap::sim::arena_meshes(arena);
    (void)sarmap::sim::sensor_info(arena.sensor);
  } catch (const sarmap::Error& e) {
    sarmap::fuzz::refused(e);
    // A malformed description refused with a message: the expected outcome.
  }
  return 0;
}
