// Writes datasets/fixtures/small_cloud.ply (or the path given as argument)
// from make_small_arena_cloud(): sarmap_make_small_cloud [output.ply]
#include <cstdio>
#include <exception>

#include "engine/io/ply.hpp"
#include "small_cloud_generator.hpp"

int main(int argc, char** argv) {
  try {
    const std::filesystem::path out =
        argc > 1 ? std::filesystem::path(argv[1])
                 : std::filesystem::path(SARMAP_SOURCE_DIR) / "datasets/fixtures/small_cloud.ply";
    const sarmap::PointBuffer points = sarmap::test::make_small_arena_cloud();
    sarmap::write_ply(out, points);
    std::printf("wrote %zu points to %s\n", points.size(), out.c_str());
  } catch (const std::exception& e) {
    std::fprintf(stderr, "sarmap_make_small_cloud: %s\n", e.what());
    return 1;
  }
  return 0;
}
