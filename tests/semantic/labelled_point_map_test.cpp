// Tests LabelledPointMap (one point per cell, exact score fusion) and
// MapBlockSchedule (membership and when a block is ready) against plain
// definitions on random and edge-case inputs.
#include <gtest/gtest.h>

#include <algorithm>
#include <cmath>
#include <cstdint>
#include <numbers>
#include <random>
#include <map>
#include <tuple>

#include <Eigen/Geometry>

#include "engine/core/error.hpp"
#include "engine/semantic/dgcnn/block_partition.hpp"
#include "engine/semantic/map/labelled_point_map.hpp"
#include "engine/semantic/map/map_block_schedule.hpp"

namespace sarmap {
namespace {

PointBuffer random_points(std::size_t n, unsigned seed, float extent) {
  std::mt19937 rng(seed);
  std::uniform_real_distribution<float> u(-extent, extent);
  PointBuffer points;
  for (std::size_t i = 0; i < n; ++i) points.push_back(u(rng), u(rng), 0.5f * u(rng));
  return points;
}

TEST(LabelledPointMap, KeepsTheFirstPointOfEachCell) {
  LabelledPointMap map(0.1, 3);
  const PointBuffer scan = random_points(5000, 1, 1.0f);
  std::vector<std::uint32_t> added;
  const std::vector<std::uint32_t> of_point = map.insert(scan, added);
  // Reference: the cells in order of first appearance.
  std::map<std::tuple<long, long, long>, std::size_t> first;
  for (std::size_t i = 0; i < scan.size(); ++i) {
    first.try_emplace({std::lround(std::floor(scan.x()[i] / 0.1)), std::lround(std::floor(scan.y()[i] / 0.1)),
                       std::lround(std::floor(scan.z()[i] / 0.1))},
                      i);
  }
  ASSERT_EQ(map.size(), first.size());
  EXPECT_EQ(added.size(), first.size());
  for (std::size_t i = 0; i < scan.size(); ++i) {
    const std::uint32_t p = of_point[i];
    ASSERT_LT(p, map.size());
    const std::size_t owner = first.at({std::lround(std::floor(scan.x()[i] / 0.1)),
                                        std::lround(std::floor(scan.y()[i] / 0.1)),
                                        std::lround(std::floor(scan.z()[i] / 0.1))});
    EXPECT_EQ(map.points().x()[p], scan.x()[owner]);
    EXPECT_EQ(map.points().z()[p], scan.z()[owner]);
    EXPECT_EQ(map.find(scan.x()[i], scan.y()[i], scan.z()[i]), p);
  }
  // The same points again add nothing.
  map.insert(scan, added);
  EXPECT_TRUE(added.empty());
  EXPECT_EQ(map.size(), first.size());
}

// Every voxel of several grids, against a check of every point: the
// default 0.025 m cells in 0.05 m voxels (two across) and in 0.1 m ones
// (four), cells as large as the voxels, and voxels no power of two of the
// cells across (the general path). Half the points lie on cell boundaries.
TEST(LabelledPointMap, EachVoxelVisitsExactlyItsPoints) {
  LabelledPointMap map(0.025, 2);
  PointBuffer scan = random_points(4000, 9, 0.6f);
  for (std::size_t i = 0; i < scan.size(); i += 2) {
    scan.x()[i] = static_cast<float>(std::round(scan.x()[i] / 0.025) * 0.025);
    scan.z()[i] = static_cast<float>(std::round(scan.z()[i] / 0.05) * 0.05);
  }
  std::vector<std::uint32_t> added;
  map.insert(scan, added);
  const PointBuffer& points = map.points();
  for (const double inv_resolution : {1 / 0.05, 1 / 0.1, 1 / 0.025, 1 / 0.06, 1 / 0.03}) {
    const auto voxel_of = [&](std::uint32_t p) {
      return std::tuple(std::int64_t(std::floor(double(points.x()[p]) * inv_resolution)),
                        std::int64_t(std::floor(double(points.y()[p]) * inv_resolution)),
                        std::int64_t(std::floor(double(points.z()[p]) * inv_resolution)));
    };
    std::map<std::tuple<std::int64_t, std::int64_t, std::int64_t>, std::vector<std::uint32_t>> expected;
    for (std::uint32_t p = 0; p < map.size(); ++p) expected[voxel_of(p)].push_back(p);
    for (const auto& [key, in_it] : expected) {
      const std::int64_t voxel[3] = {std::get<0>(key), std::get<1>(key), std::get<2>(key)};
      std::vector<std::uint32_t> got;
      map.for_each_in_voxel(voxel, inv_resolution, [&](std::uint32_t p) { got.push_back(p); });
      std::sort(got.begin(), got.end());
      ASSERT_EQ(got, in_it) << "voxel " << voxel[0] << " " << voxel[1] << " " << voxel[2] << " of "
                            << 1 / inv_resolution << " m";
    }
    const std::int64_t empty[3] = {1000, 0, 0};
    map.for_each_in_voxel(empty, inv_resolution, [&](std::uint32_t) { ADD_FAILURE() << "a point in an empty voxel"; });
  }
}

TEST(LabelledPointMap, SkipsPointsBeyondTheMapLimitsAndNonFiniteOnes) {
  LabelledPointMap map(0.025, 2);
  PointBuffer scan;
  scan.push_back(0.0f, 0.0f, 0.0f);
  scan.push_back(2.0e4f, 0.0f, 0.0f);
  scan.push_back(std::nanf(""), 0.0f, 0.0f);
  scan.push_back(-1.0e4f, 1.0e4f, -1.0e4f);  // at the limit: kept
  std::vector<std::uint32_t> added;
  const std::vector<std::uint32_t> of_point = map.insert(scan, added);
  EXPECT_EQ(map.size(), 2u);
  EXPECT_EQ(of_point[1], LabelledPointMap::kNoPoint);
  EXPECT_EQ(of_point[2], LabelledPointMap::kNoPoint);
  EXPECT_EQ(map.find(2.0e4, 0, 0), LabelledPointMap::kNoPoint);
  EXPECT_EQ(map.best_channel(of_point[0]), -1);
}

TEST(LabelledPointMap, FusionTakesABlockOutExactlyInAnyOrder) {
  LabelledPointMap map(0.05, 4);
  std::vector<std::uint32_t> added;
  map.insert(random_points(400, 2, 0.5f), added);
  std::mt19937 rng(5);
  std::uniform_int_distribution<int> score(0, 255);
  std::vector<std::uint32_t> all(map.size());
  for (std::uint32_t p = 0; p < map.size(); ++p) all[p] = p;
  std::vector<std::vector<std::uint8_t>> blocks(5, std::vector<std::uint8_t>(all.size() * 4));
  for (auto& b : blocks) {
    for (auto& s : b) s = static_cast<std::uint8_t>(score(rng));
  }
  for (const auto& b : blocks) map.fuse(all, b, +1);
  map.fuse(all, blocks[3], -1);
  map.fuse(all, blocks[0], -1);
  std::vector<float> mean(4);
  for (std::uint32_t p = 0; p < map.size(); ++p) {
    ASSERT_EQ(map.hits(p), 3u);
    map.mean_scores(p, mean.data());
    for (std::size_t c = 0; c < 4; ++c) {
      const double expected = (blocks[1][p * 4 + c] + blocks[2][p * 4 + c] + blocks[4][p * 4 + c]) / (3.0 * 255.0);
      EXPECT_NEAR(mean[c], expected, 1e-6);
    }
  }
  map.fuse(all, blocks[1], -1);
  map.fuse(all, blocks[2], -1);
  map.fuse(all, blocks[4], -1);
  for (std::uint32_t p = 0; p < map.size(); ++p) EXPECT_EQ(map.best_channel(p), -1);
  EXPECT_THROW(map.fuse(all, std::vector<std::uint8_t>(3), +1), Error);
}

// Merging against a reference: each of the other map's points, carried by
// the transform, lands in its cell; a new cell takes the point with its
// sums and block count, a shared cell keeps its own point and adds them.
TEST(LabelledPointMap, MergeAddsNewCellsAndSumsSharedOnes) {
  const std::size_t classes = 3;
  LabelledPointMap here(0.05, classes), other(0.05, classes);
  std::vector<std::uint32_t> added;
  here.insert(random_points(600, 3, 0.5f), added);
  other.insert(random_points(600, 4, 0.5f), added);
  std::mt19937 rng(6);
  std::uniform_int_distribution<int> score(0, 255);
  const auto fuse_random = [&](LabelledPointMap& map, int times) {
    std::vector<std::uint32_t> all(map.size());
    for (std::uint32_t p = 0; p < map.size(); ++p) all[p] = p;
    for (int t = 0; t < times; ++t) {
      std::vector<std::uint8_t> block(all.size() * classes);
      for (auto& v : block) v = static_cast<std::uint8_t>(score(rng));
      map.fuse(all, block, +1);
    }
  };
  fuse_random(here, 2);
  fuse_random(other, 1);
  const LabelledPointMap before = here;
  // A quarter turn and a whole-cell shift: other's cells land on cells.
  const Pose turn(Eigen::AngleAxisd(std::numbers::pi / 2, Eigen::Vector3d::UnitZ()).toRotationMatrix(),
                  Eigen::Vector3d(0.25, 0.0, 0.0));
  const std::size_t new_points = here.merge(other, turn);
  EXPECT_EQ(here.size(), before.size() + new_points);
  std::size_t shared = 0;
  for (std::uint32_t p = 0; p < other.size(); ++p) {
    const Eigen::Vector3d at = turn * Eigen::Vector3d(other.points().x()[p], other.points().y()[p], other.points().z()[p]);
    const std::uint32_t q = here.find(at.x(), at.y(), at.z());
    ASSERT_NE(q, LabelledPointMap::kNoPoint);
    const std::uint32_t old = q < before.size() ? q : LabelledPointMap::kNoPoint;
    shared += old != LabelledPointMap::kNoPoint;
    EXPECT_EQ(here.hits(q), other.hits(p) + (old != LabelledPointMap::kNoPoint ? before.hits(old) : 0));
    for (std::size_t c = 0; c < classes; ++c) {
      const std::uint32_t mine = old != LabelledPointMap::kNoPoint ? before.score_sums(old)[c] : 0;
      EXPECT_EQ(here.score_sums(q)[c], other.score_sums(p)[c] + mine);
    }
    if (old == LabelledPointMap::kNoPoint) {
      EXPECT_NEAR(here.points().x()[q], at.x(), 1e-6);
    }
  }
  EXPECT_GT(shared, 10u);
  EXPECT_EQ(new_points + shared, other.size());
  // Another cell size or class count is refused, and nothing changes.
  LabelledPointMap coarse(0.1, classes), fewer(0.05, 2);
  coarse.insert(random_points(50, 7, 0.5f), added);
  const std::size_t size = here.size();
  EXPECT_THROW(here.merge(coarse, Pose()), Error);
  EXPECT_THROW(here.merge(fewer, Pose()), Error);
  EXPECT_EQ(here.size(), size);
}

TEST(LabelledPointMap, StateReloadsAndRefusesAnotherCell) {
  LabelledPointMap map(0.05, 2);
  std::vector<std::uint32_t> added;
  map.insert(random_points(300, 3, 1.0f), added);
  std::vector<std::uint8_t> scores(added.size() * 2, 100);
  map.fuse(added, scores, +1);
  StateWriter out;
  map.save_state(out);
  LabelledPointMap again(0.05, 2);
  StateReader in(out.bytes(), "state");
  again.load_state(in);
  ASSERT_EQ(again.size(), map.size());
  for (std::uint32_t p = 0; p < map.size(); ++p) {
    EXPECT_EQ(again.find(map.points().x()[p], map.points().y()[p], map.points().z()[p]), p);
    EXPECT_EQ(again.hits(p), 1u);
  }
  LabelledPointMap other(0.1, 2);
  StateReader in2(out.bytes(), "state");
  EXPECT_THROW(other.load_state(in2), Error);
  EXPECT_THROW(LabelledPointMap(0.005, 2), Error);
  EXPECT_THROW(LabelledPointMap(0.05, 0), Error);
}

TEST(MapBlockSchedule, EachPointJoinsEveryBlockThatHoldsIt) {
  MapBlockSettings settings;
  settings.min_points = 1;
  MapBlockSchedule schedule(settings);
  const PointBuffer points = random_points(2000, 4, 3.0f);
  std::vector<std::uint32_t> all(points.size());
  for (std::uint32_t p = 0; p < points.size(); ++p) all[p] = p;
  schedule.add_points(points, all);
  // Reference: the exact interval test over a window of block indices.
  std::map<std::pair<long long, long long>, std::vector<std::uint32_t>> expected;
  for (std::uint32_t p = 0; p < points.size(); ++p) {
    for (long long j = -8; j <= 8; ++j) {
      for (long long i = -8; i <= 8; ++i) {
        const double x = points.x()[p], y = points.y()[p];
        if (i * 0.75 <= x && x < i * 0.75 + 1.0 && j * 0.75 <= y && y < j * 0.75 + 1.0) expected[{j, i}].push_back(p);
      }
    }
  }
  EXPECT_EQ(schedule.block_count(), expected.size());
  for (const auto& [key, members] : expected) {
    const MapBlock* block = schedule.find(key.second, key.first);
    ASSERT_NE(block, nullptr);
    EXPECT_EQ(block->points, members);
  }
  // Points exactly on block edges belong to the block that starts there.
  MapBlockSchedule edges(settings);
  PointBuffer on_edge;
  on_edge.push_back(0.75f, 1.5f, 0.0f);
  const std::vector<std::uint32_t> first{0};
  edges.add_points(on_edge, first);
  EXPECT_NE(edges.find(1, 2), nullptr);
  EXPECT_NE(edges.find(0, 1), nullptr);
  EXPECT_EQ(edges.find(0, 0), nullptr);  // [0, 1) in x holds 0.75 but [0, 1) in y misses 1.5
  EXPECT_EQ(edges.block_count(), 4u);
}

// One unit block (block size = stride = 1 m) that points are added to a
// batch at a time; classify_ready() marks the ready blocks classified, as
// the classifier does, and says how many there were.
class OneBlock {
 public:
  explicit OneBlock(std::size_t min_new_points) : schedule_(settings(min_new_points)) {}

