// Tests kernels/simd_level.hpp: names round-trip, the baseline is always
// there, and forcing a level the CPU lacks is refused.
#include "kernels/simd_level.hpp"

#include <gtest/gtest.h>

#include <cstdio>
#include <cstdlib>
#include <string>

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

// The kernel tests run every level this CPU has and skip the others without
// failing, so a green run on an AVX2-only machine says nothing of AVX-512.
// This case prints which levels this run covers (CI prints it too), and
// SARMAP_REQUIRE_SIMD=avx512 (or avx2) makes a machine without it a failure.
TEST(SimdLevel, ReportsTheLevelsThisRunTests) {
  std::string tested, untested;
  for (SimdLevel level : {SimdLevel::Sse42, SimdLevel::Avx2, SimdLevel::Avx512}) {
    std::string& list = simd_level_supported(level) ? tested : untested;
    list += (list.empty() ? "" : " ") + std::string(to_string(level));
  }
  std::printf("kernel SIMD levels tested: %s; untested (CPU lacks them): %s\n", tested.c_str(),
              untested.empty() ? "none" : untested.c_str());
  ::testing::Test::RecordProperty("simd_levels_tested", tested);
  if (const char* required = std::getenv("SARMAP_REQUIRE_SIMD"); required != nullptr && *required != '\0') {
    const auto level = simd_level_from_string(required);
    ASSERT_TRUE(level.has_value()) << "SARMAP_REQUIRE_SIMD=" << required << " is not a level name";
    EXPECT_TRUE(simd_level_supported(*level)) << "SARMAP_REQUIRE_SIMD=" << required << " but this CPU lacks it";
  }
}

TEST(SimdLevel, PanelWidthIsTwoVectors) {
  EXPECT_EQ(panel_width(SimdLevel::Sse42), 8);
  EXPECT_EQ(panel_width(SimdLevel::Avx2), 16);
  EXPECT_EQ(panel_width(SimdLevel::Avx512), 32);
}

}  // namespace
}  // namespace sarmap::kernels
