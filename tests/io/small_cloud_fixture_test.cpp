// The shipped fixture datasets/fixtures/small_cloud.ply must be exactly what
// its generator (sarmap_make_small_cloud) writes, and small enough to ship.
#include <filesystem>
#include <gtest/gtest.h>

#include "engine/io/ply.hpp"
#include "point_cloud_test_support.hpp"
#include "small_cloud_generator.hpp"

namespace sarmap {
namespace {

const std::filesystem::path kFixture = std::filesystem::path(SARMAP_SOURCE_DIR) / "datasets/fixtures/small_cloud.ply";

TEST(SmallCloudFixture, MatchesItsGenerator) {
  PointCloudFileInfo info;
  const PointBuffer shipped = read_ply(kFixture, &info);
  EXPECT_EQ(info.encoding, "binary_little_endian");
  test::expect_same_cloud(test::make_small_arena_cloud(), shipped);
}

TEST(SmallCloudFixture, IsSmallAndHasTheThreeClasses) {
  EXPECT_LT(std::filesystem::file_size(kFixture), 100u * 1024u);
  const PointBuffer cloud = read_ply(kFixture);
  EXPECT_GE(cloud.size(), 2000u);
  EXPECT_LE(cloud.size(), 5000u);
  std::size_t per_class[6] = {};
  for (const std::uint8_t label : cloud.labels()) ++per_class[label];
  EXPECT_EQ(per_class[0], 0u);
  EXPECT_GT(per_class[1], 0u);
  EXPECT_GT(per_class[2], 0u);
  EXPECT_GT(per_class[3], 0u);
}

}  // namespace
}  // namespace sarmap
