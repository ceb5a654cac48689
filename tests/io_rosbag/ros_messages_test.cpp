// The ROS 1 message decoders on hand-built bytes: PointCloud2 with its
// strides, types, labels and NaN points, the pose messages, and bytes that
// are not the message they claim (each refused naming the field and offset).
#include "engine/io_rosbag/ros_messages.hpp"

#include <gmock/gmock.h>
#include <gtest/gtest.h>

#include <cmath>
#include <limits>

#include "engine/core/error.hpp"
#include "tests/io_rosbag/ros_message_bytes.hpp"

namespace sarmap::ros1 {
namespace {

using ::testing::HasSubstr;
using testing::RosBytes;

// x, y, z float32 at 0, 4, 8, a uint16 label at 12, point_step 16; rows of
// `width` points with `row_pad` bytes after each row.
RosBytes cloud(std::uint32_t height, std::uint32_t width, const std::vector<float>& xyz,
               const std::vector<std::uint16_t>& labels, std::uint32_t row_pad = 0) {
  RosBytes m;
  m.header(12, 500'000'000, "lidar").put(height).put(width).put(std::uint32_t{4});
  m.field("x", 0, 7).field("y", 4, 7).field("z", 8, 7).field("label", 12, 4);
  const std::uint32_t point_step = 16, row_step = width * point_step + row_pad;
  m.put(std::uint8_t{0}).put(point_step).put(row_step);
  RosBytes data;
  for (std::uint32_t r = 0; r < height; ++r) {
    for (std::uint32_t c = 0; c < width; ++c) {
      const std::size_t i = r * width + c;
      data.put(xyz[3 * i]).put(xyz[3 * i + 1]).put(xyz[3 * i + 2]).put(labels[i]).put(std::uint16_t{0xBEEF});
    }
    for (std::uint32_t p = 0; p < row_pad; ++p) data.put(std::uint8_t{0xEE});
  }
  m.put(static_cast<std::uint32_t>(data.bytes.size()));
  m.bytes.insert(m.bytes.end(), data.bytes.begin(), data.bytes.end());
  m.put(std::uint8_t{0});
  return m;
}

template <class F>
std::string error_of(F&& f) {
  try {
    f();
  } catch (const Error& e) {
    return e.what();
  }
  return "no error";
}

TEST(RosMessages, PointCloud2HonoursRowStepLabelsAndDropsNaN) {
  const float nan = std::numeric_limits<float>::quiet_NaN();
  const RosBytes m = cloud(2, 2, {1, 2, 3, nan, 0, 0, 4, 5, 6, 7, 8, 9}, {1, 0, 2, 5}, 6);
  const CloudMessage c = decode_point_cloud2(m.bytes, "t");
  EXPECT_DOUBLE_EQ(c.header.stamp, 12.5);
  EXPECT_EQ(c.header.frame_id, "lidar");
  ASSERT_EQ(c.points.size(), 3u);
  EXPECT_EQ(c.dropped_non_finite, 1u);
  EXPECT_EQ(c.points.x()[1], 4.0f);
  EXPECT_EQ(c.points.z()[2], 9.0f);
  ASSERT_TRUE(c.points.has_labels());
  EXPECT_EQ(c.points.labels()[0], 1);
  EXPECT_EQ(c.points.labels()[1], 2);
  EXPECT_EQ(c.points.labels()[2], 5);
}

TEST(RosMessages, PointCloud2Float64AndNoLabel) {
  RosBytes m;
  m.header(1, 0, "f").put(std::uint32_t{1}).put(std::uint32_t{1}).put(std::uint32_t{3});
  m.field("z", 16, 8).field("x", 0, 8).field("y", 8, 8);
  m.put(std::uint8_t{0}).put(std::uint32_t{24}).put(std::uint32_t{24}).put(std::uint32_t{24});
  m.put(1.5).put(-2.25).put(3.0).put(std::uint8_t{1});
  const CloudMessage c = decode_point_cloud2(m.bytes, "t");
  ASSERT_EQ(c.points.size(), 1u);
  EXPECT_FALSE(c.points.has_labels());
  EXPECT_EQ(c.points.x()[0], 1.5f);
  EXPECT_EQ(c.points.y()[0], -2.25f);
  EXPECT_EQ(c.points.z()[0], 3.0f);
}

TEST(RosMessages, PointCloud2RefusesWhatItCannotRead) {
  const RosBytes good = cloud(1, 2, {1, 2, 3, 4, 5, 6}, {1, 1});
  // Every cut is an error naming the message, never a read past the end.
  for (std::size_t keep = 0; keep < good.bytes.size(); ++keep) {
    const std::vector<std::uint8_t> cut(good.bytes.begin(), good.bytes.begin() + static_cast<long>(keep));
    EXPECT_THAT(error_of([&] { decode_point_cloud2(cut, "bag /points message 3"); }),
                HasSubstr("bag /points message 3"))
        << keep;
  }
  EXPECT_THAT(error_of([&] {
                decode_point_cloud2(cloud(1, 2, {1, 2, 3, 4, 5, 6}, {1, 9}).bytes, "m");
              }),
              HasSubstr("point 1 has label 9"));
  InputLimits small;
  small.max_points = 1;
  EXPECT_THAT(error_of([&] { decode_point_cloud2(good.bytes, "m", small); }), HasSubstr("m"));

  RosBytes no_z;
  no_z.header(1, 0, "f").put(std::uint32_t{1}).put(std::uint32_t{1}).put(std::uint32_t{2});
  no_z.field("x", 0, 7).field("y", 4, 7).put(std::uint8_t{0}).put(std::uint32_t{8}).put(std::uint32_t{8});
  no_z.put(std::uint32_t{8}).put(1.0f).put(2.0f).put(std::uint8_t{1});
  EXPECT_THAT(error_of([&] { decode_point_cloud2(no_z.bytes, "m"); }), HasSubstr("no 'z' field"));

  RosBytes outside;
  outside.header(1, 0, "f").put(std::uint32_t{1}).put(std::uint32_t{1}).put(std::uint32_t{3});
  outside.field("x", 0, 7).field("y", 4, 7).field("z", 8, 7);
  outside.put(std::uint8_t{0}).put(std::uint32_t{8}).put(std::uint32_t{8}).put(std::uint32_t{8});
  outside.put(1.0f).put(2.0f).put(std::uint8_t{1});
  EXPECT_THAT(error_of([&] { decode_point_cloud2(outside.bytes, "m"); }),
              HasSubstr("field 'z' (offset 8, 1 x 4 bytes) does not fit point_step 8"));

  RosBytes ints;
  ints.header(1, 0, "f").put(std::uint32_t{1}).put(std::uint32_t{1}).put(std::uint32_t{3});
  ints.field("x", 0, 5).field("y", 4, 5).field("z", 8, 5);
  ints.put(std::uint8_t{0}).put(std::uint32_t{12}).put(std::uint32_t{12}).put(std::uint32_t{12});
  ints.put(1).put(2).put(3).put(std::uint8_t{1});
  EXPECT_THAT(error_of([&] { decode_point_cloud2(ints.bytes, "m"); }),
              HasSubstr("must be float32 (7) or float64 (8)"));

  // A field count that the bytes cannot hold fails on the count, before allocating.
  RosBytes many;
  many.header(1, 0, "f").put(std::uint32_t{1}).put(std::uint32_t{1}).put(std::uint32_t{0xFFFFFFFF});
  EXPECT_THAT(error_of([&] { decode_point_cloud2(many.bytes, "m"); }), HasSubstr("fields cannot fit"));

  // The data must hold every row the header declares.
  RosBytes short_data = cloud(1, 2, {1, 2, 3, 4, 5, 6}, {1, 1});
  short_data.bytes[4 + 4 + 4 + (4 + 5) + 4] = 3;  // after seq, stamp, "lidar", height: width 2 -> 3
  EXPECT_THAT(error_of([&] { decode_point_cloud2(short_data.bytes, "m"); }),
              HasSubstr("cannot hold 1 rows of 3"));
}

// Fuzzing found it (2026-11-27): 4 billion rows of no points took seconds.
TEST(RosMessages, ACloudOfNoPointsReturnsAtOnceWhateverItsRowCount) {
  RosBytes m;
  m.header(1, 0, "f").put(std::uint32_t{0xFFFFFFFF}).put(std::uint32_t{0}).put(std::uint32_t{3});
  m.field("x", 0, 7).field("y", 4, 7).field("z", 8, 7);
  m.put(std::uint8_t{0})
      .put(std::uint32_t{12})
      .put(std::uint32_t{0})
      .put(std::uint32_t{0})
      .put(std::uint8_t{1});
  const CloudMessage c = decode_point_cloud2(m.bytes, "m");
  EXPECT_EQ(c.points.size(), 0u);
  EXPECT_EQ(c.dropped_non_finite, 0u);
}

TEST(RosMessages, OdometryPoseStampedAndTf) {
  RosBytes odom;
  odom.header(3, 0, "map").string("base").pose(1, 2, 3, 0, 0, 0, 1);
  for (int i = 0; i < 36; ++i) odom.put(0.0);
  const StampedTransform o = decode_odometry(odom.bytes, "o");
  EXPECT_EQ(o.header.frame_id, "map");
  EXPECT_EQ(o.child_frame_id, "base");
  EXPECT_EQ(o.transform.translation.y(), 2.0);
  EXPECT_EQ(o.transform.qw, 1.0);

  RosBytes pose;
  pose.header(4, 250'000'000, "map").pose(0, 0, 1, 0, 0, 1, 0);
  const StampedTransform p = decode_pose_stamped(pose.bytes, "p");
  EXPECT_DOUBLE_EQ(p.header.stamp, 4.25);
  EXPECT_EQ(p.transform.qz, 1.0);

  RosBytes tf;
  tf.put(std::uint32_t{2});
  tf.header(5, 0, "map").string("odom").pose(1, 0, 0, 0, 0, 0, 1);
  tf.header(5, 0, "odom").string("base").pose(0, 1, 0, 0, 0, 0, 1);
  const auto edges = decode_tf_message(tf.bytes, "tf");
  ASSERT_EQ(edges.size(), 2u);
  EXPECT_EQ(edges[1].header.frame_id, "odom");
  EXPECT_EQ(edges[1].child_frame_id, "base");

  RosBytes huge;
  huge.put(std::uint32_t{1'000'000});
  EXPECT_THAT(error_of([&] { decode_tf_message(huge.bytes, "tf"); }), HasSubstr("transforms cannot fit"));
  odom.bytes.resize(odom.bytes.size() - 1);
  EXPECT_THAT(error_of([&] { decode_odometry(odom.bytes, "o"); }), HasSubstr("pose.covariance"));
}

}  // namespace
}  // namespace sarmap::ros1
