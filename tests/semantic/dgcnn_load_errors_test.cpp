// Tests the DGCNN loader's errors (engine/semantic/dgcnn/dgcnn_weights.hpp,
// engine/io/safetensors.hpp, engine/io/npy.hpp): a truncated file, an offset
// past the end, a wrong dtype, a missing tensor, shapes that do not chain,
// bad metadata, malformed .npy files. Each message must name the culprit.
#include <gtest/gtest.h>

#include <algorithm>
#include <cmath>
#include <cstring>
#include <filesystem>
#include <fstream>
#include <limits>
#include <string>
#include <vector>

#include <nlohmann/json.hpp>

#include "engine/core/error.hpp"
#include "engine/io/npy.hpp"
#include "engine/io/safetensors.hpp"
#include "engine/semantic/dgcnn/dgcnn_model.hpp"

namespace sarmap {
namespace {

namespace fs = std::filesystem;
const std::string kModel = std::string(SARMAP_TEST_DATA_DIR) + "/dgcnn/model_c6.safetensors";

std::vector<std::uint8_t> model_bytes() {
  std::ifstream in(kModel, std::ios::binary);
  return {std::istreambuf_iterator<char>(in), std::istreambuf_iterator<char>()};
}

// Error message of loading the model from these bytes ("" when it loads).
std::string load_error(std::vector<std::uint8_t> bytes) {
  try {
    const SafetensorsFile file = SafetensorsFile::parse(std::move(bytes), "m.safetensors");
    load_dgcnn_weights(file);
    parse_dgcnn_metadata(file.metadata(), file.source());
  } catch (const Error& e) {
    return e.what();
  }
  return "";
}

// The model file with its JSON header rebuilt from `header` (data unchanged).
std::vector<std::uint8_t> with_header_json(const nlohmann::json& header) {
  const auto bytes = model_bytes();
  std::uint64_t len = 0;
  std::memcpy(&len, bytes.data(), 8);
  const std::string text = header.dump();
  std::vector<std::uint8_t> out;
  const std::uint64_t new_len = text.size();
  for (int i = 0; i < 8; ++i) out.push_back(static_cast<std::uint8_t>(new_len >> (8 * i)));
  out.insert(out.end(), text.begin(), text.end());
  out.insert(out.end(), bytes.begin() + 8 + static_cast<std::ptrdiff_t>(len), bytes.end());
  return out;
}

nlohmann::json model_header() {
  const auto bytes = model_bytes();
  std::uint64_t len = 0;
  std::memcpy(&len, bytes.data(), 8);
  return nlohmann::json::parse(bytes.begin() + 8, bytes.begin() + 8 + static_cast<std::ptrdiff_t>(len));
}

// The model file with one textual replacement in its JSON header.
std::vector<std::uint8_t> with_header(const std::string& from, const std::string& to) {
  std::string text = model_header().dump();
  const auto pos = text.find(from);
  EXPECT_NE(pos, std::string::npos) << from;
  if (pos != std::string::npos) text.replace(pos, from.size(), to);
  return with_header_json(nlohmann::json::parse(text));
}

TEST(DgcnnLoad, FixtureLoads) { EXPECT_EQ(load_error(model_bytes()), ""); }

TEST(DgcnnLoad, TruncatedFileNamesATensorPastTheEnd) {
  auto bytes = model_bytes();
  bytes.resize(bytes.size() - 100);
  const std::string e = load_error(bytes);
  EXPECT_NE(e.find("run past the end"), std::string::npos) << e;
  EXPECT_NE(e.find("tensor '"), std::string::npos) << e;
  EXPECT_NE(load_error({1, 2, 3}).find("truncated"), std::string::npos);
  auto header_cut = model_bytes();
  header_cut.resize(40);
  EXPECT_NE(load_error(header_cut).find("truncated"), std::string::npos);
}

TEST(DgcnnLoad, WrongDtypeNamesTheTensor) {
  // Same byte count, other dtype: conv2's weight as I32.
  nlohmann::json h = model_header();
  h["conv2.0.weight"]["dtype"] = "I32";
  const std::string e = load_error(with_header_json(h));
  EXPECT_NE(e.find("conv2.0.weight"), std::string::npos) << e;
  EXPECT_NE(e.find("I32"), std::string::npos) << e;
}

TEST(DgcnnLoad, MissingTensorIsNamed) {
  const std::string e = load_error(with_header("\"conv8.1.running_var\"", "\"conv8.1.running_varX\""));
  EXPECT_NE(e.find("conv8.1.running_var"), std::string::npos) << e;
  EXPECT_NE(e.find("missing"), std::string::npos) << e;
}

TEST(DgcnnLoad, ShapeThatDoesNotChainIsNamed) {
  // conv3 declared with 64 inputs (and half its bytes) where 2 x 64 chain in.
  nlohmann::json h = model_header();
  auto& t = h["conv3.0.weight"];
  t["shape"] = {64, 64, 1, 1};
  t["data_offsets"][1] = t["data_offsets"][0].get<std::size_t>() + 64 * 64 * 4;
  const std::string e = load_error(with_header_json(h));
  EXPECT_NE(e.find("conv3.0.weight"), std::string::npos) << e;
  EXPECT_NE(e.find("do not chain"), std::string::npos) << e;
}

TEST(DgcnnLoad, ByteCountThatDoesNotFitTheShapeIsNamed) {
  nlohmann::json h = model_header();
  h["conv9.weight"]["shape"] = {5, 32, 1};
  const std::string e = load_error(with_header_json(h));
  EXPECT_NE(e.find("conv9.weight"), std::string::npos) << e;
}

// fuzz/safetensors_fuzz found that an empty tensor's values were copied
// through a null pointer (undefined behaviour); reading that code showed
// [2^32, 2^32] elements wrapping to 0 in size_t, so an empty byte range
// passed for a huge tensor.
TEST(DgcnnLoad, ShapeWhoseElementCountOverflowsIsRefusedAndEmptyTensorsRead) {
  nlohmann::json h = model_header();
  h["huge"] = {{"dtype", "F32"}, {"shape", {4294967296ull, 4294967296ull}}, {"data_offsets", {0, 0}}};
  std::string e;
  try {
    SafetensorsFile::parse(with_header_json(h), "m.safetensors");
  } catch (const Error& err) {
    e = err.what();
  }
  EXPECT_NE(e.find("tensor 'huge': shape [4294967296, 4294967296] holds more elements than memory can address"),
            std::string::npos)
      << e;

  h.erase("huge");
  h["empty"] = {{"dtype", "F32"}, {"shape", {0, 4}}, {"data_offsets", {0, 0}}};
  const SafetensorsFile file = SafetensorsFile::parse(with_header_json(h), "m.safetensors");
  ASSERT_NE(file.find("empty"), nullptr);
  EXPECT_TRUE(file.floats(*file.find("empty")).empty());
}

TEST(DgcnnLoad, BadMetadataIsNamed) {
  const std::string e = load_error(with_header("\"sarmap.k\":\"20\"", "\"sarmap.k\":\"zz\""));
  EXPECT_NE(e.find("sarmap.k"), std::string::npos) << e;
  // Any class name loads (it counts as other); a map onto no sarmap class does not.
  EXPECT_EQ(load_error(with_header("inclined_ramp,flat_ramp\"", "inclined_ramp,lava\"")), "");
  nlohmann::json h = model_header();
  h["__metadata__"]["sarmap.class_map"] = R"({"wall": "lava"})";
  const std::string c = load_error(with_header_json(h));
  EXPECT_NE(c.find("sarmap.class_map"), std::string::npos) << c;
  EXPECT_NE(c.find("lava"), std::string::npos) << c;
}

// The model file with one float of a tensor's data replaced (index into the tensor).
std::vector<std::uint8_t> with_value(const std::string& tensor, std::size_t index, float value) {
  auto bytes = model_bytes();
  std::uint64_t len = 0;
  std::memcpy(&len, bytes.data(), 8);
  const auto offsets = model_header().at(tensor).at("data_offsets");
  const std::size_t at = 8 + len + offsets[0].get<std::size_t>() + 4 * index;
  std::memcpy(bytes.data() + at, &value, 4);
  return bytes;
}

// Weights that would make the network write NaN scores, or give every point
// the same class, are refused at load, naming the tensor.
TEST(DgcnnLoad, WeightsThatCannotBeATrainedModelAreRefused) {
  for (const float v : {std::nanf(""), std::numeric_limits<float>::infinity(), 1e38f}) {
    const std::string e = load_error(with_value("conv3.0.weight", 5, v));
    EXPECT_NE(e.find("tensor 'conv3.0.weight': value 5"), std::string::npos) << v << ": " << e;
  }
  const std::string bn = load_error(with_value("conv2.1.bias", 0, std::nanf("")));
  EXPECT_NE(bn.find("conv2.1.bias"), std::string::npos) << bn;
  auto zero = model_bytes();
  {
    std::uint64_t len = 0;
    std::memcpy(&len, zero.data(), 8);
    const auto offsets = model_header().at("conv9.weight").at("data_offsets");
    std::fill(zero.begin() + static_cast<std::ptrdiff_t>(8 + len + offsets[0].get<std::size_t>()),
              zero.begin() + static_cast<std::ptrdiff_t>(8 + len + offsets[1].get<std::size_t>()), 0);
  }
  const std::string z = load_error(zero);
  EXPECT_NE(z.find("tensor 'conv9.weight': every weight is zero"), std::string::npos) << z;
  const std::string d = load_error(with_header("inclined_ramp,flat_ramp\"", "inclined_ramp,wall\""));
  EXPECT_NE(d.find("\"wall\" repeats"), std::string::npos) << d;
}

// A model trained with another feature normalisation would get features it
// never saw: refused by name rather than run.
TEST(DgcnnLoad, UnknownNormalisationIsRefused) {
  nlohmann::json h = model_header();
  ASSERT_TRUE(h["__metadata__"].contains("sarmap.normalisation"));
  h["__metadata__"]["sarmap.normalisation"] = "room_extent";
  const std::string e = load_error(with_header_json(h));
  EXPECT_NE(e.find("sarmap.normalisation"), std::string::npos) << e;
  EXPECT_NE(e.find("room_extent"), std::string::npos) << e;
}

TEST(DgcnnLoad, ModulePrefixAndBnAliasesAreAccepted) {
  // DataParallel's "module." on every tensor, and conv1's BN only under its
  // bn1 alias (the conv1.1.* entries renamed away).
  const nlohmann::json h = model_header();
  nlohmann::json renamed = nlohmann::json::object();
  for (const auto& [key, value] : h.items()) {
    std::string name = key;
    if (name.rfind("conv1.1.", 0) == 0) name = "unused." + name;
    renamed[key == "__metadata__" ? key : "module." + name] = value;
  }
  EXPECT_EQ(load_error(with_header_json(renamed)), "");
  EXPECT_NE(h.find("bn1.weight"), h.end()) << "the fixture carries the reference's bnN duplicates";
}

TEST(DgcnnLoad, MetadataClassCountMustMatchTheClassifier) {
  const SafetensorsFile file = SafetensorsFile::parse(with_header("inclined_ramp,flat_ramp\"", "inclined_ramp\""), "m");
  EXPECT_THROW(DgcnnModel(load_dgcnn_weights(file), parse_dgcnn_metadata(file.metadata(), "m"),
                          kernels::SimdLevel::Sse42),
               Error);
}

class NpyErrors : public ::testing::Test {
 protected:
  fs::path dir = fs::temp_directory_path() / ("sarmap_npy_" + std::to_string(::getpid()));
  void SetUp() override { fs::create_directories(dir); }
  void TearDown() override { fs::remove_all(dir); }
  fs::path write(const std::string& name, const std::string& header, std::size_t data_bytes) {
    std::string h = header;
    while ((10 + h.size() + 1) % 64 != 0) h += ' ';
    h += '\n';
    std::ofstream out(dir / name, std::ios::binary);
    out.write("\x93NUMPY\x01\x00", 8);
    const std::uint16_t len = static_cast<std::uint16_t>(h.size());
    out.write(reinterpret_cast<const char*>(&len), 2);
    out << h << std::string(data_bytes, '\0');
    return dir / name;
  }
  std::string error(const fs::path& p) {
    try {
      read_npy_f32(p);
    } catch (const Error& e) {
      return e.what();
    }
    return "";
  }
};

TEST_F(NpyErrors, RoundTripAndEachCheck) {
  const std::vector<float> v{1, 2, 3, 4, 5, 6};
  const std::size_t shape[2] = {3, 2};
  write_npy_f32(dir / "ok.npy", shape, v);
  const NpyArray a = read_npy_f32(dir / "ok.npy");
  EXPECT_EQ(a.shape, (std::vector<std::size_t>{3, 2}));
  EXPECT_EQ(a.values, v);

  EXPECT_EQ(error(write("good.npy", "{'descr': '<f4', 'fortran_order': False, 'shape': (2, 3), }", 24)), "");
  EXPECT_NE(error(write("f8.npy", "{'descr': '<f8', 'fortran_order': False, 'shape': (2, 3), }", 48)).find("<f8"),
            std::string::npos);
  EXPECT_NE(error(write("fo.npy", "{'descr': '<f4', 'fortran_order': True, 'shape': (2, 3), }", 24)).find("fortran"),
            std::string::npos);
  EXPECT_NE(error(write("short.npy", "{'descr': '<f4', 'fortran_order': False, 'shape': (2, 3), }", 20)).find("24 bytes"),
            std::string::npos);
  EXPECT_NE(error(write("noshape.npy", "{'descr': '<f4', 'fortran_order': False, }", 0)).find("shape"),
            std::string::npos);
  std::ofstream(dir / "magic.npy") << "NUMPY not really";
  EXPECT_NE(error(dir / "magic.npy").find("magic"), std::string::npos);
  std::ofstream v9(dir / "v9.npy", std::ios::binary);
  v9.write("\x93NUMPY\x09\x00\x00\x00\x00\x00", 12);
  v9.close();
  EXPECT_NE(error(dir / "v9.npy").find("version"), std::string::npos);
}

// Found by fuzz/safetensors_fuzz: a number beyond a double in the header
// ('608e736') made nlohmann::json throw out_of_range, which escaped the
// parse_error handler as an internal error.
TEST(DgcnnLoad, HeaderNumberBeyondADoubleIsAParseError) {
  const std::string header = R"({"a": {"dtype": "F32", "shape": [608e736], "data_offsets": [0, 4]}})";
  std::vector<std::uint8_t> bytes;
  for (int i = 0; i < 8; ++i) bytes.push_back(static_cast<std::uint8_t>(header.size() >> (8 * i)));
  bytes.insert(bytes.end(), header.begin(), header.end());
  bytes.resize(bytes.size() + 4, 0);
  const std::string e = load_error(bytes);
  EXPECT_NE(e.find("m.safetensors: header is not valid JSON: "), std::string::npos) << e;
  EXPECT_NE(e.find("number overflow"), std::string::npos) << e;
}

// fuzz/npy_fuzz found that a (0, 3) array was copied through a null pointer
// (undefined behaviour); reading that code showed (2**40, 2**40) elements
// wrapping to 0 in size_t, read as an empty array of that shape.
TEST_F(NpyErrors, ShapeWhoseElementCountOverflowsIsRefusedAndEmptyArraysRead) {
  const std::string e = error(
      write("wrap.npy", "{'descr': '<f4', 'fortran_order': False, 'shape': (1099511627776, 1099511627776), }", 0));
  EXPECT_NE(e.find("shape holds more elements than memory can address"), std::string::npos) << e;
  EXPECT_EQ(error(write("empty.npy", "{'descr': '<f4', 'fortran_order': False, 'shape': (0, 3), }", 0)), "");
  const NpyArray empty = read_npy_f32(dir / "empty.npy");
  EXPECT_EQ(empty.shape, (std::vector<std::size_t>{0, 3}));
  EXPECT_TRUE(empty.values.empty());
}

// conv9 has no bias in the reference layout, but a model trained with one
// loads and adds it to every point's logits.
TEST(DgcnnLoad, OptionalClassifierBiasIsAddedToTheLogits) {
  nlohmann::json h = model_header();
  const std::size_t classes = h["conv9.weight"]["shape"][0].get<std::size_t>();
  std::size_t end = 0;
  for (const auto& [name, t] : h.items())
    if (name != "__metadata__") end = std::max(end, t["data_offsets"][1].get<std::size_t>());
  h["conv9.bias"] = {{"dtype", "F32"}, {"shape", {classes}}, {"data_offsets", {end, end + 4 * classes}}};
  auto bytes = with_header_json(h);
  std::vector<float> bias(classes);
  for (std::size_t c = 0; c < classes; ++c) bias[c] = 0.5f * static_cast<float>(c) - 1.0f;
  const auto* raw = reinterpret_cast<const std::uint8_t*>(bias.data());
  bytes.insert(bytes.end(), raw, raw + 4 * classes);

  const SafetensorsFile plain_file = SafetensorsFile::parse(model_bytes(), "plain.safetensors");
  const SafetensorsFile biased_file = SafetensorsFile::parse(std::move(bytes), "biased.safetensors");
  const auto level = kernels::active_simd_level();
  const DgcnnModel plain(load_dgcnn_weights(plain_file), parse_dgcnn_metadata(plain_file.metadata(), "p"), level);
  const DgcnnModel biased(load_dgcnn_weights(biased_file), parse_dgcnn_metadata(biased_file.metadata(), "b"), level);
  const NpyArray block = read_npy_f32(std::string(SARMAP_TEST_DATA_DIR) + "/dgcnn/block_c6_n1024.npy");
  const std::size_t n = block.shape[0];
  std::vector<float> a(n * classes), b(n * classes);
  DgcnnWorkspace ws;
  plain.forward(block.values.data(), n, a.data(), ws);
  biased.forward(block.values.data(), n, b.data(), ws);
  for (std::size_t i = 0; i < n; ++i)
    for (std::size_t c = 0; c < classes; ++c) ASSERT_NEAR(b[i * classes + c], a[i * classes + c] + bias[c], 1e-4f);
}

}  // namespace
}  // namespace sarmap
