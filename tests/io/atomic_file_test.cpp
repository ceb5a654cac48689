#include "engine/io/atomic_file.hpp"

#include <filesystem>
#include <fstream>
#include <gtest/gtest.h>
#include <iterator>
#include <string>
#include <unistd.h>
#include "tests/file_bytes.hpp"

namespace sarmap {
namespace {

using test::slurp;

TEST(AtomicFileWriter, CommitReplacesTargetAndAbandonLeavesItIntact) {
  // Unique per process: ctest may run test processes in parallel.
  const auto dir = std::filesystem::temp_directory_path() / ("sarmap_atomic_test_" + std::to_string(::getpid()));
  std::filesystem::remove_all(dir);
  std::filesystem::create_directories(dir);
  const auto target = dir / "out.txt";
  {
    AtomicFileWriter w(target);
    w.write("first");
    w.commit();
  }
  EXPECT_EQ(slurp(target), "first");
  {
    AtomicFileWriter w(target);
    w.write("half-writ");
    // destroyed without commit, as when an error interrupts a writer
  }
  EXPECT_EQ(slurp(target), "first");
  // No temporary file is left behind.
  EXPECT_EQ(std::distance(std::filesystem::directory_iterator(dir), std::filesystem::directory_iterator()), 1);
  std::filesystem::remove_all(dir);
}

}  // namespace
}  // namespace sarmap
