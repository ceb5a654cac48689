#include "engine/io/seven_scenes_sequence.hpp"

#include <gmock/gmock.h>
#include <gtest/gtest.h>
#include <string>
#include <vector>

#include "engine/core/error.hpp"
#include "error_message.hpp"
#include "png_test_writer.hpp"
#include "scratch_folder.hpp"

namespace sarmap {
namespace {

using test::error_message;
using ::testing::HasSubstr;

constexpr int kW = 3, kH = 2;

// Frame numbers 2 and 10, written 10 first: frames are ordered by number,
// not by directory order.
void write_seven_scenes_folder(const test::ScratchFolder& dir) {
  test::write_png_gray16(dir / "frame-000010.depth.png", kW, kH, {1000, 0, 2000, 65535, 1500, 3000});
  dir.write("frame-000010.pose.txt", "0 -1 0 1\n1 0 0 2\n0 0 1 3\n0 0 0 1\n");
  test::write_png_gray16(dir / "frame-000002.depth.png", kW, kH, {500, 500, 500, 500, 500, 500});
  dir.write("frame-000002.pose.txt", "1 0 0 0\n0 1 0 0\n0 0 1 0\n0 0 0 1\n");
  dir.write("frame-000002.color.png", "not read");
  dir.write("camera-intrinsics.txt", "100 0 1\n0 100 0.5\n0 0 1\n");
}

TEST(SevenScenesSequence, ReadsFramesInNumberOrderWithPosesAndMillimetres) {
  test::ScratchFolder dir;
  write_seven_scenes_folder(dir);
  auto source = open_scan_sequence(dir.path());
  EXPECT_EQ(source->layout(), "7scenes");
  ASSERT_EQ(source->size(), 2u);
  EXPECT_EQ(source->sensor().intrinsics->fx, 100.0);

  Scan scan;
  ASSERT_TRUE(source->next(scan));
  EXPECT_THAT(scan.source, HasSubstr("frame-000002.depth.png"));
  EXPECT_DOUBLE_EQ(scan.timestamp, 2.0 / 30.0);
  EXPECT_EQ(scan.points.size(), 6u);
  EXPECT_FLOAT_EQ(scan.points.z()[0], 0.5f);

  ASSERT_TRUE(source->next(scan));
  EXPECT_EQ(scan.index, 1u);
  EXPECT_DOUBLE_EQ(scan.timestamp, 10.0 / 30.0);
  EXPECT_TRUE(scan.origin.isApprox(Eigen::Vector3d(1, 2, 3)));
  // 0 and 65535 are invalid: 4 of 6 pixels stay.
  ASSERT_EQ(scan.points.size(), 4u);
  const int us[] = {0, 2, 1, 2}, vs[] = {0, 0, 1, 1};
  const double mm[] = {1000, 2000, 1500, 3000};
  Eigen::Matrix3d r;
  r << 0, -1, 0, 1, 0, 0, 0, 0, 1;
  for (std::size_t i = 0; i < 4; ++i) {
    const double d = mm[i] / 1000.0;
    const Eigen::Vector3d expected =
        r * Eigen::Vector3d((us[i] - 1.0) * d / 100, (vs[i] - 0.5) * d / 100, d) + Eigen::Vector3d(1, 2, 3);
    EXPECT_NEAR(scan.points.x()[i], expected.x(), 1e-6);
    EXPECT_NEAR(scan.points.y()[i], expected.y(), 1e-6);
    EXPECT_NEAR(scan.points.z()[i], expected.z(), 1e-6);
  }
  EXPECT_FALSE(source->next(scan));
}

TEST(SevenScenesSequence, MissingPoseFileAndIntrinsicsAreNamed) {
  test::ScratchFolder dir;
  write_seven_scenes_folder(dir);
  std::filesystem::remove(dir / "frame-000010.pose.txt");
  EXPECT_THAT(error_message([&] { open_scan_sequence(dir.path()); }),
              HasSubstr("missing pose file " + (dir / "frame-000010.pose.txt").string()));
  write_seven_scenes_folder(dir);
  std::filesystem::remove(dir / "camera-intrinsics.txt");
  EXPECT_THAT(error_message([&] { open_scan_sequence(dir.path()); }), HasSubstr("intrinsics_file"));
  ScanSequenceOptions options;
  options.intrinsics_file = dir.write("k.txt", "585 0 320\n0 585 240\n0 0 1\n");
  EXPECT_EQ(open_scan_sequence(dir.path(), options)->sensor().intrinsics->fx, 585.0);
}

TEST(SevenScenesSequence, BadPoseFilesNameFileLineAndField) {
  test::ScratchFolder dir;
  write_seven_scenes_folder(dir);
  auto read_error = [&] {
    auto source = open_scan_sequence(dir.path());
    Scan scan;
    return error_message([&] { source->next(scan); });
  };
  dir.write("frame-000002.pose.txt", "2 0 0 0\n0 2 0 0\n0 0 2 0\n0 0 0 1\n");
  std::string msg = read_error();
  EXPECT_THAT(msg, HasSubstr("frame-000002.pose.txt"));
  EXPECT_THAT(msg, HasSubstr("not orthonormal"));
  dir.write("frame-000002.pose.txt", "1 0 0 0\n0 1 0 0\n0 0 1 zero\n0 0 0 1\n");
  msg = read_error();
  EXPECT_THAT(msg, HasSubstr("frame-000002.pose.txt:3: M[2][3]: expected a number, got 'zero'"));
  dir.write("frame-000002.pose.txt", "1 0 0 0\n0 1 0 0\n0 0 1 0\n");
  EXPECT_THAT(read_error(), HasSubstr("expected a 4x4 pose matrix"));
  dir.write("frame-000002.pose.txt", "1 0 0 0\n0 1 0 0\n0 0 1 0\n0 0 1 1\n");
  EXPECT_THAT(read_error(), HasSubstr("last row"));
}

TEST(SevenScenesSequence, FrameNumbersComeOnlyFromDepthImageNames) {
  EXPECT_EQ(seven_scenes_frame_number("frame-000123.depth.png"), 123ul);
  EXPECT_EQ(seven_scenes_frame_number("frame-0.depth.png"), 0ul);
  EXPECT_FALSE(seven_scenes_frame_number("frame-000123.color.png"));
  EXPECT_FALSE(seven_scenes_frame_number("frame-.depth.png"));
  EXPECT_FALSE(seven_scenes_frame_number("frame-12a.depth.png"));
  EXPECT_FALSE(seven_scenes_frame_number("frame--12.depth.png"));
  EXPECT_FALSE(seven_scenes_frame_number("xframe-1.depth.png"));
}

TEST(ScanSequence, UnrecognisedOrMissingPathsAreErrors) {
  test::ScratchFolder dir;
  dir.write("notes.txt", "hello");
  EXPECT_THAT(error_message([&] { open_scan_sequence(dir.path()); }),
              HasSubstr("not a recognised scan sequence"));
  EXPECT_THAT(error_message([&] { open_scan_sequence(dir / "absent"); }),
              HasSubstr("no such file or folder"));
}

}  // namespace
}  // namespace sarmap
