// Tests DgcnnMapClassifier with the fixture model on scans of a small scene
// that grows: blocks classified only when grown past the threshold, every
// point's scores the mean of the last scores of the blocks holding it, scan
// labels from the map, the same result for 1 and 2 threads, and a state that
// continues identically.
#include <gtest/gtest.h>

#include <algorithm>
#include <functional>
#include <map>
#include <memory>
#include <numeric>
#include <random>

#include <tbb/global_control.h>

#include "engine/core/classes.hpp"
#include "engine/core/error.hpp"
#include "engine/semantic/map/dgcnn_map_classifier.hpp"
#include "tests/release_only.hpp"
#include "tests/semantic/fixture_model.hpp"

namespace sarmap {
namespace {

const DgcnnModel& fixture_model() {
  static const DgcnnModel model = DgcnnModel::load(test::fixture_model_c6());
  return model;
}

// Scan k of a floor strip and a wall, seen a little further along each time.
PointBuffer growing_scan(int k) {
  std::mt19937 rng(100 + k);
  std::uniform_real_distribution<float> u(0.0f, 1.0f);
  PointBuffer scan;
  const float reach = 0.6f + 0.3f * static_cast<float>(k);
  for (int i = 0; i < 1500; ++i) scan.push_back(reach * u(rng), 1.5f * u(rng), 0.01f * u(rng));
  for (int i = 0; i < 800; ++i) scan.push_back(reach * u(rng), 1.6f, 1.2f * u(rng));
  return scan;
}

DgcnnMapClassifierSettings settings() {
  DgcnnMapClassifierSettings s;
  s.cell = 0.05;
  s.min_points = 100;
  s.growth = 0.25;
  s.min_new_points = 40;
  return s;
}

std::vector<PointBuffer> run(DgcnnMapClassifier& classifier, int scans, std::vector<DgcnnMapClassifyStats>* stats) {
  std::vector<PointBuffer> labelled;
  for (int k = 0; k < scans; ++k) {
    PointBuffer scan = growing_scan(k);
    const DgcnnMapClassifyStats s = classifier.classify(scan);
    if (stats) stats->push_back(s);
    labelled.push_back(std::move(scan));
  }
  return labelled;
}

// Block (i, j) before a scan: its size, the size it had when last
// classified, and how often it was.
struct BlockBefore {
  std::size_t points = 0, classified_points = 0;
  std::uint32_t classifications = 0;
};

TEST(DgcnnMapClassifier, ClassifiesABlockWhenItHasGrownPastTheThresholdOrStoppedGrowing) {
  RELEASE_ONLY();  // many network blocks, minutes under the sanitizers; the other cases cover the code there
  DgcnnMapClassifier classifier(fixture_model(), settings());
  std::vector<DgcnnMapClassifyStats> stats;
  std::size_t grown = 0, quiet = 0, held_back = 0;
  // Scans 0-7 grow the scene; 8 and 9 see what scan 0 saw, adding little.
  for (int k = 0; k < 10; ++k) {
    PointBuffer scan = growing_scan(k < 8 ? k : 0);
    std::map<std::pair<long long, long long>, BlockBefore> before;
    for (long long j = -2; j < 4; ++j) {
      for (long long i = -2; i < 6; ++i) {
        if (const MapBlock* b = classifier.blocks().find(i, j)) {
          before[{j, i}] = {b->points.size(), b->classified_points, b->classifications};
        }
      }
    }
    const DgcnnMapClassifyStats s = classifier.classify(scan);
    std::size_t reclassified = 0;
    for (long long j = -2; j < 4; ++j) {
      for (long long i = -2; i < 6; ++i) {
        const MapBlock* b = classifier.blocks().find(i, j);
        if (!b) continue;
        const BlockBefore old = before.count({j, i}) ? before[{j, i}] : BlockBefore{};
        const std::size_t n = b->points.size();
        const bool grew = n > old.points;
        // Grown past a quarter of its last classification and by 40 points
        // (or never classified), or not grown with points its last one did
        // not see (40 of them, if it was classified before).
        const std::size_t unseen = n - old.classified_points;
        const bool enough_new = old.classified_points == 0 || unseen >= 40;
        const bool due_to_growth = grew && n >= 100 && enough_new &&
                                   (old.classified_points == 0 || n >= 1.25 * old.classified_points);
        const bool due_to_quiet = !grew && n >= 100 && unseen > 0 && enough_new;
        held_back += n >= 100 && unseen > 0 && !enough_new && (!grew || n >= 1.25 * old.classified_points);
        const bool due = due_to_growth || due_to_quiet;
        EXPECT_EQ(b->classifications, old.classifications + (due ? 1 : 0)) << "scan " << k << " block " << i << "," << j;
        reclassified += b->classifications - old.classifications;
        grown += due_to_growth && old.classified_points > 0;
        quiet += due_to_quiet;
        if (b->classifications > 0) {
          EXPECT_EQ(b->scores.size(), b->classified_points * fixture_model().classes());
        }
      }
    }
    EXPECT_EQ(s.blocks, reclassified) << k;
    stats.push_back(s);
  }
  // Each way of becoming ready happened.
  EXPECT_GT(stats.front().blocks, 0u);
  EXPECT_GT(grown, 0u);
  EXPECT_GT(quiet, 0u);
  EXPECT_GT(held_back, 0u);  // grown enough or quiet, but with too few new points
  EXPECT_EQ(classifier.blocks_classified(),
            std::accumulate(stats.begin(), stats.end(), std::size_t{0},
                            [](std::size_t a, const DgcnnMapClassifyStats& s) { return a + s.blocks; }));
}

TEST(DgcnnMapClassifier, FinishClassifiesEveryBlockWithUnseenPoints) {
  DgcnnMapClassifier classifier(fixture_model(), settings());
  run(classifier, 3, nullptr);
  const std::size_t done = classifier.finish();
  EXPECT_GT(done, 0u);  // the last scan's new points wait for growth or a quiet scan
  for (long long j = -2; j < 4; ++j) {
    for (long long i = -2; i < 6; ++i) {
      const MapBlock* b = classifier.blocks().find(i, j);
      if (b && b->points.size() >= 100) {
        EXPECT_EQ(b->classified_points, b->points.size()) << i << "," << j;
      }
    }
  }
  EXPECT_EQ(classifier.finish(), 0u);
}

// How many scans each map point waits for its class, against a reference:
// runs `scans` scans through the classifier, asks every map point after
// every scan (and after finish()) whether it has a class, and compares the
// waits that gives with the classifier's own record.
void expect_delays_match_asking_every_point(DgcnnMapClassifier& classifier,
                                            const std::function<PointBuffer(int)>& scan_number,
                                            std::uint32_t scans) {
  std::vector<std::uint32_t> added_at, classed_at;  // by map point; classed_at 0: not yet
  const auto ask = [&](std::uint32_t number) {
    for (std::uint32_t p = 0; p < classifier.map().size(); ++p) {
      if (classed_at[p] == 0 && classifier.map_point_class(p) != ClassId::Unknown) classed_at[p] = number;
    }
  };
  for (std::uint32_t number = 1; number <= scans; ++number) {
    PointBuffer scan = scan_number(static_cast<int>(number) - 1);
    classifier.classify(scan);
    added_at.resize(classifier.map().size(), number);  // new map points come last
    classed_at.resize(classifier.map().size(), 0);
    ask(number);
  }
  classifier.finish();
  ask(scans);
  std::vector<std::uint64_t> reference;
  std::size_t never = 0;
  for (std::size_t p = 0; p < added_at.size(); ++p) {
    if (classed_at[p] == 0) {
      ++never;
      continue;
    }
    const std::uint32_t delay = classed_at[p] - added_at[p];
    if (reference.size() <= delay) reference.resize(delay + 1, 0);
    ++reference[delay];
  }
  const ClassDelays& delays = classifier.class_delays();
  EXPECT_EQ(delays.histogram(), reference);
  EXPECT_EQ(delays.waiting(), never);
  EXPECT_EQ(delays.recorded() + delays.waiting(), classifier.map().size());
  EXPECT_GT(reference.size(), 1u) << "some points should wait";
  EXPECT_GT(reference[0], 0u) << "some points should have their class at once";
}

TEST(DgcnnMapClassifier, ClassDelaysMatchAReferenceAskingEveryPointAfterEveryScan) {
  // Blocks of at least 400 map points: the edge of each scan's new strip waits.
  DgcnnMapClassifierSettings s = settings();
  s.min_points = 400;
  DgcnnMapClassifier classifier(fixture_model(), s);
  expect_delays_match_asking_every_point(classifier, growing_scan, 4);
}

// Scans of a floor seen in random patches, so that sparse blocks wait next
// to classified ones and their points borrow classes from neighbours in
// other blocks, which the growing strip above never makes them do.
TEST(DgcnnMapClassifier, ClassDelaysMatchTheReferenceOnPatchyScans) {
  DgcnnMapClassifierSettings s = settings();
  s.min_points = 150;
  s.min_new_points = 120;
  for (const unsigned seed : {1u, 2u, 3u}) {
    DgcnnMapClassifier classifier(fixture_model(), s);
    const auto patchy_scan = [seed](int k) {
      std::mt19937 rng(seed * 1000 + static_cast<unsigned>(k));
      std::uniform_real_distribution<float> centre(0.0f, 3.0f), offset(-0.35f, 0.35f), height(0.0f, 0.01f);
      PointBuffer scan;
      for (int patch = 0; patch < 3; ++patch) {
        const float cx = centre(rng), cy = centre(rng);
        for (int i = 0; i < 90; ++i) scan.push_back(cx + offset(rng), cy + offset(rng), height(rng));
      }
      return scan;
    };
    expect_delays_match_asking_every_point(classifier, patchy_scan, 10);
  }
}

// Blocks classified once and then never again for growth (a huge minimum of
// new points): the strip each scan adds beyond a cell of classified points
// waits for its class, unless max_wait_scans has its block classified.
TEST(DgcnnMapClassifier, APointWaitingMaxWaitScansHasItsBlockClassified) {
  constexpr std::uint32_t kScans = 6, kWait = 2;
  const auto classify_scans = [](std::size_t max_wait_scans, std::vector<std::uint32_t>& added_at) {
    DgcnnMapClassifierSettings s = settings();
    s.min_new_points = 1000000;
    s.max_wait_scans = max_wait_scans;
    auto classifier = std::make_unique<DgcnnMapClassifier>(fixture_model(), s);
    for (std::uint32_t number = 1; number <= kScans; ++number) {
      PointBuffer scan = growing_scan(static_cast<int>(number) - 1);
      classifier->classify(scan);
      added_at.resize(classifier->map().size(), number);  // new map points come last
    }
    return classifier;
  };
  std::vector<std::uint32_t> added_waiting, added_bounded;
  const auto waiting = classify_scans(0, added_waiting);
  const auto bounded = classify_scans(kWait, added_bounded);
  ASSERT_EQ(added_waiting, added_bounded);  // the same map points
  std::size_t still_waiting = 0;
  for (std::uint32_t p = 0; p < added_bounded.size(); ++p) {
    if (added_bounded[p] + kWait <= kScans) {
      EXPECT_NE(bounded->map_point_class(p), ClassId::Unknown) << "map point " << p << " of scan " << added_bounded[p];
    }
    still_waiting += waiting->map_point_class(p) == ClassId::Unknown;
  }
  EXPECT_GT(still_waiting, 0u) << "without the bound, some points should still wait";
  EXPECT_LE(bounded->class_delays().histogram().size(), kWait + 1);
  EXPECT_GT(waiting->class_delays().waiting(), bounded->class_delays().waiting());
  EXPECT_GT(bounded->blocks_classified(), waiting->blocks_classified());
}

// What a bounded map drops, the labelled point map lets go of; the rest keep
// their scores exactly, and the classifier goes on.
TEST(DgcnnMapClassifier, ForgettingARegionKeepsTheRestsClassesAndGoesOn) {
  DgcnnMapClassifier classifier(fixture_model(), settings());
  run(classifier, 5, nullptr);
  const LabelledPointMap& map = classifier.map();
  const std::size_t classes = fixture_model().classes();
  struct Kept {
    float x, y, z;
    std::vector<float> mean;
    std::uint32_t hits;
  };
  std::vector<Kept> expected;
  std::size_t beyond = 0;
  for (std::uint32_t p = 0; p < map.size(); ++p) {
    if (map.points().x()[p] > 1.0f) {
      ++beyond;
      continue;
    }
    Kept k{map.points().x()[p], map.points().y()[p], map.points().z()[p], std::vector<float>(classes), map.hits(p)};
    map.mean_scores(p, k.mean.data());
    expected.push_back(std::move(k));
  }
  ASSERT_GT(beyond, 0u);
  ASSERT_GT(expected.size(), 0u);
  EXPECT_EQ(classifier.forget([](double x, double, double) { return x > 1.0; }), beyond);
  ASSERT_EQ(map.size(), expected.size());
  std::vector<float> mean(classes);
  for (std::uint32_t p = 0; p < map.size(); ++p) {
    EXPECT_EQ(map.points().x()[p], expected[p].x);
    EXPECT_EQ(map.find(expected[p].x, expected[p].y, expected[p].z), p);
    EXPECT_EQ(map.hits(p), expected[p].hits);
    map.mean_scores(p, mean.data());
    EXPECT_EQ(mean, expected[p].mean) << p;
  }
  // Blocks name only kept points, with a score row per classified one.
  for (long long j = -2; j < 4; ++j) {
    for (long long i = -2; i < 6; ++i) {
      if (const MapBlock* b = classifier.blocks().find(i, j)) {
        EXPECT_FALSE(b->points.empty());
        for (const std::uint32_t p : b->points) EXPECT_LT(p, map.size());
        EXPECT_EQ(b->scores.size(), b->classified_points * classes);
      }
    }
  }
  EXPECT_EQ(classifier.forget([](double, double, double) { return false; }), 0u);
  // It goes on, and its state still reloads.
  PointBuffer scan = growing_scan(6);
  classifier.classify(scan);
  StateWriter out;
  classifier.save_state(out);
  DgcnnMapClassifier again(fixture_model(), settings());
  StateReader in(out.bytes(), "state");
  again.load_state(in);
  EXPECT_EQ(again.map().size(), map.size());
}

TEST(DgcnnMapClassifier, APointsScoresAreTheMeanOfItsBlocksLastScores) {
  DgcnnMapClassifier classifier(fixture_model(), settings());
  run(classifier, 6, nullptr);
  const LabelledPointMap& map = classifier.map();
  const std::size_t classes = fixture_model().classes();
  // Reference: sum each block's stored scores into its points from scratch.
  std::vector<double> sums(map.size() * classes, 0.0);
  std::vector<std::uint32_t> hits(map.size(), 0);
  for (long long j = -2; j < 4; ++j) {
    for (long long i = -2; i < 6; ++i) {
      const MapBlock* b = classifier.blocks().find(i, j);
      if (!b) continue;
      for (std::size_t k = 0; k < b->classified_points; ++k) {
        const std::uint32_t p = b->points[k];
        ++hits[p];
        for (std::size_t c = 0; c < classes; ++c) sums[p * classes + c] += b->scores[k * classes + c] / 255.0;
      }
    }
  }
  std::vector<float> mean(classes);
  std::size_t classified = 0;
  for (std::uint32_t p = 0; p < map.size(); ++p) {
    ASSERT_EQ(map.hits(p), hits[p]) << p;
    map.mean_scores(p, mean.data());
    for (std::size_t c = 0; c < classes; ++c) {
      EXPECT_NEAR(mean[c], hits[p] ? sums[p * classes + c] / hits[p] : 0.0, 1e-5);
    }
    classified += hits[p] > 0;
  }
  EXPECT_GT(classified, map.size() / 2);
}

TEST(DgcnnMapClassifier, ScanPointsTakeTheClassesOfTheirMapPoints) {
  DgcnnMapClassifier classifier(fixture_model(), settings());
  const std::vector<PointBuffer> scans = run(classifier, 4, nullptr);
  const PointBuffer& last = scans.back();
  const DgcnnMetadata& m = fixture_model().metadata();
  PointBuffer again = last;
  again.enable_labels();
  std::fill(again.labels().begin(), again.labels().end(), 0);
  const std::size_t unknown = classifier.relabel(again);
  std::size_t counted = 0;
  for (std::size_t i = 0; i < last.size(); ++i) {
    const std::uint32_t own = classifier.map().find(last.x()[i], last.y()[i], last.z()[i]);
    ASSERT_NE(own, LabelledPointMap::kNoPoint);
    // Its own map point's class, or a classified neighbour's while its block waits.
    const std::uint32_t p = classifier.map().scored_point(own);
    const int best = p == LabelledPointMap::kNoPoint ? -1 : classifier.map().best_channel(p);
    const auto expected = best < 0 ? ClassId::Unknown : m.classes[static_cast<std::size_t>(best)];
    // The network's class alone: the rules run after the classifier (rule_chain.hpp).
    EXPECT_EQ(last.labels()[i], static_cast<std::uint8_t>(expected)) << i;
    EXPECT_EQ(again.labels()[i], static_cast<std::uint8_t>(expected)) << i;
    counted += best < 0;
  }
  EXPECT_EQ(unknown, counted);
  ASSERT_EQ(last.score_count(), fixture_model().classes());
}

TEST(DgcnnMapClassifier, SparseBlocksStayUnknownUntilTheyFill) {
  DgcnnMapClassifierSettings s = settings();
  s.min_points = 10000;
  DgcnnMapClassifier classifier(fixture_model(), s);
  PointBuffer scan = growing_scan(0);
  const DgcnnMapClassifyStats stats = classifier.classify(scan);
  EXPECT_EQ(stats.blocks, 0u);
  EXPECT_EQ(stats.unlabelled, scan.size());
  EXPECT_TRUE(std::all_of(scan.labels().begin(), scan.labels().end(),
                          [](std::uint8_t l) { return l == static_cast<std::uint8_t>(ClassId::Unknown); }));
}

TEST(DgcnnMapClassifier, SameLabelsForOneAndTwoThreads) {
  RELEASE_ONLY();  // many network blocks, minutes under the sanitizers; the other cases cover the code there
  std::vector<PointBuffer> one, two;
  {
    tbb::global_control limit(tbb::global_control::max_allowed_parallelism, 1);
    DgcnnMapClassifier classifier(fixture_model(), settings());
    one = run(classifier, 5, nullptr);
  }
  {
    tbb::global_control limit(tbb::global_control::max_allowed_parallelism, 2);
    DgcnnMapClassifier classifier(fixture_model(), settings());
    two = run(classifier, 5, nullptr);
  }
  for (std::size_t k = 0; k < one.size(); ++k) {
    EXPECT_TRUE(std::equal(one[k].labels().begin(), one[k].labels().end(), two[k].labels().begin())) << k;
    for (std::size_t c = 0; c < one[k].score_count(); ++c) {
      EXPECT_TRUE(std::equal(one[k].score(c).begin(), one[k].score(c).end(), two[k].score(c).begin())) << k;
    }
  }
}

TEST(DgcnnMapClassifier, ALoadedStateContinuesIdentically) {
  RELEASE_ONLY();  // many network blocks, minutes under the sanitizers; the other cases cover the code there
  DgcnnMapClassifier straight(fixture_model(), settings());
  const std::vector<PointBuffer> expected = run(straight, 6, nullptr);
  DgcnnMapClassifier first(fixture_model(), settings());
  run(first, 3, nullptr);
  StateWriter out;
  first.save_state(out);
  DgcnnMapClassifier resumed(fixture_model(), settings());
  StateReader in(out.bytes(), "state");
  resumed.load_state(in);
  in.expect_end();
  for (int k = 3; k < 6; ++k) {
    PointBuffer scan = growing_scan(k);
    resumed.classify(scan);
    EXPECT_TRUE(std::equal(scan.labels().begin(), scan.labels().end(), expected[k].labels().begin())) << k;
  }
  EXPECT_EQ(resumed.blocks_classified(), straight.blocks_classified());
  EXPECT_EQ(resumed.class_delays().histogram(), straight.class_delays().histogram());
  EXPECT_EQ(resumed.class_delays().waiting(), straight.class_delays().waiting());
  // A damaged state (a block naming a point past the map) is refused.
  std::string bytes = out.bytes();
  DgcnnMapClassifierSettings other = settings();
  other.cell = 0.1;
  DgcnnMapClassifier wrong_cell(fixture_model(), other);
  StateReader in2(bytes, "state");
  EXPECT_THROW(wrong_cell.load_state(in2), Error);
}

}  // namespace
}  // namespace sarmap
