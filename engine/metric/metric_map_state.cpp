// The metric map's part of a checkpoint: its resolution and fusion as a check,
// then every block (key and its voxels as DenseVoxels) in (z, y, x) order.
#include <cstdlib>
#include <string>

#include "engine/core/error.hpp"
#include "engine/metric/metric_map.hpp"

namespace sarmap::metric {

void MetricMap::save_state(StateWriter& out) const {
  out.tag("MMAP");
  out.put<double>(settings_.resolution);
  out.put<std::uint8_t>(static_cast<std::uint8_t>(settings_.fusion.fusion));
  const std::vector<BlockKey> keys = blocks_.sorted_block_keys();
  out.put<std::uint64_t>(keys.size());
  for (const BlockKey& key : keys) {
    out.put(key);
    out.put(blocks_.find(key)->dense());
  }
}

void MetricMap::load_state(StateReader& in) {
  in.expect_tag("MMAP");
  const auto resolution = in.get<double>();
  const auto fusion = in.get<std::uint8_t>();
  if (resolution != settings_.resolution || fusion != static_cast<std::uint8_t>(settings_.fusion.fusion)) {
    in.fail("the saved metric map has voxel " + std::to_string(resolution) + " m and fusion " +
            std::to_string(fusion) + ", this run " + std::to_string(settings_.resolution) + " m and " +
            std::to_string(static_cast<int>(settings_.fusion.fusion)));
  }
  const std::size_t count = in.get_count(sizeof(BlockKey) + sizeof(DenseVoxels));
  const std::int64_t max_block = static_cast<std::int64_t>((kMaxCoordinate / resolution) / kBlockEdge) + 1;
  Blocks loaded;
  for (std::size_t b = 0; b < count; ++b) {
    const auto key = in.get<BlockKey>();
    const auto beyond = [max_block](std::int32_t v) { return std::abs(std::int64_t{v}) > max_block; };
    if (beyond(key.x) || beyond(key.y) || beyond(key.z)) in.fail("a map block lies beyond the map limits");
    if (loaded.find(key) != nullptr) in.fail("a map block is stored twice");
    const auto voxels = in.get<DenseVoxels>();
    for (const SemanticVoxel& v : voxels) {
      if (!Blocks::storable(v)) in.fail("a map voxel holds a value outside the stored range");
    }
    loaded.assign(key, voxels);
  }
  blocks_ = std::move(loaded);
}

}  // namespace sarmap::metric
