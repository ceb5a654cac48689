// The end-voxel dedupe on its own: local groups that lose a voxel from their
// cache and open it again, merged into one group per voxel with every
// point's observation, in order of first appearance, identically through
// the dense table and the hash table; labels or scores as the class source.
#include "engine/metric/end_voxel_groups.hpp"

#include <gtest/gtest.h>

#include <algorithm>
#include <string>
#include <vector>

#include "engine/core/classes.hpp"

namespace sarmap::metric {
namespace {

// Points whose voxel (i % distinct, -3, 7) cycles through more voxels than
// the local cache holds, so every voxel is opened again on each round.
struct CyclingScan {
  PointBuffer points;
  std::vector<VoxelKey> keys;

  CyclingScan(int distinct, int rounds) {
    points.enable_labels();
    for (int r = 0; r < rounds; ++r) {
      for (int v = 0; v < distinct; ++v) {
        points.push_back(static_cast<float>(v), -3.0f, 7.0f);
        points.labels()[points.size() - 1] = static_cast<std::uint8_t>((v + r) % kClassCount);
        keys.push_back({v, -3, 7});
      }
    }
  }
};

std::vector<LocalEndGroups> group_in_stretches(const CyclingScan& scan, std::size_t stretch, const ClassSource& source) {
  std::vector<LocalEndGroups> stretches((scan.keys.size() + stretch - 1) / stretch);
  for (std::size_t i = 0; i < scan.keys.size(); ++i) stretches[i / stretch].add(pack(scan.keys[i]), i, source);
  return stretches;
}

TEST(EndVoxelGroups, VoxelsEvictedFromTheLocalCacheMergeIntoOneGroupEach) {
  const int distinct = 5000, rounds = 3;
  const CyclingScan scan(distinct, rounds);
  const ClassSource source = ClassSource::of(scan.points, true);
  const std::vector<LocalEndGroups> stretches = group_in_stretches(scan, 4096, source);
  std::size_t local = 0;
  for (const LocalEndGroups& s : stretches) local += s.keys().size();
  ASSERT_GT(local, static_cast<std::size_t>(distinct) * rounds / 2);  // the cache really missed

  for (const std::size_t dense_limit : {std::size_t{1} << 20, std::size_t{0}}) {
    EndVoxelGroups groups;
    groups.merge(stretches, dense_limit);
    EXPECT_EQ(groups.used_dense_table(), dense_limit != 0);
    ASSERT_EQ(groups.size(), static_cast<std::size_t>(distinct));
    for (int v = 0; v < distinct; ++v) {
      EXPECT_EQ(groups.keys()[v], (VoxelKey{v, -3, 7}));  // order of first appearance
      const ClassObservation& obs = groups.observations()[v];
      EXPECT_EQ(obs.points, static_cast<std::uint32_t>(rounds));
      for (int r = 0; r < rounds; ++r) EXPECT_GE(obs.counts[(v + r) % kClassCount], 1u);
      EXPECT_FALSE(obs.has_scores);
    }
    // The dense table is left clean: a second merge gives the same groups.
    EndVoxelGroups again = groups;
    again.merge(stretches, dense_limit);
    EXPECT_EQ(again.keys(), groups.keys());
  }
}

// What the merge reports while it goes on (the walk of the rays starts on
// it): counts that only grow, one after every kProgressGroups new groups and
// after each stretch, ending at the number of groups, and keys below a
// reported count that are already the final ones, at the addresses they
// keep; through either table.
TEST(EndVoxelGroups, ProgressReportsFinalKeysAsTheMergeGoesOn) {
  const int distinct = 3000, rounds = 2;
  const CyclingScan scan(distinct, rounds);
  const ClassSource source = ClassSource::of(scan.points, false);
  const std::vector<LocalEndGroups> stretches = group_in_stretches(scan, 1000, source);
  for (const std::size_t dense_limit : {std::size_t{1} << 20, std::size_t{0}}) {
    EndVoxelGroups groups;
    std::vector<std::size_t> reported;
    std::vector<std::vector<VoxelKey>> seen;  // the keys below each report, read as it is made
    const VoxelKey* first = nullptr;
    groups.merge(stretches, dense_limit, [&](std::size_t n) {
      reported.push_back(n);
      if (first == nullptr) first = groups.keys().data();
      EXPECT_EQ(groups.keys().data(), first);  // never moved
      seen.emplace_back(first, first + n);
    });
    ASSERT_EQ(groups.size(), static_cast<std::size_t>(distinct));
    ASSERT_FALSE(reported.empty());
    EXPECT_EQ(reported.back(), groups.size());
    EXPECT_TRUE(std::is_sorted(reported.begin(), reported.end()));
    // At least one report per kProgressGroups new groups, and one per stretch.
    EXPECT_GE(reported.size(), groups.size() / EndVoxelGroups::kProgressGroups + stretches.size() - 1);
    for (const std::vector<VoxelKey>& prefix : seen) {
      EXPECT_TRUE(std::equal(prefix.begin(), prefix.end(), groups.keys().begin()));
    }
  }
}

TEST(EndVoxelGroups, ScoresAreSummedPerVoxelAndTheSameThroughEitherTable) {
  CyclingScan scan(1500, 2);
  std::vector<std::size_t> channels;
  for (const ClassInfo& info : kClassTable) channels.push_back(scan.points.add_score(std::string(info.name)));
  for (std::size_t i = 0; i < scan.points.size(); ++i) {
    for (std::size_t c = 0; c < channels.size(); ++c) {
      scan.points.score(channels[c])[i] = c == i % kClassCount ? 0.75f : 0.05f;
    }
  }
  const ClassSource source = ClassSource::of(scan.points, true);
  ASSERT_EQ(source.scores.size(), kClassCount);
  const std::vector<LocalEndGroups> stretches = group_in_stretches(scan, 1000, source);
  EndVoxelGroups dense, hashed;
  dense.merge(stretches, std::size_t{1} << 20);
  hashed.merge(stretches, 0);
  ASSERT_EQ(dense.size(), 1500u);
  ASSERT_EQ(hashed.keys(), dense.keys());
  for (std::size_t v = 0; v < dense.size(); ++v) {
    const ClassObservation& a = dense.observations()[v];
    const ClassObservation& b = hashed.observations()[v];
    EXPECT_TRUE(a.has_scores);
    EXPECT_EQ(a.points, 2u);
    float total = 0;
    for (std::size_t c = 0; c < kClassCount; ++c) {
      EXPECT_EQ(a.score_sums[c], b.score_sums[c]);
      total += a.score_sums[c];
    }
    EXPECT_NEAR(total, 2 * (0.75f + 5 * 0.05f), 1e-5f);
  }
  // Without use_scores the labels are the source even when scores exist.
  EXPECT_TRUE(ClassSource::of(scan.points, false).scores.empty());
}

// add_labelled(key, label) is add() for a source without scores: the same
// groups in the same order and the same counts, with labels and without
// (class 0), saturating at 0xffff alike.
TEST(EndVoxelGroups, LabelledPointsFoldLikeAdd) {
  const CyclingScan scan(1500, 3);
  for (const bool with_labels : {true, false}) {
    // Without labels the source is empty and every point counts as class 0.
    const ClassSource source = with_labels ? ClassSource::of(scan.points, false) : ClassSource{};
    LocalEndGroups by_add, by_label;
    for (std::size_t i = 0; i < scan.keys.size(); ++i) {
      by_add.add(pack(scan.keys[i]), i, source);
      by_label.add_labelled(pack(scan.keys[i]), with_labels ? scan.points.labels()[i] : std::uint8_t{0});
    }
    // One voxel seen 70,000 times: its count saturates.
    for (std::size_t n = 0; n < 70000; ++n) {
      by_add.add(pack(VoxelKey{0, 0, 0}), 0, source);
      by_label.add_labelled(pack(VoxelKey{0, 0, 0}), with_labels ? scan.points.labels()[0] : std::uint8_t{0});
    }
    ASSERT_EQ(by_label.keys(), by_add.keys());
    for (std::size_t g = 0; g < by_add.keys().size(); ++g) {
      EXPECT_EQ(by_label.observations()[g].points, by_add.observations()[g].points);
      EXPECT_EQ(by_label.observations()[g].counts, by_add.observations()[g].counts);
      EXPECT_FALSE(by_label.observations()[g].has_scores);
    }
    EXPECT_EQ(by_label.observations().back().counts[with_labels ? scan.points.labels()[0] : 0], 0xffffu);
  }
}

}  // namespace
}  // namespace sarmap::metric
