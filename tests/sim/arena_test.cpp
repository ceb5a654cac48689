// Tests of engine/sim/arena.hpp: the shipped arenas parse, and every kind of
// malformed description is rejected with a message naming the key.
#include "engine/sim/arena.hpp"

#include <gtest/gtest.h>

#include <functional>

#include "engine/core/error.hpp"
#include "engine/io/sha256.hpp"
#include "tests/sim/test_arenas.hpp"

namespace sarmap::sim {
namespace {

using nlohmann::json;
using testing::base_arena_json;
using testing::parse_test_arena;

TEST(Arena, ShippedArenasParse) {
  const Arena esogu = load_arena(SARMAP_SOURCE_DIR "/datasets/arenas/esogu-6x4.json");
  EXPECT_EQ(esogu.name, "esogu-6x4");
  EXPECT_EQ(esogu.trajectory.frames, 160u);
  EXPECT_EQ(esogu.sensor.intrinsics.width, 320);
  EXPECT_EQ(esogu.sensor.noise.kind, NoiseKind::Kinect);
  int inclined = 0, flat = 0;
  for (const auto& e : esogu.elements) {
    inclined += e.label == ClassId::InclinedRamp;
    flat += e.label == ClassId::FlatRamp;
  }
  EXPECT_EQ(inclined, 2);
  EXPECT_EQ(flat, 1);
  EXPECT_EQ(esogu.eval_pairs.size(), 2u);
  const Arena building = load_arena(SARMAP_SOURCE_DIR "/datasets/arenas/building-52x15.json");
  EXPECT_DOUBLE_EQ(building.bounds_max.x(), 52.0);
  EXPECT_DOUBLE_EQ(building.bounds_max.y(), 15.0);
}

// The hash a simulated sequence records is the file's, byte for byte.
TEST(Arena, Sha256IsOfTheBytesAsRead) {
  const std::filesystem::path file = SARMAP_SOURCE_DIR "/datasets/arenas/esogu-6x4.json";
  const Arena esogu = load_arena(file);
  EXPECT_EQ(esogu.sha256, digest_file(file).sha256);
  EXPECT_NE(load_arena(SARMAP_SOURCE_DIR "/datasets/arenas/building-52x15.json").sha256, esogu.sha256);
  const std::string text = base_arena_json().dump();
  EXPECT_EQ(parse_arena(text, "a.json", ".").sha256, sha256_hex(text));
  // One more space is another file.
  EXPECT_NE(parse_arena(text + " ", "a.json", ".").sha256, sha256_hex(text));
  EXPECT_EQ(Arena{}.sha256, "");
}

TEST(Arena, ParsesEveryElementAndDefaults) {
  json j = base_arena_json();
  j["elements"] = json::parse(R"([
    {"type": "wall", "from": [0, 0], "to": [4, 0], "height": 1.2, "thickness": 0.1},
    {"type": "inclined_ramp", "center": [2, 1], "length": 1.2, "width": 1.0, "angle_deg": 15},
    {"type": "flat_ramp", "center": [3, 3], "size": [1, 1], "height": 0.3, "yaw_deg": 10},
    {"type": "box", "center": [1, 3, 0.2], "size": [0.4, 0.4, 0.4]},
    {"type": "box", "center": [1, 3, 0.2], "size": [0.4, 0.4, 0.4], "label": "wall"}
  ])");
  const Arena a = parse_test_arena(j);
  ASSERT_EQ(a.elements.size(), 5u);
  EXPECT_EQ(a.elements[0].label, ClassId::Wall);
  EXPECT_EQ(a.elements[1].label, ClassId::InclinedRamp);
  EXPECT_DOUBLE_EQ(std::get<InclinedRampSpec>(a.elements[1].shape).yaw_deg, 0.0);
  EXPECT_EQ(a.elements[2].label, ClassId::FlatRamp);
  EXPECT_EQ(a.elements[3].label, ClassId::Other);
  EXPECT_EQ(a.elements[4].label, ClassId::Wall);
  EXPECT_EQ(element_type_name(a.elements[3]), "box");
}

TEST(Arena, ExplicitPosesAndLidar) {
  json j = base_arena_json();
  j["trajectory"] = {{"poses", {testing::pose_json(Eigen::Matrix3d::Identity(), {1, 2, 0.5}),
                                testing::pose_json(Eigen::Matrix3d::Identity(), {2, 2, 0.5})}}};
  j["sensor"] = json::parse(R"({"type": "lidar", "rings": 16, "horizontal_samples": 360,
      "vertical_fov_deg": [-15, 15], "min_range": 0.2, "max_range": 30, "noise": "gaussian", "sigma": 0.01,
      "dropout": 0.1})");
  const Arena a = parse_test_arena(j);
  ASSERT_EQ(a.trajectory.poses.size(), 2u);
  EXPECT_EQ(a.trajectory.frames, 2u);
  EXPECT_DOUBLE_EQ(a.trajectory.poses[1].translation().x(), 2.0);
  EXPECT_EQ(a.sensor.type, SensorType::Lidar);
  EXPECT_EQ(a.sensor.rings, 16);
  EXPECT_EQ(a.sensor.noise.kind, NoiseKind::Gaussian);
  EXPECT_DOUBLE_EQ(a.sensor.noise.sigma, 0.01);
  EXPECT_DOUBLE_EQ(a.sensor.noise.dropout, 0.1);
  EXPECT_EQ(sensor_info(a.sensor).type, SensorType::Lidar);
  EXPECT_FALSE(sensor_info(a.sensor).intrinsics.has_value());
}

