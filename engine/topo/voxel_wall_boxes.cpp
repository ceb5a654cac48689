#include "engine/topo/voxel_wall_boxes.hpp"

#include <unordered_map>

namespace sarmap::topo {
namespace {

bool obstacle(ClassId label) { return label == ClassId::Wall || label == ClassId::Other; }

// What two boxes must share to merge along one axis: their extents on the other two.
struct MergeKey {
  std::int32_t a, b, c, d;
  bool operator==(const MergeKey&) const = default;
};

struct MergeKeyHash {
  std::size_t operator()(const MergeKey& k) const {
    std::uint64_t h = 0x9e3779b97f4a7c15ull;
    for (const std::int32_t v : {k.a, k.b, k.c, k.d}) h = (h ^ static_cast<std::uint32_t>(v)) * 0x100000001b3ull;
    return static_cast<std::size_t>(h ^ (h >> 29));
  }
};

}  // namespace

std::vector<VoxelBox> obstacle_runs(const VoxelColumns& columns) {
  std::vector<VoxelBox> runs;
  for (int y = 0; y < columns.height; ++y) {
    for (int x = 0; x < columns.width; ++x) {
      const std::size_t c = columns.column(x, y);
      for (std::uint32_t i = columns.start[c]; i < columns.start[c + 1];) {
        if (!obstacle(columns.label[i])) {
          ++i;
          continue;
        }
        std::uint32_t end = i + 1;
        while (end < columns.start[c + 1] && obstacle(columns.label[end]) && columns.z[end] == columns.z[end - 1] + 1) ++end;
        const std::int32_t vx = columns.x0 + x, vy = columns.y0 + y;
        runs.push_back({vx, vx, vy, vy, columns.z[i], columns.z[end - 1]});
        i = end;
      }
    }
  }
  return runs;
}

std::vector<VoxelBox> merge_runs(std::span<const VoxelBox> runs) {
  // Along x: a run extends the strip of its row that has its heights and ends in the column before.
  std::vector<VoxelBox> strips;
  std::unordered_map<MergeKey, std::uint32_t, MergeKeyHash> open;
  for (const VoxelBox& run : runs) {
    const auto [it, added] = open.try_emplace(MergeKey{run.y0, run.z0, run.z1, 0}, static_cast<std::uint32_t>(strips.size()));
    if (!added && strips[it->second].x1 + 1 == run.x0) {
      strips[it->second].x1 = run.x1;
      continue;
    }
    it->second = static_cast<std::uint32_t>(strips.size());
    strips.push_back(run);
  }
  // Along y: strips come row by row, so a strip extends the box with its x
  // extent and heights that ends in the row before.
  std::vector<VoxelBox> boxes;
  open.clear();
  for (const VoxelBox& strip : strips) {
    const auto [it, added] =
        open.try_emplace(MergeKey{strip.x0, strip.x1, strip.z0, strip.z1}, static_cast<std::uint32_t>(boxes.size()));
    if (!added && boxes[it->second].y1 + 1 == strip.y0) {
      boxes[it->second].y1 = strip.y1;
      continue;
    }
    it->second = static_cast<std::uint32_t>(boxes.size());
    boxes.push_back(strip);
  }
  return boxes;
}

geometry::OrientedBox grown_box(const VoxelBox& box, double resolution, double grow) {
  const Eigen::Vector3d lo(box.x0 * resolution, box.y0 * resolution, box.z0 * resolution);
  const Eigen::Vector3d hi((box.x1 + 1) * resolution, (box.y1 + 1) * resolution, (box.z1 + 1) * resolution);
  geometry::OrientedBox out;
  out.center = (lo + hi) / 2;
  out.half_extents = (hi - lo) / 2 + Eigen::Vector3d::Constant(grow);
  return out;
}

}  // namespace sarmap::topo
