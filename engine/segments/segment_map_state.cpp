// The segment map's part of a checkpoint: everything a later scan's outcome
// depends on, bit for bit, down to the running plane sums (re-adding the
// points would round differently), the stale member entries and the pending
// lists with their duplicates. Every index read back is checked against what
// it will index, so a corrupt stream is an error, never a crash.
#include <algorithm>
#include <string>

#include "engine/core/metres_text.hpp"
#include "engine/segments/segment_map.hpp"
#include "engine/segments/segment_record.hpp"

namespace sarmap::segments {
namespace {

// The fewest bytes a record takes (no members, outline or left points): a
// bound on how many records the rest of a stream can hold.
constexpr std::size_t kSegmentBytes = 4 + 1 + 8 * 28;
constexpr std::size_t kRecordBytes = kSegmentBytes + 1 + 8 * 13 + 8 * 3 + 8 + 8 + 8 + 8 * 6 + 1 + 8 + 8;

void put3(StateWriter& out, const Eigen::Vector3d& v) { out.put(v.x()), out.put(v.y()), out.put(v.z()); }

Eigen::Vector3d get3(StateReader& in) {
  const auto x = in.get<double>(), y = in.get<double>(), z = in.get<double>();
  return {x, y, z};
}

bool get_flag(StateReader& in, const char* name) {
  const auto value = in.get<std::uint8_t>();
  if (value > 1) {
    in.fail(std::string("the ") + name + " flag holds " + std::to_string(value) + ", not 0 or 1");
  }
  return value == 1;
}

// Point indices that will index the map's point columns.
std::vector<std::uint32_t> get_points(StateReader& in, std::size_t point_count, const std::string& what) {
  std::vector<std::uint32_t> points = in.get_vector<std::uint32_t>();
  for (std::uint32_t point : points) {
    if (point >= point_count) {
      in.fail(what + " names point " + std::to_string(point) + " of " + std::to_string(point_count));
    }
  }
  return points;
}

void put_segment(StateWriter& out, const Segment& s) {
  out.put(s.id);
  out.put(s.label);
  put3(out, s.plane.normal);
  out.put(s.plane.offset);
  put3(out, s.centroid);
  out.put<std::uint64_t>(s.inliers);
  put3(out, s.rectangle.center);
  put3(out, s.rectangle.axes[0]), put3(out, s.rectangle.axes[1]);
  out.put(s.rectangle.half_extents[0]), out.put(s.rectangle.half_extents[1]);
  out.put(s.thickness);
  put3(out, s.min), put3(out, s.max);
  out.put(s.slope_deg);
  out.put(s.area_m2);
}

Segment get_segment(StateReader& in) {
  Segment s;
  s.id = in.get<std::uint32_t>();
  s.label = in.get<ClassId>();
  if (static_cast<std::size_t>(s.label) >= kClassCount) {
    in.fail("segment " + std::to_string(s.id) + " has class " +
            std::to_string(static_cast<unsigned>(s.label)));
  }
  s.plane.normal = get3(in);
  s.plane.offset = in.get<double>();
  s.centroid = get3(in);
  s.inliers = in.get<std::uint64_t>();
  s.rectangle.center = get3(in);
  s.rectangle.axes[0] = get3(in);
  s.rectangle.axes[1] = get3(in);
  s.rectangle.half_extents[0] = in.get<double>();
  s.rectangle.half_extents[1] = in.get<double>();
  s.thickness = in.get<double>();
  s.min = get3(in);
  s.max = get3(in);
  s.slope_deg = in.get<double>();
  s.area_m2 = in.get<double>();
  return s;
}

}  // namespace

void SegmentMap::save_state(StateWriter& out) const {
  out.tag("SEGM");
  // Points and keys mean nothing under another voxel size: the one setting
  // a stream is checked against.
  out.put(settings_.voxel);
  voxels_.save_state(out);
  out.put<std::uint64_t>(origins_.size());
  for (const Eigen::Vector3d& origin : origins_) put3(out, origin);
  out.put_vector(queued_in_);
  out.put(calls_);
  out.put_vector(marks_);
  out.put(mark_);

  out.tag("SREC");
  out.put<std::uint64_t>(records_.size());
  for (const Record& r : records_) {
    put_segment(out, r.view);
    out.put<std::uint8_t>(r.alive);
    out.put<std::uint64_t>(r.moments.count());
    put3(out, r.moments.sum());
    for (int k = 0; k < 9; ++k) out.put(r.moments.outer().data()[k]);
    put3(out, r.view_sum);
    out.put_vector(r.members);
    out.put<std::uint64_t>(r.stale);
    std::vector<float> outline;
    outline.reserve(3 * r.outline.size());
    for (const Eigen::Vector3f& p : r.outline) outline.insert(outline.end(), {p.x(), p.y(), p.z()});
    out.put_vector(outline);
    put3(out, r.box.min), put3(out, r.box.max);
    out.put<std::uint8_t>(r.changed);
    out.put_vector(r.left);
    out.put<std::uint64_t>(r.lost_since_rebuild);
  }
  out.put_vector(merged_into_);
  out.put<std::uint64_t>(merges_.size());
  for (const auto& [absorbed, survivor] : merges_) out.put(absorbed), out.put(survivor);
  for (const std::vector<std::uint32_t>& list : pending_) out.put_vector(list);
  out.put(new_pending_);
  out.put(searches_);
}

void SegmentMap::load_state(StateReader& in) {
  in.expect_tag("SEGM");
  const auto voxel = in.get<double>();
  if (voxel != settings_.voxel) {
    in.fail("the segment map was saved with a voxel size of " + metres_text(voxel) + ", this one's is " +
            metres_text(settings_.voxel));
  }
  LabelledVoxels voxels(settings_.voxel);
  voxels.load_state(in);
  const std::size_t n = voxels.size();
  std::vector<Eigen::Vector3d> origins(in.get_count(3 * sizeof(double)));
  for (Eigen::Vector3d& origin : origins) origin = get3(in);
  // Both grow to the point count on use, never past it.
  std::vector<std::uint64_t> queued_in = in.get_vector<std::uint64_t>();
  if (queued_in.size() > n) {
    in.fail("queue stamps for " + std::to_string(queued_in.size()) + " points of " + std::to_string(n));
  }
  const auto calls = in.get<std::uint64_t>();
  std::vector<std::uint32_t> marks = in.get_vector<std::uint32_t>();
  if (marks.size() > n) {
    in.fail("marks for " + std::to_string(marks.size()) + " points of " + std::to_string(n));
  }
  const auto mark = in.get<std::uint32_t>();

  // Every position a record ever took in lies in the voxel its point still
  // holds (give or take a float's rounding): a box, outline or sum beyond the
  // points' extent is corrupt, and would make the segment index loop all but
  // for ever or a plane fit overflow into NaN.
  Bounds extent;
  for (std::uint32_t i = 0; i < n; ++i) extent.extend(voxels.position(i));
  const double slack = 3 * voxels.voxel();
  const Eigen::Array3d lo = extent.min.array() - slack, hi = extent.max.array() + slack;
  const double farthest = n == 0 ? 0.0 : std::max(lo.abs().maxCoeff(), hi.abs().maxCoeff());
  auto inside = [&](const Eigen::Vector3d& p) { return (p.array() >= lo).all() && (p.array() <= hi).all(); };

  in.expect_tag("SREC");
  std::vector<Record> records(in.get_count(kRecordBytes));
  for (std::size_t id = 0; id < records.size(); ++id) {
    Record& r = records[id];
    const std::string name = "segment record " + std::to_string(id);
    r.view = get_segment(in);
    r.alive = get_flag(in, "alive");
    // An absorbed record is reset, id included; a live one keeps its own.
    if (r.alive && r.view.id != id) in.fail(name + " holds id " + std::to_string(r.view.id));
    const auto count = in.get<std::uint64_t>();
    const Eigen::Vector3d sum = get3(in);
    Eigen::Matrix3d outer;
    for (int k = 0; k < 9; ++k) outer.data()[k] = in.get<double>();
    const double c = static_cast<double>(count);
    if (!(sum.array().abs() <= 2 * c * farthest + 1).all() ||
        !(outer.array().abs() <= 2 * c * farthest * farthest + 1).all()) {
      in.fail(name + "'s plane sums are beyond its " + std::to_string(count) + " points' reach");
    }
    r.moments = PlaneMoments(count, sum, outer);
    r.view_sum = get3(in);
    r.members = get_points(in, n, name + "'s member list");
    r.stale = in.get<std::uint64_t>();
    const std::vector<float> outline = in.get_vector<float>();
    if (outline.size() % 3 != 0) {
      in.fail(name + "'s outline holds " + std::to_string(outline.size()) + " coordinates");
    }
    r.outline.resize(outline.size() / 3);
    for (std::size_t k = 0; k < r.outline.size(); ++k) {
      r.outline[k] = {outline[3 * k], outline[3 * k + 1], outline[3 * k + 2]};
      if (!inside(r.outline[k].cast<double>())) {
        in.fail(name + "'s outline point " + std::to_string(k) + " is off the map");
      }
    }
    r.box.min = get3(in);
    r.box.max = get3(in);
    // An empty box is skipped by every use.
    if (!r.box.empty() && !(inside(r.box.min) && inside(r.box.max))) {
      in.fail(name + "'s box reaches off the map");
    }
    r.changed = get_flag(in, "changed");
    r.left = get_points(in, n, name + "'s left list");
    r.lost_since_rebuild = in.get<std::uint64_t>();
  }
  // Each record's sums hold exactly the points it owns.
  std::vector<std::size_t> owned(records.size(), 0);
  for (std::size_t i = 0; i < n; ++i) {
    const std::int32_t owner = voxels.owner[i];
    if (owner != LabelledVoxels::kNoSegment &&
        (owner < 0 || static_cast<std::size_t>(owner) >= records.size())) {
      in.fail("point " + std::to_string(i) + " belongs to segment " + std::to_string(owner) + " of " +
              std::to_string(records.size()));
    }
    if (owner != LabelledVoxels::kNoSegment) ++owned[static_cast<std::size_t>(owner)];
    const std::uint32_t scan = voxels.scan[i];
    if (scan != LabelledVoxels::kNoScan && scan >= origins.size()) {
      in.fail("point " + std::to_string(i) + " was seen by scan " + std::to_string(scan) + " of " +
              std::to_string(origins.size()));
    }
  }
  for (std::size_t id = 0; id < records.size(); ++id) {
    if (records[id].moments.count() != owned[id]) {
      in.fail("segment record " + std::to_string(id) + " sums " +
              std::to_string(records[id].moments.count()) + " points but owns " + std::to_string(owned[id]));
    }
  }
  std::vector<std::int64_t> merged_into = in.get_vector<std::int64_t>();
  if (merged_into.size() != records.size()) {
    in.fail("merge targets for " + std::to_string(merged_into.size()) + " segments of " +
            std::to_string(records.size()));
  }
  for (std::size_t id = 0; id < merged_into.size(); ++id) {
    // A survivor has the lower id, so resolve() cannot loop.
    const std::int64_t next = merged_into[id];
    const bool fits = records[id].alive
                          ? next == kAlive
                          : next == kDissolved || (next >= 0 && static_cast<std::size_t>(next) < id);
    if (!fits) {
      in.fail("segment " + std::to_string(id) + (records[id].alive ? " (live)" : " (gone)") +
              " has merge target " + std::to_string(next));
    }
  }
  std::vector<std::pair<std::uint32_t, std::uint32_t>> merges(in.get_count(2 * sizeof(std::uint32_t)));
  for (auto& [absorbed, survivor] : merges) {
    absorbed = in.get<std::uint32_t>(), survivor = in.get<std::uint32_t>();
    if (survivor >= absorbed || absorbed >= records.size()) {
      in.fail("a merge of segment " + std::to_string(absorbed) + " into " + std::to_string(survivor) +
              " among " + std::to_string(records.size()));
    }
  }
  std::array<std::vector<std::uint32_t>, kClassCount> pending;
  for (std::size_t c = 0; c < kClassCount; ++c) {
    pending[c] = get_points(in, n, "the pending list of class " + std::to_string(c));
  }
  const auto new_pending = in.get<std::array<std::size_t, kClassCount>>();
  const auto searches = in.get<std::array<std::uint64_t, kClassCount>>();
  voxels_ = std::move(voxels);
  origins_ = std::move(origins);
  queued_in_ = std::move(queued_in);
  calls_ = calls;
  marks_ = std::move(marks);
  mark_ = mark;
  records_ = std::move(records);
  merged_into_ = std::move(merged_into);
  merges_ = std::move(merges);
  pending_ = std::move(pending);
  new_pending_ = new_pending;
  searches_ = searches;
}

}  // namespace sarmap::segments
