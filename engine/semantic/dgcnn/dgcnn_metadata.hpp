// What a sarmap DGCNN model file says about its use besides the weights: the
// string entries of its safetensors __metadata__ (k, block size and points,
// the feature normalisation, the model's own name of each logit and the
// sarmap class each counts for). A model without them
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
  // The model's own name of each logit (any strings: an S3DIS model's
  // "ceiling", "floor", ...); empty when the file does not say.
  std::vector<std::string> class_names;
  // Logit index -> the sarmap class it counts for: sarmap.class_map's entry
  // for its name, else default_sarmap_class(name).
  std::vector<ClassId> classes;

  bool has_preprocessing() const { return !normalisation.empty() && !classes.empty(); }
};

// The sarmap class a model's class name counts for when sarmap.class_map does
// not say: a sarmap class name ("wall") itself, "floor" and "ground" terrain
// (S3DIS, ScanNet and Semantic3D call the floor so), anything else other.
ClassId default_sarmap_class(const std::string& model_class);

// Parses the "sarmap.*" entries; a malformed value is a sarmap::Error naming
// `source` and the key. Absent keys keep their defaults.
DgcnnMetadata parse_dgcnn_metadata(const std::map<std::string, std::string>& entries, const std::string& source);

// The entries that parse back to `metadata` (for writing model files);
// sarmap.class_map holds only the names whose class is not the default.
std::map<std::string, std::string> dgcnn_metadata_entries(const DgcnnMetadata& metadata);

}  // namespace sarmap
