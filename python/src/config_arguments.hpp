// Configs and sensors as Python gives them. A config is a dict in the one
// JSON schema of a MapperConfig (engine/pipeline/mapper_config_json.hpp),
// or the path of a config file or a run's manifest.json; a sensor is a dict
// with sequence.json's "sensor" keys (docs/formats.md).
#pragma once

#include <pybind11/pybind11.h>
#include <nlohmann/json.hpp>

#include "engine/core/sensor_info.hpp"
#include "engine/pipeline/mapper.hpp"

namespace sarmap::python {

namespace py = pybind11;

// None (every default), a dict or a path (str or os.PathLike). Unknown keys
// and wrong types are ValueErrors naming the dotted key; another type of
// argument a TypeError. A dgcnn config without a model takes the shipped
// one (sarmap._data.shipped_model()), as `sarmap run` does.
pipeline::MapperConfig config_argument(const py::handle& value, const char* name);

// None (no sensor information), or a dict: "type" ("depth_camera", "lidar" or
// "unknown"), "min_range", "max_range" and "intrinsics" ({"width", "height",
// "fx", "fy", "cx", "cy"}), each optional.
SensorInfo sensor_argument(const py::handle& value, const char* name);
py::dict sensor_dict(const SensorInfo& sensor);

// A JSON value as Python objects (dicts, lists, numbers, strings).
py::object to_python(const nlohmann::ordered_json& json);

}  // namespace sarmap::python
