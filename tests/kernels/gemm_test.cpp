// Tests kernels/gemm.hpp: the packed, fused GEMMs against their scalar
// references at every instruction set, odd sizes, and 1 vs 2 threads.
#include "kernels/gemm.hpp"

#include <gtest/gtest.h>
#include <tbb/global_control.h>

#include <cmath>
#include <vector>

#include "tests/kernels/kernel_test_support.hpp"

namespace sarmap::kernels {
namespace {

struct Shape {
  std::size_t m, rows, cols;
};

// Tolerance from the magnitude of the products summed (float vs double).
float tolerance(std::size_t cols) { return 1e-5f * static_cast<float>(cols) + 1e-5f; }

TEST(Gemm, MatchesReferenceAtEveryLevelAndShape) {
  const Shape shapes[] = {{1, 1, 1}, {5, 7, 3}, {13, 64, 64}, {97, 33, 70}, {200, 100, 12}, {96, 64, 128}};
  for (SimdLevel level : test::supported_levels()) {
    for (const Shape& s : shapes) {
      for (float slope : {1.0f, 0.2f}) {
        const std::size_t ldx = s.cols + 3, ldy = s.rows + 5;
        const auto x = test::random_floats(s.m * ldx, 1);
        const auto w = test::random_floats(s.rows * s.cols, 2);
        const auto bias = test::random_floats(s.rows, 3);
        std::vector<float> y(s.m * ldy, 42.0f), ref(s.m * ldy, 42.0f);
        gemm_bias_act(x.data(), ldx, s.m, PackedMatrix(w.data(), bias.data(), s.rows, s.cols, level), slope, y.data(),
                      ldy);
        gemm_bias_act_reference(x.data(), ldx, s.m, w.data(), bias.data(), s.rows, s.cols, slope, ref.data(), ldy);
        for (std::size_t i = 0; i < y.size(); ++i) {
          ASSERT_NEAR(y[i], ref[i], tolerance(s.cols))
              << to_string(level) << " m=" << s.m << " rows=" << s.rows << " cols=" << s.cols << " at " << i;
        }
      }
    }
  }
}

TEST(Gemm, ColumnMaxMatchesReference) {
  const Shape shapes[] = {{1, 5, 3}, {7, 64, 64}, {300, 70, 19}, {4096 / 8, 130, 192}};
  for (SimdLevel level : test::supported_levels()) {
    for (const Shape& s : shapes) {
      const auto x = test::random_floats(s.m * s.cols, 4);
      const auto w = test::random_floats(s.rows * s.cols, 5);
      std::vector<float> got(s.rows), ref(s.rows);
      gemm_column_max(x.data(), s.cols, s.m, PackedMatrix(w.data(), nullptr, s.rows, s.cols, level), got.data());
      gemm_column_max_reference(x.data(), s.cols, s.m, w.data(), s.rows, s.cols, ref.data());
      for (std::size_t o = 0; o < s.rows; ++o) ASSERT_NEAR(got[o], ref[o], tolerance(s.cols)) << to_string(level);
    }
  }
}

TEST(Gemm, ColumnMaxOfAllEqualRowsIsThatRow) {
  const std::size_t m = 50, rows = 20, cols = 8;
  std::vector<float> x(m * cols, 0.5f);
  const auto w = test::random_floats(rows * cols, 6);
  std::vector<float> one(rows), all(rows);
  for (SimdLevel level : test::supported_levels()) {
    const PackedMatrix packed(w.data(), nullptr, rows, cols, level);
    gemm_column_max(x.data(), cols, 1, packed, one.data());
    gemm_column_max(x.data(), cols, m, packed, all.data());
    EXPECT_EQ(one, all);
  }
}

TEST(Gemm, SameResultWithOneAndTwoThreads) {
  const std::size_t m = 1000, rows = 96, cols = 64;
  const auto x = test::random_floats(m * cols, 7);
  const auto w = test::random_floats(rows * cols, 8);
  for (SimdLevel level : test::supported_levels()) {
    const PackedMatrix packed(w.data(), nullptr, rows, cols, level);
    std::vector<float> one(m * rows), two(m * rows), max1(rows), max2(rows);
    {
      tbb::global_control c(tbb::global_control::max_allowed_parallelism, 1);
      gemm_bias_act(x.data(), cols, m, packed, 0.2f, one.data(), rows);
      gemm_column_max(x.data(), cols, m, packed, max1.data());
    }
    {
      tbb::global_control c(tbb::global_control::max_allowed_parallelism, 2);
      gemm_bias_act(x.data(), cols, m, packed, 0.2f, two.data(), rows);
      gemm_column_max(x.data(), cols, m, packed, max2.data());
    }
    EXPECT_EQ(one, two);
    EXPECT_EQ(max1, max2);
  }
}

}  // namespace
}  // namespace sarmap::kernels
