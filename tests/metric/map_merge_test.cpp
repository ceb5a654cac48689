// Merging metric maps: the voxel rule against its definition on random
// values, and whole maps against mapping a sequence whole (exact where one
// part saw a voxel, within the documented bound where both did).
#include "engine/metric/map_merge.hpp"

#include <gtest/gtest.h>

#include <algorithm>
#include <cstdio>
#include <cstring>
#include <random>
#include <string>
#include <vector>

#include "engine/core/error.hpp"
#include "engine/metric/ray_integrator.hpp"
#include "tests/metric/synthetic_room.hpp"

namespace sarmap::metric {
namespace {

constexpr double kResolution = 0.1;

// Strong hits and misses, so that voxels seen a few times reach the clamps,
// and points with 3 cm of noise, so that voxels near a surface are hit by
// some scans and missed by others: the order of updates matters only where
// a voxel's walk reaches a clamp and turns back.
MetricMap map_frames(int first, int last, ClassFusion fusion, double resolution = kResolution) {
  MetricMapSettings s = settings_at_resolution(resolution);
  s.fusion.fusion = fusion;
  s.occupancy.prob_hit = 0.9;
  s.occupancy.prob_miss = 0.2;
  MetricMap map(s);
  RayIntegrator integrator;
  testing::SyntheticRoom room;
  for (int f = first; f < last; ++f) {
    auto scan = room.frame(f, 8, 48, 36);
    std::mt19937 rng(static_cast<unsigned>(f));
    std::normal_distribution<float> noise(0.0f, 0.03f);
    for (auto axis : {scan.points.x(), scan.points.y(), scan.points.z()}) {
      for (float& v : axis) v += noise(rng);
    }
    integrator.integrate(map, scan.points, scan.origin);
  }
  return map;
}

// Every voxel of every block either map holds, by key.
std::vector<VoxelKey> voxel_keys_of(const MetricMap& a, const MetricMap& b) {
  std::vector<BlockKey> blocks = a.blocks().sorted_block_keys();
  for (const BlockKey& k : b.blocks().sorted_block_keys()) blocks.push_back(k);
  std::sort(blocks.begin(), blocks.end(), [](const BlockKey& x, const BlockKey& y) { return pack(x) < pack(y); });
  blocks.erase(std::unique(blocks.begin(), blocks.end()), blocks.end());
  std::vector<VoxelKey> keys;
  for (const BlockKey& k : blocks) {
    for (int z = 0; z < kBlockEdge; ++z)
      for (int y = 0; y < kBlockEdge; ++y)
        for (int x = 0; x < kBlockEdge; ++x)
          keys.push_back({k.x * kBlockEdge + x, k.y * kBlockEdge + y, k.z * kBlockEdge + z});
  }
  return keys;
}

SemanticVoxel voxel_or_unknown(const MetricMap& map, const VoxelKey& key) {
  return map.blocks().voxel(key).value_or(SemanticVoxel{});
}

bool same(const SemanticVoxel& a, const SemanticVoxel& b) {
  return a.log_odds == b.log_odds && a.evidence == b.evidence;
}

TEST(MergeVoxels, AddsAndClampsAsAnObservationDoes) {
  const OccupancyModel occupancy;
  for (const ClassFusion fusion : {ClassFusion::Bayesian, ClassFusion::Histogram}) {
    LabelFusionSettings settings;
    settings.fusion = fusion;
    const LabelFusion fuse(settings);
    std::mt19937 rng(7);
    std::uniform_int_distribution<int> log_odds(occupancy.min(), occupancy.max());
    std::uniform_int_distribution<int> evidence(fusion == ClassFusion::Bayesian ? -fuse.evidence_clamp_units() : 0,
                                                fusion == ClassFusion::Bayesian ? fuse.evidence_clamp_units() : kMaxEvidence);
    for (int trial = 0; trial < 2000; ++trial) {
      SemanticVoxel a, b;
      a.log_odds = trial % 7 == 0 ? kUnknownLogOdds : static_cast<std::int16_t>(log_odds(rng));
      b.log_odds = trial % 5 == 0 ? kUnknownLogOdds : static_cast<std::int16_t>(log_odds(rng));
      for (std::size_t c = 1; c < kClassCount; ++c) {
        if (a.log_odds != kUnknownLogOdds && trial % 3 != 0) a.evidence[c] = static_cast<std::int16_t>(evidence(rng));
        if (b.log_odds != kUnknownLogOdds && trial % 4 != 0) b.evidence[c] = static_cast<std::int16_t>(evidence(rng));
      }
      const SemanticVoxel ab = merge_voxels(a, b, occupancy, fuse);
      ASSERT_TRUE(same(ab, merge_voxels(b, a, occupancy, fuse))) << "the merge is symmetric";
      // Occupancy: unknown is no observation; known values add and clamp.
      if (a.log_odds == kUnknownLogOdds || b.log_odds == kUnknownLogOdds) {
        EXPECT_EQ(ab.log_odds, a.log_odds == kUnknownLogOdds ? b.log_odds : a.log_odds);
      } else {
        EXPECT_EQ(ab.log_odds, std::clamp(a.log_odds + b.log_odds, int{occupancy.min()}, int{occupancy.max()}));
      }
      // Evidence: Bayesian sums clamp; histogram counts keep their ratios when halved.
      int largest = 0;
      for (std::size_t c = 0; c < kClassCount; ++c) largest = std::max(largest, a.evidence[c] + b.evidence[c]);
      for (std::size_t c = 0; c < kClassCount; ++c) {
        const int sum = a.evidence[c] + b.evidence[c];
        if (fusion == ClassFusion::Bayesian) {
          EXPECT_EQ(ab.evidence[c], std::clamp(sum, -fuse.evidence_clamp_units(), fuse.evidence_clamp_units()));
        } else {
          EXPECT_EQ(ab.evidence[c], largest > kMaxEvidence ? sum / 2 : sum) << "histogram counts, class " << c;
        }
      }
    }
  }
}

// Frames 0-5 and 6-11 of a circuit and a half (frame i + 8 looks where frame
// i did), mapped apart and merged, against all twelve mapped in order.
TEST(MapMerge, PartsMergedEqualTheWholeWhereOnePartSawAVoxelAndStayWithinTheBoundElsewhere) {
  for (const ClassFusion fusion : {ClassFusion::Bayesian, ClassFusion::Histogram}) {
    const MetricMap whole = map_frames(0, 12, fusion);
    const MetricMap first = map_frames(0, 6, fusion);
    const MetricMap second = map_frames(6, 12, fusion);
    MetricMap merged = map_frames(0, 6, fusion);
    const MergeCounts counts = merge_into(merged, second);
    EXPECT_GT(counts.blocks_added, 0u);
    EXPECT_GT(counts.blocks_merged, 0u);

    std::size_t only_one = 0, both = 0, both_same_state = 0, both_equal = 0;
    for (const VoxelKey& key : voxel_keys_of(whole, merged)) {
      const SemanticVoxel w = voxel_or_unknown(whole, key), m = voxel_or_unknown(merged, key);
      const SemanticVoxel a = voxel_or_unknown(first, key), b = voxel_or_unknown(second, key);
      const bool in_a = a.log_odds != kUnknownLogOdds, in_b = b.log_odds != kUnknownLogOdds;
      ASSERT_EQ(m.log_odds != kUnknownLogOdds, w.log_odds != kUnknownLogOdds) << "the same voxels are known";
      if (in_a != in_b) {
        ++only_one;
        ASSERT_TRUE(same(m, w)) << "a voxel only one part saw is the whole sequence's";
      } else if (in_a && in_b) {
        ++both;
        // Both lie between the later part's log-odds and it plus the earlier's.
        const int lo = std::min(int{b.log_odds}, b.log_odds + a.log_odds);
        const int hi = std::max(int{b.log_odds}, b.log_odds + a.log_odds);
        ASSERT_GE(w.log_odds, lo);
        ASSERT_LE(w.log_odds, hi);
        ASSERT_GE(m.log_odds, lo);
        ASSERT_LE(m.log_odds, hi);
        both_equal += m.log_odds == w.log_odds;
        both_same_state += merged.occupancy().state(m.log_odds) == whole.occupancy().state(w.log_odds);
      }
    }
    std::printf("%s: %zu voxels seen by one part, %zu by both: %zu equal, %zu in the same state\n",
                std::string(to_string(fusion)).c_str(), only_one, both, both_equal, both_same_state);
    EXPECT_GT(only_one, 1000u);
    EXPECT_GT(both, 1000u);
    // The clamps make the order matter only for voxels seen often: most
    // agree exactly and nearly all in state, but not all (else the bound
    // above was not put to the test).
    EXPECT_LT(both_equal, both);
    EXPECT_GT(static_cast<double>(both_equal) / both, 0.5) << both_equal << " of " << both;
    EXPECT_GT(static_cast<double>(both_same_state) / both, 0.97) << both_same_state << " of " << both;
    EXPECT_EQ(counts.voxels_in_both, both);
  }
}

TEST(MapMerge, WhichMapIsMergedIntoWhichDoesNotMatter) {
  const MetricMap first = map_frames(0, 3, ClassFusion::Bayesian);
  const MetricMap second = map_frames(2, 6, ClassFusion::Bayesian);
  MetricMap ab = map_frames(0, 3, ClassFusion::Bayesian);
  merge_into(ab, second);
  MetricMap ba = map_frames(2, 6, ClassFusion::Bayesian);
  merge_into(ba, first);
  ASSERT_EQ(ab.blocks().sorted_block_keys(), ba.blocks().sorted_block_keys());
  for (const BlockKey& k : ab.blocks().sorted_block_keys()) {
    const DenseVoxels x = ab.blocks().find(k)->dense(), y = ba.blocks().find(k)->dense();
    ASSERT_EQ(std::memcmp(x.data(), y.data(), sizeof(x)), 0);
  }
  // Into an empty map, a merge is a copy.
  MetricMap copy(first.settings());
  merge_into(copy, first);
  for (const BlockKey& k : first.blocks().sorted_block_keys()) {
    const DenseVoxels x = first.blocks().find(k)->dense(), y = copy.blocks().find(k)->dense();
    ASSERT_EQ(std::memcmp(x.data(), y.data(), sizeof(x)), 0);
  }
}

TEST(MapMerge, MapsOfDifferentSettingsAreRefusedNamingBoth) {
  MetricMap into = map_frames(0, 2, ClassFusion::Bayesian);
  const std::size_t blocks = into.blocks().block_count();
  const auto error_of = [&](const MetricMap& other) -> std::string {
    try {
      merge_into(into, other);
    } catch (const Error& e) {
      EXPECT_EQ(e.code(), ErrorCode::InvalidArgument);
      return e.what();
    }
    return "";
  };
  const std::string resolution = error_of(map_frames(2, 4, ClassFusion::Bayesian, 0.05));
  EXPECT_NE(resolution.find("different resolution: 0.100000 and 0.050000"), std::string::npos) << resolution;
  const std::string fusion = error_of(map_frames(2, 4, ClassFusion::Histogram));
  EXPECT_NE(fusion.find("different class fusion: bayesian and histogram"), std::string::npos) << fusion;
  MetricMapSettings clamp = into.settings();
  clamp.occupancy.clamp_max = 0.9;
  const std::string occupancy = error_of(MetricMap(clamp));
  EXPECT_NE(occupancy.find("occupancy clamp_max: 0.970000 and 0.900000"), std::string::npos) << occupancy;
  EXPECT_EQ(into.blocks().block_count(), blocks) << "a refused merge changes nothing";
}

}  // namespace
}  // namespace sarmap::metric
