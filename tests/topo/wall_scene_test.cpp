// Tests of engine/topo/wall_scene.hpp: its voxel boxes merged tile by tile
// answer as the exact union of the boxes merged over the whole map, and a
// wall scene rebuilt update after update on its own storage (as the
// topological map keeps it) holds the same boxes and answers every question
// as a scene made anew from the same segments and voxel columns.
#include "engine/topo/wall_scene.hpp"

#include <gtest/gtest.h>

#include <array>
#include <cmath>
#include <map>
#include <random>
#include <vector>

#include "engine/geometry/segment_box.hpp"
#include "engine/topo/voxel_wall_boxes.hpp"
#include "tests/topo/columns_of_labels.hpp"

namespace sarmap::topo {
namespace {

// Random voxel columns over width x height columns from (x0, y0): walls
// along a row and a column, then `scattered` random voxels of several classes
// (one per column by default).
VoxelColumns random_columns(std::mt19937& rng, int width, int height, std::int32_t x0, std::int32_t y0,
                            int scattered = -1) {
  constexpr int kDepth = 12;
  std::vector<ClassId> labels(static_cast<std::size_t>(width) * height * kDepth, ClassId::Unknown);
  auto at = [&](int x, int y, int z) -> ClassId& { return labels[x + width * (y + height * z)]; };
  const int wall_y = static_cast<int>(rng() % height), wall_x = static_cast<int>(rng() % width);
  for (int z = 1; z < 9; ++z) {
    for (int x = 0; x < width; ++x) at(x, wall_y, z) = ClassId::Wall;
    for (int y = 0; y < height; ++y) at(wall_x, y, z) = ClassId::Other;
  }
  const ClassId choices[] = {ClassId::Unknown, ClassId::Terrain, ClassId::Wall, ClassId::Other};
  for (int k = 0; k < (scattered < 0 ? width * height : scattered); ++k) {
    at(static_cast<int>(rng() % width), static_cast<int>(rng() % height), static_cast<int>(rng() % kDepth)) =
        choices[rng() % 4];
  }
  return testing::columns_of(labels, width, height, kDepth, x0, y0, 0);
}

// `count` upright wall segments (and one floor, which is no wall) at random places.
std::vector<segments::Segment> random_segments(std::mt19937& rng, int count) {
  std::uniform_real_distribution<double> coord(-1, 3), half(0.1, 1.0), angle(0, 3.14);
  std::vector<segments::Segment> out;
  for (int k = 0; k <= count; ++k) {
    segments::Segment s;
    s.id = static_cast<std::uint32_t>(k);
    s.label = k == count ? ClassId::Terrain : ClassId::Wall;
    const double a = angle(rng);
    s.rectangle.center = {coord(rng), coord(rng), 0.4};
    s.rectangle.axes = {Eigen::Vector3d(std::cos(a), std::sin(a), 0), Eigen::Vector3d::UnitZ()};
    s.rectangle.half_extents = {half(rng), 0.4};
    s.plane.normal = Eigen::Vector3d(-std::sin(a), std::cos(a), 0);
    s.thickness = 0.02;
    out.push_back(s);
  }
  return out;
}

// Columns spanning several tiles (walls across their borders), against the
// exact geometry of the boxes merged over the whole map: a stand is clear
// exactly when it is farther than the tolerance from every such box at each
// body height, and a drive between clear stands is blocked exactly when it
// meets one at some height (drives within the tolerance of a surface left out).
TEST(WallScene, TilesAnswerAsTheBoxesOfTheWholeMap) {
  const TopoSettings settings;
  std::mt19937 rng(5);
  const VoxelColumns columns = random_columns(rng, 3 * WallScene::kTileColumns + 9, 70, -WallScene::kTileColumns - 5, -20, 60);
  const WallScene scene({}, &columns, settings);
  std::vector<geometry::OrientedBox> whole;
  for (const VoxelBox& box : merge_runs(obstacle_runs(columns))) {
    whole.push_back(grown_box(box, columns.resolution, settings.robot_radius));
  }
  ASSERT_GT(scene.boxes().size(), whole.size());  // the tiles split boxes at their borders

  // Each obstacle voxel lies in exactly one of the scene's boxes (taken back
  // to voxels), and each box within one tile.
  std::map<std::array<std::int32_t, 3>, int> covered;
  const auto tile_of = [](std::int32_t v) {
    return static_cast<std::int32_t>(std::floor(static_cast<double>(v) / WallScene::kTileColumns));
  };
  for (const geometry::OrientedBox& box : scene.boxes()) {
    const Eigen::Vector3d lo = (box.center - box.half_extents).array() + settings.robot_radius;
    const Eigen::Vector3d hi = (box.center + box.half_extents).array() - settings.robot_radius;
    const auto index = [&](double v) { return static_cast<std::int32_t>(std::lround(v / columns.resolution)); };
    const VoxelBox v{index(lo.x()), index(hi.x()) - 1, index(lo.y()), index(hi.y()) - 1, index(lo.z()), index(hi.z()) - 1};
    EXPECT_EQ(tile_of(v.x0), tile_of(v.x1));
    EXPECT_EQ(tile_of(v.y0), tile_of(v.y1));
    for (std::int32_t vx = v.x0; vx <= v.x1; ++vx) {
      for (std::int32_t vy = v.y0; vy <= v.y1; ++vy) {
        for (std::int32_t vz = v.z0; vz <= v.z1; ++vz) ++covered[{vx, vy, vz}];
      }
    }
  }
  std::map<std::array<std::int32_t, 3>, int> obstacles;
  for (int cy = 0; cy < columns.height; ++cy) {
    for (int cx = 0; cx < columns.width; ++cx) {
      const std::size_t c = columns.column(cx, cy);
      for (std::uint32_t i = columns.start[c]; i < columns.start[c + 1]; ++i) {
        if (columns.label[i] == ClassId::Wall || columns.label[i] == ClassId::Other) {
          obstacles[{columns.x0 + cx, columns.y0 + cy, columns.z[i]}] = 1;
        }
      }
    }
  }
  EXPECT_EQ(covered, obstacles);

  const auto lifted = [&](const Eigen::Vector3d& p, double h) { return Eigen::Vector3d(p + Eigen::Vector3d(0, 0, h)); };
  std::uniform_real_distribution<double> x(-3.5, 6.5), y(-1.0, 2.5);
  std::size_t clear_stands = 0, compared_drives = 0, blocked_drives = 0;
  std::vector<StandPair> pairs;
  for (int k = 0; k < 2000 && pairs.size() < 300; ++k) {
    const Eigen::Vector3d stand(x(rng), y(rng), 0);
    double nearest = 1e9;
    for (const geometry::OrientedBox& box : whole) {
      for (double h : settings.body_heights) nearest = std::min(nearest, geometry::signed_distance(lifted(stand, h), box));
    }
    if (std::abs(nearest - geometry::kSurfaceTolerance) < 1e-6) continue;  // on the tolerance's edge
    const bool clear = nearest > geometry::kSurfaceTolerance;
    ASSERT_EQ(scene.clear(stand), clear) << stand.transpose();
    if (!clear) continue;
    ++clear_stands;
    if (k % 2 == 1 && clear_stands > 1) pairs.back().to = stand;
    else pairs.push_back({stand, stand});
  }
  std::vector<std::uint8_t> blocked(pairs.size());
  scene.blocked(pairs, blocked);
  for (std::size_t i = 0; i < pairs.size(); ++i) {
    bool expected = false, near = false;
    for (const geometry::OrientedBox& box : whole) {
      for (double h : settings.body_heights) {
        const geometry::Segment drive{lifted(pairs[i].from, h), lifted(pairs[i].to, h)};
        expected |= geometry::segment_intersects_box(drive, box);
        near |= geometry::segment_near_box_surface(drive, box);
      }
    }
    if (near) continue;
    ++compared_drives;
    blocked_drives += expected;
    EXPECT_EQ(blocked[i] != 0, expected) << "drive " << i;
  }
  EXPECT_GT(clear_stands, 100u);
  EXPECT_GT(compared_drives, 100u);
  EXPECT_GT(blocked_drives, 10u);
  EXPECT_LT(blocked_drives, compared_drives - 10);
}

TEST(WallScene, RebuiltSceneEqualsOneMadeAnew) {
  const TopoSettings settings;
  std::mt19937 rng(11);
  std::uniform_real_distribution<double> coord(-1.5, 3.5);
  WallScene rebuilt(settings);
  // Extents and contents that grow, shrink and move; a build with no voxels
  // and one with neither voxels nor walls among them.
  const int sizes[][2] = {{20, 10}, {40, 30}, {60, 50}, {30, 60}, {0, 0}, {70, 20}, {10, 10}, {50, 50}};
  for (int round = 0; round < 8; ++round) {
    const int width = sizes[round][0], height = sizes[round][1];
    const VoxelColumns columns = random_columns(rng, std::max(width, 1), std::max(height, 1),
                                                static_cast<std::int32_t>(rng() % 20) - 10, -5);
    const std::vector<segments::Segment> walls = random_segments(rng, width == 0 ? 0 : 1 + static_cast<int>(rng() % 4));
    std::vector<const segments::Segment*> segments;
    for (const segments::Segment& s : walls) segments.push_back(&s);
    const VoxelColumns* voxels = width == 0 ? nullptr : &columns;
    rebuilt.rebuild(segments, voxels);
    const WallScene anew(segments, voxels, settings);

    ASSERT_EQ(rebuilt.boxes().size(), anew.boxes().size()) << "round " << round;
    EXPECT_EQ(rebuilt.segment_boxes(), anew.segment_boxes());
    for (std::size_t b = 0; b < anew.boxes().size(); ++b) {
      EXPECT_EQ(rebuilt.boxes()[b].center, anew.boxes()[b].center);
      EXPECT_EQ(rebuilt.boxes()[b].half_extents, anew.boxes()[b].half_extents);
    }
    if (width > 0) {
      EXPECT_GT(anew.boxes().size(), anew.segment_boxes()) << "round " << round;
    }

    std::size_t blocked_count = 0, clear_count = 0;
    std::vector<StandPair> pairs(500);
    for (StandPair& p : pairs) {
      p.from = {coord(rng), coord(rng), 0};
      p.to = {coord(rng), coord(rng), 0};
      const bool clear = anew.clear(p.from);
      EXPECT_EQ(rebuilt.clear(p.from), clear);
      clear_count += clear;
    }
    std::vector<std::uint8_t> blocked_rebuilt(pairs.size()), blocked_anew(pairs.size());
    rebuilt.blocked(pairs, blocked_rebuilt);
    anew.blocked(pairs, blocked_anew);
    EXPECT_EQ(blocked_rebuilt, blocked_anew) << "round " << round;
    for (std::uint8_t b : blocked_anew) blocked_count += b;
    if (width > 0) {
      // Both answers are asked somewhere: the test would not see a scene that blocks everything.
      EXPECT_GT(blocked_count, 0u) << "round " << round;
      EXPECT_LT(blocked_count, pairs.size()) << "round " << round;
      EXPECT_GT(clear_count, 0u) << "round " << round;
      EXPECT_LT(clear_count, pairs.size()) << "round " << round;
    } else {
      EXPECT_EQ(blocked_count, 0u);
      EXPECT_EQ(clear_count, pairs.size());
    }
  }
}

// The topological map's way: each build told which columns changed since
// the last (a rectangle of new labels, sometimes all cleared; the extent
// cropped, the cropped columns counted as changed), the tiles elsewhere kept;
// boxes and answers as a scene made anew from the same columns.
TEST(WallScene, RebuiltWhereTheColumnsChangedEqualsOneMadeAnew) {
  const TopoSettings settings;
  std::mt19937 rng(21);
  constexpr int kWidth = 3 * WallScene::kTileColumns + 11, kHeight = 2 * WallScene::kTileColumns + 3, kDepth = 12;
  const std::int32_t x0 = -WallScene::kTileColumns - 7, y0 = -30;
  std::vector<ClassId> labels(static_cast<std::size_t>(kWidth) * kHeight * kDepth, ClassId::Unknown);
  // A voxel in ten holds a wall, one in ten something else, one in ten terrain.
  const ClassId choices[] = {ClassId::Wall, ClassId::Other, ClassId::Terrain};
  const auto fill = [&](int xa, int xb, int ya, int yb, bool clear) {
    for (int z = 0; z < kDepth; ++z) {
      for (int y = ya; y <= yb; ++y) {
        for (int x = xa; x <= xb; ++x) {
          const unsigned pick = rng() % 10;
          labels[x + kWidth * (y + kHeight * z)] = clear || pick >= 3 ? ClassId::Unknown : choices[pick];
        }
      }
    }
  };
  fill(0, kWidth - 1, 0, kHeight - 1, false);
  WallScene rebuilt(settings);
  rebuilt.rebuild({}, nullptr);
  int width = kWidth;
  for (int round = 0; round < 12; ++round) {
    ColumnRect changed;
    if (round == 0) {
      changed = {x0, x0 + kWidth - 1, y0, y0 + kHeight - 1};  // the first build: everything is new
    } else if (round == 9) {
      width = kWidth - WallScene::kTileColumns - 20;  // cropped: its last columns are gone
      changed = {x0 + width, x0 + kWidth - 1, y0, y0 + kHeight - 1};
    } else {
      const int xa = static_cast<int>(rng() % width), ya = static_cast<int>(rng() % kHeight);
      const int xb = std::min(width - 1, xa + static_cast<int>(rng() % 40)), yb = std::min(kHeight - 1, ya + static_cast<int>(rng() % 40));
      fill(xa, xb, ya, yb, round % 4 == 3);
      changed = {x0 + xa, x0 + xb, y0 + ya, y0 + yb};
    }
    std::vector<ClassId> cropped(static_cast<std::size_t>(width) * kHeight * kDepth);
    for (int z = 0; z < kDepth; ++z) {
      for (int y = 0; y < kHeight; ++y) {
        for (int x = 0; x < width; ++x) cropped[x + width * (y + kHeight * z)] = labels[x + kWidth * (y + kHeight * z)];
      }
    }
    const VoxelColumns columns = testing::columns_of(cropped, width, kHeight, kDepth, x0, y0, 0);
    rebuilt.rebuild({}, &columns, &changed);
    const WallScene anew({}, &columns, settings);

    ASSERT_EQ(rebuilt.boxes().size(), anew.boxes().size()) << "round " << round;
    for (std::size_t b = 0; b < anew.boxes().size(); ++b) {
      ASSERT_EQ(rebuilt.boxes()[b].center, anew.boxes()[b].center) << "round " << round << ", box " << b;
      ASSERT_EQ(rebuilt.boxes()[b].half_extents, anew.boxes()[b].half_extents) << "round " << round << ", box " << b;
    }
    std::uniform_real_distribution<double> x(x0 * 0.05, (x0 + kWidth) * 0.05), y(y0 * 0.05, (y0 + kHeight) * 0.05);
    std::vector<StandPair> pairs(300);
    for (StandPair& p : pairs) {
      p.from = {x(rng), y(rng), 0};
      p.to = p.from + Eigen::Vector3d(x(rng) / 4, y(rng) / 4, 0);
      EXPECT_EQ(rebuilt.clear(p.from), anew.clear(p.from)) << "round " << round;
    }
    std::vector<std::uint8_t> blocked_rebuilt(pairs.size()), blocked_anew(pairs.size());
    rebuilt.blocked(pairs, blocked_rebuilt);
    anew.blocked(pairs, blocked_anew);
    EXPECT_EQ(blocked_rebuilt, blocked_anew) << "round " << round;
  }
}

}  // namespace
}  // namespace sarmap::topo
