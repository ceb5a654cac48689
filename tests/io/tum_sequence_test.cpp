#include "engine/io/tum_sequence.hpp"

#include <gmock/gmock.h>
#include <gtest/gtest.h>
#include <cmath>
#include <random>
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

constexpr int kImageWidth = 4, kImageHeight = 3;
constexpr double kFx = 50, kFy = 60, kCx = 1.5, kCy = 1.0;

std::vector<std::uint16_t> depth_pixels(int frame) {
  std::vector<std::uint16_t> p(kImageWidth * kImageHeight);
  for (std::size_t i = 0; i < p.size(); ++i) p[i] = static_cast<std::uint16_t>(5000 + 700 * i + 100 * frame);
  p[5] = 0;  // no measurement
  return p;
}

// Depth frames at 1.00, 1.10, 1.50, 1.20 s (listed out of time order is an
// error, so 1.50 comes last); ground truth at 0.99, 1.095, 1.21, 2.0 s.
void write_tum_folder(const test::ScratchFolder& dir) {
  const double times[] = {1.00, 1.10, 1.20, 1.50};
  std::string list = "# depth maps\n# file: 'rgbd_dataset'\n# timestamp filename\n";
  for (int f = 0; f < 4; ++f) {
    const std::string name = "depth/" + std::to_string(f) + ".png";
    std::filesystem::create_directories(dir / "depth");
    test::write_png_gray16(dir / name, kImageWidth, kImageHeight, depth_pixels(f));
    list += std::to_string(times[f]) + " " + name + "\n";
  }
  dir.write("depth.txt", list);
  dir.write("groundtruth.txt",
            "# ground truth trajectory\n# timestamp tx ty tz qx qy qz qw\n"
            "0.99 1 2 3 0 0 0 1\n"
            "1.095 -1 0.5 2 0 0 0.7071067811865476 0.7071067811865476\n"
            "1.21 0 0 1 0.5 0.5 0.5 0.5\n"
            "2.0 0 0 0 0 0 0 1\n");
  dir.write("intrinsics.json", R"({"fx": 50, "fy": 60, "cx": 1.5, "cy": 1.0, "width": 4, "height": 3})");
}

TEST(TumSequence, FramesTakeTheNearestPoseAndFarOnesAreSkipped) {
  test::ScratchFolder dir;
  write_tum_folder(dir);
  auto source = open_scan_sequence(dir.path());
  EXPECT_EQ(source->layout(), "tum");
  ASSERT_EQ(source->size(), 3u);
  EXPECT_EQ(source->skipped_frames(), 1u);  // 1.50 s is 0.29 s from any pose
  EXPECT_EQ(source->sensor().type, SensorType::DepthCamera);
  ASSERT_TRUE(source->sensor().intrinsics.has_value());

  const Pose poses[] = {
      Pose::from_quaternion(0, 0, 0, 1, Eigen::Vector3d(1, 2, 3)),
      Pose::from_quaternion(0, 0, std::sqrt(0.5), std::sqrt(0.5), Eigen::Vector3d(-1, 0.5, 2)),
      Pose::from_quaternion(0.5, 0.5, 0.5, 0.5, Eigen::Vector3d(0, 0, 1)),
  };
  const double times[] = {1.00, 1.10, 1.20};
  Scan scan;
  for (int f = 0; f < 3; ++f) {
    ASSERT_TRUE(source->next(scan));
    EXPECT_EQ(scan.index, static_cast<std::size_t>(f));
    EXPECT_DOUBLE_EQ(scan.timestamp, times[f]);
    EXPECT_TRUE(scan.pose.matrix().isApprox(poses[f].matrix(), 1e-12));
    EXPECT_TRUE(scan.origin.isApprox(poses[f].translation()));
    const auto pixels = depth_pixels(f);
    ASSERT_EQ(scan.points.size(), pixels.size() - 1);
    std::size_t i = 0;
    for (int v = 0; v < kImageHeight; ++v) {
      for (int u = 0; u < kImageWidth; ++u) {
        const std::uint16_t raw = pixels[static_cast<std::size_t>(v * kImageWidth + u)];
        if (raw == 0) continue;
        const double d = raw / 5000.0;
        const Eigen::Vector3d expected =
            poses[f] * Eigen::Vector3d((u - kCx) * d / kFx, (v - kCy) * d / kFy, d);
        EXPECT_NEAR(scan.points.x()[i], expected.x(), 1e-5);
        EXPECT_NEAR(scan.points.y()[i], expected.y(), 1e-5);
        EXPECT_NEAR(scan.points.z()[i], expected.z(), 1e-5);
        ++i;
      }
    }
  }
  EXPECT_FALSE(source->next(scan));
  source->rewind();
  ASSERT_TRUE(source->next(scan));
  EXPECT_EQ(scan.index, 0u);
}

TEST(TumSequence, IntrinsicsOptionWinsAndTheirAbsenceNamesTheOption) {
  test::ScratchFolder dir;
  write_tum_folder(dir);
  const auto other = dir.write("other.txt", "100 0 1.5\n0 100 1\n0 0 1\n");
  ScanSequenceOptions options;
  options.intrinsics_file = other;
  EXPECT_EQ(open_scan_sequence(dir.path(), options)->sensor().intrinsics->fx, 100.0);
  std::filesystem::remove(dir / "intrinsics.json");
  const std::string msg = error_message([&] { open_scan_sequence(dir.path()); });
  EXPECT_THAT(msg, HasSubstr("intrinsics_file"));
  EXPECT_THAT(msg, HasSubstr("TUM RGB-D"));
}

