#include "engine/segments/segment_map.hpp"

#include <algorithm>
#include <cmath>
#include <limits>
#include <numbers>
#include <optional>
#include <span>
#include <string>
#include <unordered_map>

#include <tbb/blocked_range.h>
#include <tbb/parallel_for.h>

#include "engine/core/capacity_bytes.hpp"
#include "engine/core/error.hpp"
#include "engine/core/prefetched_key_walk.hpp"
#include "engine/segments/plane_extraction.hpp"
#include "engine/segments/plane_moments.hpp"
#include "engine/segments/plane_rectangle.hpp"
#include "engine/segments/plane_regions.hpp"
#include "engine/segments/segment_merge.hpp"
#include "engine/segments/segment_record.hpp"
#include "engine/segments/walkable.hpp"

namespace sarmap::segments {

SegmentUpdate& SegmentUpdate::operator+=(const SegmentUpdate& o) {
  points_in += o.points_in;
  points_rejected += o.points_rejected;
  points_far += o.points_far;
  points_new += o.points_new;
  points_changed += o.points_changed;
  points_attached += o.points_attached;
  planes_found += o.planes_found;
  created += o.created;
  merged += o.merged;
  split += o.split;
  removed += o.removed;
  points_forgotten += o.points_forgotten;
  return *this;
}

// One call's scratch.
struct SegmentMap::Work {
  SegmentUpdate update;
  std::vector<std::uint32_t> fresh;  // points new, relabelled or moved in this call
  // A reclassified region is re-derived at once; a scan's few boundary votes
  // wait until they add up (their moments are exact meanwhile, only the
  // outline and the split check lag).
  bool rebuild_every_loss = false;
};

namespace {

// Cells of the index that finds the segments a point may join, metres.
constexpr double kIndexCell = 1.0;
// Planes within this of level (45 degrees) have their normal up; steeper
// ones face the side they were seen from.
const double kLevelNormalZ = std::cos(std::numbers::pi / 4);

std::uint64_t cell_key(std::int64_t x, std::int64_t y, std::int64_t z) {
  constexpr std::int64_t kHalf = std::int64_t{1} << 20;
  return static_cast<std::uint64_t>((x + kHalf) & 0x1fffff) | (static_cast<std::uint64_t>((y + kHalf) & 0x1fffff) << 21) |
         (static_cast<std::uint64_t>((z + kHalf) & 0x1fffff) << 42);
}

std::int64_t cell_of(double v) { return static_cast<std::int64_t>(std::floor(v / kIndexCell)); }

Eigen::Vector3d oriented_normal(Eigen::Vector3d n, const Eigen::Vector3d& view_sum) {
  if (std::abs(n.z()) >= kLevelNormalZ) return n.z() < 0 ? Eigen::Vector3d(-n) : n;
  const double facing = n.dot(view_sum);
  if (facing != 0) return facing < 0 ? Eigen::Vector3d(-n) : n;
  // Never seen from a known origin: any fixed rule keeps it deterministic.
  for (int axis : {2, 0, 1}) {
    if (n[axis] != 0) return n[axis] < 0 ? Eigen::Vector3d(-n) : n;
  }
  return n;
}

bool boxes_near(const Bounds& a, const Bounds& b, double margin) {
  return (a.min.array() - margin <= b.max.array()).all() && (b.min.array() - margin <= a.max.array()).all();
}

void require_labels(const PointBuffer& points) {
  if (!points.has_labels()) throw Error(ErrorCode::InvalidArgument, "segments: the points carry no labels");
}

}  // namespace

SegmentMap::SegmentMap(const SegmentSettings& settings) : settings_(settings), voxels_(settings.voxel) {
  validate(settings_);
}
SegmentMap::~SegmentMap() = default;
SegmentMap::SegmentMap(SegmentMap&&) noexcept = default;
SegmentMap& SegmentMap::operator=(SegmentMap&&) noexcept = default;

SegmentUpdate SegmentMap::integrate(const PointBuffer& points, const Eigen::Vector3d& origin) {
  require_labels(points);
  if (!origin.allFinite()) throw Error(ErrorCode::InvalidArgument, "segments: the scan's origin is not finite");
  // Look-ups first, in parallel (the map does not change while they run);
  // then every change in point order, so the result is the same on any
  // thread count.
  enum Verdict : std::uint8_t { kSkip, kNonFinite, kFar, kBeyondReach, kLookedUp };
  const std::size_t n = points.size();
  std::vector<Verdict> verdict(n, kSkip);
  std::vector<std::uint64_t> keys(n);
  std::vector<std::uint32_t> found(n, FlatKeyIndex::kAbsent);
  std::vector<float> ranges(n);
  const double max_range = settings_.max_range;
  const auto labels = points.labels();
  // A point's verdict and range, and its voxel's key where it has one.
  const auto voxel_key = [&](std::size_t i, std::uint64_t& key) {
    const auto label = class_from_value(labels[i]);
    if (!label || *label == ClassId::Unknown) return false;
    const Eigen::Vector3d p(points.x()[i], points.y()[i], points.z()[i]);
    if (!p.allFinite()) {
      verdict[i] = kNonFinite;
      return false;
    }
    const double distance = (p - origin).norm();
    ranges[i] = static_cast<float>(distance);
    if (max_range > 0 && distance > max_range) {
      verdict[i] = kFar;
      return false;
    }
    const std::optional<std::uint64_t> found_key = voxels_.key_of(p);
    if (!found_key) {
      verdict[i] = kBeyondReach;
      return false;
    }
    key = keys[i] = *found_key;
    verdict[i] = kLookedUp;
    return true;
  };
  // Each range of points with its own last look-up, for the repeats.
  const auto look_up_range = [&](const tbb::blocked_range<std::size_t>& r) {
    std::uint32_t last_found = FlatKeyIndex::kAbsent;
    const auto look_up = [&](std::size_t i, std::uint64_t key, bool repeat) {
      if (!repeat) {
        const auto stored = voxels_.find(key);
        last_found = stored ? *stored : FlatKeyIndex::kAbsent;
      }
      found[i] = last_found;
    };
    walk_keys_prefetched(voxels_, r.begin(), r.end(), voxel_key, look_up);
  };
  tbb::parallel_for(tbb::blocked_range<std::size_t>(0, n, 4096), look_up_range);
  for (std::size_t i = 0; i < n; ++i) {
    if (verdict[i] == kNonFinite) {
      throw Error(ErrorCode::InvalidArgument, "segments: point " + std::to_string(i) + " is not finite");
    }
  }
  ++calls_;
  const auto scan = static_cast<std::uint32_t>(origins_.size());
  origins_.push_back(origin);
  Work work;
  for (std::size_t i = 0; i < n; ++i) {
    if (verdict[i] == kSkip) continue;
    ++work.update.points_in;
    if (verdict[i] == kFar) {
      ++work.update.points_far;
      continue;
    }
    if (verdict[i] == kBeyondReach) {
      ++work.update.points_rejected;
      continue;
    }
    const Eigen::Vector3d p(points.x()[i], points.y()[i], points.z()[i]);
    const auto label = static_cast<ClassId>(labels[i]);
    // A voxel first filled by an earlier point of this very scan.
    const std::optional<std::uint32_t> stored =
        found[i] != FlatKeyIndex::kAbsent ? std::optional<std::uint32_t>(found[i]) : voxels_.find(keys[i]);
    if (!stored) {
      queue(work, voxels_.add(keys[i], p, label, ranges[i], scan));
      ++work.update.points_new;
      continue;
    }
    const std::uint32_t k = *stored;
    const auto before = static_cast<ClassId>(voxels_.label[k]);
    const ClassId after = voxels_.vote(k, label);
    // A voxel that changes class takes this point, of the new class, as its
    // own: a floor point labelled wall would tilt the wall's plane.
    if (after == before && !(ranges[i] < voxels_.range[k] * settings_.closer_view_ratio)) continue;
    detach(k);
    voxels_.x[k] = static_cast<float>(p.x());
    voxels_.y[k] = static_cast<float>(p.y());
    voxels_.z[k] = static_cast<float>(p.z());
    voxels_.range[k] = ranges[i];
    voxels_.scan[k] = scan;
    ++work.update.points_changed;
    queue(work, k);
  }
  return finish(work);
}

SegmentUpdate SegmentMap::reclassify(const PointBuffer& points) {
  require_labels(points);
  ++calls_;
  Work work;
  work.rebuild_every_loss = true;
  const auto labels = points.labels();
  for (std::size_t i = 0; i < points.size(); ++i) {
    const auto label = class_from_value(labels[i]);
    if (!label || *label == ClassId::Unknown) continue;
    const Eigen::Vector3d p(points.x()[i], points.y()[i], points.z()[i]);
    if (!p.allFinite()) {
      throw Error(ErrorCode::InvalidArgument, "segments: point " + std::to_string(i) + " is not finite");
    }
    ++work.update.points_in;
    const std::optional<std::uint64_t> key = voxels_.key_of(p);
    if (!key) {
      ++work.update.points_rejected;
      continue;
    }
    const std::optional<std::uint32_t> stored = voxels_.find(*key);
    if (!stored) {
      queue(work, voxels_.add(*key, p, *label, std::numeric_limits<float>::infinity(), LabelledVoxels::kNoScan));
      ++work.update.points_new;
      continue;
    }
    if (static_cast<ClassId>(voxels_.label[*stored]) == *label) continue;
    detach(*stored);
    voxels_.set_label(*stored, *label);
    ++work.update.points_changed;
    queue(work, *stored);
  }
  return finish(work);
}

SegmentUpdate SegmentMap::forget(const std::function<bool(const Eigen::Vector3d&)>& forgotten) {
  const std::size_t n = voxels_.size();
  std::vector<std::uint8_t> keep(n);
  tbb::parallel_for(tbb::blocked_range<std::size_t>(0, n, 4096), [&](const tbb::blocked_range<std::size_t>& r) {
    for (std::size_t i = r.begin(); i < r.end(); ++i) {
      keep[i] = !forgotten(voxels_.position(static_cast<std::uint32_t>(i)));
    }
  });
  Work work;
  for (std::uint32_t i = 0; i < n; ++i) {
    if (keep[i]) continue;
    detach(i);
    voxels_.pending[i] = 0;
    ++work.update.points_forgotten;
  }
  if (work.update.points_forgotten == 0) return work.update;
  // Each segment that lost points is re-derived from the points it keeps.
  for (std::uint32_t id = 0; id < records_.size(); ++id) {
    Record& r = records_[id];
    if (!r.alive || r.left.empty()) continue;
    r.left.clear();
    repair(id, work);
  }
  compact_points(keep);
  for (std::uint32_t id = 0; id < records_.size(); ++id) {
    if (records_[id].alive && records_[id].changed) refresh(id);
  }
  merge_changed(work);
  for (Record& r : records_) r.changed = false;
  return work.update;
}

void SegmentMap::compact_points(const std::vector<std::uint8_t>& keep) {
  const std::size_t before = voxels_.size();
  const std::vector<std::uint32_t> moved = voxels_.keep_only(keep);
  const auto renumber = [&](std::vector<std::uint32_t>& points) {
    std::erase_if(points, [&](std::uint32_t p) { return moved[p] == LabelledVoxels::kDropped; });
    for (std::uint32_t& p : points) p = moved[p];
  };
  for (Record& r : records_) {
    renumber(r.members);
    renumber(r.left);
  }
  for (std::vector<std::uint32_t>& list : pending_) renumber(list);
  // Per-point scratch moves with its point (sized lazily, so maybe short).
  const auto compact_column = [&](auto& column) {
    for (std::size_t i = 0; i < std::min(before, column.size()); ++i) {
      if (moved[i] != LabelledVoxels::kDropped) column[moved[i]] = column[i];
    }
    column.resize(std::min(column.size(), voxels_.size()));
  };
  compact_column(queued_in_);
  compact_column(marks_);
  // Only the scans some kept point was seen from keep their origin.
  std::vector<std::uint32_t> scan_moved(origins_.size(), LabelledVoxels::kNoScan);
  for (std::uint32_t s : voxels_.scan) {
    if (s != LabelledVoxels::kNoScan) scan_moved[s] = 0;
  }
  std::uint32_t next = 0;
  for (std::size_t s = 0; s < origins_.size(); ++s) {
    if (scan_moved[s] == LabelledVoxels::kNoScan) continue;
    scan_moved[s] = next;
    origins_[next++] = origins_[s];
  }
  origins_.resize(next);
  for (std::uint32_t& s : voxels_.scan) {
    if (s != LabelledVoxels::kNoScan) s = scan_moved[s];
  }
}

void SegmentMap::queue(Work& work, std::uint32_t point) {
  if (queued_in_.size() < voxels_.size()) queued_in_.resize(voxels_.size(), 0);
  if (queued_in_[point] == calls_) return;
  queued_in_[point] = calls_;
  // A queued point is judged afresh: it leaves the pending list it was on.
  voxels_.pending[point] = 0;
  work.fresh.push_back(point);
}

bool SegmentMap::known_origin(std::uint32_t point) const { return voxels_.scan[point] != LabelledVoxels::kNoScan; }

Eigen::Vector3d SegmentMap::origin_of(std::uint32_t point) const { return origins_[voxels_.scan[point]]; }

void SegmentMap::attach(std::uint32_t point, std::uint32_t id) {
  Record& r = records_[id];
  const Eigen::Vector3d p = voxels_.position(point);
  voxels_.owner[point] = static_cast<std::int32_t>(id);
  voxels_.pending[point] = 0;
  r.moments.add(p);
  if (known_origin(point)) r.view_sum += origin_of(point) - p;
  r.members.push_back(point);
  r.outline.push_back(p.cast<float>());
  r.box.extend(p);
  r.changed = true;
}

void SegmentMap::detach(std::uint32_t point) {
  const std::int32_t owner = voxels_.owner[point];
  if (owner == LabelledVoxels::kNoSegment) return;
  Record& r = records_[static_cast<std::size_t>(owner)];
  const Eigen::Vector3d p = voxels_.position(point);
  r.moments.remove(p);
  if (known_origin(point)) r.view_sum -= origin_of(point) - p;
  ++r.stale;
  r.left.push_back(point);
  r.changed = true;
  voxels_.owner[point] = LabelledVoxels::kNoSegment;
}

void SegmentMap::add_pending(std::uint32_t point, ClassId label, Work&) {
  const auto c = static_cast<std::size_t>(label);
  if (voxels_.pending[point] == c) return;
  voxels_.pending[point] = static_cast<std::uint8_t>(c);
  voxels_.rounds[point] = 0;
  pending_[c].push_back(point);
  ++new_pending_[c];
}

// Which segments may a point lie on? Those whose box, grown by a margin,
// holds it: found through a coarse grid of cells.
struct SegmentMap::SegmentIndex {
  std::unordered_map<std::uint64_t, std::vector<std::uint32_t>> cells;

