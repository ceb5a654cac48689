#include "engine/semantic/geometric/geometric_classifier.hpp"

#include <algorithm>
#include <array>
#include <cmath>
#include <cstdint>
#include <numbers>
#include <unordered_map>
#include <vector>

#include "engine/core/classes.hpp"
#include "engine/core/error.hpp"
#include "engine/semantic/grid_keys.hpp"

namespace sarmap {

namespace {

double cos_deg(double degrees) { return std::cos(degrees * std::numbers::pi / 180.0); }

// The raised, non-vertical surfaces of each xy column: their top and a vote
// per class — what a short vertical face (a ramp's or box's side) holds up.
class SurfaceCaps {
 public:
  explicit SurfaceCaps(double column) : inv_column_(1.0 / column) {}

  void add(double x, double y, double z, ClassId label) {
    auto [it, fresh] =
        caps_.try_emplace(grid_keys::column_key(cell(x), cell(y)), Cap{static_cast<float>(z), {}});
    Cap& cap = it->second;
    cap.top = std::max(cap.top, static_cast<float>(z));
    ++cap.votes[static_cast<std::size_t>(label)];
  }

  // The majority class of the caps in the 3 x 3 columns around (x, y) whose
  // top is not below z - tolerance (a rim point of the wrong class cannot
  // outvote the surface); `fallback` when there is none.
  ClassId class_above(double x, double y, double z, double tolerance, ClassId fallback) const {
    const std::int64_t cx = cell(x), cy = cell(y);
    std::array<std::uint32_t, kClassCount> votes{};
    for (std::int64_t dx = -1; dx <= 1; ++dx) {
      for (std::int64_t dy = -1; dy <= 1; ++dy) {
        const auto it = caps_.find(grid_keys::column_key(cx + dx, cy + dy));
        if (it == caps_.end() || it->second.top < z - tolerance) continue;
        for (std::size_t c = 0; c < kClassCount; ++c) votes[c] += it->second.votes[c];
      }
    }
    const auto best = std::max_element(votes.begin(), votes.end());
    return *best > 0 ? static_cast<ClassId>(best - votes.begin()) : fallback;
  }

 private:
  struct Cap {
    float top;
    std::array<std::uint32_t, kClassCount> votes;
  };
  // Points with a normal lie within the metric map's limits, so their
  // columns fit the packed key.
  std::int64_t cell(double v) const { return grid_keys::index(v, inv_column_); }
  double inv_column_;
  std::unordered_map<std::uint64_t, Cap> caps_;
};

}  // namespace

GeometricClassifier::GeometricClassifier(GeometricClassifierSettings settings) : settings_(settings) {
  const auto& s = settings_;
  if (!(0 <= s.horizontal_max_deg && s.horizontal_max_deg < s.inclined_max_deg &&
        s.inclined_max_deg <= s.vertical_min_deg && s.vertical_min_deg <= 90)) {
    throw Error(ErrorCode::InvalidArgument, "geometric classifier: need 0 <= horizontal_max_deg < inclined_max_deg "
                                            "<= vertical_min_deg <= 90");
  }
  if (!(0 <= s.raised_min_height && s.raised_min_height < s.flat_ramp_max_height &&
        s.flat_ramp_max_height < s.wall_min_height && std::isfinite(s.wall_min_height))) {
    throw Error(ErrorCode::InvalidArgument, "geometric classifier: need 0 <= raised_min_height < "
                                            "flat_ramp_max_height < wall_min_height");
  }
}

GeometricClassifyStats GeometricClassifier::classify(PointBuffer& points) const {
  const auto& s = settings_;
  const SurfaceNormals normals = estimate_surface_normals(points, s.normals);
  const LocalFloor floor(points, normals, s.floor);
  const double horizontal_nz = cos_deg(s.horizontal_max_deg), inclined_nz = cos_deg(s.inclined_max_deg),
               vertical_nz = cos_deg(s.vertical_min_deg);
  points.enable_labels();
  GeometricClassifyStats stats;
  SurfaceCaps caps(s.floor.column);
  std::vector<bool> short_sides;
  short_sides.reserve(points.size());
  for (std::size_t p = 0; p < points.size(); ++p) {
    const double x = points.x()[p], y = points.y()[p], z = points.z()[p];
    ClassId label = ClassId::Other;
    bool side_face = false;
    bool cap = false;
    if (!normals.valid[p]) {
      ++stats.without_normal;
      // No normal and outside the map's limits: nothing can be said.
      if (std::abs(x) > 10'000.0 || std::abs(y) > 10'000.0 || std::abs(z) > 10'000.0) label = ClassId::Unknown;
    } else {
      const double nz = normals.nz[p];
      const double height = z - floor.height_at(x, y);
      const bool wall_tall = floor.column_top(x, y) - floor.height_at(x, y) >= s.wall_min_height;
      if (normals.curvature[p] > s.edge_curvature) {
        // An edge no plane fits (a wall's foot, a box's rim): its slope means
        // nothing, so height alone decides, as for a side face.
        if (height < s.raised_min_height) {
          label = ClassId::Terrain;
        } else {
          label = wall_tall ? ClassId::Wall : ClassId::Other;
          side_face = true;
        }
      } else if (nz >= horizontal_nz) {
        if (height < s.raised_min_height) {
          label = ClassId::Terrain;
        } else if (height <= s.flat_ramp_max_height) {
          label = ClassId::FlatRamp;
          cap = true;
        } else {
          label = wall_tall ? ClassId::Wall : ClassId::Other;
          cap = !wall_tall;  // a box's top
        }
      } else if (nz >= inclined_nz) {
        label = ClassId::InclinedRamp;
        cap = height >= s.raised_min_height;
      } else if (nz <= vertical_nz) {
        label = wall_tall ? ClassId::Wall : ClassId::Other;
        side_face = true;
      }
      // Only surfaces something can stand on cap a side face; a slope
      // between inclined and vertical is no evidence of what is below it.
      if (cap) caps.add(x, y, z, label);
    }
    points.labels()[p] = static_cast<std::uint8_t>(label);
    short_sides.push_back(side_face && label == ClassId::Other);
  }
  // Second pass: a short vertical face takes the class of the surface it
  // holds up — a flat ramp's side is flat ramp, an inclined ramp's inclined.
  // With nothing on top it is a wall whose top the sensor does not see (a
  // camera pitched down sees walls only to its own height).
  for (std::size_t p = 0; p < points.size(); ++p) {
    if (!short_sides[p]) continue;
    points.labels()[p] = static_cast<std::uint8_t>(
        caps.class_above(points.x()[p], points.y()[p], points.z()[p], s.side_tolerance, ClassId::Wall));
  }
  return stats;
}

}  // namespace sarmap
