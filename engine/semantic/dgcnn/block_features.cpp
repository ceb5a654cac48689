// Per-block DGCNN features, computed in double and rounded once to float like
// the Python reference (numpy float64 then astype("<f4")).
#include "engine/semantic/dgcnn/block_features.hpp"

#include <string>

#include "engine/core/error.hpp"

namespace sarmap {

std::vector<float> block_features(const PointBuffer& points, std::span<const std::uint32_t> indices,
                                  const BlockFrame& frame, bool with_rgb) {
  if (!(frame.block_size > 0.0)) {
    throw Error(ErrorCode::InvalidArgument, "block_features: block_size must be > 0, got " + std::to_string(frame.block_size));
  }
  if (!(frame.z_max > frame.z_min)) {
    throw Error(ErrorCode::InvalidArgument, "block_features: z_max must exceed z_min");
  }
  if (with_rgb && !points.has_colors()) {
    throw Error(ErrorCode::InvalidArgument, "block_features: colour features requested but the cloud has no colours");
  }
  const std::size_t channels = with_rgb ? 9 : 6;
  std::vector<float> out(indices.size() * channels);
  const double cx = frame.origin_x + 0.5 * frame.block_size;
  const double cy = frame.origin_y + 0.5 * frame.block_size;
  const double z_range = frame.z_max - frame.z_min;
  for (std::size_t i = 0; i < indices.size(); ++i) {
    const std::uint32_t p = indices[i];
    if (p >= points.size()) {
      throw Error(ErrorCode::InvalidArgument, "block_features: index " + std::to_string(p) + " past the cloud's " +
                                                  std::to_string(points.size()) + " points");
    }
    const double x = points.x()[p], y = points.y()[p], z = points.z()[p];
    float* row = out.data() + i * channels;
    row[0] = static_cast<float>(x - cx);
    row[1] = static_cast<float>(y - cy);
    row[2] = static_cast<float>(z);
    std::size_t c = 3;
    if (with_rgb) {
      row[c++] = static_cast<float>(points.red()[p] / 255.0);
      row[c++] = static_cast<float>(points.green()[p] / 255.0);
      row[c++] = static_cast<float>(points.blue()[p] / 255.0);
    }
    row[c++] = static_cast<float>((x - frame.origin_x) / frame.block_size);
    row[c++] = static_cast<float>((y - frame.origin_y) / frame.block_size);
    row[c] = static_cast<float>((z - frame.z_min) / z_range);
  }
  return out;
}

}  // namespace sarmap