  void add(int n) {
    std::vector<std::uint32_t> batch;
    for (int k = 0; k < n; ++k) {
      batch.push_back(static_cast<std::uint32_t>(points_.size()));
      points_.push_back(0.5f, 0.5f, 0.0f);
    }
    schedule_.add_points(points_, batch);
  }
  std::size_t classify_ready() {
    const std::vector<MapBlock*> ready = schedule_.ready();
    for (MapBlock* block : ready) block->classified_points = block->points.size();
    return ready.size();
  }

 private:
  static MapBlockSettings settings(std::size_t min_new_points) {
    MapBlockSettings s;
    s.block_size = 1.0;
    s.stride = 1.0;
    s.min_points = 100;
    s.growth = 0.25;
    s.min_new_points = min_new_points;
    return s;
  }

  MapBlockSchedule schedule_;
  PointBuffer points_;
};

TEST(MapBlockSchedule, ABlockIsReadyAtItsMinimumThenOnlyAfterGrowingEnough) {
  OneBlock block(0);
  block.add(99);
  EXPECT_EQ(block.classify_ready(), 0u);
  block.add(1);
  EXPECT_EQ(block.classify_ready(), 1u);
  block.add(24);  // 124 < 1.25 x 100
  EXPECT_EQ(block.classify_ready(), 0u);
  block.add(1);  // 125
  EXPECT_EQ(block.classify_ready(), 1u);
  EXPECT_EQ(block.classify_ready(), 0u);  // nothing grew since, nothing unseen
  block.add(1);  // one new point: not grown enough, then quiet
  EXPECT_EQ(block.classify_ready(), 0u);
  EXPECT_EQ(block.classify_ready(), 1u);  // with min_new_points 0, one unseen point is enough
  EXPECT_THROW(MapBlockSchedule({1.0, 1.5, 100, 0.25}), Error);
  EXPECT_THROW(MapBlockSchedule({1.0, 0.01, 100, 0.25}), Error);
  EXPECT_THROW(MapBlockSchedule({1.0, 0.5, 100, -1.0}), Error);
}

TEST(MapBlockSchedule, ABlockClassifiedBeforeWaitsForItsMinimumOfNewPointsGrowingOrQuiet) {
  OneBlock block(50);
  block.add(100);
  EXPECT_EQ(block.classify_ready(), 1u);  // the first classification needs only min_points
  block.add(30);                          // 130 >= 1.25 x 100, but 30 new points
  EXPECT_EQ(block.classify_ready(), 0u);
  EXPECT_EQ(block.classify_ready(), 0u);  // quiet, with 30 unseen points: still waiting
  block.add(19);                          // 49 new
  EXPECT_EQ(block.classify_ready(), 0u);
  block.add(1);  // 50 new
  EXPECT_EQ(block.classify_ready(), 1u);
  // Large blocks: the fraction decides (25 % of 150 = 37.5 < 50; 25 % of 500 = 125 > 50).
  block.add(350);
  EXPECT_EQ(block.classify_ready(), 1u);  // 500
  block.add(100);                         // 600 < 625
  EXPECT_EQ(block.classify_ready(), 0u);
  EXPECT_EQ(block.classify_ready(), 1u);  // quiet with 100 unseen points
}

// The block a long-waiting point is classified with: of the blocks holding
// it with min_points and unseen points, the one whose centre is nearest,
// against a search over every block of a window.
TEST(MapBlockSchedule, TheMostCentralUnfinishedBlockOfAPointMatchesASearchOfEveryBlock) {
  MapBlockSettings settings;  // 1 m blocks every 0.75 m
  settings.min_points = 30;
  MapBlockSchedule schedule(settings);
  const PointBuffer points = random_points(3000, 7, 3.0f);
  std::vector<std::uint32_t> first, rest;
  for (std::uint32_t p = 0; p < points.size(); ++p) (p < 2000 ? first : rest).push_back(p);
  schedule.add_points(points, first);
  for (MapBlock* block : schedule.ready()) block->classified_points = block->points.size();
  // Some blocks get new points, some stay as classified; the edges keep fewer than min_points.
  std::erase_if(rest, [&](std::uint32_t p) { return points.x()[p] > 1.0f; });
  schedule.add_points(points, rest);
  std::size_t found = 0, none = 0;
  for (std::uint32_t p = 0; p < points.size(); p += 7) {
    const double x = points.x()[p], y = points.y()[p];
    const MapBlock* expected = nullptr;
    double nearest = 0.0;
    for (long long j = -8; j <= 8; ++j) {
      for (long long i = -8; i <= 8; ++i) {
        const MapBlock* block = schedule.find(i, j);
        if (!block || !(i * 0.75 <= x && x < i * 0.75 + 1.0 && j * 0.75 <= y && y < j * 0.75 + 1.0)) continue;
        if (block->points.size() < 30 || block->points.size() == block->classified_points) continue;
        const double d = std::hypot(x - (i * 0.75 + 0.5), y - (j * 0.75 + 0.5));
        if (!expected || d < nearest) {
          expected = block;
          nearest = d;
        }
      }
    }
    EXPECT_EQ(schedule.most_central_unfinished(x, y), expected) << x << ", " << y;
    (expected ? found : none) += 1;
  }
  EXPECT_GT(found, 50u);
  EXPECT_GT(none, 50u);  // held only by blocks classified with all their points, or too sparse
}

}  // namespace
}  // namespace sarmap
