// A metric map written voxel by voxel, so that every count, class and bound
// a test expects is known without integrating any scan.
#pragma once

#include <array>
#include <cstddef>

#include "engine/metric/metric_map.hpp"

namespace sarmap::testing {

// At 0.1 m, two blocks:
// - block (0, 0, 0): voxels 0..11 occupied, voxel l of class l % 6 (class 0:
//   no evidence, so Unknown), i.e. voxels x 0..7 at y 0 and x 0..3 at y 1,
//   z 0; voxels 100..104 free (at z 1);
// - block (-1, 2, 0): voxel 511, key (-1, 23, 7), occupied wall; voxel 0,
//   key (-8, 16, 0), free.
// 13 occupied (unknown 2, terrain 2, wall 3, inclined ramp 2, flat ramp 2,
// other 2), 6 free; occupied voxels span (-0.1, 0, 0) to (0.8, 2.4, 0.8),
// known ones (-0.8, 0, 0) to (0.8, 2.4, 0.8).
inline metric::MetricMap hand_made_map() {
  metric::MetricMap map(metric::settings_at_resolution(0.1));
  const std::int16_t occupied = map.occupancy().max(), free = map.occupancy().min();
  const metric::BlockKey a{0, 0, 0}, b{-1, 2, 0};
  for (int l = 0; l < 12; ++l) {
    metric::SemanticVoxel v{occupied, {}};
    if (l % 6 != 0) v.evidence[l % 6] = 100;
    map.blocks().set_voxel(metric::voxel_of(a, l), v);
  }
  for (int l = 100; l < 105; ++l) map.blocks().set_voxel(metric::voxel_of(a, l), {free, {}});
  metric::SemanticVoxel wall{occupied, {}};
  wall.evidence[static_cast<std::size_t>(ClassId::Wall)] = 100;
  map.blocks().set_voxel(metric::voxel_of(b, 511), wall);
  map.blocks().set_voxel(metric::voxel_of(b, 0), {free, {}});
  return map;
}

inline constexpr std::array<std::size_t, kClassCount> kHandMadeOccupiedByClass = {2, 2, 3, 2, 2, 2};

}  // namespace sarmap::testing
