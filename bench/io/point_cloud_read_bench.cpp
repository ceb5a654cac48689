// Read throughput of sarmap's point-cloud readers (MB/s of file read) on a
// 1M-point labelled cloud written to a temp folder at setup: binary PLY, binary
// and binary_compressed PCD, and ASCII of both for contrast. ReadFileBytes is
// the floor: reading the same binary PLY into memory without decoding.
#include <benchmark/benchmark.h>

#include <filesystem>
#include <string>
#include <unistd.h>

#include "engine/core/point_buffer.hpp"
#include "engine/io/file_bytes.hpp"
#include "engine/io/point_cloud_file.hpp"

namespace sarmap {
namespace {

constexpr std::size_t kPoints = 1'000'000;

// The clouds, written once per process and removed at exit.
class BenchFiles {
 public:
  static const BenchFiles& get() {
    static const BenchFiles files;
    return files;
  }
  std::filesystem::path path(const std::string& name) const { return dir_ / name; }

  ~BenchFiles() {
    std::error_code ignored;
    std::filesystem::remove_all(dir_, ignored);
  }

 private:
  BenchFiles() : dir_(std::filesystem::temp_directory_path() / ("sarmap_io_bench_" + std::to_string(::getpid()))) {
    std::filesystem::create_directories(dir_);
    PointBuffer cloud(kPoints);
    cloud.enable_labels();
    // A 1000 x 1000 grid of a gently curved floor, labels in stripes: values
    // like a real scan (not all-equal), so compression is not trivial.
    std::uint32_t noise = 12345;
    for (std::size_t i = 0; i < kPoints; ++i) {
      noise = noise * 1664525u + 1013904223u;
      const float jitter = static_cast<float>(noise >> 8) * 0x1p-24f * 0.01f;
      const float x = static_cast<float>(i % 1000) * 0.02f;
      const float y = static_cast<float>(i / 1000) * 0.02f;
      cloud.x()[i] = x + jitter;
      cloud.y()[i] = y - jitter;
      cloud.z()[i] = 0.05f * x * y + jitter;
      cloud.labels()[i] = static_cast<std::uint8_t>(1 + (i / 1000) % 4);
    }
    write_point_cloud(path("cloud_binary.ply"), cloud, {.binary = true});
    write_point_cloud(path("cloud_ascii.ply"), cloud, {.binary = false});
    write_point_cloud(path("cloud_binary.pcd"), cloud, {.binary = true});
    write_point_cloud(path("cloud_compressed.pcd"), cloud, {.binary = true, .compressed = true});
    write_point_cloud(path("cloud_ascii.pcd"), cloud, {.binary = false});
  }

  std::filesystem::path dir_;
};

void read_bench(benchmark::State& state, const char* name) {
  const std::filesystem::path path = BenchFiles::get().path(name);
  const auto file_size = static_cast<std::int64_t>(std::filesystem::file_size(path));
  std::size_t points = 0;
  for (auto _ : state) {
    const PointBuffer cloud = read_point_cloud(path);
    points = cloud.size();
    benchmark::DoNotOptimize(cloud.labels().data());
  }
  if (points != kPoints) state.SkipWithError("wrong point count read back");
  state.SetBytesProcessed(state.iterations() * file_size);
  state.counters["points/s"] =
      benchmark::Counter(static_cast<double>(state.iterations() * kPoints), benchmark::Counter::kIsRate);
  state.counters["file_MB"] = static_cast<double>(file_size) / 1e6;
}

void BM_ReadFileBytes(benchmark::State& state) {
  const std::filesystem::path path = BenchFiles::get().path("cloud_binary.ply");
  const auto file_size = static_cast<std::int64_t>(std::filesystem::file_size(path));
  for (auto _ : state) {
    const FileBytes bytes = read_file_bytes(path);
    benchmark::DoNotOptimize(bytes.data());
  }
  state.SetBytesProcessed(state.iterations() * file_size);
}

BENCHMARK(BM_ReadFileBytes)->Unit(benchmark::kMillisecond);
BENCHMARK_CAPTURE(read_bench, PlyBinary, "cloud_binary.ply")->Unit(benchmark::kMillisecond);
BENCHMARK_CAPTURE(read_bench, PcdBinary, "cloud_binary.pcd")->Unit(benchmark::kMillisecond);
BENCHMARK_CAPTURE(read_bench, PcdBinaryCompressed, "cloud_compressed.pcd")->Unit(benchmark::kMillisecond);
BENCHMARK_CAPTURE(read_bench, PlyAscii, "cloud_ascii.ply")->Unit(benchmark::kMillisecond);
BENCHMARK_CAPTURE(read_bench, PcdAscii, "cloud_ascii.pcd")->Unit(benchmark::kMillisecond);

}  // namespace
}  // namespace sarmap

BENCHMARK_MAIN();
