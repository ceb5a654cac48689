// Limits on one input file, checked before anything is allocated for it: a
// file larger than max_file_bytes (a sparse 5 GiB file: no disk used), a
// header declaring more points than max_points, a depth image with more
// pixels; each error names the file and the limit, and a file at the limit
// still reads.
#include "engine/io/input_limits.hpp"

#include <gtest/gtest.h>

#include <cstdint>
#include <filesystem>
#include <fstream>
#include <functional>
#include <string>
#include <vector>

#include "engine/core/error.hpp"
#include "engine/io/depth_image.hpp"
#include "engine/io/file_bytes.hpp"
#include "engine/io/point_cloud_file.hpp"
#include "engine/io/sarmap_sequence_manifest.hpp"
#include "tests/io/png_test_writer.hpp"
#include "tests/io/scratch_folder.hpp"

namespace sarmap {
namespace {

namespace fs = std::filesystem;

std::string error_of(const std::function<void()>& f, ErrorCode expected = ErrorCode::OutOfRange) {
  try {
    f();
  } catch (const Error& e) {
    EXPECT_EQ(e.code(), expected) << e.what();
    return e.what();
  }
  ADD_FAILURE() << "no error";
  return "";
}

void write_text(const fs::path& path, const std::string& text) { std::ofstream(path, std::ios::binary) << text; }

std::string ascii_ply(std::uint64_t declared, std::size_t written) {
  std::string text = "ply\nformat ascii 1.0\nelement vertex " + std::to_string(declared) +
                     "\nproperty float x\nproperty float y\nproperty float z\nend_header\n";
  for (std::size_t i = 0; i < written; ++i) text += "1 2 3\n";
  return text;
}

class InputLimitsTest : public ::testing::Test {
 protected:
  test::ScratchFolder scratch_;
};

TEST_F(InputLimitsTest, AFileOverTheByteLimitIsRefusedBeforeReading) {
  const fs::path file = scratch_ / "cloud.ply";
  write_text(file, ascii_ply(4, 4));
  const auto size = fs::file_size(file);
  EXPECT_EQ(read_file_bytes(file, size).size(), size);  // at the limit: read
  const std::string e = error_of([&] { read_file_bytes(file, size - 1); });
  EXPECT_NE(e.find(file.string()), std::string::npos) << e;
  EXPECT_NE(e.find("more than the limit of " + std::to_string(size - 1) + " bytes"), std::string::npos) << e;
  InputLimits limits;
  limits.max_file_bytes = size - 1;
  EXPECT_NE(error_of([&] { read_point_cloud(file, nullptr, limits); }).find("--max-file-mb"), std::string::npos);
}

TEST_F(InputLimitsTest, DefaultLimitRefusesAHugeSparseFileWithoutReadingIt) {
  const fs::path file = scratch_ / "huge.ply";
  write_text(file, ascii_ply(4, 4));
  fs::resize_file(file, (std::uint64_t{5} << 30));  // sparse: no blocks written
  EXPECT_NE(error_of([&] { read_point_cloud(file); }).find("bytes for one input file"), std::string::npos);
  const fs::path json = scratch_ / "sequence.json";
  write_text(json, "{}");
  fs::resize_file(json, (std::uint64_t{5} << 30));
  EXPECT_NE(error_of([&] { read_sequence_manifest(json); }).find(json.string()), std::string::npos);
}

TEST_F(InputLimitsTest, AHeaderDeclaringTooManyPointsIsRefusedBeforeAllocating) {
  InputLimits limits;
  limits.max_points = 4;
  const fs::path at_limit = scratch_ / "four.ply";
  write_text(at_limit, ascii_ply(4, 4));
  EXPECT_EQ(read_point_cloud(at_limit, nullptr, limits).size(), 4u);
  const fs::path over = scratch_ / "five.ply";
  write_text(over, ascii_ply(5, 5));
  std::string e = error_of([&] { read_point_cloud(over, nullptr, limits); });
  EXPECT_NE(e.find(over.string() + ": the header declares 5 points, more than the limit of 4"), std::string::npos)
      << e;
  // A tiny file declaring four billion points fails the size check first,
  // whose error says more; both come before anything is allocated.
  const fs::path lying = scratch_ / "lying.ply";
  write_text(lying, ascii_ply(4'000'000'000ULL, 1));
  e = error_of([&] { read_point_cloud(lying); }, ErrorCode::Parse);
  EXPECT_NE(e.find("header declares 4000000000 vertices but only"), std::string::npos) << e;
  const fs::path pcd = scratch_ / "nine.pcd";
  std::string text = "VERSION .7\nFIELDS x y z\nSIZE 4 4 4\nTYPE F F F\nCOUNT 1 1 1\nWIDTH 9\nHEIGHT 1\n"
                     "VIEWPOINT 0 0 0 1 0 0 0\nPOINTS 9\nDATA ascii\n";
  for (int i = 0; i < 9; ++i) text += "1 2 3\n";
  write_text(pcd, text);
  limits.max_points = 8;
  e = error_of([&] { read_point_cloud(pcd, nullptr, limits); });
  EXPECT_NE(e.find("declares 9 points, more than the limit of 8"), std::string::npos) << e;
  limits.max_points = 9;
  EXPECT_EQ(read_point_cloud(pcd, nullptr, limits).size(), 9u);
}

TEST_F(InputLimitsTest, ADepthImageWithMorePixelsThanPointsAllowedIsRefused) {
  const fs::path png = scratch_ / "depth.png";
  test::write_png_gray16(png, 8, 6, std::vector<std::uint16_t>(48, 1000));
  InputLimits limits;
  limits.max_points = 48;
  EXPECT_EQ(read_depth_png(png, limits).width, 8);
  limits.max_points = 47;
  const std::string e = error_of([&] { read_depth_png(png, limits); });
  EXPECT_NE(e.find("8x6 image has more pixels than the limit of 47"), std::string::npos) << e;
}

}  // namespace
}  // namespace sarmap
