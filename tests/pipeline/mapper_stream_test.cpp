// Mapper::integrate_stream: scans fed as a stream build the same maps as one
// scan at a time through integrate(), with the stages overlapping or in
// order, on one thread or two, in one call or several; a bounded map's
// forgetting reaches the classifier at the same scan either way; frames that
// cannot be read and scans the Mapper refuses cost only themselves.
#include "engine/pipeline/mapper.hpp"

#include <gtest/gtest.h>
#include <tbb/global_control.h>

#include <algorithm>
#include <cmath>
#include <cstdio>
#include <filesystem>
#include <limits>
#include <string>
#include <utility>
#include <vector>

#include "engine/sim/arena.hpp"
#include "engine/sim/simulator.hpp"
#include "tests/pipeline/default_arena.hpp"
#include "tests/pipeline/same_maps.hpp"
#include "tests/semantic/fixture_model.hpp"

namespace sarmap::pipeline {
namespace {

using testing::default_arena;

// The classifier of the accumulated map with the small test network, on a
// map small enough that it forgets (the labelled point map among the rest).
MapperConfig bounded_map_classifier_config() {
  MapperConfig config;
  config.voxel = 0.1;
  config.semantic_points_voxel = 0.1;
  config.bounds.max_blocks = 100;
  config.classifier.kind = ClassifierKind::Dgcnn;
  config.classifier.model = test::fixture_model_c6();
  // Few, coarse blocks: the test is about when they run, not how well.
  config.classifier.dgcnn.min_points = 400;
  config.classifier.map_cell = 0.1;
  config.classifier.map_growth = 1.0;
  return config;
}

SensorInfo sensor() { return sim::sensor_info(default_arena().sensor); }

// Frames 0, stride, 2 stride, ... below `end`; a reader that hands them out,
// throwing for `unreadable` frames, giving `refused` ones a NaN origin and
// `bad_label` ones a point whose label is no class (the metric stage's rays
// refuse it, after the classify stage took the scan).
struct Frames {
  std::size_t end = 48, stride = 3;
  std::vector<std::size_t> unreadable, refused, bad_label;

