#include "engine/segments/labelled_voxels.hpp"

#include <algorithm>
#include <array>
#include <initializer_list>
#include <limits>
#include <string>
#include <utility>

#include "engine/core/capacity_bytes.hpp"
#include "engine/core/metres_text.hpp"

namespace sarmap::segments {
namespace {

constexpr int kBits = 21;
constexpr std::int64_t kHalf = std::int64_t{1} << (kBits - 1);
// A voxel size of 0 keeps points a millimetre apart.
constexpr double kExactVoxel = 0.001;
constexpr std::size_t kInitialVoxels = 4096;

}  // namespace

LabelledVoxels::LabelledVoxels(double voxel) : index_(kInitialVoxels) {
  const double size = voxel > 0 ? voxel : kExactVoxel;
  inverse_voxel_ = 1.0 / size;
  reach_ = size * static_cast<double>(kHalf - 1);
}

std::optional<std::uint64_t> LabelledVoxels::key_of(const Eigen::Vector3d& p) const {
  // Written so NaN fails the test as well.
  if (!(std::abs(p.x()) < reach_ && std::abs(p.y()) < reach_ && std::abs(p.z()) < reach_)) return std::nullopt;
  std::uint64_t key = 0;
  for (int axis = 0; axis < 3; ++axis) {
    const auto cell = static_cast<std::int64_t>(std::floor(p[axis] * inverse_voxel_)) + kHalf;
    key |= static_cast<std::uint64_t>(cell) << (kBits * axis);
  }
  return key;
}

std::optional<std::uint32_t> LabelledVoxels::find(std::uint64_t key) const {
  const std::uint32_t i = index_.find(key);
  if (i == FlatKeyIndex::kAbsent) return std::nullopt;
  return i;
}

std::uint32_t LabelledVoxels::add(std::uint64_t key, const Eigen::Vector3d& p, ClassId l, float r, std::uint32_t s) {
  const std::uint32_t i = index_.find_or_insert(key);
  x.push_back(static_cast<float>(p.x()));
  y.push_back(static_cast<float>(p.y()));
  z.push_back(static_cast<float>(p.z()));
  range.push_back(r);
  scan.push_back(s);
  label.push_back(static_cast<std::uint8_t>(l));
  owner.push_back(kNoSegment);
  pending.push_back(0);
  rounds.push_back(0);
  votes_.emplace_back();
  votes_.back()[static_cast<std::size_t>(l)] = 1;
  return i;
}

ClassId LabelledVoxels::vote(std::uint32_t i, ClassId l) {
  auto& v = votes_[i];
  auto& mine = v[static_cast<std::size_t>(l)];
  if (mine == std::numeric_limits<std::uint16_t>::max()) {
    // Halve every count: the proportions stay and nothing overflows.
    for (auto& c : v) c = static_cast<std::uint16_t>(c / 2);
  }
  ++mine;
  const auto current = static_cast<std::size_t>(label[i]);
  if (v[static_cast<std::size_t>(l)] > v[current]) label[i] = static_cast<std::uint8_t>(l);
  return static_cast<ClassId>(label[i]);
}

void LabelledVoxels::set_label(std::uint32_t i, ClassId l) {
  auto& v = votes_[i];
  const std::uint16_t most = *std::max_element(v.begin(), v.end());
  v.fill(0);
  v[static_cast<std::size_t>(l)] = std::max<std::uint16_t>(most, 1);
  label[i] = static_cast<std::uint8_t>(l);
}

std::size_t LabelledVoxels::memory_bytes() const {
  return capacity_bytes(x) + capacity_bytes(y) + capacity_bytes(z) + capacity_bytes(range) + capacity_bytes(scan) +
         capacity_bytes(label) + capacity_bytes(owner) + capacity_bytes(pending) + capacity_bytes(rounds) +
         capacity_bytes(votes_) + index_.memory_bytes();
}

std::vector<std::uint32_t> LabelledVoxels::keep_only(const std::vector<std::uint8_t>& keep) {
  std::vector<std::uint32_t> moved(size(), kDropped);
  const std::vector<std::uint64_t> keys = index_.keys();
  // The index is rebuilt as a checkpoint rebuilds it: the kept keys in order.
  FlatKeyIndex index(kInitialVoxels);
  std::uint32_t next = 0;
  for (std::uint32_t i = 0; i < size(); ++i) {
    if (!keep[i]) continue;
    moved[i] = next;
    index.find_or_insert(keys[i]);
    x[next] = x[i], y[next] = y[i], z[next] = z[i];
    range[next] = range[i];
    scan[next] = scan[i];
    label[next] = label[i];
    owner[next] = owner[i];
    pending[next] = pending[i];
    rounds[next] = rounds[i];
    votes_[next] = votes_[i];
    ++next;
  }
  for (auto* column : {&x, &y, &z, &range}) column->resize(next);
  scan.resize(next);
  for (auto* column : {&label, &pending, &rounds}) column->resize(next);
  owner.resize(next);
  votes_.resize(next);
  index_ = std::move(index);
  return moved;
}

void LabelledVoxels::save_state(StateWriter& out) const {
  out.tag("LVOX");
  out.put(inverse_voxel_);
  out.put_vector(index_.keys());
  out.put_vector(x), out.put_vector(y), out.put_vector(z);
  out.put_vector(range);
  out.put_vector(scan);
  out.put_vector(label);
  out.put_vector(owner);
  out.put_vector(pending);
  out.put_vector(rounds);
  out.put_vector(votes_);
}

void LabelledVoxels::load_state(StateReader& in) {
  in.expect_tag("LVOX");
  const auto inverse_voxel = in.get<double>();
  if (inverse_voxel != inverse_voxel_) {
    in.fail("the points were saved with voxels of " + metres_text(1.0 / inverse_voxel) + ", these are " +
            metres_text(1.0 / inverse_voxel_));
  }
  const std::vector<std::uint64_t> keys = in.get_vector<std::uint64_t>();
  // Inserted in their order, every key gets back its index, and a table
  // grown from the same capacity by the same keys is the same table.
  FlatKeyIndex index(kInitialVoxels);
  for (std::size_t i = 0; i < keys.size(); ++i) {
    if (index.find_or_insert(keys[i]) != i) {
      in.fail("voxel key " + std::to_string(i) + " repeats an earlier one");
    }
  }
  const std::size_t n = keys.size();
  auto column = [&]<class T>(std::vector<T>& values, const char* name) {
    values = in.get_vector<T>();
    if (values.size() != n) {
      in.fail(std::string("the ") + name + " column holds " + std::to_string(values.size()) +
              " points, not " + std::to_string(n));
    }
  };
  std::vector<float> xs, ys, zs, ranges;
  std::vector<std::uint32_t> scans;
  std::vector<std::uint8_t> labels, pending_classes, search_rounds;
  std::vector<std::int32_t> owners;
  std::vector<std::array<std::uint16_t, kClassCount>> votes;
  column(xs, "x"), column(ys, "y"), column(zs, "z");
  column(ranges, "range");
  column(scans, "scan");
  column(labels, "label");
  column(owners, "owner");
  column(pending_classes, "pending");
  column(search_rounds, "rounds");
  column(votes, "votes");
  // A label indexes the votes; a pending class names a pending list.
  for (std::size_t i = 0; i < n; ++i) {
    if (labels[i] >= kClassCount || pending_classes[i] >= kClassCount) {
      in.fail("point " + std::to_string(i) + " has class " + std::to_string(labels[i]) +
              " and pending class " + std::to_string(pending_classes[i]) + ", beyond the " +
              std::to_string(kClassCount) + " classes");
    }
    // A stored float may round into the next voxel, never farther; a point
    // far from its voxel (or not finite) would corrupt every sum it joins.
    const std::array<float, 3> p{xs[i], ys[i], zs[i]};
    for (int axis = 0; axis < 3; ++axis) {
      const std::int64_t cell = static_cast<std::int64_t>((keys[i] >> (kBits * axis)) & ((1u << kBits) - 1)) - kHalf;
      const double at = p[axis] * inverse_voxel_;
      if (!(std::abs(p[axis]) < 2 * reach_) || std::abs(static_cast<std::int64_t>(std::floor(at)) - cell) > 1) {
        in.fail("point " + std::to_string(i) + " at " + std::to_string(p[axis]) + " on axis " + std::to_string(axis) +
                " lies outside its voxel");
      }
    }
  }
  index_ = std::move(index);
  x = std::move(xs), y = std::move(ys), z = std::move(zs);
  range = std::move(ranges);
  scan = std::move(scans);
  label = std::move(labels);
  owner = std::move(owners);
  pending = std::move(pending_classes);
  rounds = std::move(search_rounds);
  votes_ = std::move(votes);
}

}  // namespace sarmap::segments
