#include "engine/io/pcd.hpp"

#include <cmath>
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
using ::testing::ElementsAre;
using ::testing::HasSubstr;

struct Encoding {
  const char* name;
  PointCloudWriteOptions options;
};

class PcdEncodings : public ::testing::TestWithParam<Encoding> {};

TEST_P(PcdEncodings, RoundTripsEveryAttribute) {
  test::ScratchDir dir("pcd");
  const PointBuffer original = make_cloud(20000, 21);
  write_pcd(dir / "cloud.pcd", original, GetParam().options);
  PointCloudFileInfo info;
  const PointBuffer read = read_pcd(dir / "cloud.pcd", &info);
  expect_same_cloud(original, read);
  EXPECT_EQ(info.format, PointCloudFormat::Pcd);
  EXPECT_EQ(info.encoding, GetParam().name);
  EXPECT_EQ(info.points_in_file, 20000u);
  EXPECT_THAT(info.fields, ElementsAre("x", "y", "z", "rgb", "label", "gt_label", "normal_x", "normal_y", "normal_z",
                                       "intensity", "scalar_terrain", "scalar_wall"));
}

TEST_P(PcdEncodings, RoundTripsCoordinatesOnlyAndEmptyClouds) {
  test::ScratchDir dir("pcd");
  const PointBuffer xyz = make_cloud(300, 22, {false, false, false, false, false, false});
  write_pcd(dir / "xyz.pcd", xyz, GetParam().options);
  expect_same_cloud(xyz, read_pcd(dir / "xyz.pcd"));
  const PointBuffer empty = make_cloud(0, 23);
  write_pcd(dir / "empty.pcd", empty, GetParam().options);
  expect_same_cloud(empty, read_pcd(dir / "empty.pcd"));
}

TEST_P(PcdEncodings, DropsAndCountsNonFinitePoints) {
  test::ScratchDir dir("pcd");
  PointBuffer cloud = make_cloud(64, 24);
  cloud.x()[0] = std::numeric_limits<float>::quiet_NaN();
  cloud.z()[63] = std::numeric_limits<float>::infinity();
  cloud.y()[30] = -std::numeric_limits<float>::infinity();
  write_pcd(dir / "nan.pcd", cloud, GetParam().options);
  PointCloudFileInfo info;
  const PointBuffer read = read_pcd(dir / "nan.pcd", &info);
  EXPECT_EQ(info.dropped_non_finite, 3u);
  PointBuffer expected = cloud;
  expected.remove_non_finite();
  expect_same_cloud(expected, read);
}

INSTANTIATE_TEST_SUITE_P(
    Pcd, PcdEncodings,
    ::testing::Values(Encoding{"ascii", {.binary = false}}, Encoding{"binary", {.binary = true}},
                      Encoding{"binary_compressed", {.binary = true, .compressed = true}}),
    [](const auto& info) { return std::string(info.param.name); });

TEST(Pcd, WritesAPclStyleHeader) {
  test::ScratchDir dir("pcd");
  const PointBuffer cloud = make_cloud(3, 25, {.colors = true, .labels = true, .gt_labels = false,
                                               .normals = false, .intensity = false, .scores = false});
  write_pcd(dir / "c.pcd", cloud);
  const std::string header =
      "# .PCD v0.7 - Point Cloud Data file format\nVERSION 0.7\nFIELDS x y z rgb label\nSIZE 4 4 4 4 4\n"
      "TYPE F F F U U\nCOUNT 1 1 1 1 1\nWIDTH 3\nHEIGHT 1\nVIEWPOINT 0 0 0 1 0 0 0\nPOINTS 3\nDATA binary\n";
  const std::string text = slurp(dir / "c.pcd");
  ASSERT_EQ(text.substr(0, header.size()), header);
  EXPECT_EQ(text.size(), header.size() + 3 * 20);
  // rgb is 0x00RRGGBB in a little-endian uint32 after x y z.
  std::uint32_t rgb = 0;
  std::memcpy(&rgb, text.data() + header.size() + 12, 4);
  EXPECT_EQ(rgb, (std::uint32_t{cloud.red()[0]} << 16) | (std::uint32_t{cloud.green()[0]} << 8) | cloud.blue()[0]);
}

