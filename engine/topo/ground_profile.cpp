#include "engine/topo/ground_profile.hpp"

#include <array>
#include <cmath>
#include <numbers>
#include <vector>

namespace sarmap::topo {
namespace {

constexpr double kSlopeStretch = 0.5;  // metres

}  // namespace

std::string_view to_string(DriveVerdict verdict) {
  switch (verdict) {
    case DriveVerdict::Passes: return "passes";
    case DriveVerdict::Wall: return "wall";
    case DriveVerdict::Drop: return "drop";
    case DriveVerdict::Steep: return "steep";
    case DriveVerdict::Unknown: return "unknown";
  }
  return "?";
}

GroundProfile ground_profile(const TraversabilityGrid& t, const Eigen::Vector3d& from, const Eigen::Vector3d& to,
                             const TopoSettings& settings) {
  GroundProfile out;
  const Eigen::Vector2d a = from.head<2>(), b = to.head<2>();
  const double run = (b - a).norm();
  const double rise = std::abs(to.z() - from.z());
  out.slope_deg = run > 0 ? std::atan2(rise, run) * 180 / std::numbers::pi : (rise == 0 ? 0.0 : 90.0);
  const double tan_max = std::tan(settings.max_slope_deg * std::numbers::pi / 180);
  const double res = t.grid.resolution();
  // Stand points may sit on voxel-quantised heights: a voxel of rise is allowed for.
  if (rise - res > tan_max * run) out.verdict = DriveVerdict::Steep;

  const auto steps = static_cast<std::size_t>(std::ceil(run / (res / 2)));
  std::array<std::size_t, kClassCount> votes{};
  // Known samples: distance along the drive and ground height.
  std::vector<std::pair<double, double>> known;
  known.reserve(steps + 1);
  bool unknown = false, drop = false, steep = false;
  for (std::size_t k = 0; k <= steps; ++k) {
    const double f = steps == 0 ? 0.0 : static_cast<double>(k) / static_cast<double>(steps);
    const GridCell cell = t.grid.cell_at(a + f * (b - a));
    if (t.grid.contains(cell) && t.near_drop[t.grid.index_of(cell)]) drop = true;
    const float g = t.ground_at(cell);
    if (std::isnan(g)) {
      unknown = true;
      continue;
    }
    ++votes[static_cast<std::size_t>(t.ground_class[t.grid.index_of(cell)])];
    const double along = f * run;
    if (!known.empty() && std::abs(g - known.back().second) > settings.max_step) drop = true;
    known.emplace_back(along, g);
  }
  // Over each stretch of at least kSlopeStretch, the climb less one voxel of quantisation.
  for (std::size_t i = 0, j = 0; i < known.size(); ++i) {
    while (j < known.size() && known[j].first - known[i].first < kSlopeStretch) ++j;
    if (j == known.size()) break;
    const double length = known[j].first - known[i].first;
    if (std::abs(known[j].second - known[i].second) - res > tan_max * length) steep = true;
  }
  if (drop) {
    out.verdict = DriveVerdict::Drop;
  } else if (steep || out.verdict == DriveVerdict::Steep) {
    out.verdict = DriveVerdict::Steep;
  } else if (unknown && !settings.unknown_traversable) {
    out.verdict = DriveVerdict::Unknown;
  }
  std::size_t best = 0;
  for (std::size_t c = 1; c < kClassCount; ++c) {
    if (votes[c] > votes[best]) best = c;
  }
  out.ground = votes[best] > 0 ? static_cast<ClassId>(best) : ClassId::Unknown;
  return out;
}

}  // namespace sarmap::topo
