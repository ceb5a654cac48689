// Builds ROS 1 serialised messages byte by byte for the decoder tests.
#pragma once

#include <cstdint>
#include <cstring>
#include <string>
#include <vector>

namespace sarmap::testing {

struct RosBytes {
  std::vector<std::uint8_t> bytes;

  template <class T>
  RosBytes& put(T value) {
    const auto at = bytes.size();
    bytes.resize(at + sizeof(T));
    std::memcpy(bytes.data() + at, &value, sizeof(T));
    return *this;
  }
  RosBytes& string(const std::string& s) {
    put(static_cast<std::uint32_t>(s.size()));
    bytes.insert(bytes.end(), s.begin(), s.end());
    return *this;
  }
  RosBytes& header(std::uint32_t sec, std::uint32_t nsec, const std::string& frame) {
    return put(std::uint32_t{0}).put(sec).put(nsec).string(frame);
  }
  RosBytes& field(const std::string& name, std::uint32_t offset, std::uint8_t datatype,
                  std::uint32_t count = 1) {
    return string(name).put(offset).put(datatype).put(count);
  }
  RosBytes& pose(double x, double y, double z, double qx, double qy, double qz, double qw) {
    return put(x).put(y).put(z).put(qx).put(qy).put(qz).put(qw);
  }
};

}  // namespace sarmap::testing
