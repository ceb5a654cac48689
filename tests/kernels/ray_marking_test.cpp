// The ray-marking kernel at every instruction set against marking each ray's
// dda_walk() cells one by one: random rays from inside and outside the
// cells' grid, rays along axes and through cell edges and corners, rays that
// stay in their start cell, negative coordinates, and batches whose lanes
// finish at very different times; both into block masks found through a
// sink and into a dense grid of blocks, and into a dense grid from rays
// handed out in pieces.
#include "kernels/ray_marking.hpp"

#include <gtest/gtest.h>

#include <algorithm>
#include <array>
#include <cmath>
#include <cstdint>
#include <map>
#include <random>
#include <set>
#include <tuple>
#include <vector>

#include "kernels/dda_walk.hpp"
#include "tests/kernels/kernel_test_support.hpp"

namespace sarmap::kernels {
namespace {

using Cell = std::tuple<std::int32_t, std::int32_t, std::int32_t>;

// A sink over an ordered map, and the cells its bits stand for.
struct MaskTable {
  std::map<Cell, std::uint32_t> index;
  std::vector<Cell> blocks;
  std::vector<std::uint64_t> words;
  std::uint64_t* base = nullptr;

  static std::uint32_t block_index(void* self, std::int32_t bx, std::int32_t by, std::int32_t bz) {
    auto& t = *static_cast<MaskTable*>(self);
    const auto [it, inserted] = t.index.emplace(Cell{bx, by, bz}, static_cast<std::uint32_t>(t.blocks.size()));
    if (inserted) {
      t.blocks.push_back({bx, by, bz});
      t.words.resize(t.words.size() + kMarkBlockWords, 0);
      t.base = t.words.data();
    }
    return it->second;
  }
  BlockMaskSink sink() { return {&MaskTable::block_index, this, &base}; }

  std::set<Cell> cells() const {
    std::set<Cell> out;
    for (std::size_t b = 0; b < blocks.size(); ++b) {
      const auto [bx, by, bz] = blocks[b];
      for (int local = 0; local < 512; ++local) {
        if ((words[b * kMarkBlockWords + local / 64] >> (local % 64)) & 1) {
          out.insert({bx * 8 + (local & 7), by * 8 + ((local >> 3) & 7), bz * 8 + (local >> 6)});
        }
      }
    }
    return out;
  }
};

std::set<Cell> walked_cells(const double start[3], const std::vector<double>& ends, std::size_t* visits) {
  std::set<Cell> out;
  *visits = 0;
  for (std::size_t r = 0; r < ends.size() / 3; ++r) {
    *visits += dda_walk(start, &ends[3 * r], [&](std::int32_t x, std::int32_t y, std::int32_t z) {
      out.insert({x, y, z});
      return true;
    });
  }
  return out;
}

// A dense grid over the blocks of start and every end, with one block of
// margin on each side so a stray mark outside the walk's box would show.
struct DenseGrid {
  DenseMaskGrid grid;
  std::vector<std::uint64_t> words;

  DenseGrid(const std::array<double, 3>& start, const std::vector<double>& ends)
      : grid(dense_grid_covering(start.data(), ends.data(), ends.size() / 3)) {
    for (int i = 0; i < 3; ++i) {
      grid.first_block[i] -= 1;
      grid.blocks[i] += 2;
    }
    words.assign(dense_grid_blocks(grid) * kMarkBlockWords, 0);
    grid.words = words.data();
  }

  std::set<Cell> cells() const {
    std::set<Cell> out;
    for (std::size_t w = 0; w < words.size(); ++w) {
      const auto block = static_cast<std::int32_t>(w / kMarkBlockWords);
      const std::int32_t bx = grid.first_block[0] + block % grid.blocks[0];
      const std::int32_t by = grid.first_block[1] + (block / grid.blocks[0]) % grid.blocks[1];
      const std::int32_t bz = grid.first_block[2] + block / (grid.blocks[0] * grid.blocks[1]);
      for (int bit = 0; bit < 64; ++bit) {
        if ((words[w] >> bit) & 1) {
          out.insert({bx * 8 + (bit & 7), by * 8 + (bit >> 3), bz * 8 + static_cast<std::int32_t>(w % kMarkBlockWords)});
        }
      }
    }
    return out;
  }
};

// The rays of ends handed out in pieces of the given sizes (0 for an empty
// piece), one after the other, through RayPieces.
struct PieceList {
  const std::vector<double>& ends;
  std::vector<std::size_t> sizes;
  std::size_t next_piece = 0, next_ray = 0;

