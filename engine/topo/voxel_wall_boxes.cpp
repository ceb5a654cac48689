#include "engine/topo/voxel_wall_boxes.hpp"

#include <algorithm>

#include "engine/metric/voxel_key.hpp"

namespace sarmap::topo {
namespace {

bool obstacle(ClassId label) { return label == ClassId::Wall || label == ClassId::Other; }

// Boxes merged along one axis (`lo`, `hi` its extent's members; `other_lo`,
// `other_hi` those of the other horizontal axis): a box extends the one
// before it that ends just before it there and has the same extents on the
// other two axes. `boxes` must come so that such a neighbour always comes
// first. The key leaves out other_hi: only the latest box with a given
// (other_lo, z0, z1) can still be the one just before, so only it is kept,
// and it is compared in full.
void merge_along(std::span<const VoxelBox> boxes, std::int32_t VoxelBox::*lo, std::int32_t VoxelBox::*hi,
                 std::int32_t VoxelBox::*other_lo, std::int32_t VoxelBox::*other_hi, FlatKeyMap<std::uint32_t>& open,
                 std::vector<VoxelBox>& merged) {
  merged.clear();
  // Each key's latest box, by its index in `merged`.
  open.clear();
  for (const VoxelBox& box : boxes) {
    const auto [at, added] =
        open.try_emplace(metric::pack(box.*other_lo, box.z0, box.z1), static_cast<std::uint32_t>(merged.size()));
    std::uint32_t& latest = open.values()[at];
    if (!added) {
      VoxelBox& last = merged[latest];
      if (last.*hi + 1 == box.*lo && last.*other_hi == box.*other_hi) {
        last.*hi = box.*hi;
        continue;
      }
      latest = static_cast<std::uint32_t>(merged.size());
    }
    merged.push_back(box);
  }
}

}  // namespace

std::vector<VoxelBox> obstacle_runs(const VoxelColumns& columns) {
  std::vector<VoxelBox> runs;
  const ColumnRect all{columns.x0, columns.x0 + columns.width - 1, columns.y0, columns.y0 + columns.height - 1};
  obstacle_runs(columns, all, runs);
  return runs;
}

void obstacle_runs(const VoxelColumns& columns, const ColumnRect& within, std::vector<VoxelBox>& runs) {
  runs.clear();
  const int x_begin = std::max(within.x0 - columns.x0, 0), x_end = std::min(within.x1 - columns.x0 + 1, columns.width);
  const int y_begin = std::max(within.y0 - columns.y0, 0), y_end = std::min(within.y1 - columns.y0 + 1, columns.height);
  for (int y = y_begin; y < y_end; ++y) {
    for (int x = x_begin; x < x_end; ++x) {
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
}

std::vector<VoxelBox> merge_runs(std::span<const VoxelBox> runs) {
  BoxMergeScratch scratch;
  std::vector<VoxelBox> merged;
  merge_runs(runs, scratch, merged);
  return merged;
}

void merge_runs(std::span<const VoxelBox> runs, BoxMergeScratch& scratch, std::vector<VoxelBox>& merged) {
  // Runs come column by column along each row, so along x first; the strips
  // then come row by row, so along y.
  merge_along(runs, &VoxelBox::x0, &VoxelBox::x1, &VoxelBox::y0, &VoxelBox::y1, scratch.open, scratch.strips);
  merge_along(scratch.strips, &VoxelBox::y0, &VoxelBox::y1, &VoxelBox::x0, &VoxelBox::x1, scratch.open, merged);
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