struct BadCase {
  const char* what;
  std::function<void(json&)> mutate;
  const char* message;  // expected substring of the error
};

const json kRamp = json::parse(R"({"type": "inclined_ramp", "center": [2, 1], "length": 1.2, "width": 1.0,
                                   "angle_deg": 15})");

void set_element(json& j, const json& element) {
  j["elements"] = json::array({kRamp, kRamp, kRamp, element});
}
json ramp_with(const char* key, const json& value) {
  json r = kRamp;
  r[key] = value;
  return r;
}

TEST(Arena, RejectsEveryMalformedDescription) {
  const std::vector<BadCase> cases = {
      {"unknown top key", [](json& j) { j["colour"] = "red"; }, "test.json: unknown key \"colour\""},
      {"missing name", [](json& j) { j.erase("name"); }, "test.json: missing required key \"name\""},
      {"missing floor", [](json& j) { j.erase("floor"); }, "missing required key \"floor\""},
      {"missing sensor", [](json& j) { j.erase("sensor"); }, "missing required key \"sensor\""},
      {"bad version", [](json& j) { j["version"] = 2; }, "version must be 1"},
      {"bounds inverted", [](json& j) { j["bounds"]["max"] = {4, -1, 2}; }, "bounds: max must exceed min"},
      {"bounds short", [](json& j) { j["bounds"]["min"] = {0, 0}; }, "bounds: min must be an array of 3 numbers"},
      {"bounds far", [](json& j) { j["bounds"]["max"] = {4, 4, 1e19}; }, "bounds: max must lie within 100000 m"},
      {"bounds far below", [](json& j) { j["bounds"]["min"] = {-2e5, 0, 0}; }, "bounds: min must lie within"},
      {"floor not bool", [](json& j) { j["floor"] = 1; }, "floor must be true or false"},
      {"angle too big", [](json& j) { set_element(j, ramp_with("angle_deg", 95)); },
       "test.json: elements[3] (inclined_ramp): angle_deg must be in (0, 90), got 95"},
      {"angle zero", [](json& j) { set_element(j, ramp_with("angle_deg", 0)); }, "angle_deg must be in (0, 90), got 0"},
      {"negative length", [](json& j) { set_element(j, ramp_with("length", -1)); },
       "elements[3] (inclined_ramp): length must be positive, got -1"},
      {"unknown element key", [](json& j) { set_element(j, ramp_with("colour", "red")); },
       "elements[3] (inclined_ramp): unknown key \"colour\""},
      {"label on ramp", [](json& j) { set_element(j, ramp_with("label", "wall")); },
       "elements[3] (inclined_ramp): unknown key \"label\""},
      {"missing width", [](json& j) { json r = kRamp; r.erase("width"); set_element(j, r); },
       "elements[3] (inclined_ramp): missing required key \"width\""},
      {"string number", [](json& j) { set_element(j, ramp_with("width", "1")); },
       "elements[3] (inclined_ramp): width must be a number, got string"},
      {"unknown type", [](json& j) { set_element(j, {{"type", "ramp"}}); }, "elements[3]: unknown type \"ramp\""},
      {"no type", [](json& j) { set_element(j, {{"center", {1, 2}}}); }, "elements[3]: missing required key \"type\""},
      {"element not object", [](json& j) { set_element(j, 3); }, "elements[3]: must be a JSON object"},
      {"wall zero thickness",
       [](json& j) { set_element(j, {{"type", "wall"}, {"from", {0, 0}}, {"to", {1, 0}}, {"height", 1}, {"thickness", 0}}); },
       "elements[3] (wall): thickness must be positive, got 0"},
      {"wall degenerate",
       [](json& j) { set_element(j, {{"type", "wall"}, {"from", {1, 0}}, {"to", {1, 0}}, {"height", 1}, {"thickness", 0.1}}); },
       "elements[3] (wall): to must differ from from"},
      {"flat ramp negative size",
       [](json& j) { set_element(j, {{"type", "flat_ramp"}, {"center", {1, 1}}, {"size", {1, -2}}, {"height", 0.2}}); },
       "elements[3] (flat_ramp): size must hold positive sizes, got -2"},
      {"box bad label",
       [](json& j) { set_element(j, {{"type", "box"}, {"center", {1, 1, 0}}, {"size", {1, 1, 1}}, {"label", "door"}}); },
       "elements[3] (box): label must be one of"},
      {"box unknown label class",
       [](json& j) { set_element(j, {{"type", "box"}, {"center", {1, 1, 0}}, {"size", {1, 1, 1}}, {"label", "unknown"}}); },
       "elements[3] (box): label must be one of"},
      {"mesh missing file", [](json& j) { set_element(j, {{"type", "mesh"}, {"path", "no/such.dae"}}); },
       "elements[3] (mesh): path: "},
      {"mesh bad scale",
       [](json& j) { set_element(j, {{"type", "mesh"}, {"path", "x.obj"}, {"scale", {1, 0, 1}}}); },
       "elements[3] (mesh): scale must hold positive factors, got 0"},
      {"elements not array", [](json& j) { j["elements"] = json::object(); }, "elements must be an array"},
      {"one waypoint", [](json& j) { j["trajectory"]["waypoints"] = {{1, 1}}; },
       "trajectory: waypoints must be an array of at least two"},
      {"zero frames", [](json& j) { j["trajectory"]["frames"] = 0; }, "trajectory: frames must be an integer >= 1, got 0"},
      {"fraction frames", [](json& j) { j["trajectory"]["frames"] = 1.5; }, "trajectory: frames must be an integer"},
      {"too many frames", [](json& j) { j["trajectory"]["frames"] = 100'000'000; },
       "trajectory: frames must be at most 108000, got 100000000"},
      {"negative height", [](json& j) { j["trajectory"]["height"] = -0.5; }, "trajectory: height must be positive"},
      {"pitch out of range", [](json& j) { j["trajectory"]["pitch_deg"] = -95; }, "trajectory: pitch_deg must be in (-90, 90)"},
      {"poses and waypoints", [](json& j) { j["trajectory"]["poses"] = json::array(); },
       "trajectory: give either waypoints or poses, not both"},
      {"pose short",
       [](json& j) { j["trajectory"] = {{"poses", {{1, 0, 0}}}}; }, "trajectory: poses[0] must be an array of 16 numbers"},
      {"pose not rotation",
       [](json& j) {
         j["trajectory"] = {{"poses", {testing::pose_json(Eigen::Matrix3d::Identity() * 2, {0, 0, 0})}}};
       },
       "trajectory: poses[0]: rotation is not orthonormal"},
      {"sensor type", [](json& j) { j["sensor"]["type"] = "sonar"; }, "sensor: type must be \"depth_camera\" or \"lidar\""},
      {"sensor fx", [](json& j) { j["sensor"]["fx"] = 0; }, "sensor: fx must be positive, got 0"},
      {"sensor width", [](json& j) { j["sensor"]["width"] = 0; }, "sensor: width must be an integer >= 1"},
      {"sensor range", [](json& j) { j["sensor"]["max_range"] = 0.05; }, "sensor: max_range must be greater than min_range"},
      {"sensor noise", [](json& j) { j["sensor"]["noise"] = "pink"; }, "sensor: noise must be \"none\", \"gaussian\" or \"kinect\""},
      {"gaussian no sigma", [](json& j) { j["sensor"]["noise"] = "gaussian"; }, "sensor: missing required key \"sigma\""},
      {"sigma without gaussian", [](json& j) { j["sensor"]["sigma"] = 0.1; }, "sensor: unknown key \"sigma\""},
      {"dropout one", [](json& j) { j["sensor"]["dropout"] = 1.0; }, "sensor: dropout must be in [0, 1), got 1"},
      {"lidar keys on camera", [](json& j) { j["sensor"]["rings"] = 16; }, "sensor: unknown key \"rings\""},
      {"lidar fov", [](json& j) {
         j["sensor"] = {{"type", "lidar"}, {"rings", 4}, {"horizontal_samples", 8}, {"vertical_fov_deg", {10, -10}},
                        {"min_range", 0.1}, {"max_range", 10}};
       },
       "sensor: vertical_fov_deg must be [min, max]"},
      {"eval pair", [](json& j) { j["eval_pairs"] = {{{0, 0, 0}}}; }, "eval_pairs[0] must be a pair"},
  };
  for (const BadCase& c : cases) {
    json j = base_arena_json();
    c.mutate(j);
    try {
      parse_test_arena(j);
      ADD_FAILURE() << c.what << ": accepted";
    } catch (const Error& e) {
      EXPECT_NE(std::string(e.what()).find(c.message), std::string::npos)
          << c.what << ": message was \"" << e.what() << "\"";
    }
  }
}

