// Tests kernels/simd_level.hpp: names round-trip, the baseline is always
// there, and forcing a level the CPU lacks is refused.
#include "kernels/simd_level.hpp"

#include <gtest/gtest.h>

namespace sarmap::kernels {
namespace {

TEST(SimdLevel, NamesRoundTrip) {
  for (SimdLevel level : {SimdLevel::Sse42, SimdLevel::Avx2, SimdLevel::Avx512}) {
    EXPECT_EQ(simd_level_from_string(to_string(level)), level);
  }
  EXPECT_FALSE(simd_level_from_string("neon").has_value());
}

TEST(SimdLevel, BaselineIsSupportedAndActiveLevelIsRunnable) {
  EXPECT_TRUE(simd_level_supported(SimdLevel::Sse42));
  EXPECT_TRUE(simd_level_supported(active_simd_level()));
}

TEST(SimdLevel, ForcingALevelSticksOnlyWhenSupported) {
  const SimdLevel before = active_simd_level();
  EXPECT_TRUE(set_simd_level(SimdLevel::Sse42));
  EXPECT_EQ(active_simd_level(), SimdLevel::Sse42);
  for (SimdLevel level : {SimdLevel::Avx2, SimdLevel::Avx512}) {
    EXPECT_EQ(set_simd_level(level), simd_level_supported(level));
  }
  set_simd_level(before);
}

TEST(SimdLevel, PanelWidthIsTwoVectors) {
  EXPECT_EQ(panel_width(SimdLevel::Sse42), 8);
  EXPECT_EQ(panel_width(SimdLevel::Avx2), 16);
  EXPECT_EQ(panel_width(SimdLevel::Avx512), 32);
}

}  // namespace
}  // namespace sarmap::kernels