TEST(Pcd, CompressedAndUncompressedFilesReadTheSame) {
  test::ScratchDir dir("pcd");
  // Repetitive values (a grid) so the compressor emits many back-references.
  PointBuffer cloud(30000);
  cloud.enable_labels();
  for (std::size_t i = 0; i < cloud.size(); ++i) {
    cloud.x()[i] = static_cast<float>(i % 100) * 0.05f;
    cloud.y()[i] = static_cast<float>(i / 100) * 0.05f;
    cloud.z()[i] = 0.0f;
    cloud.labels()[i] = 1;
  }
  write_pcd(dir / "plain.pcd", cloud, {.binary = true});
  write_pcd(dir / "packed.pcd", cloud, {.binary = true, .compressed = true});
  EXPECT_LT(std::filesystem::file_size(dir / "packed.pcd"), std::filesystem::file_size(dir / "plain.pcd") / 2);
  expect_same_cloud(read_pcd(dir / "plain.pcd"), read_pcd(dir / "packed.pcd"));
  expect_same_cloud(cloud, read_pcd(dir / "packed.pcd"));
}

TEST(Pcd, ReadsPclBinaryWithFloatRgbAndUint32Label) {
  const PointBuffer cloud = read_pcd(data_path("clouds/pcl_xyzrgbl_binary.pcd"));
  ASSERT_EQ(cloud.size(), 4u);
  EXPECT_THAT(std::vector<float>(cloud.y().begin(), cloud.y().end()), ElementsAre(-1.25f, 0.0f, 4.75f, 20.0f));
  EXPECT_THAT(std::vector<int>(cloud.red().begin(), cloud.red().end()), ElementsAre(255, 0, 0, 12));
  EXPECT_THAT(std::vector<int>(cloud.green().begin(), cloud.green().end()), ElementsAre(0, 255, 0, 34));
  EXPECT_THAT(std::vector<int>(cloud.blue().begin(), cloud.blue().end()), ElementsAre(0, 0, 255, 56));
  EXPECT_THAT(std::vector<int>(cloud.labels().begin(), cloud.labels().end()), ElementsAre(1, 2, 3, 4));
}

TEST(Pcd, ReadsPclAsciiRgbAsIntegerOrFloatBitsAndDropsNan) {
  PointCloudFileInfo info;
  const PointBuffer cloud = read_pcd(data_path("clouds/pcl_xyzrgb_ascii.pcd"), &info);
  EXPECT_EQ(info.points_in_file, 5u);
  EXPECT_EQ(info.dropped_non_finite, 1u);
  ASSERT_EQ(cloud.size(), 4u);
  EXPECT_THAT(std::vector<int>(cloud.red().begin(), cloud.red().end()), ElementsAre(255, 0, 0, 12));
  EXPECT_THAT(std::vector<int>(cloud.green().begin(), cloud.green().end()), ElementsAre(0, 255, 0, 34));
  EXPECT_THAT(std::vector<int>(cloud.blue().begin(), cloud.blue().end()), ElementsAre(0, 0, 255, 56));
  EXPECT_FALSE(cloud.has_labels());
}

TEST(Pcd, ReadsCompressedFieldsWithPaddingUnknownFieldsAndHeight) {
  PointCloudFileInfo info;
  const PointBuffer cloud = read_pcd(data_path("clouds/normals_compressed.pcd"), &info);
  EXPECT_EQ(info.encoding, "binary_compressed");
  ASSERT_EQ(cloud.size(), 4u);
  EXPECT_THAT(std::vector<float>(cloud.z().begin(), cloud.z().end()), ElementsAre(2.0f, -3.5f, 0.125f, 30.0f));
  ASSERT_TRUE(cloud.has_normals());
  EXPECT_THAT(std::vector<float>(cloud.normal_x().begin(), cloud.normal_x().end()),
              ElementsAre(0.0f, 1.0f, 0.0f, 0.6f));
  EXPECT_THAT(std::vector<float>(cloud.normal_y().begin(), cloud.normal_y().end()),
              ElementsAre(0.0f, 0.0f, 1.0f, 0.8f));
  ASSERT_TRUE(cloud.has_intensity());
  EXPECT_THAT(std::vector<float>(cloud.intensity().begin(), cloud.intensity().end()),
              ElementsAre(10.0f, 20.0f, 30.0f, 65535.0f));
  EXPECT_FALSE(cloud.has_colors());
}

