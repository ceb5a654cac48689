// Checkpoints: a Mapper that loads another's state between two scans goes on
// exactly as the other would (every map bit for bit), for each classifier
// kind; a checkpoint of other settings, a damaged or truncated file, or
// another classifier's state is refused with an error naming it.
#include "engine/pipeline/checkpoint.hpp"

#include <gtest/gtest.h>

#include <filesystem>
#include <fstream>
#include <iterator>
#include <memory>
#include <string>
#include <vector>

#include "engine/core/error.hpp"
#include "engine/sim/arena.hpp"
#include "engine/sim/simulator.hpp"
#include "tests/io/scratch_folder.hpp"
#include "tests/pipeline/default_arena.hpp"
#include "tests/pipeline/same_maps.hpp"
#include "tests/release_only.hpp"

namespace sarmap::pipeline {
namespace {

namespace fs = std::filesystem;

using testing::default_arena;

MapperConfig config_for(const std::string& classifier, std::size_t max_blocks = 0) {
  MapperConfig config;
  config.bounds.max_blocks = max_blocks;
  config.classifier.kind = classifier_kind_from_name(classifier);
  if (classifier == "dgcnn") {
    config.classifier.model = fs::path(SARMAP_SOURCE_DIR) / "datasets" / "models" / "ramps-dgcnn.safetensors";
  }
  return config;
}

void integrate_frames(Mapper& mapper, std::size_t from, std::size_t to, std::size_t stride) {
  const sim::Simulator simulator(default_arena());
  for (std::size_t f = from; f < to; f += stride) {
    Scan scan = simulator.simulate(f);
    mapper.integrate(scan);
  }
}

// Runs frames [0, end) in one Mapper, and in two: the second loads the
// first's checkpoint taken after `cut`.
// Returns the points the segment stage forgot in the whole run.
double expect_resume_matches(const std::string& classifier, std::size_t cut, std::size_t end, std::size_t stride,
                             std::size_t max_blocks = 0) {
  test::ScratchFolder scratch;
  const MapperConfig config = config_for(classifier, max_blocks);
  const SensorInfo sensor = sim::sensor_info(default_arena().sensor);
  Mapper whole(config, sensor);
  integrate_frames(whole, 0, end, stride);

  const fs::path file = scratch / "state.bin";
  {
    Mapper first(config, sensor);
    integrate_frames(first, 0, cut, stride);
    save_checkpoint(file, {"fingerprint", cut, first.profile().scan_count(), 1.5}, first);
  }
  Mapper resumed(config, sensor);
  const CheckpointHeader header = load_checkpoint(file, "fingerprint", resumed);
  EXPECT_EQ(header.next_frame, cut);
  EXPECT_EQ(header.elapsed_s, 1.5);
  integrate_frames(resumed, cut, end, stride);
  expect_same_maps(whole, resumed);
  return whole.profile().counter("segment", "points_forgotten");
}

TEST(Checkpoint, LabelsRunResumesBitForBit) {
  // Near the start, mid-run and late; under the sanitizers one cut covers the
  // save and load paths (each run there costs ten times as much).
  const std::vector<std::size_t> cuts =
      kSanitizedBuild ? std::vector<std::size_t>{52} : std::vector<std::size_t>{4, 52, 100};
  for (std::size_t cut : cuts) {
    SCOPED_TRACE(cut);
    expect_resume_matches("labels", cut, 160, 4);
  }
}

TEST(Checkpoint, GeometricRunResumesBitForBit) { expect_resume_matches("geometric", 24, 48, 4); }

TEST(Checkpoint, DgcnnRunResumesBitForBitWithItsRampDecks) {
  RELEASE_ONLY();  // the network under the sanitizers takes minutes; DgcnnClassifier's own tests cover it there
  expect_resume_matches("dgcnn", 60, 100, 20);
}

// A bounded map forgets segment and kept points in passes, every eighth of
// the map's blocks dropped: how far the next pass is is part of the state.
TEST(Checkpoint, BoundedRunResumesBitForBitAcrossForgetting) {
  for (std::size_t cut : {21u, 42u}) {
    SCOPED_TRACE(cut);
    EXPECT_GT(expect_resume_matches("labels", cut, 60, 3, 400), 0.0);
  }
}

TEST(Checkpoint, ResumingAfterTheLastScanKeepsTheMaps) { expect_resume_matches("labels", 40, 40, 8); }

class CheckpointRefusal : public ::testing::Test {
 protected:
  void SetUp() override {
    Mapper mapper(config_for("labels"), sim::sensor_info(default_arena().sensor));
    integrate_frames(mapper, 0, 40, 8);
    save_checkpoint(file_, {"fingerprint", 40, 5, 0.0}, mapper);
    std::ifstream in(file_, std::ios::binary);
    bytes_.assign(std::istreambuf_iterator<char>(in), {});
  }
  void write(const std::string& bytes) { std::ofstream(file_, std::ios::binary | std::ios::trunc) << bytes; }
  std::string load_error(const MapperConfig& config, const std::string& fingerprint = "fingerprint") {
    Mapper mapper(config, sim::sensor_info(default_arena().sensor));
    try {
      load_checkpoint(file_, fingerprint, mapper);
    } catch (const Error& e) {
      return e.what();
    }
    return "";
  }
  test::ScratchFolder scratch_;
  fs::path file_ = scratch_ / "state.bin";
  std::string bytes_;
};

TEST_F(CheckpointRefusal, OtherSettingsOrInput) {
  const std::string e = load_error(config_for("labels"), "another");
  EXPECT_NE(e.find("other settings or input"), std::string::npos) << e;
}

TEST_F(CheckpointRefusal, AnotherClassifiersState) {
  const std::string e = load_error(config_for("geometric"));
  EXPECT_NE(e.find("labels classifier"), std::string::npos) << e;
}

TEST_F(CheckpointRefusal, AnotherVoxelSize) {
  MapperConfig config = config_for("labels");
  config.voxel = 0.1;
  const std::string e = load_error(config);
  EXPECT_NE(e.find("voxel"), std::string::npos) << e;
}

TEST_F(CheckpointRefusal, ADamagedOrTruncatedFile) {
  std::string damaged = bytes_;
  damaged[damaged.size() / 2] ^= 0x40;
  write(damaged);
  std::string e = load_error(config_for("labels"));
  EXPECT_NE(e.find("damaged"), std::string::npos) << e;
  EXPECT_NE(e.find(file_.string()), std::string::npos) << e;
  write(bytes_.substr(0, bytes_.size() / 3));
  e = load_error(config_for("labels"));
  EXPECT_NE(e.find("damaged"), std::string::npos) << e;
  write("SARMAP");
  e = load_error(config_for("labels"));
  EXPECT_NE(e.find("not a sarmap checkpoint"), std::string::npos) << e;
  fs::remove(file_);
  e = load_error(config_for("labels"));
  EXPECT_NE(e.find("cannot open"), std::string::npos) << e;
}

// Kept points whose voxel keys do not follow from their positions (a state
// of another semantic_points_voxel handed to load_state directly) are refused.
TEST_F(CheckpointRefusal, KeptPointsOfAnotherVoxelSize) {
  Mapper mapper(config_for("labels"), sim::sensor_info(default_arena().sensor));
  integrate_frames(mapper, 0, 16, 8);
  ASSERT_GT(mapper.semantic_points().size(), 0u);
  StateWriter out;
  mapper.save_state(out);
  const auto error_loading_into = [&out](double semantic_points_voxel) -> std::string {
    MapperConfig config = config_for("labels");
    config.semantic_points_voxel = semantic_points_voxel;
    Mapper target(config, sim::sensor_info(default_arena().sensor));
    StateReader in(out.bytes(), "state");
    try {
      target.load_state(in);
    } catch (const Error& e) {
      return e.what();
    }
    return "";
  };
  EXPECT_EQ(error_loading_into(config_for("labels").semantic_points_voxel), "");
  std::string e = error_loading_into(0.1);
  EXPECT_NE(e.find("outside the voxel of its key"), std::string::npos) << e;
  e = error_loading_into(0);
  EXPECT_NE(e.find("keeps none"), std::string::npos) << e;
}

// Past the hash (a stream handed to load_state directly), every truncation
// is a clear error, never a crash or a runaway allocation.
TEST_F(CheckpointRefusal, EveryTruncatedStateIsAnError) {
  NOT_UNDER_TSAN();
  Mapper mapper(config_for("labels"), sim::sensor_info(default_arena().sensor));
  integrate_frames(mapper, 0, 16, 8);
  StateWriter out;
  mapper.save_state(out);
  const std::string& state = out.bytes();
  for (std::size_t size = 0; size < state.size(); size += 1 + state.size() / 300) {
    Mapper target(config_for("labels"), sim::sensor_info(default_arena().sensor));
    StateReader in(std::string_view(state).substr(0, size), "state");
    EXPECT_THROW(target.load_state(in), Error) << size;
  }
}

}  // namespace
}  // namespace sarmap::pipeline
