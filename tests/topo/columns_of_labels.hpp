// Voxel columns from a dense grid of labels, for the topo tests that build
// columns by hand (the wall boxes, the wall scene).
#pragma once

#include <cstdint>
#include <vector>

#include "engine/core/classes.hpp"
#include "engine/topo/voxel_columns.hpp"

namespace sarmap::topo::testing {

// labels[x + width * (y + height * z)] (Unknown: no voxel), voxel (x0, y0, z0)
// first; the columns' resolution is VoxelColumns' default.
inline VoxelColumns columns_of(const std::vector<ClassId>& labels, int width, int height, int depth, std::int32_t x0,
                               std::int32_t y0, std::int32_t z0) {
  VoxelColumns out;
  out.x0 = x0;
  out.y0 = y0;
  out.width = width;
  out.height = height;
  out.start.push_back(0);
  for (int y = 0; y < height; ++y) {
    for (int x = 0; x < width; ++x) {
      for (int z = 0; z < depth; ++z) {
        const ClassId label = labels[x + width * (y + height * z)];
        if (label == ClassId::Unknown) continue;
        out.z.push_back(z0 + z);
        out.label.push_back(label);
      }
      out.start.push_back(static_cast<std::uint32_t>(out.z.size()));
    }
  }
  return out;
}

}  // namespace sarmap::topo::testing
