// What a sarmap DGCNN model file says about its use besides the weights: the
// string entries of its safetensors __metadata__ (k, block size and points,
// the feature normalisation, the class of each logit). A model without them
// (one converted from the reference code) gets k = 20 and can still run on
// prepared blocks; labelling clouds needs the preprocessing entries.
#pragma once

#include <cstddef>
#include <map>
#include <string>
#include <vector>

#include "engine/core/classes.hpp"

namespace sarmap {

// The only normalisation sarmap defines: x, y within the block's own cell,
// z over the fixed range [z_min, z_max] of the world frame (block_features.hpp).
inline constexpr const char* kCellXyFixedZ = "cell_xy_fixed_z";

// Four times the DGCNN authors' 4,096 points per block: the kNN is quadratic
// in the count, so a bigger block is refused, not run for minutes.
inline constexpr std::size_t kMaxPointsPerBlock = 16384;

struct DgcnnMetadata {
  std::size_t k = 20;
  std::size_t points_per_block = 4096;
  double block_size = 1.0;     // metres, square cells in xy
  std::string normalisation;   // kCellXyFixedZ, or empty when the file does not say
  double z_min = -0.5, z_max = 2.5;
  std::vector<ClassId> classes;  // logit index -> class; empty when the file does not say

  bool has_preprocessing() const { return !normalisation.empty() && !classes.empty(); }
};

// Parses the "sarmap.*" entries; a malformed value is a sarmap::Error naming
// `source` and the key. Absent keys keep their defaults.
DgcnnMetadata parse_dgcnn_metadata(const std::map<std::string, std::string>& entries, const std::string& source);

// The entries that parse back to `metadata` (for writing model files).
std::map<std::string, std::string> dgcnn_metadata_entries(const DgcnnMetadata& metadata);

}  // namespace sarmap