TEST(Arena, RejectsBrokenJsonWithOffset) {
  try {
    parse_arena("{\"name\": ", "broken.json", ".");
    FAIL();
  } catch (const Error& e) {
    EXPECT_EQ(e.code(), ErrorCode::Parse);
    EXPECT_NE(std::string(e.what()).find("broken.json (byte offset"), std::string::npos) << e.what();
  }
  EXPECT_THROW(load_arena("/no/such/arena.json"), Error);
}

// A number beyond a double makes nlohmann::json throw out_of_range, not
// parse_error, and it escaped as an internal error: fuzz/safetensors_fuzz
// found it there, and this catch had the same gap.
TEST(Arena, RejectsANumberBeyondADouble) {
  try {
    parse_arena(R"({"version": 1, "name": "x", "bounds": {"min": [0, 0, 0], "max": [1e999, 2, 1]}})",
                "huge.json", ".");
    FAIL();
  } catch (const Error& e) {
    EXPECT_EQ(e.code(), ErrorCode::Parse);
    EXPECT_NE(std::string(e.what()).find("huge.json: not valid JSON: "), std::string::npos) << e.what();
    EXPECT_NE(std::string(e.what()).find("number overflow"), std::string::npos) << e.what();
  }
}

}  // namespace
}  // namespace sarmap::sim