  std::size_t count() const { return (end + stride - 1) / stride; }
  Scan scan(std::size_t frame) const {
    static const sim::Simulator simulator(default_arena());
    Scan scan = simulator.simulate(frame * stride);
    for (std::size_t f : refused) {
      if (f == frame) scan.origin.x() = std::numeric_limits<double>::quiet_NaN();
    }
    for (std::size_t f : bad_label) {
      if (f == frame) scan.points.labels()[scan.points.size() / 2] = 200;
    }
    return scan;
  }
  // Reads [from, to): false there.
  Mapper::ScanReader reader(std::size_t to) const {
    return [this, to](std::size_t frame, Scan& out) {
      if (frame >= to || frame >= count()) return false;
      for (std::size_t f : unreadable) {
        if (f == frame) throw Error(ErrorCode::Parse, "frame " + std::to_string(frame) + " is damaged");
      }
      out = scan(frame);
      return true;
    };
  }
};

void integrate_one_by_one(Mapper& mapper, const Frames& frames) {
  for (std::size_t f = 0; f < frames.count(); ++f) {
    Scan scan = frames.scan(f);
    mapper.integrate(scan);
  }
}

// Streams [0, count) in calls that end at each of `cuts`; returns the frames
// `done` saw, in order.
std::vector<std::size_t> stream(Mapper& mapper, const Frames& frames, StageOverlap overlap,
                                std::vector<std::size_t> cuts = {}) {
  std::vector<std::size_t> seen;
  cuts.push_back(frames.count());
  std::size_t from = 0;
  for (std::size_t to : cuts) {
    mapper.integrate_stream(from, frames.reader(to), [&](StreamedScan& s) { seen.push_back(s.frame); }, overlap);
    from = to;
  }
  return seen;
}

TEST(MapperStream, OverlappedStagesBuildTheSameMapsAsOneScanAtATime) {
  const Frames frames;
  const MapperConfig config = bounded_map_classifier_config();
  Mapper reference(config, sensor());
  integrate_one_by_one(reference, frames);
  // The case this guards: the labelled point map forgets while scans are in flight.
  ASSERT_GT(reference.profile().counter("classify", "map_points_forgotten"), 0.0);
  ASSERT_GT(reference.profile().counter("segment", "points_forgotten"), 0.0);

  for (const auto& [threads, overlap] : {std::pair{2, StageOverlap::Off}, std::pair{1, StageOverlap::On},
                                        std::pair{2, StageOverlap::On}}) {
    const tbb::global_control limit(tbb::global_control::max_allowed_parallelism, static_cast<std::size_t>(threads));
    {
      SCOPED_TRACE(std::to_string(threads) + " threads, overlap " + (overlap == StageOverlap::On ? "on" : "off"));
      Mapper streamed(config, sensor());
      const std::vector<std::size_t> seen = stream(streamed, frames, overlap);
      ASSERT_EQ(seen.size(), frames.count());
      for (std::size_t i = 0; i < seen.size(); ++i) EXPECT_EQ(seen[i], i);
      expect_same_maps(reference, streamed);
      for (const char* counter : {"map_points_forgotten", "map_points_added", "blocks"}) {
        EXPECT_EQ(streamed.profile().counter("classify", counter), reference.profile().counter("classify", counter))
            << counter;
      }
      // The stream times its reads too.
      std::vector<std::string> stages = streamed.profile().stage_names();
      ASSERT_EQ(stages.front(), "read");
      stages.erase(stages.begin());
      EXPECT_EQ(stages, reference.profile().stage_names());
    }
  }
}

// A caller reads or saves the Mapper between calls (snapshots, checkpoints):
// a forgetting pass still waiting for its classify stage waits across them.
TEST(MapperStream, AStreamCutIntoCallsBuildsTheSameMaps) {
  const Frames frames;
  const MapperConfig config = bounded_map_classifier_config();
  Mapper whole(config, sensor());
  stream(whole, frames, StageOverlap::On);
  Mapper cut(config, sensor());
  std::vector<std::size_t> cuts;
  for (std::size_t c = 1; c < frames.count(); c += 1 + c % 3) cuts.push_back(c);
  stream(cut, frames, StageOverlap::On, cuts);
  expect_same_maps(whole, cut);
}

// A scan whose rays are refused is refused after its rays were traced ahead
// (with stages overlapping) or not: either way nothing of it reaches the
// maps, and the scans after it go in with their own rays.
TEST(MapperStream, UnreadableFramesAndRefusedScansCostOnlyThemselves) {
  Frames frames;
  frames.end = 36;
  frames.unreadable = {2, 7};
  frames.refused = {4};
  frames.bad_label = {5, 6};
  MapperConfig config;
  config.voxel = 0.1;
  config.classifier.kind = ClassifierKind::Labels;
  const std::vector<std::size_t> lost = {2, 4, 5, 6, 7};
  Mapper reference(config, sensor());
  for (std::size_t f = 0; f < frames.count(); ++f) {
    if (std::find(lost.begin(), lost.end(), f) != lost.end()) continue;
    Scan scan = frames.scan(f);
    reference.integrate(scan);
  }
  for (StageOverlap overlap : {StageOverlap::Off, StageOverlap::On}) {
    SCOPED_TRACE(overlap == StageOverlap::On ? "overlap on" : "overlap off");
    Mapper mapper(config, sensor());
    std::vector<std::size_t> mapped, failed;
    mapper.integrate_stream(0, frames.reader(frames.count()), [&](StreamedScan& s) {
      (s.mapped ? mapped : failed).push_back(s.frame);
      if (s.mapped) return;
      ASSERT_TRUE(s.error.has_value());
      const std::string what = s.error->what();
      if (s.read_failed) {
        EXPECT_NE(what.find("damaged"), std::string::npos) << what;
        return;
      }
      EXPECT_NE(what.find("scan "), std::string::npos) << what;  // named
      const char* const cause = s.frame == 4 ? "origin" : "label";
      EXPECT_NE(what.find(cause), std::string::npos) << what;
    }, overlap);
    EXPECT_EQ(failed, lost);
    EXPECT_EQ(mapped.size(), frames.count() - lost.size());
    EXPECT_EQ(mapper.profile().scan_count(), mapped.size());
    EXPECT_GT(mapper.metric_map().counts().occupied, 0u);
    expect_same_maps(reference, mapper);
  }
}

// `done` rethrowing (--strict) ends the stream with that error, no later
// scan reaching `done` or the maps. (The scan after it may have been
// classified already: a Mapper whose stream threw is not to be continued.)
TEST(MapperStream, AnErrorFromDoneEndsTheStream) {
  Frames frames;
  frames.end = 40;
  frames.unreadable = {3};
  MapperConfig config;
  config.voxel = 0.1;
  config.classifier.kind = ClassifierKind::Labels;
  Mapper mapper(config, sensor());
  std::size_t last = 0;
  EXPECT_THROW(mapper.integrate_stream(0, frames.reader(frames.count()),
                                       [&](StreamedScan& s) {
                                         last = s.frame;
                                         if (s.error) throw *s.error;
                                       }),
               Error);
  EXPECT_EQ(last, 3u);
  EXPECT_EQ(mapper.profile().scan_count(), 3u);
}

// Each scan's latency runs from the start of its read to the end of its
// last stage: never shorter than its stages' times together.
TEST(MapperStream, ProfilesEachScansLatency) {
  Frames frames;
  frames.end = 40;
  MapperConfig config;
  config.voxel = 0.1;
  config.classifier.kind = ClassifierKind::Labels;
  Mapper mapper(config, sensor());
  stream(mapper, frames, StageOverlap::On);
  const StageProfile& p = mapper.profile();
  double stages = 0;
  for (const std::string& stage : p.stage_names()) stages += p.stats(stage).total_s;
  EXPECT_EQ(p.latency().scans, frames.count());
  EXPECT_GE(p.latency().mean_s * static_cast<double>(frames.count()), stages * 0.999);
  EXPECT_GT(p.stats("read").scans, 0u);
}

}  // namespace
}  // namespace sarmap::pipeline