  static bool next(void* self, const double** out, std::size_t* count) {
    auto& p = *static_cast<PieceList*>(self);
    if (p.next_piece == p.sizes.size()) return false;
    *count = p.sizes[p.next_piece++];
    *out = p.ends.data() + 3 * p.next_ray;
    p.next_ray += *count;
    return true;
  }
  RayPieces pieces() { return {&PieceList::next, this}; }
};

// Piece sizes over n rays: empty pieces, single rays and runs of up to 70
// (shorter and longer than a vector walk's stage of rays), mixed at random.
std::vector<std::size_t> random_piece_sizes(std::size_t n, unsigned seed) {
  std::mt19937 rng(seed);
  std::vector<std::size_t> sizes{0};
  for (std::size_t left = n; left > 0;) {
    const std::size_t pick = rng() % 4;
    const std::size_t size = std::min(left, pick == 0 ? 0 : pick == 1 ? 1 : 1 + rng() % 70);
    sizes.push_back(size);
    left -= size;
  }
  sizes.push_back(0);
  return sizes;
}

void expect_same_cells(const std::array<double, 3>& start, const std::vector<double>& ends, const char* what) {
  std::size_t expected_visits = 0;
  const std::set<Cell> expected = walked_cells(start.data(), ends, &expected_visits);
  {
    MaskTable table;
    EXPECT_EQ(mark_ray_cells_reference(start.data(), ends.data(), ends.size() / 3, table.sink()), expected_visits)
        << what;
    EXPECT_EQ(table.cells(), expected) << what << ": reference";
  }
  for (SimdLevel level : test::supported_levels()) {
    MaskTable table;
    EXPECT_EQ(mark_ray_cells(start.data(), ends.data(), ends.size() / 3, table.sink(), level), expected_visits)
        << what << " at " << to_string(level);
    EXPECT_EQ(table.cells(), expected) << what << " at " << to_string(level);
  }
  {
    DenseGrid dense(start, ends);
    EXPECT_EQ(mark_ray_cells_dense_reference(start.data(), ends.data(), ends.size() / 3, dense.grid),
              expected_visits)
        << what << ": dense reference";
    EXPECT_EQ(dense.cells(), expected) << what << ": dense reference";
  }
  for (SimdLevel level : test::supported_levels()) {
    DenseGrid dense(start, ends);
    EXPECT_EQ(mark_ray_cells_dense(start.data(), ends.data(), ends.size() / 3, dense.grid, level), expected_visits)
        << what << " dense at " << to_string(level);
    EXPECT_EQ(dense.cells(), expected) << what << " dense at " << to_string(level);
  }
  // The same rays in pieces, at every level: in random pieces, all in one,
  // and one ray per piece.
  const std::size_t n = ends.size() / 3;
  for (SimdLevel level : test::supported_levels()) {
    for (const std::vector<std::size_t>& sizes :
         {random_piece_sizes(n, 17), std::vector<std::size_t>{n}, std::vector<std::size_t>(n, 1)}) {
      DenseGrid dense(start, ends);
      PieceList list{ends, sizes};
      EXPECT_EQ(mark_ray_pieces_dense(start.data(), list.pieces(), dense.grid, level), expected_visits)
          << what << " in " << sizes.size() << " pieces at " << to_string(level);
      EXPECT_EQ(list.next_piece, sizes.size()) << what << ": every piece asked for";
      EXPECT_EQ(dense.cells(), expected)
          << what << " in " << sizes.size() << " pieces at " << to_string(level);
    }
  }
}

TEST(RayMarking, RandomRaysMarkTheCellsOfEveryWalk) {
  std::mt19937 rng(5);
  std::uniform_real_distribution<double> around(-40.0, 40.0);
  for (const std::array<double, 3> start : {std::array<double, 3>{0.3, 0.6, 0.1}, std::array<double, 3>{-17.25, 3.5, 9.0},
                                            std::array<double, 3>{1000.5, -2000.5, 7.75}}) {
    std::vector<double> ends;
    for (int r = 0; r < 1001; ++r) {
      for (int i = 0; i < 3; ++i) ends.push_back(start[i] + around(rng) * (r % 7 == 0 ? 0.05 : 1.0));
    }
    expect_same_cells(start, ends, "random rays");
  }
}

TEST(RayMarking, AxesEdgesCornersAndEmptyRays) {
  const std::array<double, 3> start{0.5, 0.5, 0.5};
  std::vector<double> ends = {
      10.5, 0.5, 0.5,   -9.5, 0.5, 0.5,  0.5, 12.5, 0.5, 0.5, 0.5, -7.5,  // along axes
      8.5, 8.5, 0.5,    -6.5, 6.5, 0.5,  5.5, 5.5, 5.5, -4.5, -4.5, -4.5,  // through edges and corners
      0.9, 0.1, 0.7,    0.5, 0.5, 0.5,                                     // never leave the start cell
      16.5, 8.5, -7.5,  3.0, 3.0, 3.0,   -3.0, 2.0, 1.0};                   // ends on faces
  expect_same_cells(start, ends, "hand-picked rays");
  // A corner start: every ray leaves through a grid vertex.
  expect_same_cells({0.0, 0.0, 0.0}, ends, "rays from a grid vertex");
}

TEST(RayMarking, LanesOfVeryDifferentLengthsAndFewRays) {
  const std::array<double, 3> start{2.25, -3.5, 1.125};
  std::vector<double> ends;
  for (int r = 0; r < 37; ++r) {
    const double length = (r % 5 == 0) ? 300.0 : 1.5 + r % 3;
    const double a = 0.37 * r, b = 0.11 * r;
    ends.insert(ends.end(), {start[0] + length * std::cos(a) * std::cos(b), start[1] + length * std::sin(a) * std::cos(b),
                             start[2] + length * std::sin(b)});
  }
  expect_same_cells(start, ends, "mixed lengths");
  for (std::size_t n : {0u, 1u, 3u, 9u}) {
    expect_same_cells(start, std::vector<double>(ends.begin(), ends.begin() + 3 * n), "a few rays");
  }
  // Lanes are refilled every few steps: rays of one to three cells arrive
  // between two refills, some lanes several times over a long one's walk.
  std::vector<double> short_ends;
  for (int r = 0; r < 101; ++r) {
    const double length = r % 17 == 0 ? 40.0 : 0.6 + 0.9 * (r % 3);
    const double a = 0.61 * r, b = 0.23 * r;
    short_ends.insert(short_ends.end(),
                      {start[0] + length * std::cos(a) * std::cos(b), start[1] + length * std::sin(a) * std::cos(b),
                       start[2] + length * std::sin(b)});
  }
  expect_same_cells(start, short_ends, "rays shorter than a refill's steps");
}

TEST(RayMarking, FarFromTheOriginAndStartsOnTheEdgeOfACell) {
  // The map's keys reach 10 km at 1 cm, 1e6 cells: the vector walks hold
  // cells in floats, exact up to 2^24. Starts whose fraction rounds to 1 in
  // float (kept below it by dda_setup) and ends a hair below a face.
  std::mt19937 rng(11);
  std::uniform_real_distribution<double> around(-60.0, 60.0);
  for (const std::array<double, 3> start :
       {std::array<double, 3>{999999.25, -999999.75, 1048000.5}, std::array<double, 3>{-1048575.5, 524287.999999999, 3.0},
        std::array<double, 3>{7.999999999, -0.000000001, 0.99999999999},
        // On a grid vertex: the end a hair below (-1e-50) rounds to -0 in
        // float, which dda_setup() keeps below 0 (else 1 / (end - start) = -inf).
        std::array<double, 3>{0.0, 0.0, 0.0}}) {
    std::vector<double> ends;
    for (int r = 0; r < 300; ++r) {
      for (int i = 0; i < 3; ++i) ends.push_back(start[i] + around(rng));
    }
    for (int i = 0; i < 3; ++i) ends.push_back(std::floor(start[i]) - 1e-50);  // just into the cell below
    for (int i = 0; i < 3; ++i) ends.push_back(std::floor(start[i]) + 1.0);    // on the face above
    expect_same_cells(start, ends, "far or edge starts");
  }
}

}  // namespace
}  // namespace sarmap::kernels
