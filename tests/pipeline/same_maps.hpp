// Two Mappers hold the same maps: every stage's state compared byte for byte
// (not the profile, whose timings differ between runs).
#pragma once

#include <gtest/gtest.h>

#include <string>

#include "engine/core/state_stream.hpp"
#include "engine/pipeline/mapper.hpp"

namespace sarmap::pipeline {

struct MapBytes {
  std::string metric, segments, topo, points, classifier;
};

inline MapBytes bytes_of(const Mapper& mapper) {
  StateWriter metric, segments, topo, points, classifier;
  mapper.metric_map().save_state(metric);
  mapper.segment_map().save_state(segments);
  mapper.topo_map().save_state(topo);
  mapper.semantic_points().save_state(points);
  mapper.classifier().save_state(classifier);
  return {metric.bytes(), segments.bytes(), topo.bytes(), points.bytes(), classifier.bytes()};
}

// Compared as booleans: a failure would print megabytes of state otherwise.
inline void expect_same_maps(const Mapper& a, const Mapper& b) {
  const MapBytes x = bytes_of(a), y = bytes_of(b);
  EXPECT_TRUE(x.metric == y.metric) << "metric map";
  EXPECT_TRUE(x.segments == y.segments) << "segment map";
  EXPECT_TRUE(x.topo == y.topo) << "topological map";
  EXPECT_TRUE(x.points == y.points) << "semantic points";
  EXPECT_TRUE(x.classifier == y.classifier) << "classifier memory (ramp decks, labelled point map)";
  EXPECT_EQ(a.profile().scan_count(), b.profile().scan_count());
  EXPECT_EQ(a.profile().counter("metric", "rays"), b.profile().counter("metric", "rays"));
  EXPECT_EQ(a.profile().counter("segment", "created"), b.profile().counter("segment", "created"));
}

}  // namespace sarmap::pipeline
