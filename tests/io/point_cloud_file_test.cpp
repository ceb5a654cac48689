#include "engine/io/point_cloud_file.hpp"

#include <gmock/gmock.h>
#include <gtest/gtest.h>

#include <string>
#include <vector>

#include "point_cloud_test_support.hpp"

namespace sarmap {
namespace {

using test::expect_same_cloud;
using test::make_cloud;
using ::testing::HasSubstr;

TEST(PointCloudFile, ChoosesTheFormatByExtensionIgnoringCase) {
  EXPECT_EQ(point_cloud_format_of("a/b/scan.ply"), PointCloudFormat::Ply);
  EXPECT_EQ(point_cloud_format_of("scan.PLY"), PointCloudFormat::Ply);
  EXPECT_EQ(point_cloud_format_of("scan.Pcd"), PointCloudFormat::Pcd);

  test::ScratchDir dir("pcf");
  const PointBuffer cloud = make_cloud(500, 31);
  for (const char* name : {"one.PLY", "two.pcd", "three.PcD"}) {
    write_point_cloud(dir / name, cloud);
    PointCloudFileInfo info;
    expect_same_cloud(cloud, read_point_cloud(dir / name, &info));
    const bool ply = std::string(name).find("PLY") != std::string::npos;
    EXPECT_EQ(info.format, ply ? PointCloudFormat::Ply : PointCloudFormat::Pcd) << name;
    EXPECT_EQ(info.encoding, ply ? "binary_little_endian" : "binary") << name;
  }
}

TEST(PointCloudFile, UnknownExtensionIsAnErrorNamingIt) {
  const Error e = test::error_from([] { read_point_cloud("scans/cloud.xyz"); });
  EXPECT_EQ(e.code(), ErrorCode::Unsupported);
  EXPECT_THAT(e.what(), HasSubstr("scans/cloud.xyz"));
  EXPECT_THAT(e.what(), HasSubstr("'.xyz'"));
  EXPECT_THAT(e.what(), HasSubstr("expected .ply or .pcd"));
  EXPECT_THAT(test::error_from([] { write_point_cloud("noextension", PointBuffer(1)); }).what(),
              HasSubstr("noextension: unknown point-cloud extension ''"));
}

TEST(PointCloudFile, MissingFileIsAnIoErrorNamingThePath) {
  const Error e = test::error_from([] { read_point_cloud("/nonexistent/sarmap/cloud.pcd"); });
  EXPECT_EQ(e.code(), ErrorCode::Io);
  EXPECT_THAT(e.what(), HasSubstr("/nonexistent/sarmap/cloud.pcd: cannot open"));
  test::ScratchDir dir("pcf");
  std::filesystem::create_directories(dir / "folder.ply");
  EXPECT_EQ(test::error_from([&] { read_point_cloud(dir / "folder.ply"); }).code(), ErrorCode::Io);
}

TEST(PointCloudFile, AnUnwritableScoreNameIsRejectedAndTheTargetKept) {
  test::ScratchDir dir("pcf");
  const PointBuffer good = make_cloud(10, 32);
  for (const char* name : {"keep.ply", "keep.pcd"}) {
    write_point_cloud(dir / name, good);
    PointBuffer bad = make_cloud(10, 33);
    bad.add_score("not a name");  // whitespace cannot be a property name
    const Error e = test::error_from([&] { write_point_cloud(dir / name, bad); });
    EXPECT_EQ(e.code(), ErrorCode::InvalidArgument);
    EXPECT_THAT(e.what(), HasSubstr("'not a name'"));
    expect_same_cloud(good, read_point_cloud(dir / name));
  }
  // Only the two targets: no temporary file left behind.
  EXPECT_EQ(std::distance(std::filesystem::directory_iterator(dir.path()), {}), 2);
}

// Header comments (voxels.ply's "voxel_size") come back through the reader
// in every format and encoding, after sarmap's own "written by" line; PCD's
// ".PCD v0.7" banner is not one of them.
TEST(PointCloudFile, HeaderCommentsRoundTripInEveryFormatAndEncoding) {
  test::ScratchDir dir("pcf");
  const PointBuffer cloud = make_cloud(20, 34);
  struct Case {
    const char* name;
    PointCloudWriteOptions options;
  };
  const std::vector<std::string> comments = {"voxel_size 0.05", "second line"};
  for (const Case& c : {Case{"b.ply", {.binary = true}}, Case{"a.ply", {.binary = false}},
                        Case{"b.pcd", {.binary = true}}, Case{"a.pcd", {.binary = false}},
                        Case{"c.pcd", {.binary = true, .compressed = true}}}) {
    PointCloudWriteOptions options = c.options;
    options.comments = comments;
    write_point_cloud(dir / c.name, cloud, options);
    PointCloudFileInfo info;
    expect_same_cloud(cloud, read_point_cloud(dir / c.name, &info));
    const bool ply = std::string(c.name).ends_with(".ply");
    const std::vector<std::string> want =
        ply ? std::vector<std::string>{"written by sarmap", "voxel_size 0.05", "second line"} : comments;
    EXPECT_EQ(info.comments, want) << c.name;
  }
}

TEST(PointCloudFile, AHeaderCommentWithALineBreakIsRefusedAndTheTargetKept) {
  test::ScratchDir dir("pcf");
  const PointBuffer good = make_cloud(5, 35);
  for (const char* name : {"keep.ply", "keep.pcd"}) {
    write_point_cloud(dir / name, good);
    PointCloudWriteOptions options;
    options.comments = {"voxel_size 0.05\nelement vertex 0"};
    const Error e = test::error_from([&] { write_point_cloud(dir / name, make_cloud(5, 36), options); });
    EXPECT_EQ(e.code(), ErrorCode::InvalidArgument) << name;
    EXPECT_THAT(e.what(), HasSubstr("line break")) << name;
    expect_same_cloud(good, read_point_cloud(dir / name));
  }
}

}  // namespace
}  // namespace sarmap
