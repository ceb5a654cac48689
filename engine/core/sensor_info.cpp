#include "engine/core/sensor_info.hpp"

namespace sarmap {

std::string_view to_string(SensorType type) {
  switch (type) {
    case SensorType::DepthCamera: return "depth_camera";
    case SensorType::Lidar: return "lidar";
    case SensorType::Unknown: break;
  }
  return "unknown";
}

}  // namespace sarmap