TEST(Pcd, SkipsMultiValuedAndUnknownAsciiFields) {
  const PointBuffer cloud = read_pcd(data_path("clouds/pcl_fpfh_count_ascii.pcd"));
  ASSERT_EQ(cloud.size(), 3u);
  EXPECT_THAT(std::vector<float>(cloud.x().begin(), cloud.x().end()), ElementsAre(1.0f, 4.0f, 7.0f));
  EXPECT_THAT(std::vector<float>(cloud.z().begin(), cloud.z().end()), ElementsAre(3.0f, 6.0f, 9.0f));
  EXPECT_THAT(std::vector<int>(cloud.labels().begin(), cloud.labels().end()), ElementsAre(1, 2, 5));
}

// Files PCL 1.13 wrote itself (tests/data/clouds/make_pcl_clouds.sh): its
// binary writer leaves zero bytes after the points, which are padding.
TEST(Pcd, ReadsPclToolsBinaryWithZeroPaddingAsItsAsciiSource) {
  const PointBuffer ascii = read_pcd(data_path("clouds/pcl_tools_ascii.pcd"));
  ASSERT_EQ(ascii.size(), 300u);
  EXPECT_EQ(ascii.x()[21], -0.875f);
  EXPECT_EQ(ascii.y()[21], 0.25f);
  EXPECT_EQ(+ascii.red()[1], 7);
  EXPECT_EQ(+ascii.blue()[2], 58);
  EXPECT_EQ(+ascii.labels()[11], 5);

  const std::string bytes = slurp(data_path("clouds/pcl_tools_binary.pcd"));
  const std::string data_line = "DATA binary\n";
  const std::size_t data_end = bytes.find(data_line) + data_line.size() + 300 * 20;
  ASSERT_EQ(bytes.size() - data_end, 3906u) << "the sample no longer holds PCL's padding";
  EXPECT_EQ(bytes.find_first_not_of('\0', data_end), std::string::npos);

  PointCloudFileInfo info;
  expect_same_cloud(ascii, read_pcd(data_path("clouds/pcl_tools_binary.pcd"), &info));
  EXPECT_EQ(info.encoding, "binary");
  expect_same_cloud(ascii, read_pcd(data_path("clouds/pcl_tools_binary_compressed.pcd"), &info));
  EXPECT_EQ(info.encoding, "binary_compressed");
}

// The rule itself, on files of our own in both binary encodings: zeros after
// the data are read as padding, and one non-zero byte among them is refused
// with its offset.
TEST(Pcd, AcceptsZeroBytesAfterBinaryDataAndRefusesAnyOther) {
  test::ScratchDir dir("pcd");
  const PointBuffer cloud = make_cloud(50, 27);
  struct Encoding {
    bool compressed;
    std::string data;  // what the message says the padding follows
  };
  for (const Encoding& encoding : {Encoding{false, "50 points the header declares"},
                                   Encoding{true, " compressed bytes the file declares"}}) {
    SCOPED_TRACE(encoding.compressed ? "binary_compressed" : "binary");
    write_pcd(dir / "c.pcd", cloud, {.binary = true, .compressed = encoding.compressed});
    std::string bytes = slurp(dir / "c.pcd");
    const std::size_t data_end = bytes.size();
    bytes.append(4096, '\0');
    test::spit(dir / "padded.pcd", bytes);
    expect_same_cloud(cloud, read_pcd(dir / "padded.pcd"));

    bytes[data_end + 4000] = 1;
    test::spit(dir / "dirty.pcd", bytes);
    const std::string path = (dir / "dirty.pcd").string();
    const Error e = test::error_from([&] { read_pcd(path); });
    EXPECT_EQ(e.code(), ErrorCode::Parse);
    EXPECT_THAT(e.what(), HasSubstr(path + " (byte offset " + std::to_string(data_end) + "): 4096 bytes follow the "));
    EXPECT_THAT(e.what(), HasSubstr(encoding.data + " and the one at byte offset " + std::to_string(data_end + 4000) +
                                    " is not zero"));
  }
}

TEST(Pcd, AsciiAndBinaryOfTheSameCloudAgree) {
  test::ScratchDir dir("pcd");
  const PointBuffer cloud = make_cloud(5000, 26);
  write_pcd(dir / "a.pcd", cloud, {.binary = false});
  write_pcd(dir / "b.pcd", cloud, {.binary = true});
  expect_same_cloud(read_pcd(dir / "a.pcd"), read_pcd(dir / "b.pcd"));
}

}  // namespace
}  // namespace sarmap
