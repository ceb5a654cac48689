#include "engine/io_rosbag/ros_messages.hpp"

#include <cmath>
#include <cstring>
#include <optional>

#include "engine/core/classes.hpp"
#include "engine/core/error.hpp"

namespace sarmap::ros1 {
namespace {

// Reads ROS 1's serialisation, every read bounded by the message's bytes.
class Reader {
 public:
  Reader(std::span<const std::uint8_t> bytes, const std::string& what) : bytes_(bytes), what_(what) {}

  std::size_t offset() const { return at_; }
  std::size_t left() const { return bytes_.size() - at_; }

  [[noreturn]] void fail(const std::string& message, std::size_t offset) const {
    throw Error(ErrorCode::Parse, at_offset(what_, offset, message));
  }
  std::span<const std::uint8_t> take(std::size_t n, const char* field) {
    if (n > left()) {
      fail(std::string(field) + ": needs " + std::to_string(n) + " bytes, the message has " +
               std::to_string(left()) + " left (truncated or not this message type)",
           at_);
    }
    const auto out = bytes_.subspan(at_, n);
    at_ += n;
    return out;
  }
  template <class T>
  T scalar(const char* field) {
    T value;
    std::memcpy(&value, take(sizeof(T), field).data(), sizeof(T));  // little-endian hosts only, as ROS 1
    return value;
  }
  std::string string(const char* field) {
    const auto n = scalar<std::uint32_t>(field);
    const auto s = take(n, field);
    return {reinterpret_cast<const char*>(s.data()), s.size()};
  }
  MessageHeader header() {
    MessageHeader h;
    scalar<std::uint32_t>("header.seq");
    const auto sec = scalar<std::uint32_t>("header.stamp.sec");
    const auto nsec = scalar<std::uint32_t>("header.stamp.nsec");
    h.stamp = sec + nsec * 1e-9;
    h.frame_id = string("header.frame_id");
    return h;
  }
  RosTransform pose(const char* field) {
    RosTransform t;
    for (int i = 0; i < 3; ++i) t.translation[i] = scalar<double>(field);
    t.qx = scalar<double>(field);
    t.qy = scalar<double>(field);
    t.qz = scalar<double>(field);
    t.qw = scalar<double>(field);
    return t;
  }
  const std::string& what() const { return what_; }

