#include "engine/semantic/rules/ramp_side_faces.hpp"

#include <algorithm>
#include <cmath>
#include <numbers>
#include <string>

#include "engine/core/classes.hpp"
#include "engine/core/error.hpp"
#include "engine/semantic/grid_keys.hpp"
#include "engine/semantic/rules/class_move.hpp"
#include "engine/semantic/rules/finite_points.hpp"
#include "engine/semantic/surface_normals.hpp"

namespace sarmap {

using grid_keys::in_reach;

RampDeckMemory::RampDeckMemory(const RampSideSettings& s) : settings_(s) {
  if (!(s.radius >= 0.01) || !std::isfinite(s.radius)) {
    throw Error(ErrorCode::InvalidArgument, "ramp side faces: the radius must be at least 0.01 m");
  }
  if (!(s.normal_cell >= 0.01) || !std::isfinite(s.normal_cell)) {
    throw Error(ErrorCode::InvalidArgument, "ramp side faces: the normal cell must be at least 0.01 m");
  }
  if (!(s.min_rise >= 0.0 && s.min_rise < s.max_rise) || !std::isfinite(s.max_rise)) {
    throw Error(ErrorCode::InvalidArgument, "ramp side faces: need 0 <= min_rise < max_rise, got " +
                                                std::to_string(s.min_rise) + " and " + std::to_string(s.max_rise));
  }
  if (!(s.deck_max_slope_deg > 0.0 && s.deck_max_slope_deg <= 90.0)) {
    throw Error(ErrorCode::InvalidArgument, "ramp side faces: the deck slope must be in (0, 90] degrees, got " +
                                                std::to_string(s.deck_max_slope_deg));
  }
  if (!(s.deck_max_curvature >= 0.0)) {
    throw Error(ErrorCode::InvalidArgument, "ramp side faces: the deck curvature limit must be >= 0");
  }
}

void RampDeckMemory::remember_decks(const PointBuffer& points) {
  const auto inclined = static_cast<std::uint8_t>(ClassId::InclinedRamp);
  const auto labels = points.labels();
  if (std::find(labels.begin(), labels.end(), inclined) == labels.end()) return;
  SurfaceNormalSettings fit;
  fit.cell = settings_.normal_cell;
  fit.min_points = settings_.min_points;
  const SurfaceNormals normals = estimate_surface_normals(points, fit);
  const double min_nz = std::cos(settings_.deck_max_slope_deg * std::numbers::pi / 180.0);
  const double inv = 1.0 / settings_.radius;
  const auto xs = points.x(), ys = points.y(), zs = points.z();
  for (std::size_t p = 0; p < points.size(); ++p) {
    if (labels[p] != inclined || normals.valid[p] == 0 || !(normals.nz[p] >= min_nz) ||
        !(normals.curvature[p] <= settings_.deck_max_curvature) || !in_reach(xs[p], ys[p])) {
      continue;
    }
    const auto [c, is_new] =
        decks_.try_emplace(grid_keys::column_key_of(xs[p], ys[p], inv), HeightSpan{zs[p], zs[p]});
    if (!is_new) {
      HeightSpan& span = decks_.values()[c];
      span.low = std::min(span.low, zs[p]);
      span.high = std::max(span.high, zs[p]);
    }
  }
}

RampDeckMemory::DecksAround RampDeckMemory::decks_around(std::int64_t cx, std::int64_t cy) const {
  DecksAround around;
  for (std::int64_t dx = -1; dx <= 1; ++dx) {
    for (std::int64_t dy = -1; dy <= 1; ++dy) {
      if (const HeightSpan* span = decks_.find(grid_keys::column_key(cx + dx, cy + dy))) {
        around.spans[around.count++] = *span;
      }
    }
  }
  return around;
}

// Deck in the 3 x 3 columns around the point's (each a radius wide, so every
// point within the radius is among them) whose height span reaches into
// (z + min_rise, z + max_rise]. Coarser than the radius by up to twice, and
// a column's span stands for all its points: cheap, and the rises are loose.
bool RampDeckMemory::under_a_deck(const DecksAround& decks, double z) const {
  for (int c = 0; c < decks.count; ++c) {
    if (decks.spans[c].high > z + settings_.min_rise && decks.spans[c].low <= z + settings_.max_rise) return true;
  }
  return false;
}

std::size_t RampDeckMemory::label_side_faces(PointBuffer& points) {
  if (!settings_.enabled || !points.has_labels()) return 0;
  require_finite_points(points, "ramp side faces");  // refused whether or not the scan shows a deck
  remember_decks(points);
  return label_under_known_decks(points);
}

std::size_t RampDeckMemory::label_under_known_decks(PointBuffer& points) const {
  if (!settings_.enabled || !points.has_labels()) return 0;
  require_finite_points(points, "ramp side faces");
  if (decks_.empty()) return 0;
  const auto xs = points.x(), ys = points.y(), zs = points.z();
  const auto wall = static_cast<std::uint8_t>(ClassId::Wall), other = static_cast<std::uint8_t>(ClassId::Other);
  const auto labels = points.labels();
  ClassMove wall_to_ramp(points, ClassId::Wall, ClassId::InclinedRamp);
  ClassMove other_to_ramp(points, ClassId::Other, ClassId::InclinedRamp);
  std::size_t changed = 0;
  // Neighbouring points (a depth image's row, a ring) mostly share a
  // column: its decks are looked up once for the run of them.
  const double inv = 1.0 / settings_.radius;
  std::int64_t last_cx = 0, last_cy = 0;
  bool looked_up = false;
  DecksAround decks;
  for (std::size_t p = 0; p < points.size(); ++p) {
    if ((labels[p] != wall && labels[p] != other) || !in_reach(xs[p], ys[p])) continue;
    const std::int64_t cx = grid_keys::index(xs[p], inv), cy = grid_keys::index(ys[p], inv);
    if (!looked_up || cx != last_cx || cy != last_cy) {
      decks = decks_around(cx, cy);
      last_cx = cx, last_cy = cy, looked_up = true;
    }
    if (!under_a_deck(decks, zs[p])) continue;
    (labels[p] == wall ? wall_to_ramp : other_to_ramp).apply(p);
    ++changed;
  }
  return changed;
}

std::size_t label_ramp_side_faces(PointBuffer& points, const RampSideSettings& settings) {
  RampDeckMemory memory(settings);
  return memory.label_side_faces(points);
}

void RampDeckMemory::save_state(StateWriter& out) const {
  out.tag("DECK");
  out.put(settings_.radius);  // the columns' size
  // Sorted, so that one state always gives the same bytes.
  std::vector<std::pair<std::uint64_t, HeightSpan>> columns;
  columns.reserve(decks_.size());
  for (std::size_t c = 0; c < decks_.size(); ++c) columns.emplace_back(decks_.keys()[c], decks_.values()[c]);
  std::sort(columns.begin(), columns.end(), [](const auto& a, const auto& b) { return a.first < b.first; });
  out.put<std::uint64_t>(columns.size());
  for (const auto& [key, span] : columns) {
    out.put(key);
    out.put(span.low), out.put(span.high);
  }
}

void RampDeckMemory::load_state(StateReader& in) {
  in.expect_tag("DECK");
  if (in.get<double>() != settings_.radius) in.fail("the saved ramp decks use another column size");
  const std::size_t n = in.get_count(16);
  FlatKeyMap<HeightSpan> decks(n);
  for (std::size_t i = 0; i < n; ++i) {
    const auto key = in.get<std::uint64_t>();
    HeightSpan span;
    span.low = in.get<float>(), span.high = in.get<float>();
    decks[key] = span;  // a key saved twice keeps its last span
  }
  decks_ = std::move(decks);
}

}  // namespace sarmap
