#include "engine/segments/labelled_voxels.hpp"

#include <algorithm>
#include <limits>

namespace sarmap::segments {
namespace {

constexpr int kBits = 21;
constexpr std::int64_t kHalf = std::int64_t{1} << (kBits - 1);
// A voxel size of 0 keeps points a millimetre apart.
constexpr double kExactVoxel = 0.001;

}  // namespace

LabelledVoxels::LabelledVoxels(double voxel) : index_(4096) {
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

}  // namespace sarmap::segments
