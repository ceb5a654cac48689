// sarmap's geometric baseline, after paper 001's normal-based classification:
// slope of the PCA surface normal and height above the local floor decide the
// class, no model needed. It is the fallback when no network is at hand and
// the row the DGCNN must beat.
//
//   slope <= horizontal_max_deg:  terrain at floor height; flat ramp when
//                                 raised up to flat_ramp_max_height; above
//                                 that wall if its column is wall-tall, else other
//   slope <= inclined_max_deg:    inclined ramp
//   slope >= vertical_min_deg:    wall if its column reaches wall_min_height
//                                 above the floor; else the class of the raised
//                                 surface it holds up (a ramp's or box's side:
//                                 the highest within one column around that is
//                                 not below it), else wall (its top unseen)
//   on an edge (curvature above edge_curvature): terrain when low, else as
//                                 a vertical face
//   in between, or no normal:     other
#pragma once

#include <cstddef>

#include "engine/core/point_buffer.hpp"
#include "engine/semantic/geometric/local_floor.hpp"
#include "engine/semantic/surface_normals.hpp"

namespace sarmap {

struct GeometricClassifierSettings {
  SurfaceNormalSettings normals;
  LocalFloorSettings floor;
  double horizontal_max_deg = 8.0;
  double inclined_max_deg = 35.0;  // NIST ramps are 10 to 25 degrees
  double vertical_min_deg = 60.0;
  double raised_min_height = 0.06;     // above the floor: no longer terrain
  double flat_ramp_max_height = 0.45;  // flat ramps are 0.1 to 0.4 m high
  double wall_min_height = 0.7;        // taller than ramps and obstacles
  // Above this normal curvature a point sits on an edge: height alone decides
  // (terrain when low, else as a side face).
  double edge_curvature = 0.05;
  double side_tolerance = 0.05;        // a side's cap may sit this far below the side point
};

struct GeometricClassifyStats {
  std::size_t without_normal = 0;  // too few neighbours or too far out: labelled other / unknown
};

class GeometricClassifier {
 public:
  // Throws sarmap::Error(InvalidArgument) for inconsistent angles or heights.
  explicit GeometricClassifier(GeometricClassifierSettings settings = {});

  // Sets labels (sarmap class ids) on every point; points beyond the metric
  // map's 10 km limit get unknown. Throws on non-finite points.
  GeometricClassifyStats classify(PointBuffer& points) const;

  const GeometricClassifierSettings& settings() const { return settings_; }

 private:
  GeometricClassifierSettings settings_;
};

}  // namespace sarmap
