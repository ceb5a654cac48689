// Damaged copies of valid files (cut at every length, random bytes changed)
// must read either successfully or with a sarmap::Error: never a crash, a
// hang or an allocation out of proportion to the file (run under ASan in CI).
#include <fstream>
#include <gtest/gtest.h>
#include <iterator>
#include <string>

#include "engine/io/point_cloud_file.hpp"
#include "point_cloud_test_support.hpp"
#include "tests/file_bytes.hpp"

namespace sarmap {
namespace {

using test::slurp;
using test::spit;

// Reads path and reports whether it failed with sarmap::Error; anything else
// escaping (std::bad_alloc, std::length_error, ...) fails the test.
bool reads_or_fails_cleanly(const std::filesystem::path& path, bool& failed) {
  try {
    const PointBuffer cloud = read_point_cloud(path);
    failed = false;
    return cloud.size() <= 1000;  // never more points than the file could hold
  } catch (const Error&) {
    failed = true;
    return true;
  } catch (const std::exception& e) {
    ADD_FAILURE() << path << ": escaped as " << typeid(e).name() << ": " << e.what();
    return false;
  }
}

struct Variant {
  const char* name;
  const char* extension;
  PointCloudWriteOptions options;
};

class CorruptedFile : public ::testing::TestWithParam<Variant> {};

TEST_P(CorruptedFile, EveryTruncationFailsCleanly) {
  test::ScratchDir dir("corrupt");
  const auto original = dir / (std::string("original") + GetParam().extension);
  write_point_cloud(original, test::make_cloud(12, 41), GetParam().options);
  const std::string bytes = slurp(original);
  const auto damaged = dir / (std::string("damaged") + GetParam().extension);
  for (std::size_t length = 0; length < bytes.size(); ++length) {
    spit(damaged, bytes.substr(0, length));
    bool failed = false;
    ASSERT_TRUE(reads_or_fails_cleanly(damaged, failed)) << "cut at " << length;
    // A shorter file can only read when the cut falls in trailing whitespace
    // of an ASCII file.
    if (!failed) {
      EXPECT_FALSE(GetParam().options.binary) << "binary file cut at " << length << " still read";
    }
  }
}

TEST_P(CorruptedFile, RandomByteChangesFailCleanly) {
  test::ScratchDir dir("corrupt");
  const auto original = dir / (std::string("original") + GetParam().extension);
  write_point_cloud(original, test::make_cloud(12, 42), GetParam().options);
  const std::string bytes = slurp(original);
  const auto damaged = dir / (std::string("damaged") + GetParam().extension);
  test::Random random(43);
  for (int trial = 0; trial < 2000; ++trial) {
    std::string copy = bytes;
    const int changes = 1 + static_cast<int>(random.next() % 4);
    for (int c = 0; c < changes; ++c) copy[random.next() % copy.size()] = static_cast<char>(random.byte());
    spit(damaged, copy);
    bool failed = false;
    ASSERT_TRUE(reads_or_fails_cleanly(damaged, failed)) << "trial " << trial;
  }
}

INSTANTIATE_TEST_SUITE_P(
    Formats, CorruptedFile,
    ::testing::Values(Variant{"PlyBinary", ".ply", {.binary = true}}, Variant{"PlyAscii", ".ply", {.binary = false}},
                      Variant{"PcdBinary", ".pcd", {.binary = true}}, Variant{"PcdAscii", ".pcd", {.binary = false}},
                      Variant{"PcdCompressed", ".pcd", {.binary = true, .compressed = true}}),
    [](const auto& info) { return std::string(info.param.name); });

}  // namespace
}  // namespace sarmap
