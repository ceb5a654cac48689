#include "engine/segments/plane_regions.hpp"

#include <gtest/gtest.h>

#include "engine/core/error.hpp"

namespace sarmap::segments {
namespace {

std::vector<Eigen::Vector2d> strip(double x0, double x1, double step) {
  std::vector<Eigen::Vector2d> p;
  for (double x = x0; x <= x1 + 1e-9; x += step) {
    for (double y = 0; y <= 1.0 + 1e-9; y += step) p.emplace_back(x, y);
  }
  return p;
}

TEST(PlaneRegions, ADoorwaySplitsAWallInTwo) {
  auto p = strip(0, 1.5, 0.025);
  const auto right = strip(2.3, 4.0, 0.025);
  p.insert(p.end(), right.begin(), right.end());
  const auto regions = plane_regions(p, 0.1);
  ASSERT_EQ(regions.size(), 2u);
  EXPECT_EQ(regions[0].size(), right.size());  // the larger first
  EXPECT_EQ(regions[1].size(), p.size() - right.size());
  EXPECT_EQ(regions[1].front(), 0u);
}

TEST(PlaneRegions, ANarrowGapBelowTwoCellsDoesNotSplit) {
  // Last point at x = 1.025 (cell 10), next at 1.12 (cell 11): neighbouring cells.
  auto p = strip(0, 1.04, 0.025);
  const auto right = strip(1.12, 2.0, 0.025);
  p.insert(p.end(), right.begin(), right.end());
  EXPECT_EQ(plane_regions(p, 0.1).size(), 1u);
}

TEST(PlaneRegions, DiagonalNeighboursConnectAndEveryPointIsInOneRegion) {
  std::vector<Eigen::Vector2d> p = {{0.05, 0.05}, {0.15, 0.15}, {0.25, 0.25}, {0.95, 0.05}};
  const auto regions = plane_regions(p, 0.1);
  ASSERT_EQ(regions.size(), 2u);
  EXPECT_EQ(regions[0], (std::vector<std::uint32_t>{0, 1, 2}));
  EXPECT_EQ(regions[1], (std::vector<std::uint32_t>{3}));
}

TEST(PlaneRegions, RejectsABadCellSize) {
  std::vector<Eigen::Vector2d> p = {{0, 0}};
  EXPECT_THROW(plane_regions(p, 0), Error);
  EXPECT_THROW(plane_regions(p, std::nan("")), Error);
  EXPECT_TRUE(plane_regions(std::vector<Eigen::Vector2d>{}, 0.1).empty());
}

}  // namespace
}  // namespace sarmap::segments
