// PlanningGrid: world <-> cell conversion at the cell edges, far outside and
// with a negative origin; the constructor's checks; reset.
#include "engine/topo/planning_grid.hpp"

#include <gtest/gtest.h>

#include <algorithm>
#include <cmath>
#include <limits>

#include "engine/core/error.hpp"

namespace sarmap::topo {
namespace {

TEST(PlanningGrid, CellsHoldTheirLowerAndLeftEdges) {
  const PlanningGrid grid(4, 3, 0.5, Eigen::Vector2d(-1.0, 2.0));
  EXPECT_EQ(grid.cell_at({-1.0, 2.0}), (GridCell{0, 0}));
  EXPECT_EQ(grid.cell_at({-0.5, 2.5}), (GridCell{1, 1}));
  EXPECT_EQ(grid.cell_at({-0.5000001, 2.4999999}), (GridCell{0, 0}));
  EXPECT_EQ(grid.cell_at({0.99, 3.49}), (GridCell{3, 2}));
  // The far edges belong to the next cell, outside.
  EXPECT_FALSE(grid.contains(grid.cell_at({1.0, 3.0})));
  EXPECT_EQ(grid.cell_at({-1.01, 1.99}), (GridCell{-1, -1}));
}

TEST(PlanningGrid, CentresConvertBackToTheirCell) {
  const PlanningGrid grid(7, 5, 0.05, Eigen::Vector2d(-3.3, 0.7));
  for (int y = 0; y < grid.height(); ++y) {
    for (int x = 0; x < grid.width(); ++x) {
      const Eigen::Vector2d centre = grid.centre_of({x, y});
      EXPECT_EQ(grid.cell_at(centre), (GridCell{x, y}));
    }
  }
  EXPECT_TRUE(grid.centre_of({0, 0}).isApprox(Eigen::Vector2d(-3.275, 0.725)));
}

TEST(PlanningGrid, PointsFarOutsideOrNotFiniteAreOutside) {
  const PlanningGrid grid(10, 10, 0.1, Eigen::Vector2d::Zero());
  EXPECT_FALSE(grid.contains(grid.cell_at({1e30, 0.5})));
  EXPECT_FALSE(grid.contains(grid.cell_at({-1e30, 0.5})));
  EXPECT_FALSE(grid.contains(grid.cell_at({std::nan(""), 0.5})));
  EXPECT_FALSE(grid.contains(grid.cell_at({0.5, std::numeric_limits<double>::infinity()})));
}

TEST(PlanningGrid, StoresRowMajorFromTheLowestRow) {
  PlanningGrid grid(3, 2, 1.0, Eigen::Vector2d::Zero(), CellState::Free);
  grid.set({2, 1}, CellState::Occupied);
  grid.set({0, 1}, CellState::Unknown);
  EXPECT_EQ(grid.cells()[5], CellState::Occupied);
  EXPECT_EQ(grid.cells()[3], CellState::Unknown);
  EXPECT_EQ(grid.at({1, 0}), CellState::Free);
}

// A reset grid is the grid constructed with the same arguments; a smaller
// one keeps the storage, and bad shapes are refused as by the constructor.
TEST(PlanningGrid, ResetIsANewGridOnTheSameStorage) {
  PlanningGrid grid(4, 3, 0.1, Eigen::Vector2d(1.0, 2.0), CellState::Free);
  grid.reset(6, 5, 0.05, Eigen::Vector2d(-1.0, 0.5), CellState::Occupied);
  const PlanningGrid fresh(6, 5, 0.05, Eigen::Vector2d(-1.0, 0.5), CellState::Occupied);
  EXPECT_EQ(grid.width(), 6);
  EXPECT_EQ(grid.height(), 5);
  EXPECT_EQ(grid.resolution(), 0.05);
  EXPECT_EQ(grid.origin(), fresh.origin());
  EXPECT_TRUE(std::equal(grid.cells().begin(), grid.cells().end(), fresh.cells().begin(), fresh.cells().end()));
  EXPECT_EQ(grid.cell_at({-0.97, 0.52}), (GridCell{0, 0}));
  const CellState* storage = grid.cells().data();
  grid.reset(2, 2, 0.05, Eigen::Vector2d::Zero());
  EXPECT_EQ(grid.cells().data(), storage);
  EXPECT_EQ(grid.cells().size(), 4u);
  EXPECT_EQ(grid.at({1, 1}), CellState::Unknown);
  EXPECT_THROW(grid.reset(0, 2, 0.05, Eigen::Vector2d::Zero()), Error);
  EXPECT_THROW(grid.reset(2, 2, 0.05, Eigen::Vector2d(std::nan(""), 0.0)), Error);
}

TEST(PlanningGrid, RefusesEmptyOrUnusableGrids) {
  const Eigen::Vector2d zero = Eigen::Vector2d::Zero();
  EXPECT_THROW(PlanningGrid(0, 5, 0.1, zero), Error);
  EXPECT_THROW(PlanningGrid(5, -1, 0.1, zero), Error);
  EXPECT_THROW(PlanningGrid(70000, 70000, 0.1, zero), Error);
  EXPECT_THROW(PlanningGrid(5, 5, 0.0, zero), Error);
  EXPECT_THROW(PlanningGrid(5, 5, std::nan(""), zero), Error);
  EXPECT_THROW(PlanningGrid(5, 5, 0.1, Eigen::Vector2d(std::nan(""), 0.0)), Error);
  try {
    PlanningGrid(5, 5, -0.5, zero);
  } catch (const Error& e) {
    EXPECT_EQ(e.code(), ErrorCode::InvalidArgument);
    EXPECT_NE(std::string(e.what()).find("resolution must be a finite number > 0"), std::string::npos)
        << e.what();
  }
}

}  // namespace
}  // namespace sarmap::topo