TEST(TumSequence, ToleranceIsAnOption) {
  test::ScratchFolder dir;
  write_tum_folder(dir);
  ScanSequenceOptions options;
  options.max_time_difference = 0.006;  // only 1.10 -> 1.095 stays
  auto source = open_scan_sequence(dir.path(), options);
  EXPECT_EQ(source->size(), 1u);
  EXPECT_EQ(source->skipped_frames(), 3u);
  options.max_time_difference = 0.001;
  EXPECT_THAT(error_message([&] { open_scan_sequence(dir.path(), options); }),
              HasSubstr("none of the 4 depth frames"));
}

TEST(TumSequence, BadFilesNameFileLineAndField) {
  test::ScratchFolder dir;
  write_tum_folder(dir);
  auto open_error = [&] { return error_message([&] { open_scan_sequence(dir.path()); }); };

  dir.write("groundtruth.txt", "0.99 1 2 3 0 0 0 1\n1.095 -1 x 2 0 0 0 1\n");
  std::string msg = open_error();
  EXPECT_THAT(msg, HasSubstr("groundtruth.txt:2"));
  EXPECT_THAT(msg, HasSubstr("ty: expected a number, got 'x'"));

  dir.write("groundtruth.txt", "0.99 1 2 3 0 0 0 1\n1.095 -1 0 2 0 0 0\n");
  EXPECT_THAT(open_error(),
              HasSubstr("groundtruth.txt:2: expected 8 values (timestamp tx ty tz qx qy qz qw), got 7"));

  dir.write("groundtruth.txt", "# c\n0.99 1 2 3 0 0 0 0\n");
  msg = open_error();
  EXPECT_THAT(msg, HasSubstr("groundtruth.txt:2"));
  EXPECT_THAT(msg, HasSubstr("quaternion is zero"));

  dir.write("groundtruth.txt", "0.99 1 2 inf 0 0 0 1\n");
  EXPECT_THAT(open_error(), HasSubstr("tz: expected a finite number"));

  dir.write("groundtruth.txt", "1.5 0 0 0 0 0 0 1\n1.0 0 0 0 0 0 0 1\n");
  EXPECT_THAT(open_error(), HasSubstr("groundtruth.txt:2: timestamp 1.0 is earlier"));

  dir.write("groundtruth.txt", "");
  EXPECT_THAT(open_error(), HasSubstr("no ground-truth poses"));

  std::filesystem::remove(dir / "groundtruth.txt");
  EXPECT_THAT(open_error(), HasSubstr("no groundtruth.txt"));
}

TEST(TumSequence, BadDepthListAndImagesAreErrors) {
  test::ScratchFolder dir;
  write_tum_folder(dir);
  auto open_error = [&] { return error_message([&] { open_scan_sequence(dir.path()); }); };
  dir.write("depth.txt", "1.0 depth/0.png\n1.1 depth/missing.png\n");
  EXPECT_THAT(open_error(), HasSubstr("depth.txt:2: depth image"));
  dir.write("depth.txt", "1.0 depth/0.png extra\n");
  EXPECT_THAT(open_error(), HasSubstr("depth.txt:1: expected 2 values"));
  dir.write("depth.txt", "one depth/0.png\n");
  EXPECT_THAT(open_error(), HasSubstr("depth.txt:1: timestamp: expected a number"));
  dir.write("depth.txt", "# nothing\n");
  EXPECT_THAT(open_error(), HasSubstr("lists no depth images"));
  // A name longer than NAME_MAX threw filesystem_error (an internal error).
  dir.write("depth.txt", "1.0 depth/" + std::string(300, 'd') + ".png\n");
  EXPECT_THAT(open_error(), HasSubstr("depth.txt:1: depth image"));
  EXPECT_THAT(open_error(), HasSubstr("File name too long"));

  // An 8-bit image is found when its frame is read.
  test::write_png_gray8(dir / "depth/eight.png", kImageWidth, kImageHeight, std::vector<std::uint8_t>(kImageWidth * kImageHeight, 9));
  dir.write("depth.txt", "1.0 depth/eight.png\n");
  auto source = open_scan_sequence(dir.path());
  Scan scan;
  const std::string msg = error_message([&] { source->next(scan); });
  EXPECT_THAT(msg, HasSubstr("eight.png"));
  EXPECT_THAT(msg, HasSubstr("16-bit"));
}

TEST(AssociateNearest, AgreesWithBruteForce) {
  std::mt19937 rng(7);
  std::uniform_real_distribution<double> time(0.0, 10.0);
  for (int trial = 0; trial < 20; ++trial) {
    std::vector<double> refs(static_cast<std::size_t>(trial * 3 + 1));
    for (double& t : refs) t = time(rng);
    std::sort(refs.begin(), refs.end());
    std::vector<double> queries(50);
    for (double& t : queries) t = time(rng);
    const double tolerance = 0.1 * trial;
    const auto got = associate_nearest(queries, refs, tolerance);
    for (std::size_t q = 0; q < queries.size(); ++q) {
      std::size_t best = 0;
      for (std::size_t r = 1; r < refs.size(); ++r) {
        if (std::abs(refs[r] - queries[q]) < std::abs(refs[best] - queries[q])) best = r;
      }
      if (std::abs(refs[best] - queries[q]) <= tolerance) {
        ASSERT_TRUE(got[q].has_value());
        EXPECT_EQ(*got[q], best);
      } else {
        EXPECT_FALSE(got[q].has_value());
      }
    }
  }
  EXPECT_TRUE(associate_nearest(std::vector<double>{1.0}, std::vector<double>{}, 1.0)[0] == std::nullopt);
}

}  // namespace
}  // namespace sarmap
