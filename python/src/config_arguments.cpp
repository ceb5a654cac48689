#include "python/src/config_arguments.hpp"

#include <string>

#include "engine/pipeline/mapper_config_json.hpp"
#include "python/src/array_arguments.hpp"
#include "python/src/errors.hpp"

namespace sarmap::python {

namespace {

bool is_path(const py::handle& value) {
  return py::isinstance<py::str>(value) || py::hasattr(value, "__fspath__");
}

double number(const py::dict& d, const char* key, const std::string& name) {
  const py::object v = d[key];
  if (!py::isinstance<py::int_>(v) && !py::isinstance<py::float_>(v)) {
    type_error(name.c_str(), std::string(key) + ": expected a number, got a " + describe(v));
  }
  return v.cast<double>();
}

}  // namespace

pipeline::MapperConfig config_argument(const py::handle& value, const char* name) {
  pipeline::MapperConfig config;
  if (value.is_none()) {
  } else if (is_path(value)) {
    config = pipeline::read_config_file(path_argument(value, name));
  } else if (py::isinstance<py::dict>(value)) {
    // Through Python's own JSON writer, so that the dict's keys keep their
    // order and a value JSON cannot hold is named by it.
    std::string text;
    try {
      text = py::module_::import("json").attr("dumps")(value).cast<std::string>();
    } catch (const py::error_already_set& e) {
      type_error(name, e.what());
    }
    config = pipeline::config_from_json(nlohmann::ordered_json::parse(text), {}, name);
  } else {
    type_error(name, "expected a dict, a config file's path or None, got a " + describe(value));
  }
  if (config.classifier.kind == pipeline::ClassifierKind::Dgcnn && config.classifier.model.empty()) {
    config.classifier.model = py::module_::import("sarmap._data").attr("shipped_model")().cast<std::string>();
  }
  return config;
}

SensorInfo sensor_argument(const py::handle& value, const char* name) {
  SensorInfo sensor;
  if (value.is_none()) return sensor;
  if (!py::isinstance<py::dict>(value)) type_error(name, "expected a dict or None, got a " + describe(value));
  const auto d = py::reinterpret_borrow<py::dict>(value);
  for (const auto& [key, item] : d) {
    const std::string k = py::str(key);
    if (k == "type") {
      const std::string type = py::str(item);
      if (type == "depth_camera") {
        sensor.type = SensorType::DepthCamera;
      } else if (type == "lidar") {
        sensor.type = SensorType::Lidar;
      } else if (type != "unknown") {
        value_error(name, "type: expected \"depth_camera\", \"lidar\" or \"unknown\", got \"" + type + "\"");
      }
    } else if (k == "min_range") {
      sensor.min_range = number(d, "min_range", name);
    } else if (k == "max_range") {
      sensor.max_range = number(d, "max_range", name);
    } else if (k == "intrinsics") {
      if (item.is_none()) continue;
      if (!py::isinstance<py::dict>(item))
        type_error(name, "intrinsics: expected a dict, got a " + describe(item));
      const auto i = py::reinterpret_borrow<py::dict>(item);
      const std::string inner = std::string(name) + ".intrinsics";
      PinholeIntrinsics pinhole;
      for (const auto& [ikey, ivalue] : i) {
        const std::string ik = py::str(ikey);
        if (ik == "width") {
          pinhole.width = static_cast<int>(number(i, "width", inner));
        } else if (ik == "height") {
          pinhole.height = static_cast<int>(number(i, "height", inner));
        } else if (ik == "fx" || ik == "fy" || ik == "cx" || ik == "cy") {
          (ik == "fx"   ? pinhole.fx
           : ik == "fy" ? pinhole.fy
           : ik == "cx" ? pinhole.cx
                        : pinhole.cy) = number(i, ik.c_str(), inner);
        } else {
          value_error(inner.c_str(), ik + ": unknown key");
        }
      }
      sensor.intrinsics = pinhole;
    } else {
      value_error(name, k + ": unknown key (type, min_range, max_range, intrinsics)");
    }
  }
  return sensor;
}

py::dict sensor_dict(const SensorInfo& sensor) {
  py::dict d;
  d["type"] = std::string(to_string(sensor.type));
  d["min_range"] = sensor.min_range;
  d["max_range"] = sensor.max_range;
  if (sensor.intrinsics) {
    const PinholeIntrinsics& i = *sensor.intrinsics;
    py::dict pinhole;
    pinhole["width"] = i.width;
    pinhole["height"] = i.height;
    pinhole["fx"] = i.fx;
    pinhole["fy"] = i.fy;
    pinhole["cx"] = i.cx;
    pinhole["cy"] = i.cy;
    d["intrinsics"] = pinhole;
  } else {
    d["intrinsics"] = py::none();
  }
  return d;
}

py::object to_python(const nlohmann::ordered_json& json) {
  return py::module_::import("json").attr("loads")(json.dump());
}

}  // namespace sarmap::python
