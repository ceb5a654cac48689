// What `sarmap view` puts into its page: the parts of a run folder the
// browser viewer draws, read with the engine's own readers and packed as
// compact JSON (large arrays as base64 little-endian typed arrays), one entry
// per layer that the run has. The viewer (web/viewer/) reads this shape.
#pragma once

#include <cstddef>
#include <filesystem>
#include <string>
#include <vector>

#include <nlohmann/json.hpp>

namespace sarmap::cli {

struct ViewDataOptions {
  // The largest number of points, voxels or free voxels drawn per layer;
  // above it a layer is thinned evenly and says how many it holds in all.
  std::size_t max_items = 500000;
  // A planned route (sarmap plan --out); empty when the run has none.
  std::filesystem::path path_file;
};

struct ViewData {
  nlohmann::ordered_json json;
  std::vector<std::string> notes;  // parts left out and why (an input that is gone)
};

// Reads the run folder `run` (already checked to be one). Throws
// sarmap::Error naming the file that cannot be read.
ViewData read_view_data(const std::filesystem::path& run, const ViewDataOptions& options);

// Standard base64 (RFC 4648) of raw bytes, for typed arrays in the page.
std::string base64(const void* data, std::size_t size);

}  // namespace sarmap::cli
