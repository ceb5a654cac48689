// mapper.state (save_mapper_file / load_mapper_file): a saved Mapper loads
// with its config, sensor, maps and merged flag and goes on mapping exactly
// as the original; damaged, truncated, foreign and other-version files are
// refused naming the file and what is wrong.
#include "engine/pipeline/mapper_file.hpp"

#include <gtest/gtest.h>

#include <filesystem>
#include <fstream>
#include <memory>
#include <string>

#include "engine/core/error.hpp"
#include "engine/io/sha256.hpp"
#include "engine/pipeline/checkpoint.hpp"
#include "engine/pipeline/mapper_config_json.hpp"
#include "engine/sim/simulator.hpp"
#include "tests/io/scratch_folder.hpp"
#include "tests/pipeline/default_arena.hpp"
#include "tests/pipeline/same_maps.hpp"

namespace sarmap::pipeline {
namespace {

namespace fs = std::filesystem;
using testing::default_arena;

MapperConfig labels_run_config() {
  MapperConfig config;
  config.voxel = 0.1;
  config.classifier.kind = ClassifierKind::Labels;
  return config;
}

void map_fifth_frames(Mapper& mapper, std::size_t from, std::size_t to) {
  static const sim::Simulator simulator(default_arena());
  for (std::size_t f = from; f < to; ++f) {
    Scan scan = simulator.simulate(f * 5);
    mapper.integrate(scan);
  }
}

std::string bytes_of_file(const fs::path& file) {
  std::ifstream in(file, std::ios::binary);
  return {std::istreambuf_iterator<char>(in), std::istreambuf_iterator<char>()};
}

void write_bytes(const fs::path& file, const std::string& bytes) {
  std::ofstream(file, std::ios::binary) << bytes;
}

// What load_mapper_file throws for the file, or "".
std::string load_error(const fs::path& file) {
  try {
    load_mapper_file(file);
  } catch (const Error& e) {
    return e.what();
  }
  return "";
}

class MapperFile : public ::testing::Test {
 protected:
  void SetUp() override {
    mapper_ = std::make_unique<Mapper>(labels_run_config(), sim::sensor_info(default_arena().sensor));
    map_fifth_frames(*mapper_, 0, 4);
    save_mapper_file(file(), *mapper_);
  }
  fs::path file() const { return scratch_ / "mapper.state"; }
  test::ScratchFolder scratch_;
  std::unique_ptr<Mapper> mapper_;
};

TEST_F(MapperFile, ALoadedMapperIsTheSavedOneAndGoesOnMappingAsIt) {
  const std::unique_ptr<Mapper> loaded = load_mapper_file(file());
  expect_same_maps(*loaded, *mapper_);
  EXPECT_EQ(config_to_json(loaded->config()).dump(), config_to_json(mapper_->config()).dump());
  EXPECT_EQ(loaded->sensor().type, mapper_->sensor().type);
  EXPECT_EQ(loaded->sensor().max_range, mapper_->sensor().max_range);
  ASSERT_EQ(loaded->sensor().intrinsics.has_value(), mapper_->sensor().intrinsics.has_value());
  if (loaded->sensor().intrinsics) {
    EXPECT_EQ(loaded->sensor().intrinsics->fx, mapper_->sensor().intrinsics->fx);
  }
  map_fifth_frames(*loaded, 4, 7);
  map_fifth_frames(*mapper_, 4, 7);
  expect_same_maps(*loaded, *mapper_);
}

TEST_F(MapperFile, AMergedMapperStaysMerged) {
  Mapper other(labels_run_config(), sim::sensor_info(default_arena().sensor));
  map_fifth_frames(other, 4, 6);
  mapper_->merge(other);
  save_mapper_file(file(), *mapper_);
  const std::unique_ptr<Mapper> loaded = load_mapper_file(file());
  EXPECT_TRUE(loaded->merged());
  expect_same_maps(*loaded, *mapper_);
}

TEST_F(MapperFile, DamagedTruncatedForeignAndOtherVersionFilesAreRefused) {
  const std::string good = bytes_of_file(file());
  std::string damaged = good;
  damaged[damaged.size() / 2] ^= 0x20;
  write_bytes(file(), damaged);
  std::string e = load_error(file());
  EXPECT_NE(e.find("damaged"), std::string::npos) << e;
  EXPECT_NE(e.find(file().string()), std::string::npos) << e;

  write_bytes(file(), good.substr(0, good.size() / 3));
  e = load_error(file());
  EXPECT_NE(e.find("damaged"), std::string::npos) << e;
  write_bytes(file(), "SARMAP");
  EXPECT_NE(load_error(file()).find("not a sarmap Mapper file"), std::string::npos);

  // A checkpoint is another kind of file.
  save_checkpoint(scratch_ / "state.bin", {"fingerprint", 4, 4, 1.0}, *mapper_);
  EXPECT_NE(load_error(scratch_ / "state.bin").find("not a sarmap Mapper file"), std::string::npos);

  // Another version, with a valid digest.
  std::string body = good.substr(0, good.size() - 64);
  body[8] = static_cast<char>(kMapperFileVersion + 1);
  write_bytes(file(), body + sha256_hex(body));
  e = load_error(file());
  EXPECT_NE(e.find("version 2"), std::string::npos) << e;

  // A missing file is an I/O error naming it.
  fs::remove(file());
  try {
    load_mapper_file(file());
    ADD_FAILURE() << "loaded a missing file";
  } catch (const Error& error) {
    EXPECT_EQ(error.code(), ErrorCode::Io);
  }
}

}  // namespace
}  // namespace sarmap::pipeline
