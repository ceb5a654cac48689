// Whether two metric maps hold the same blocks with the same voxels, byte
// for byte: what "the same map" means in the integrator's tests.
#pragma once

#include <cstring>

#include "engine/metric/metric_map.hpp"

namespace sarmap::testing {

inline bool maps_identical(const metric::MetricMap& a, const metric::MetricMap& b) {
  const auto ka = a.blocks().sorted_block_keys(), kb = b.blocks().sorted_block_keys();
  if (ka != kb) return false;
  for (const metric::BlockKey& k : ka) {
    const metric::DenseVoxels va = a.blocks().find(k)->dense(), vb = b.blocks().find(k)->dense();
    if (std::memcmp(va.data(), vb.data(), sizeof(va)) != 0) return false;
  }
  return true;
}

}  // namespace sarmap::testing