 private:
  std::span<const std::uint8_t> bytes_;
  const std::string& what_;
  std::size_t at_ = 0;
};

// sensor_msgs/PointField datatypes.
enum Datatype : std::uint8_t { Int8 = 1, Uint8, Int16, Uint16, Int32, Uint32, Float32, Float64 };

std::size_t size_of(std::uint8_t datatype) {
  switch (datatype) {
    case Int8:
    case Uint8:
      return 1;
    case Int16:
    case Uint16:
      return 2;
    case Int32:
    case Uint32:
    case Float32:
      return 4;
    case Float64:
      return 8;
    default:
      return 0;
  }
}

struct Field {
  std::string name;
  std::uint32_t offset;
  std::uint8_t datatype;
  std::uint32_t count;
};

double read_as_double(const std::uint8_t* p, std::uint8_t datatype) {
  switch (datatype) {
    case Int8:
      return static_cast<std::int8_t>(*p);
    case Uint8:
      return *p;
    case Int16: {
      std::int16_t v;
      std::memcpy(&v, p, 2);
      return v;
    }
    case Uint16: {
      std::uint16_t v;
      std::memcpy(&v, p, 2);
      return v;
    }
    case Int32: {
      std::int32_t v;
      std::memcpy(&v, p, 4);
      return v;
    }
    case Uint32: {
      std::uint32_t v;
      std::memcpy(&v, p, 4);
      return v;
    }
    case Float32: {
      float v;
      std::memcpy(&v, p, 4);
      return v;
    }
    default: {
      double v;
      std::memcpy(&v, p, 8);
      return v;
    }
  }
}

}  // namespace

CloudMessage decode_point_cloud2(std::span<const std::uint8_t> bytes, const std::string& what,
                                 const InputLimits& limits) {
  Reader in(bytes, what);
  CloudMessage cloud;
  cloud.header = in.header();
  const auto height = in.scalar<std::uint32_t>("height");
  const auto width = in.scalar<std::uint32_t>("width");
  const std::size_t fields_at = in.offset();
  const auto field_count = in.scalar<std::uint32_t>("fields");
  // Each field takes at least 13 bytes, so a huge count fails on the bytes, not on memory.
  if (field_count > in.left() / 13)
    in.fail("fields: " + std::to_string(field_count) + " fields cannot fit", fields_at);
  std::vector<Field> fields(field_count);
  for (Field& f : fields) {
    f.name = in.string("fields.name");
    f.offset = in.scalar<std::uint32_t>("fields.offset");
    f.datatype = in.scalar<std::uint8_t>("fields.datatype");
    f.count = in.scalar<std::uint32_t>("fields.count");
  }
  const bool big_endian = in.scalar<std::uint8_t>("is_bigendian") != 0;
  const auto point_step = in.scalar<std::uint32_t>("point_step");
  const auto row_step = in.scalar<std::uint32_t>("row_step");
  const std::size_t data_at = in.offset() + 4;
  const auto data_size = in.scalar<std::uint32_t>("data");
  const auto data = in.take(data_size, "data");
  in.scalar<std::uint8_t>("is_dense");  // a hint only: NaN points are dropped either way

  if (big_endian)
    throw Error(ErrorCode::Unsupported, what + ": big-endian PointCloud2 data is not supported");
  const Field* axis[3] = {nullptr, nullptr, nullptr};
  const Field* label = nullptr;
  for (const Field& f : fields) {
    const std::size_t size = size_of(f.datatype);
    if (size == 0) {
      in.fail("field '" + f.name + "' has datatype " + std::to_string(f.datatype) +
                  " (PointField types are 1 to 8)",
              fields_at);
    }
    if (f.count == 0 || std::uint64_t{f.offset} + std::uint64_t{size} * f.count > point_step) {
      in.fail("field '" + f.name + "' (offset " + std::to_string(f.offset) + ", " + std::to_string(f.count) +
                  " x " + std::to_string(size) + " bytes) does not fit point_step " +
                  std::to_string(point_step),
              fields_at);
    }
    if (f.name == "x") axis[0] = &f;
    if (f.name == "y") axis[1] = &f;
    if (f.name == "z") axis[2] = &f;
    if ((f.name == "label" || f.name == "class") && !label) label = &f;
  }
  for (int a = 0; a < 3; ++a) {
    static constexpr const char* kNames[3] = {"x", "y", "z"};
    if (!axis[a]) throw Error(ErrorCode::Parse, what + ": PointCloud2 has no '" + kNames[a] + "' field");
    if (axis[a]->datatype != Float32 && axis[a]->datatype != Float64) {
      throw Error(ErrorCode::Unsupported, what + ": field '" + kNames[a] + "' has datatype " +
                                              std::to_string(axis[a]->datatype) +
                                              "; x, y, z must be float32 (7) or float64 (8)");
    }
  }
  const std::uint64_t points = std::uint64_t{width} * height;
  check_declared_points(points, limits, what);
  if (points > 0 &&
      (std::uint64_t{point_step} * width > row_step ||
       std::uint64_t{row_step} * (height - 1) + std::uint64_t{point_step} * width > data.size())) {
    in.fail("data: " + std::to_string(data.size()) + " bytes cannot hold " + std::to_string(height) +
                " rows of " + std::to_string(width) + " points (point_step " + std::to_string(point_step) +
                ", row_step " + std::to_string(row_step) + ")",
            data_at);
  }

  if (label) cloud.points.enable_labels();
  if (points == 0) return cloud;  // else 4 billion empty rows would take seconds (found by fuzzing)
  cloud.points.reserve(points);
  for (std::uint32_t row = 0; row < height; ++row) {
    for (std::uint32_t col = 0; col < width; ++col) {
      const std::uint8_t* p = data.data() + std::size_t{row} * row_step + std::size_t{col} * point_step;
      double xyz[3];
      for (int a = 0; a < 3; ++a) xyz[a] = read_as_double(p + axis[a]->offset, axis[a]->datatype);
      const float x = static_cast<float>(xyz[0]), y = static_cast<float>(xyz[1]),
                  z = static_cast<float>(xyz[2]);
      if (!std::isfinite(x) || !std::isfinite(y) || !std::isfinite(z)) {
        ++cloud.dropped_non_finite;
        continue;
      }
      cloud.points.push_back(x, y, z);
      if (label) {
        const double value = read_as_double(p + label->offset, label->datatype);
        if (!(value >= 0 && value < static_cast<double>(kClassCount) && value == std::floor(value))) {
          throw Error(ErrorCode::InvalidData,
                      what + ": point " + std::to_string(std::size_t{row} * width + col) + " has " +
                          label->name + " " + std::to_string(value) + ", not a class id (0 to " +
                          std::to_string(kClassCount - 1) + ")");
        }
        cloud.points.labels()[cloud.points.size() - 1] = static_cast<std::uint8_t>(value);
      }
    }
  }
  return cloud;
}

StampedTransform decode_odometry(std::span<const std::uint8_t> bytes, const std::string& what) {
  Reader in(bytes, what);
  StampedTransform out;
  out.header = in.header();
  out.child_frame_id = in.string("child_frame_id");
  out.transform = in.pose("pose.pose");
  in.take(36 * 8, "pose.covariance");  // the twist after it is not needed
  return out;
}

StampedTransform decode_pose_stamped(std::span<const std::uint8_t> bytes, const std::string& what) {
  Reader in(bytes, what);
  StampedTransform out;
  out.header = in.header();
  out.transform = in.pose("pose");
  return out;
}

std::vector<StampedTransform> decode_tf_message(std::span<const std::uint8_t> bytes,
                                                const std::string& what) {
  Reader in(bytes, what);
  const std::size_t count_at = in.offset();
  const auto count = in.scalar<std::uint32_t>("transforms");
  // Each transform takes at least 76 bytes.
  if (count > in.left() / 76)
    in.fail("transforms: " + std::to_string(count) + " transforms cannot fit", count_at);
  std::vector<StampedTransform> out(count);
  for (StampedTransform& t : out) {
    t.header = in.header();
    t.child_frame_id = in.string("child_frame_id");
    t.transform = in.pose("transform");
  }
  return out;
}

}  // namespace sarmap::ros1
