// The run config schema (engine/pipeline/mapper_config_json): every key read
// back as written, partial files over the defaults, and errors naming the
// dotted key for unknown keys, wrong types and other versions.
#include "engine/pipeline/mapper_config_json.hpp"

#include <string>

#include <gtest/gtest.h>

#include "engine/core/error.hpp"
#include "tests/io/scratch_folder.hpp"

namespace sarmap::pipeline {
namespace {

using Json = nlohmann::ordered_json;

// Every leaf changed to another valid value of its type (not its default).
void change_every_leaf(Json& j, const std::string& key = "") {
  if (j.is_object()) {
    for (auto& [name, value] : j.items()) {
      if (name != "version") change_every_leaf(value, name);
    }
  } else if (j.is_boolean()) {
    j = !j.get<bool>();
  } else if (j.is_number_unsigned()) {
    j = j.get<std::uint64_t>() + 3;
  } else if (j.is_number()) {
    j = j.get<double>() * 1.5 + 0.25;
  } else if (j.is_array()) {
    j.push_back(0.7);
  } else if (j.is_string()) {
    if (key == "kind") j = "geometric";
    if (key == "model") j = "/models/other.safetensors";
    if (key == "fusion") j = j == "bayesian" ? "histogram" : "bayesian";
  }
}

std::size_t leaf_count(const Json& j) {
  if (!j.is_object()) return 1;
  std::size_t n = 0;
  for (const auto& [name, value] : j.items()) n += leaf_count(value);
  return n;
}

std::string error_of(const Json& j) {
  try {
    config_from_json(j, {}, "test.json");
  } catch (const Error& e) {
    return e.what();
  }
  return "(no error)";
}

TEST(MapperConfigJson, DefaultsRoundTripWithTheVersionFirst) {
  const Json written = config_to_json(MapperConfig{});
  EXPECT_EQ(written.begin().key(), "version");
  EXPECT_EQ(written.at("version"), kConfigVersion);
  EXPECT_EQ(written.at("voxel"), 0.05);
  EXPECT_EQ(written.at("classifier").at("dgcnn").at("min_points"), 100u);  // as sarmap run's
  EXPECT_EQ(written.at("classifier").at("per_scan"), false);  // the accumulated map is classified
  EXPECT_EQ(written.at("classifier").at("map_min_new_points"), 512u);
  EXPECT_EQ(written.at("classifier").at("map_max_wait_scans"), 20u);
  EXPECT_EQ(written.at("segments").at("voxel"), 0.025);
  EXPECT_EQ(written.at("map").at("fusion").at("fusion"), "bayesian");
  // Every setting of every stage, plus the version: a setting added to a
  // settings struct belongs in visit_config too, and then in this count.
  EXPECT_EQ(leaf_count(written), 88u);
  EXPECT_EQ(config_to_json(config_from_json(written)), written);
}

// A reader that skipped a key, or a writer that left one out, fails here:
// each changed value must come back.
TEST(MapperConfigJson, EveryKeyIsReadBackAsWritten) {
  Json changed = config_to_json(MapperConfig{});
  change_every_leaf(changed);
  ASSERT_NE(changed, config_to_json(MapperConfig{}));
  const MapperConfig read = config_from_json(changed);
  EXPECT_EQ(config_to_json(read), changed);
  EXPECT_EQ(read.classifier.kind, ClassifierKind::Geometric);
  EXPECT_EQ(read.map.fusion.fusion, metric::ClassFusion::Histogram);
  EXPECT_EQ(read.topo.body_heights.size(), 3u);
}

TEST(MapperConfigJson, APartialFileChangesOnlyItsKeys) {
  const Json partial = Json::parse(R"({"voxel": 0.1, "segments": {"min_points": 50}, "bounds": {"max_blocks": 1e3}})");
  const MapperConfig read = config_from_json(partial);
  MapperConfig expected;
  expected.voxel = 0.1;
  expected.segments.min_points = 50;
  expected.bounds.max_blocks = 1000;
  EXPECT_EQ(config_to_json(read), config_to_json(expected));
  // Over another base, the base's other values stay.
  MapperConfig base;
  base.topo.robot_radius = 0.3;
  EXPECT_EQ(config_from_json(partial, base).topo.robot_radius, 0.3);
}

TEST(MapperConfigJson, UnknownKeysAreNamedWithTheirPath) {
  EXPECT_NE(error_of(Json::parse(R"({"voxell": 0.1})")).find("test.json: voxell: unknown key"), std::string::npos)
      << error_of(Json::parse(R"({"voxell": 0.1})"));
  const std::string nested = error_of(Json::parse(R"({"classifier": {"dgcnn": {"strid": 0.5}}})"));
  EXPECT_NE(nested.find("classifier.dgcnn.strid: unknown key"), std::string::npos) << nested;
}

TEST(MapperConfigJson, WrongTypesAreNamedWithTheValue) {
  const auto expect_error = [](const char* text, const std::string& part) {
    const std::string message = error_of(Json::parse(text));
    EXPECT_NE(message.find(part), std::string::npos) << text << " -> " << message;
  };
  expect_error(R"({"voxel": "0.1"})", "voxel: must be a number, got \"0.1\"");
  expect_error(R"({"bounds": {"max_blocks": -1}})", "bounds.max_blocks: must be a whole number >= 0, got -1");
  expect_error(R"({"bounds": {"max_blocks": 2.5}})", "bounds.max_blocks: must be a whole number >= 0, got 2.5");
  expect_error(R"({"bounds": 5})", "bounds: must be an object, got 5");
  expect_error(R"({"integrator": {"discretize": 1}})", "integrator.discretize: must be true or false, got 1");
  expect_error(R"({"map": {"fusion": {"fusion": "magic"}}})",
               "map.fusion.fusion: must be \"bayesian\" or \"histogram\", got \"magic\"");
  expect_error(R"({"topo": {"body_heights": [0.1, "a"]}})", "topo.body_heights: must be an array of numbers");
  expect_error(R"({"classifier": {"model": 3}})", "classifier.model: must be a string, got 3");
  expect_error(R"({"classifier": {"kind": "oracle"}})",
               "classifier.kind: must be \"dgcnn\", \"geometric\" or \"labels\", got \"oracle\"");
  expect_error(R"([1, 2])", "a config must be a JSON object");
}

TEST(MapperConfigJson, AnotherVersionIsRefused) {
  EXPECT_NE(error_of(Json::parse(R"({"version": 2})")).find("version: this sarmap reads config version 1, got 2"),
            std::string::npos);
  EXPECT_NE(error_of(Json::parse(R"({"version": "1"})")).find("got \"1\""), std::string::npos);
  EXPECT_NO_THROW(config_from_json(Json::parse(R"({"version": 1})")));
}

TEST(MapperConfigJson, FilesAndManifestsAreRead) {
  const test::ScratchFolder dir;
  dir.write("config.json", R"({"voxel": 0.1, "classifier": {"model": "models/m.safetensors"}})");
  dir.write("manifest.json", R"({"version": 1, "config": {"voxel": 0.2}, "outputs": []})");
  dir.write("old_manifest.json", R"({"version": 1, "settings": {}, "outputs": []})");
  dir.write("broken.json", R"({"voxel": )");
  const MapperConfig config = read_config_file(dir / "config.json");
  EXPECT_EQ(config.voxel, 0.1);
  // A relative model path is taken from the config file's folder.
  EXPECT_EQ(config.classifier.model, dir / "models/m.safetensors");
  EXPECT_EQ(read_config_file(dir / "manifest.json").voxel, 0.2);
  const auto code_of = [&](const char* name) {
    try {
      read_config_file(dir / name);
    } catch (const Error& e) {
      EXPECT_NE(std::string(e.what()).find(name), std::string::npos) << e.what();
      return e.code();
    }
    return ErrorCode::Unsupported;  // no error: fails every expectation below
  };
  EXPECT_EQ(code_of("old_manifest.json"), ErrorCode::InvalidData);
  EXPECT_EQ(code_of("broken.json"), ErrorCode::Parse);
  EXPECT_EQ(code_of("missing.json"), ErrorCode::Io);
}

}  // namespace
}  // namespace sarmap::pipeline
