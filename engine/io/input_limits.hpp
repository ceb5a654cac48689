// Limits on one input file, checked before anything is allocated for it: a
// hostile or broken file (a header declaring a billion points, a 200-byte
// PNG declaring 32768 x 32768) gets a clear error instead of taking the
// machine's memory. The defaults hold any real sensor's scan many times over;
// `sarmap` takes --max-file-mb and --max-scan-points to change them.
#pragma once

#include <cstddef>
#include <cstdint>
#include <string>

namespace sarmap {

struct InputLimits {
  // Bytes of one file read whole (a point cloud, a sequence's JSON).
  std::uint64_t max_file_bytes = std::uint64_t{4} << 30;
  // Points of one cloud or scan (declared in a PLY/PCD header, or a depth
  // image's pixels). A 128-beam LiDAR gives about 0.26 M, a 4K depth image 8.3 M.
  std::size_t max_points = 50'000'000;
};

// Throws sarmap::Error (OutOfRange) naming the file when a header declares
// more points than limits.max_points.
void check_declared_points(std::uint64_t declared, const InputLimits& limits, const std::string& file);

}  // namespace sarmap
