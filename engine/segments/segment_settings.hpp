// Settings of the segment stage: how labelled points are thinned, how planes
// are found among them (RANSAC, then region growing) and when two segments
// are one surface. One default each, documented here once.
#pragma once

#include <cstddef>
#include <cstdint>

#include "engine/core/classes.hpp"

namespace sarmap::segments {

struct SegmentSettings {
  // Points are thinned to one per voxel of this size (metres) before anything
  // else; 0 takes the input as already thinned (the map's own point map) and
  // keeps every distinct point.
  double voxel = 0.025;
  // A point within this distance (metres) of a plane is its inlier (paper 000).
  double distance_threshold = 0.02;
  // RANSAC draws samples until one was all inliers with this probability,
  // judged from the best inlier ratio found so far, and at most max_iterations.
  double confidence = 0.99;
  std::size_t max_iterations = 1000;
  // The fewest points a plane or a segment may have.
  std::size_t min_points = 40;
  // Inliers this close together in their plane are one connected surface
  // (region growing over a grid of this cell size, metres).
  double cluster_radius = 0.1;
  // Two segments of one class are one surface when their normals agree within
  // merge_angle_deg, the smaller one's centroid lies within merge_offset
  // (metres) of the larger one's plane, and their rectangles overlap or are at most merge_gap apart
  // (metres; well below the arenas' doorways, which are at least 0.6 m wide).
  double merge_angle_deg = 5.0;
  // A smaller segment whose centroid lies on a larger one's rectangle (a
  // noisy or mislabelled slab inside a known surface) merges up to this
  // angle instead.
  double merge_overlap_angle_deg = 20.0;
  double merge_offset = 0.04;
  double merge_gap = 0.15;
  // Points farther than this from the sensor (metres) are left out; 0 keeps
  // all. A depth camera's noise grows with the square of the range (about
  // 1.4 cm at 3 m for a Kinect-class camera) and would pass the inlier
  // distance; a surface seen only from farther waits until the robot comes
  // closer. LiDARs, whose noise does not grow so, can raise it.
  double max_range = 3.0;
  // A stored point gives way to a later one in its voxel seen from at most
  // this fraction of its range: depth noise grows with range.
  double closer_view_ratio = 0.7;
  // A point that took part in this many plane searches without joining a
  // segment stops being searched (clutter must not slow every later scan).
  std::size_t max_search_rounds = 16;
  // Seed of RANSAC's sampling; results are the same for any thread count.
  std::uint64_t seed = 1;
};

// Throws sarmap::Error (InvalidArgument) naming the first setting out of range.
void validate(const SegmentSettings& settings);

// The classes that form planar segments: terrain, wall, inclined ramp, flat ramp.
bool is_segmented_class(ClassId label);

}  // namespace sarmap::segments
