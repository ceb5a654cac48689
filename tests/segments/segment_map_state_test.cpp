#include <algorithm>
#include <cstring>
#include <optional>
#include <string>
#include <string_view>
#include <vector>

#include <gtest/gtest.h>

#include "engine/core/error.hpp"
#include "engine/core/state_stream.hpp"
#include "engine/segments/segment_map.hpp"
#include "tests/release_only.hpp"
#include "tests/segments/segment_map_probes.hpp"
#include "tests/segments/synthetic_surfaces.hpp"

namespace sarmap::segments {
namespace {

using testing::add_patch;
using testing::Patch;
using testing::small_arena;
using testing::stripes;

// One call: a scan from its origin, or a reclassification without one.
struct Step {
  PointBuffer points;
  std::optional<Eigen::Vector3d> origin;
};

// Everything the state holds comes into play: noisy stripes leave points
// pending, a wall seen end first merges when its middle comes, a second pass
// from closer replaces points, and reclassifications split and dissolve
// segments.
std::vector<Step> session(double step = 0.02) {
  std::vector<Step> out;
  for (PointBuffer& scan : stripes(small_arena(), 5, step, 0.005, 1)) {
    const Eigen::Vector3d origin(scan.bounds().min.x() + 0.5, 1.0, 0.5);
    out.push_back({std::move(scan), origin});
  }
  PointBuffer left, right, middle;
  add_patch(left, {{0, -0.5, 0}, {1, 0, 0}, {0, 0, 1}, ClassId::Wall}, step, 0.003, 7);
  add_patch(right, {{2, -0.5, 0}, {1, 0, 0}, {0, 0, 1}, ClassId::Wall}, step, 0.003, 8);
  add_patch(middle, {{0.9, -0.5, 0}, {1.2, 0, 0}, {0, 0, 1}, ClassId::Wall}, step, 0.003, 9);
  out.push_back({std::move(left), Eigen::Vector3d(0.5, 1.5, 0.5)});
  out.push_back({std::move(right), Eigen::Vector3d(2.5, 1.5, 0.5)});
  PointBuffer platform;
  add_patch(platform, {{2.5, 0.5, 0.3}, {1, 0, 0}, {0, 1, 0}, ClassId::Other}, step);
  out.push_back({std::move(platform), std::nullopt});
  out.push_back({std::move(middle), Eigen::Vector3d(1.5, 1.5, 0.5)});
  for (PointBuffer& scan : stripes(small_arena(), 4, step, 0.002, 20)) {
    const Eigen::Vector3d origin(scan.bounds().min.x() + 0.5, 1.8, 0.8);
    out.push_back({std::move(scan), origin});
  }
  PointBuffer half_wall;
  add_patch(half_wall, {{2.3, 2.95, 0}, {0.8, 0, 0}, {0, 0, 1.2}, ClassId::Other}, step);
  out.push_back({std::move(half_wall), std::nullopt});
  return out;
}

SegmentUpdate apply(SegmentMap& map, const Step& step) {
  return step.origin ? map.integrate(step.points, *step.origin) : map.reclassify(step.points);
}

using testing::pending_total;
using testing::state_of;

void load(SegmentMap& map, std::string_view bytes) {
  StateReader in(bytes, "test checkpoint");
  map.load_state(in);
  in.expect_end();
}

void expect_same_update(const SegmentUpdate& a, const SegmentUpdate& b) {
  EXPECT_EQ(a.points_in, b.points_in);
  EXPECT_EQ(a.points_rejected, b.points_rejected);
  EXPECT_EQ(a.points_far, b.points_far);
  EXPECT_EQ(a.points_new, b.points_new);
  EXPECT_EQ(a.points_changed, b.points_changed);
  EXPECT_EQ(a.points_attached, b.points_attached);
  EXPECT_EQ(a.planes_found, b.planes_found);
  EXPECT_EQ(a.created, b.created);
  EXPECT_EQ(a.merged, b.merged);
  EXPECT_EQ(a.split, b.split);
  EXPECT_EQ(a.removed, b.removed);
}

// Exact equality, doubles included: a resumed run must match bit for bit.
void expect_same_map(const SegmentMap& a, const SegmentMap& b) {
  const auto sa = a.segments(), sb = b.segments();
  ASSERT_EQ(sa.size(), sb.size());
  for (std::size_t i = 0; i < sa.size(); ++i) {
    const Segment& x = *sa[i];
    const Segment& y = *sb[i];
    SCOPED_TRACE("segment " + std::to_string(x.id));
    EXPECT_EQ(x.id, y.id);
    EXPECT_EQ(x.label, y.label);
    EXPECT_EQ(x.plane.normal, y.plane.normal);
    EXPECT_EQ(x.plane.offset, y.plane.offset);
    EXPECT_EQ(x.centroid, y.centroid);
    EXPECT_EQ(x.inliers, y.inliers);
    EXPECT_EQ(x.rectangle.center, y.rectangle.center);
    EXPECT_EQ(x.rectangle.axes[0], y.rectangle.axes[0]);
    EXPECT_EQ(x.rectangle.axes[1], y.rectangle.axes[1]);
    EXPECT_EQ(x.rectangle.half_extents[0], y.rectangle.half_extents[0]);
    EXPECT_EQ(x.rectangle.half_extents[1], y.rectangle.half_extents[1]);
    EXPECT_EQ(x.thickness, y.thickness);
    EXPECT_EQ(x.min, y.min);
    EXPECT_EQ(x.max, y.max);
    EXPECT_EQ(x.slope_deg, y.slope_deg);
    EXPECT_EQ(x.area_m2, y.area_m2);
    EXPECT_TRUE(a.member_points(x.id) == b.member_points(y.id));
  }
  EXPECT_EQ(a.merges(), b.merges());
  EXPECT_EQ(a.point_count(), b.point_count());
  EXPECT_EQ(a.pending_counts(), b.pending_counts());
  // And what the eye cannot see: stale members, marks, stamps, sums.
  EXPECT_TRUE(state_of(a) == state_of(b));
}

TEST(SegmentMapState, ResumedMapContinuesExactlyAsTheUninterruptedOne) {
  const std::vector<Step> steps = session();
  bool saved_with_pending = false, saved_after_merges = false, reclassified_first = false;
  // Every cut, from after the first scan to before the last call (the cut
  // before step 7 has the reclassification come first after the load).
  for (std::size_t k = 1; k < steps.size(); ++k) {
    SCOPED_TRACE("saved after " + std::to_string(k) + " calls");
    SegmentMap uninterrupted;
    for (std::size_t i = 0; i < k; ++i) apply(uninterrupted, steps[i]);
    saved_with_pending |= pending_total(uninterrupted) > 0;
    saved_after_merges |= !uninterrupted.merges().empty();
    reclassified_first |= !steps[k].origin.has_value();
    SegmentMap resumed;
    load(resumed, state_of(uninterrupted));
    expect_same_map(uninterrupted, resumed);
    for (std::size_t i = k; i < steps.size(); ++i) {
      SCOPED_TRACE("call " + std::to_string(i));
      expect_same_update(apply(uninterrupted, steps[i]), apply(resumed, steps[i]));
      expect_same_map(uninterrupted, resumed);
      if (::testing::Test::HasFailure()) return;
    }
  }
  EXPECT_TRUE(saved_with_pending);
  EXPECT_TRUE(saved_after_merges);
  EXPECT_TRUE(reclassified_first);
}

TEST(SegmentMapState, SaveLoadSaveGivesTheSameBytes) {
  const std::vector<Step> steps = session();
  SegmentMap map;
  const std::string empty = state_of(map);
  SegmentMap loaded;
  load(loaded, empty);
  EXPECT_TRUE(state_of(loaded) == empty);
  for (const Step& step : steps) apply(map, step);
  const std::string bytes = state_of(map);
  load(loaded, bytes);
  EXPECT_TRUE(state_of(loaded) == bytes);
  // Loading over a map with a state of its own replaces all of it.
  SegmentMap other;
  apply(other, steps[0]);
  apply(other, steps[1]);
  load(other, bytes);
  EXPECT_TRUE(state_of(other) == bytes);
}

TEST(SegmentMapState, TruncatedStreamIsAnErrorAndChangesNothing) {
  NOT_UNDER_TSAN();
  // Sparse points keep the stream short enough to cut it everywhere.
  const std::vector<Step> steps = session(0.1);
  SegmentMap full;
  for (const Step& step : steps) apply(full, step);
  ASSERT_FALSE(full.merges().empty());
  const std::string bytes = state_of(full);
  SegmentMap target;
  apply(target, steps[0]);
  const std::string before = state_of(target);
  auto refused = [&](std::size_t length) {
    StateReader in(std::string_view(bytes).substr(0, length), "cut checkpoint");
    try {
      target.load_state(in);
    } catch (const Error& e) {
      EXPECT_NE(std::string(e.what()).find("byte offset"), std::string::npos) << e.what();
      return true;
    }
    return false;
  };
  for (std::size_t length = 0; length < bytes.size(); length += 97) EXPECT_TRUE(refused(length)) << length;
  // Every cut through the last sections (merge targets, merges, pending lists).
  for (std::size_t length = bytes.size() > 2000 ? bytes.size() - 2000 : 0; length < bytes.size(); ++length) {
    EXPECT_TRUE(refused(length)) << length;
  }
  EXPECT_TRUE(state_of(target) == before);
}

// Overwrites a value of type T at `offset`.
template <class T>
std::string with(std::string bytes, std::size_t offset, T value) {
  std::memcpy(bytes.data() + offset, &value, sizeof value);
  return bytes;
}

TEST(SegmentMapState, CorruptCountsAndIdsAreErrorsNamingTheProblem) {
  const std::vector<Step> steps = session(0.1);
  SegmentMap full;
  for (const Step& step : steps) apply(full, step);
  const std::string bytes = state_of(full);
  SegmentMap target;
  apply(target, steps[0]);
  const std::string before = state_of(target);
  auto expect_refused = [&](const std::string& corrupt, const std::string& words) {
    StateReader in(corrupt, "bad checkpoint");
    try {
      target.load_state(in);
      ADD_FAILURE() << "accepted; expected: " << words;
    } catch (const Error& e) {
      EXPECT_EQ(e.code(), ErrorCode::Parse);
      EXPECT_NE(std::string(e.what()).find(words), std::string::npos) << words << ": " << e.what();
    }
  };
  // The layout: "SEGM", voxel, "LVOX", inverse voxel, then the keys and one
  // column after another, each with its count.
  const std::size_t keys_at = 4 + 8 + 4 + 8;
  std::uint64_t n = 0;
  std::memcpy(&n, bytes.data() + keys_at, sizeof n);
  ASSERT_EQ(n, full.point_count());
  const std::size_t keys = keys_at + 8, xs = keys + 8 * n + 8, ranges = xs + 3 * (4 * n + 8);
  const std::size_t scans = ranges + 4 * n + 8, labels = scans + 4 * n + 8, owners = labels + n + 8;
  const std::size_t pendings = owners + 4 * n + 8;
  std::uint64_t first_key = 0;
  std::memcpy(&first_key, bytes.data() + keys, sizeof first_key);

  expect_refused(bytes.substr(0, 2) + "XX" + bytes.substr(4), "expected section SEGM");
  expect_refused(with<std::uint64_t>(bytes, keys_at, std::uint64_t{1} << 60), "does not fit");
  expect_refused(with<std::uint64_t>(bytes, pendings + 2 * n + 8, n - 1), "votes column holds");
  expect_refused(with(bytes, keys + 8, first_key), "repeats an earlier one");
  expect_refused(with<float>(bytes, xs, 1e30f), "outside its voxel");
  expect_refused(with<std::uint32_t>(bytes, scans, 1u << 30), "was seen by scan");
  expect_refused(with<std::uint8_t>(bytes, labels, 200), "has class 200");
  expect_refused(with<std::uint8_t>(bytes, pendings, 9), "pending class 9");
  expect_refused(with<std::int32_t>(bytes, owners, 1 << 30), "belongs to segment");
  const std::size_t tag = bytes.find("SREC");
  ASSERT_NE(tag, std::string::npos);
  const std::size_t records = tag + 4;
  expect_refused(with<std::uint64_t>(bytes, records, std::uint64_t{1} << 62), "does not fit");
  expect_refused(with<std::uint32_t>(bytes, records + 8, 7), "holds id 7");  // record 0 is alive
  // Record 0: its segment (229 bytes), alive flag, plane sums (104), view sum
  // (24), then its members.
  const std::size_t members = records + 8 + 229 + 1 + 104 + 24;
  std::uint64_t member_count = 0;
  std::memcpy(&member_count, bytes.data() + members, sizeof member_count);
  ASSERT_GT(member_count, 0u);
  expect_refused(with<std::uint32_t>(bytes, members + 8, 0xffffffffu), "names point 4294967295");
  expect_refused(with<std::uint8_t>(bytes, records + 8 + 229, 2), "alive flag holds 2");
  std::uint64_t summed = 0;
  std::memcpy(&summed, bytes.data() + records + 8 + 229 + 1, sizeof summed);
  expect_refused(with<std::uint64_t>(bytes, records + 8 + 229 + 1, summed + 1), "owns");
  expect_refused(with<double>(bytes, records + 8 + 229 + 1 + 8, 1e300), "plane sums");
  EXPECT_TRUE(state_of(target) == before);
}

TEST(SegmentMapState, FlippedBytesNeverCrash) {
  NOT_UNDER_TSAN();
  // Sparse points keep the stream short enough to flip every byte that
  // holds a segment, a merge or a pending list.
  const std::vector<Step> steps = session(0.1);
  SegmentMap full;
  for (std::size_t i = 0; i + 1 < steps.size(); ++i) apply(full, steps[i]);
  ASSERT_FALSE(full.merges().empty());
  const std::string bytes = state_of(full);
  // Either refused with an error, or a map that goes on working. The points'
  // columns are sampled, the rest is flipped byte by byte (every sixth byte
  // under ASan; the fuzz job flips the rest).
  const std::size_t records = bytes.find("SREC");
  ASSERT_NE(records, std::string::npos);
  std::size_t refused = 0, accepted = 0;
  const std::size_t stride = kSanitizedBuild ? 6 : 1;
  for (std::size_t at = 0; at < bytes.size(); at += at < records ? 31 : stride) {
    std::string corrupt = bytes;
    corrupt[at] = static_cast<char>(corrupt[at] ^ 0xff);
    SegmentMap map;
    try {
      load(map, corrupt);
    } catch (const Error&) {
      ++refused;
      continue;
    }
    // Some of them go on, to show the state they took works.
    if (++accepted % 37 == 0) apply(map, steps.back());
  }
  EXPECT_GT(refused, 0u);
  EXPECT_GT(accepted, 0u);
}

TEST(SegmentMapState, AnotherVoxelSizeIsRefusedNamingBoth) {
  SegmentMap map;
  apply(map, session(0.1)[0]);
  SegmentSettings coarse;
  coarse.voxel = 0.05;
  SegmentMap other(coarse);
  try {
    load(other, state_of(map));
    FAIL() << "a stream of 2.5 cm voxels loaded into a map of 5 cm ones";
  } catch (const Error& e) {
    const std::string what = e.what();
    EXPECT_NE(what.find("0.025 m"), std::string::npos) << what;
    EXPECT_NE(what.find("0.05 m"), std::string::npos) << what;
  }
  EXPECT_EQ(other.point_count(), 0u);
}

}  // namespace
}  // namespace sarmap::segments