  std::span<const std::uint32_t> at(const Eigen::Vector3d& p) const {
    const auto it = cells.find(cell_key(cell_of(p.x()), cell_of(p.y()), cell_of(p.z())));
    return it == cells.end() ? std::span<const std::uint32_t>() : std::span<const std::uint32_t>(it->second);
  }
};

SegmentMap::SegmentIndex SegmentMap::index_segments(double margin) const {
  SegmentIndex index;
  for (std::uint32_t id = 0; id < records_.size(); ++id) {
    const Record& r = records_[id];
    if (!r.alive || r.box.empty()) continue;
    const Eigen::Vector3d lo = r.box.min.array() - margin, hi = r.box.max.array() + margin;
    for (std::int64_t x = cell_of(lo.x()); x <= cell_of(hi.x()); ++x) {
      for (std::int64_t y = cell_of(lo.y()); y <= cell_of(hi.y()); ++y) {
        for (std::int64_t z = cell_of(lo.z()); z <= cell_of(hi.z()); ++z) index.cells[cell_key(x, y, z)].push_back(id);
      }
    }
  }
  return index;
}

std::vector<std::int64_t> SegmentMap::nearest_segments(const std::vector<std::uint32_t>& points,
                                                       double max_distance) const {
  const SegmentIndex index = index_segments(settings_.cluster_radius + max_distance);
  std::vector<std::int64_t> choice(points.size(), -1);
  tbb::parallel_for(tbb::blocked_range<std::size_t>(0, points.size(), 256),
                    [&](const tbb::blocked_range<std::size_t>& range) {
                      for (std::size_t k = range.begin(); k < range.end(); ++k) {
                        const auto label = static_cast<ClassId>(voxels_.label[points[k]]);
                        if (!is_segmented_class(label)) continue;
                        const Eigen::Vector3d p = voxels_.position(points[k]);
                        double best = std::numeric_limits<double>::infinity();
                        for (std::uint32_t id : index.at(p)) {
                          const Segment& s = records_[id].view;
                          if (s.label != label) continue;
                          const double d = std::abs(s.plane.distance(p));
                          // Ids come in increasing order: ties keep the lower one.
                          if (d <= max_distance && d < best && s.covers(p, settings_.cluster_radius)) {
                            best = d;
                            choice[k] = id;
                          }
                        }
                      }
                    });
  return choice;
}

void SegmentMap::attach_points(const std::vector<std::uint32_t>& points, Work& work, bool fresh) {
  const std::vector<std::int64_t> choice = nearest_segments(points, settings_.distance_threshold);
  for (std::size_t k = 0; k < points.size(); ++k) {
    const std::uint32_t point = points[k];
    if (choice[k] >= 0) {
      attach(point, static_cast<std::uint32_t>(choice[k]));
      ++work.update.points_attached;
    } else if (fresh) {
      const auto label = static_cast<ClassId>(voxels_.label[point]);
      if (is_segmented_class(label)) add_pending(point, label, work);
    }
  }
}

void SegmentMap::compact_members(Record& r, std::uint32_t id) {
  std::vector<std::uint32_t> kept;
  kept.reserve(r.moments.count());
  const std::uint32_t stamp = next_mark();
  for (std::uint32_t point : r.members) {
    // A point that left and came back is listed twice.
    if (voxels_.owner[point] != static_cast<std::int32_t>(id) || marks_[point] == stamp) continue;
    marks_[point] = stamp;
    kept.push_back(point);
  }
  r.members = std::move(kept);
  r.stale = 0;
}

std::uint32_t SegmentMap::next_mark() {
  marks_.resize(voxels_.size(), 0);
  if (++mark_ == 0) {
    std::fill(marks_.begin(), marks_.end(), 0);
    mark_ = 1;
  }
  return mark_;
}

void SegmentMap::repair(std::uint32_t id, Work& work) {
  Record& r = records_[id];
  compact_members(r, id);
  std::vector<std::uint32_t> members = std::move(r.members);
  // Start the record over and let its largest connected part join it again.
  for (std::uint32_t point : members) voxels_.owner[point] = LabelledVoxels::kNoSegment;
  r.moments = PlaneMoments();
  r.view_sum.setZero();
  r.members.clear();
  r.outline.clear();
  r.box = Bounds();
  r.changed = true;
  r.lost_since_rebuild = 0;
  std::vector<std::vector<std::uint32_t>> parts;
  if (members.size() >= settings_.min_points) {
    PlaneMoments moments;
    for (std::uint32_t point : members) moments.add(voxels_.position(point));
    const PlaneFit fit = fit_plane(moments);
    const PlaneFrame frame(fit.centroid, fit.plane.normal);
    std::vector<Eigen::Vector2d> in_plane(members.size());
    for (std::size_t k = 0; k < members.size(); ++k) in_plane[k] = frame.project(voxels_.position(members[k]));
    for (const std::vector<std::uint32_t>& region : plane_regions(in_plane, settings_.cluster_radius)) {
      std::vector<std::uint32_t> part(region.size());
      for (std::size_t k = 0; k < region.size(); ++k) part[k] = members[region[k]];
      parts.push_back(std::move(part));
    }
  }
  const auto label = r.view.label;
  if (parts.empty() || parts.front().size() < settings_.min_points) {
    r.alive = false;
    merged_into_[id] = kDissolved;
    ++work.update.removed;
    for (std::uint32_t point : members) add_pending(point, label, work);
    return;
  }
  for (std::uint32_t point : parts.front()) attach(point, id);
  for (std::size_t k = 1; k < parts.size(); ++k) {
    if (parts[k].size() >= settings_.min_points) {
      create(label, parts[k]);
      ++work.update.split;
      ++work.update.created;
    } else {
      for (std::uint32_t point : parts[k]) add_pending(point, label, work);
    }
  }
}

std::uint32_t SegmentMap::create(ClassId label, const std::vector<std::uint32_t>& points) {
  const auto id = static_cast<std::uint32_t>(records_.size());
  records_.emplace_back();
  merged_into_.push_back(kAlive);
  records_.back().view.id = id;
  records_.back().view.label = label;
  for (std::uint32_t point : points) attach(point, id);
  refresh(id);
  return id;
}

void SegmentMap::search(ClassId label, Work& work) {
  const auto c = static_cast<std::size_t>(label);
  new_pending_[c] = 0;
  std::vector<std::uint32_t>& list = pending_[c];
  auto still_pending = [&](std::uint32_t point) {
    return voxels_.pending[point] == c && voxels_.owner[point] == LabelledVoxels::kNoSegment;
  };
  // A point queued again after it waited is listed twice.
  const std::uint32_t stamp = next_mark();
  std::erase_if(list, [&](std::uint32_t point) {
    if (!still_pending(point) || marks_[point] == stamp) return true;
    marks_[point] = stamp;
    return false;
  });
  // Segments grow between searches: a waiting point may lie on one now.
  attach_points(list, work, false);
  std::erase_if(list, [&](std::uint32_t point) { return !still_pending(point); });
  // Points in a known segment's noise band (within merge_offset of its plane,
  // on its outline) are its noise, not a surface of their own: searched,
  // they would give thin tilted slabs beside it.
  const std::vector<std::int64_t> shadowing = nearest_segments(list, settings_.merge_offset);
  std::vector<std::uint32_t> shadowed;
  std::vector<std::uint32_t> searched;
  for (std::size_t k = 0; k < list.size(); ++k) (shadowing[k] >= 0 ? shadowed : searched).push_back(list[k]);
  auto count_round = [&](std::uint32_t point) {
    if (++voxels_.rounds[point] >= settings_.max_search_rounds) voxels_.pending[point] = 0;
  };
  for (std::uint32_t point : shadowed) count_round(point);
  list = std::move(searched);
  if (list.size() < settings_.min_points) {
    list.insert(list.end(), shadowed.begin(), shadowed.end());
    std::erase_if(pending_[c], [&](std::uint32_t point) { return !still_pending(point); });
    return;
  }

  std::vector<float> x(list.size()), y(list.size()), z(list.size());
  for (std::size_t k = 0; k < list.size(); ++k) {
    x[k] = voxels_.x[list[k]];
    y[k] = voxels_.y[list[k]];
    z[k] = voxels_.z[list[k]];
  }
  const std::uint64_t seed = mix_key(settings_.seed ^ (c << 56) ^ searches_[c]++);
  const Extraction found = extract_surfaces(PlanePoints{x, y, z}, settings_, seed);
  work.update.planes_found += found.planes;
  for (const std::vector<std::uint32_t>& surface : found.surfaces) {
    std::vector<std::uint32_t> points(surface.size());
    for (std::size_t k = 0; k < surface.size(); ++k) points[k] = list[surface[k]];
    create(label, points);
    ++work.update.created;
  }
  for (std::uint32_t point : list) {
    if (still_pending(point)) count_round(point);
  }
  list.insert(list.end(), shadowed.begin(), shadowed.end());
  std::erase_if(list, [&](std::uint32_t point) { return !still_pending(point); });
}

void SegmentMap::refresh(std::uint32_t id) {
  Record& r = records_[id];
  Segment& s = r.view;
  if (r.moments.count() < 3) return;
  const PlaneFit fit = fit_plane(r.moments);
  const Eigen::Vector3d normal = oriented_normal(fit.plane.normal, r.view_sum);
  s.plane = Plane{normal, -normal.dot(fit.centroid)};
  s.centroid = fit.centroid;
  s.inliers = r.moments.count();
  s.thickness = std::sqrt(12.0 * fit.normal_variance);
  s.min = r.box.min;
  s.max = r.box.max;
  s.slope_deg = s.plane.slope_deg();

  const PlaneFrame frame(fit.centroid, normal);
  std::vector<Eigen::Vector2d> in_plane(r.outline.size());
  for (std::size_t k = 0; k < r.outline.size(); ++k) in_plane[k] = frame.project(r.outline[k].cast<double>());
  const std::vector<std::size_t> hull = convex_hull(in_plane);
  std::vector<Eigen::Vector2d> hull_points(hull.size());
  std::vector<Eigen::Vector3f> corners(hull.size());
  for (std::size_t k = 0; k < hull.size(); ++k) {
    hull_points[k] = in_plane[hull[k]];
    corners[k] = r.outline[hull[k]];
  }
  r.outline = std::move(corners);
  s.area_m2 = polygon_area(hull_points);
  const Rectangle2d rectangle = min_area_rectangle(hull_points);
  s.rectangle.center = frame.lift(rectangle.center);
  for (int a = 0; a < 2; ++a) {
    s.rectangle.axes[a] = rectangle.axes[a].x() * frame.u + rectangle.axes[a].y() * frame.v;
    s.rectangle.half_extents[a] = rectangle.half_extents[a];
  }
}

void SegmentMap::absorb(std::uint32_t survivor, std::uint32_t absorbed) {
  Record& a = records_[absorbed];
  Record& s = records_[survivor];
  for (std::uint32_t point : a.members) {
    if (voxels_.owner[point] != static_cast<std::int32_t>(absorbed)) continue;
    voxels_.owner[point] = static_cast<std::int32_t>(survivor);
    s.members.push_back(point);
  }
  s.moments += a.moments;
  s.view_sum += a.view_sum;
  s.outline.insert(s.outline.end(), a.outline.begin(), a.outline.end());
  s.box.extend(a.box);
  s.changed = true;
  a = Record();
  a.alive = false;
  merged_into_[absorbed] = survivor;
  merges_.emplace_back(absorbed, survivor);
}

void SegmentMap::merge_changed(Work& work) {
  const double reach = settings_.merge_gap + settings_.merge_offset;
  bool again = true;
  while (again) {
    again = false;
    for (std::uint32_t id = 0; id < records_.size() && !again; ++id) {
      if (!records_[id].alive || !records_[id].changed) continue;
      for (std::uint32_t other = 0; other < records_.size(); ++other) {
        const Record& a = records_[id];
        const Record& b = records_[other];
        if (other == id || !b.alive || a.view.label != b.view.label || !boxes_near(a.box, b.box, reach)) continue;
        if (!same_surface(a.view, b.view, settings_)) continue;
        const std::uint32_t survivor = std::min(id, other);
        absorb(survivor, std::max(id, other));
        refresh(survivor);
        ++work.update.merged;
        again = true;
        break;
      }
    }
  }
}

SegmentUpdate SegmentMap::finish(Work& work) {
  attach_points(work.fresh, work, true);
  // Segments whose points left for good are rebuilt; points that moved to a
  // closer view and came straight back change nothing else.
  for (std::uint32_t id = 0; id < records_.size(); ++id) {
    Record& r = records_[id];
    if (!r.alive || r.left.empty()) continue;
    r.lost_since_rebuild += static_cast<std::size_t>(std::count_if(r.left.begin(), r.left.end(), [&](std::uint32_t point) {
      return voxels_.owner[point] != static_cast<std::int32_t>(id);
    }));
    r.left.clear();
    const std::size_t count = r.moments.count();
    const bool due = r.lost_since_rebuild > 0 &&
                     (work.rebuild_every_loss || count < 2 * settings_.min_points ||
                      r.lost_since_rebuild >= std::max(settings_.min_points, count / 20));
    if (due) {
      repair(id, work);
    } else if (r.stale > r.members.size() / 2) {
      compact_members(r, id);
    }
  }
  for (std::uint32_t id = 0; id < records_.size(); ++id) {
    if (records_[id].alive && records_[id].changed) refresh(id);
  }
  for (std::size_t c = 0; c < kClassCount; ++c) {
    const auto label = static_cast<ClassId>(c);
    if (is_segmented_class(label) && new_pending_[c] >= settings_.min_points) search(label, work);
  }
  for (std::uint32_t id = 0; id < records_.size(); ++id) {
    if (records_[id].alive && records_[id].changed) refresh(id);
  }
  merge_changed(work);
  for (Record& r : records_) r.changed = false;
  return work.update;
}

std::vector<const Segment*> SegmentMap::segments() const {
  std::vector<const Segment*> out;
  for (const Record& r : records_) {
    if (r.alive) out.push_back(&r.view);
  }
  return out;
}

std::size_t SegmentMap::memory_bytes() const {
  std::size_t bytes = voxels_.memory_bytes() + capacity_bytes(origins_) + capacity_bytes(queued_in_) +
                      capacity_bytes(marks_) + capacity_bytes(records_) + capacity_bytes(merged_into_) +
                      capacity_bytes(merges_);
  for (const Record& r : records_) bytes += capacity_bytes(r.members) + capacity_bytes(r.outline) + capacity_bytes(r.left);
  for (const auto& list : pending_) bytes += capacity_bytes(list);
  return bytes;
}

std::size_t SegmentMap::size() const {
  return static_cast<std::size_t>(std::count_if(records_.begin(), records_.end(), [](const Record& r) { return r.alive; }));
}

const Segment* SegmentMap::find(std::uint32_t id) const {
  return id < records_.size() && records_[id].alive ? &records_[id].view : nullptr;
}

std::optional<std::uint32_t> SegmentMap::resolve(std::uint32_t id) const {
  while (id < merged_into_.size()) {
    const std::int64_t next = merged_into_[id];
    if (next == kAlive) return id;
    if (next == kDissolved) return std::nullopt;
    id = static_cast<std::uint32_t>(next);
  }
  return std::nullopt;
}

std::vector<const Segment*> SegmentMap::of_class(ClassId label) const {
  std::vector<const Segment*> out;
  for (const Record& r : records_) {
    if (r.alive && r.view.label == label) out.push_back(&r.view);
  }
  return out;
}

std::vector<const Segment*> SegmentMap::in_box(const Bounds& box) const {
  std::vector<const Segment*> out;
  for (const Record& r : records_) {
    if (r.alive && boxes_near(r.box, box, 0)) out.push_back(&r.view);
  }
  return out;
}

const Segment* SegmentMap::under(const Eigen::Vector3d& p, double max_drop) const {
  return segment_under(segments(), p, max_drop, settings_.distance_threshold);
}

std::vector<Eigen::Vector3f> SegmentMap::member_points(std::uint32_t id) const {
  std::vector<Eigen::Vector3f> out;
  if (find(id) == nullptr) return out;
  std::vector<std::uint32_t> members;
  for (std::uint32_t point : records_[id].members) {
    if (voxels_.owner[point] == static_cast<std::int32_t>(id)) members.push_back(point);
  }
  std::sort(members.begin(), members.end());
  members.erase(std::unique(members.begin(), members.end()), members.end());
  for (std::uint32_t point : members) out.emplace_back(voxels_.x[point], voxels_.y[point], voxels_.z[point]);
  return out;
}

std::array<std::size_t, kClassCount> SegmentMap::pending_counts() const {
  std::array<std::size_t, kClassCount> out{};
  for (std::size_t c = 0; c < kClassCount; ++c) {
    for (std::uint32_t point : pending_[c]) {
      out[c] += voxels_.pending[point] == c && voxels_.owner[point] == LabelledVoxels::kNoSegment;
    }
  }
  return out;
}

}  // namespace sarmap::segments
