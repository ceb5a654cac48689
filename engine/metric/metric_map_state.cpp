// The metric map's part of a checkpoint: its resolution and fusion as a check,
// then every block in (z, y, x) order as the map holds it: its key, one
// log-odds byte or 512, the evidence mask and a six-byte row per voxel that
// has evidence (the .sarmap file's layout, in native byte order).
#include <algorithm>
#include <array>
#include <cstdlib>
#include <string>

#include "engine/core/error.hpp"
#include "engine/metric/metric_map.hpp"

namespace sarmap::metric {

namespace {
constexpr std::uint8_t kUniformState = 0;
constexpr std::uint8_t kSlabState = 1;
using EvidenceMask = std::array<std::uint64_t, SemanticBlock::kMaskWords>;
using StoredSlab = std::array<std::int8_t, kBlockVoxels>;
}  // namespace

void MetricMap::save_state(StateWriter& out) const {
  out.tag("MMAP");
  out.put<double>(settings_.resolution);
  out.put<std::uint8_t>(static_cast<std::uint8_t>(settings_.fusion.fusion));
  const std::vector<BlockKey> keys = blocks_.sorted_block_keys();
  out.put<std::uint64_t>(keys.size());
  for (const BlockKey& key : keys) {
    const SemanticBlock& block = *blocks_.find(key);
    out.put(key);
    // By value, as the file: a slab whose voxels all agree is written as one.
    if (SemanticBlocks::uniform_slab(block)) {
      out.put(kUniformState);
      out.put(stored_log_odds(block.log_odds(0)));
    } else {
      out.put(kSlabState);
      StoredSlab slab;
      std::copy(block.log_odds_slab(), block.log_odds_slab() + kBlockVoxels, slab.begin());
      out.put(slab);
    }
    out.put(block.evidence_mask());
    for (int l = 0; l < kBlockVoxels; ++l) {
      if (block.holds_evidence(l)) out.put(stored_evidence(block.evidence(l)));
    }
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
  const std::size_t count = in.get_count(sizeof(BlockKey) + 2 + sizeof(EvidenceMask));
  const std::int64_t max_block = static_cast<std::int64_t>((kMaxCoordinate / resolution) / kBlockEdge) + 1;
  Blocks loaded;
  for (std::size_t b = 0; b < count; ++b) {
    const auto key = in.get<BlockKey>();
    const auto beyond = [max_block](std::int32_t v) { return std::abs(std::int64_t{v}) > max_block; };
    if (beyond(key.x) || beyond(key.y) || beyond(key.z)) in.fail("a map block lies beyond the map limits");
    if (loaded.find(key) != nullptr) in.fail("a map block is stored twice");
    DenseVoxels voxels;
    const auto kind = in.get<std::uint8_t>();
    if (kind == kUniformState) {
      const std::int16_t log_odds = log_odds_of(in.get<std::int8_t>());
      for (SemanticVoxel& v : voxels) v.log_odds = log_odds;
    } else if (kind == kSlabState) {
      const auto slab = in.get<StoredSlab>();
      for (int l = 0; l < kBlockVoxels; ++l) voxels[l].log_odds = log_odds_of(slab[l]);
    } else {
      in.fail("a map block has an unknown occupancy kind " + std::to_string(kind));
    }
    const auto mask = in.get<EvidenceMask>();
    for (int l = 0; l < kBlockVoxels; ++l) {
      if (!((mask[l >> 6] >> (l & 63)) & 1u)) continue;
      const ClassEvidence evidence = evidence_of(in.get<StoredEvidence>());
      if (no_evidence(evidence) || !storable_evidence(evidence)) {
        in.fail("a map voxel's evidence row is all zero or outside +-" + std::to_string(kMaxEvidence));
      }
      voxels[l].evidence = evidence;
    }
    loaded.assign(key, voxels);
  }
  blocks_ = std::move(loaded);
}

}  // namespace sarmap::metric
