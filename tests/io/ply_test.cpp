#include "engine/io/ply.hpp"

#include <cmath>
#include <cstring>
#include <fstream>
#include <gmock/gmock.h>
#include <gtest/gtest.h>
#include <iterator>
#include <limits>
#include <string>
#include <vector>

#include "point_cloud_test_support.hpp"
#include "tests/file_bytes.hpp"

namespace sarmap {
namespace {

using test::data_path;
using test::expect_same_cloud;
using test::make_cloud;
using test::slurp;
using test::spit;
using ::testing::ElementsAre;
using ::testing::HasSubstr;

class PlyEncodings : public ::testing::TestWithParam<bool> {};

TEST_P(PlyEncodings, RoundTripsEveryAttribute) {
  const bool binary = GetParam();
  test::ScratchDir dir("ply");
  // More than one decoding block (2048 points) and one write chunk.
  const PointBuffer original = make_cloud(20000, 1);
  write_ply(dir / "cloud.ply", original, {.binary = binary});
  PointCloudFileInfo info;
  const PointBuffer read = read_ply(dir / "cloud.ply", &info);
  expect_same_cloud(original, read);
  EXPECT_EQ(info.format, PointCloudFormat::Ply);
  EXPECT_EQ(info.encoding, binary ? "binary_little_endian" : "ascii");
  EXPECT_EQ(info.points_in_file, 20000u);
  EXPECT_EQ(info.dropped_non_finite, 0u);
  EXPECT_THAT(info.fields, ElementsAre("x", "y", "z", "red", "green", "blue", "label", "gt_label", "nx", "ny", "nz",
                                       "intensity", "scalar_terrain", "scalar_wall"));
}

TEST_P(PlyEncodings, RoundTripsCoordinatesOnlyAndEmptyClouds) {
  test::ScratchDir dir("ply");
  const PointBuffer xyz = make_cloud(100, 2, {false, false, false, false, false, false});
  write_ply(dir / "xyz.ply", xyz, {.binary = GetParam()});
  expect_same_cloud(xyz, read_ply(dir / "xyz.ply"));

  const PointBuffer empty = make_cloud(0, 3);
  write_ply(dir / "empty.ply", empty, {.binary = GetParam()});
  expect_same_cloud(empty, read_ply(dir / "empty.ply"));
}

TEST_P(PlyEncodings, DropsAndCountsNonFinitePoints) {
  test::ScratchDir dir("ply");
  PointBuffer cloud = make_cloud(50, 4);
  const float nan = std::numeric_limits<float>::quiet_NaN();
  const float inf = std::numeric_limits<float>::infinity();
  cloud.x()[3] = nan;
  cloud.y()[10] = inf;
  cloud.z()[11] = -inf;
  cloud.x()[49] = nan;
  write_ply(dir / "nan.ply", cloud, {.binary = GetParam()});
  PointCloudFileInfo info;
  const PointBuffer read = read_ply(dir / "nan.ply", &info);
  EXPECT_EQ(info.points_in_file, 50u);
  EXPECT_EQ(info.dropped_non_finite, 4u);
  // The survivors keep their attributes, in order.
  PointBuffer expected = cloud;
  EXPECT_EQ(expected.remove_non_finite(), 4u);
  expect_same_cloud(expected, read);
}

INSTANTIATE_TEST_SUITE_P(Ply, PlyEncodings, ::testing::Bool(),
                         [](const auto& info) { return info.param ? "Binary" : "Ascii"; });

TEST(Ply, WritesTheHeaderMeshLabAndCloudCompareRead) {
  test::ScratchDir dir("ply");
  PointBuffer cloud = make_cloud(2, 5, {.colors = true, .labels = true, .gt_labels = false, .normals = false,
                                        .intensity = false, .scores = false});
  write_ply(dir / "c.ply", cloud);
  const std::string text = slurp(dir / "c.ply");
  const std::string header =
      "ply\nformat binary_little_endian 1.0\ncomment written by sarmap\nelement vertex 2\n"
      "property float x\nproperty float y\nproperty float z\n"
      "property uchar red\nproperty uchar green\nproperty uchar blue\nproperty uchar label\nend_header\n";
  ASSERT_EQ(text.substr(0, header.size()), header);
  EXPECT_EQ(text.size(), header.size() + 2 * 16);
  // Record 0 starts with x as a little-endian float.
  float x = 0;
  std::memcpy(&x, text.data() + header.size(), 4);
  EXPECT_EQ(x, cloud.x()[0]);

  write_ply(dir / "a.ply", cloud, {.binary = false});
  EXPECT_THAT(slurp(dir / "a.ply"), HasSubstr("format ascii 1.0\n"));
}

TEST(Ply, ReadsMixedTypesListsAndOtherElementsTheSameInBothEncodings) {
  PointCloudFileInfo info;
  const PointBuffer binary = read_ply(data_path("clouds/mixed_types_binary.ply"), &info);
  EXPECT_EQ(info.encoding, "binary_little_endian");
  EXPECT_THAT(info.fields, ElementsAre("x", "y", "z", "label", "extra", "intensity", "alpha"));
  const PointBuffer ascii = read_ply(data_path("clouds/mixed_types_ascii.ply"));
  expect_same_cloud(binary, ascii);

  ASSERT_EQ(binary.size(), 4u);
  EXPECT_THAT(std::vector<float>(binary.x().begin(), binary.x().end()), ElementsAre(0.5f, 1.5f, -2.0f, 10.0f));
  EXPECT_THAT(std::vector<float>(binary.y().begin(), binary.y().end()), ElementsAre(-1.25f, 0.0f, 4.75f, 20.0f));
  EXPECT_THAT(std::vector<float>(binary.z().begin(), binary.z().end()), ElementsAre(2.0f, -3.5f, 0.125f, 30.0f));
  ASSERT_TRUE(binary.has_labels());
  EXPECT_THAT(std::vector<int>(binary.labels().begin(), binary.labels().end()), ElementsAre(1, 2, 3, 4));
  ASSERT_TRUE(binary.has_intensity());
  EXPECT_THAT(std::vector<float>(binary.intensity().begin(), binary.intensity().end()),
              ElementsAre(1000.0f, 2000.0f, 3000.0f, 4000.0f));
  EXPECT_FALSE(binary.has_colors());
  EXPECT_EQ(binary.score_count(), 0u);
}

TEST(Ply, ReadsMeshLabStyleFileWithFacesAndDropsTheInfinitePoint) {
  PointCloudFileInfo info;
  const PointBuffer cloud = read_ply(data_path("clouds/meshlab_faces_ascii.ply"), &info);
  EXPECT_EQ(info.points_in_file, 4u);
  EXPECT_EQ(info.dropped_non_finite, 1u);
  ASSERT_EQ(cloud.size(), 3u);
  ASSERT_TRUE(cloud.has_normals());
  ASSERT_TRUE(cloud.has_colors());
  EXPECT_EQ(cloud.normal_z()[2], 1.0f);
  EXPECT_THAT(std::vector<int>(cloud.red().begin(), cloud.red().end()), ElementsAre(230, 230, 220));
  EXPECT_THAT(std::vector<int>(cloud.blue().begin(), cloud.blue().end()), ElementsAre(20, 20, 30));
  EXPECT_FALSE(cloud.has_labels());
}

// A plain, per-point encoder written independently of write_ply, for files
// the writer never produces: unknown properties of every type between the
// known ones, double coordinates, ushort labels.
struct ByteWriter {
  std::string bytes;
  template <class T>
  void put(T value) {
    char raw[sizeof(T)];
    std::memcpy(raw, &value, sizeof(T));
    bytes.append(raw, sizeof(T));
  }
};

TEST(Ply, BinaryDecodingMatchesAPlainPerPointReference) {
  test::ScratchDir dir("ply");
  test::Random random(9);
  const std::size_t n = 5000;  // spans several decoding blocks
  ByteWriter w;
  w.bytes =
      "ply\nformat binary_little_endian 1.0\nelement vertex 5000\n"
      "property double x\nproperty char skip_a\nproperty float y\nproperty short skip_b\nproperty float z\n"
      "property ushort label\nproperty uint skip_c\nproperty float scalar_risk\nproperty double skip_d\n"
      "property uchar red\nproperty uchar green\nproperty uchar blue\nproperty int gt_label\n"
      "property float nx\nproperty float ny\nproperty double nz\nproperty short intensity\nend_header\n";
  std::vector<double> xs(n), nzs(n);
  std::vector<float> ys(n), zs(n), risks(n), nxs(n), nys(n);
  std::vector<int> labels(n), gts(n), reds(n), greens(n), blues(n), intensities(n);
  for (std::size_t i = 0; i < n; ++i) {
    xs[i] = random.uniform(-100, 100) + 1e-9 * static_cast<double>(i);
    ys[i] = random.uniform(-100, 100);
    zs[i] = random.uniform(-100, 100);
    labels[i] = static_cast<int>(random.next() % 256);
    gts[i] = static_cast<int>(random.next() % 6);
    risks[i] = random.uniform(0, 1);
    reds[i] = random.byte();
    greens[i] = random.byte();
    blues[i] = random.byte();
    nxs[i] = random.uniform(-1, 1);
    nys[i] = random.uniform(-1, 1);
    nzs[i] = random.uniform(-1, 1);
    intensities[i] = static_cast<int>(random.next() % 65536) - 32768;
    w.put(xs[i]);
    w.put<std::int8_t>(-1);
    w.put(ys[i]);
    w.put<std::int16_t>(-2);
    w.put(zs[i]);
    w.put(static_cast<std::uint16_t>(labels[i]));
    w.put<std::uint32_t>(0xdeadbeef);
    w.put(risks[i]);
    w.put(std::nan(""));  // unknown properties are not checked for finiteness
    w.put(static_cast<std::uint8_t>(reds[i]));
    w.put(static_cast<std::uint8_t>(greens[i]));
    w.put(static_cast<std::uint8_t>(blues[i]));
    w.put(static_cast<std::int32_t>(gts[i]));
    w.put(nxs[i]);
    w.put(nys[i]);
    w.put(nzs[i]);
    w.put(static_cast<std::int16_t>(intensities[i]));
  }
  spit(dir / "ref.ply", w.bytes);
  const PointBuffer cloud = read_ply(dir / "ref.ply");
  ASSERT_EQ(cloud.size(), n);
  ASSERT_EQ(cloud.score_names(), std::vector<std::string>{"risk"});
  for (std::size_t i = 0; i < n; ++i) {
    ASSERT_EQ(cloud.x()[i], static_cast<float>(xs[i])) << i;
    ASSERT_EQ(cloud.y()[i], ys[i]) << i;
    ASSERT_EQ(cloud.z()[i], zs[i]) << i;
    ASSERT_EQ(cloud.labels()[i], labels[i]) << i;
    ASSERT_EQ(cloud.gt_labels()[i], gts[i]) << i;
    ASSERT_EQ(cloud.score(0)[i], risks[i]) << i;
    ASSERT_EQ(cloud.red()[i], reds[i]) << i;
    ASSERT_EQ(cloud.green()[i], greens[i]) << i;
    ASSERT_EQ(cloud.blue()[i], blues[i]) << i;
    ASSERT_EQ(cloud.normal_x()[i], nxs[i]) << i;
    ASSERT_EQ(cloud.normal_y()[i], nys[i]) << i;
    ASSERT_EQ(cloud.normal_z()[i], static_cast<float>(nzs[i])) << i;
    ASSERT_EQ(cloud.intensity()[i], static_cast<float>(intensities[i])) << i;
  }
}

TEST(Ply, AcceptsWindowsLineEndingsAndPlusSigns) {
  test::ScratchDir dir("ply");
  spit(dir / "crlf.ply",
       "ply\r\nformat ascii 1.0\r\nelement vertex 2\r\nproperty float x\r\nproperty float y\r\n"
       "property float z\r\nproperty uchar label\r\nend_header\r\n+1 2 3 4\r\n5\t6 7 +2\r\n");
  const PointBuffer cloud = read_ply(dir / "crlf.ply");
  ASSERT_EQ(cloud.size(), 2u);
  EXPECT_EQ(cloud.x()[0], 1.0f);
  EXPECT_EQ(cloud.y()[1], 6.0f);
  EXPECT_EQ(cloud.labels()[1], 2);
}

}  // namespace
}  // namespace sarmap
