#include "engine/pipeline/mapper_file.hpp"

#include <string>
#include <string_view>

#include <nlohmann/json.hpp>

#include "engine/core/error.hpp"
#include "engine/core/state_stream.hpp"
#include "engine/io/digested_file.hpp"
#include "engine/pipeline/mapper_config_json.hpp"

namespace sarmap::pipeline {
namespace {

constexpr std::string_view kMapperFileMagic = "SARMAPMF";

void put_sensor(StateWriter& out, const SensorInfo& sensor) {
  out.put(static_cast<std::uint8_t>(sensor.type));
  out.put(sensor.min_range);
  out.put(sensor.max_range);
  out.put(static_cast<std::uint8_t>(sensor.intrinsics ? 1 : 0));
  if (!sensor.intrinsics) return;
  const PinholeIntrinsics& i = *sensor.intrinsics;
  out.put(static_cast<std::int32_t>(i.width));
  out.put(static_cast<std::int32_t>(i.height));
  out.put(i.fx), out.put(i.fy), out.put(i.cx), out.put(i.cy);
}

SensorInfo get_sensor(StateReader& in, const std::filesystem::path& file) {
  SensorInfo sensor;
  const auto type = in.get<std::uint8_t>();
  if (type > static_cast<std::uint8_t>(SensorType::Lidar)) {
    throw Error(ErrorCode::Parse, file.string() + ": unknown sensor type " + std::to_string(type));
  }
  sensor.type = static_cast<SensorType>(type);
  sensor.min_range = in.get<double>();
  sensor.max_range = in.get<double>();
  if (in.get<std::uint8_t>() != 0) {
    PinholeIntrinsics i;
    i.width = in.get<std::int32_t>();
    i.height = in.get<std::int32_t>();
    i.fx = in.get<double>(), i.fy = in.get<double>(), i.cx = in.get<double>(), i.cy = in.get<double>();
    sensor.intrinsics = i;
  }
  return sensor;
}

}  // namespace

void save_mapper_file(const std::filesystem::path& file, const Mapper& mapper) {
  StateWriter out;
  out.tag("SARM");
  out.tag("APMF");
  out.put(kMapperFileVersion);
  out.put_string(config_to_json(mapper.config()).dump());
  put_sensor(out, mapper.sensor());
  mapper.save_state(out);
  write_digested_file(file, out.bytes());
}

void load_mapper_file(const std::filesystem::path& file, const MakeMapper& make) {
  const FileBytes bytes = read_digested_file(file, kMapperFileMagic, "Mapper file");
  StateReader in(digested_body(bytes), file.string());
  in.expect_tag("SARM");
  in.expect_tag("APMF");
  const auto version = in.get<std::uint32_t>();
  if (version != kMapperFileVersion) {
    throw Error(ErrorCode::Parse, file.string() + ": Mapper file version " + std::to_string(version) +
                                      ", this sarmap reads version " + std::to_string(kMapperFileVersion));
  }
  const std::string config_text = in.get_string();
  const auto config_json = nlohmann::ordered_json::parse(config_text, nullptr, /*allow_exceptions=*/false);
  if (config_json.is_discarded()) throw Error(ErrorCode::Parse, file.string() + ": its config is not JSON");
  const MapperConfig config = config_from_json(config_json, {}, file.string());
  const SensorInfo sensor = get_sensor(in, file);
  Mapper& mapper = make(config, sensor);
  mapper.load_state(in);
  in.expect_end();
}

std::unique_ptr<Mapper> load_mapper_file(const std::filesystem::path& file) {
  std::unique_ptr<Mapper> mapper;
  load_mapper_file(file, [&](const MapperConfig& config, const SensorInfo& sensor) -> Mapper& {
    mapper = std::make_unique<Mapper>(config, sensor);
    return *mapper;
  });
  return mapper;
}

}  // namespace sarmap::pipeline
