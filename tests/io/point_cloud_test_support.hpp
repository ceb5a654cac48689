// Helpers for the point-cloud file tests: a deterministic cloud with every
// attribute, exact comparison of two clouds, a scratch folder, and paths into
// tests/data.
#pragma once

#include <unistd.h>

#include <bit>
#include <cmath>
#include <cstdint>
#include <filesystem>
#include <functional>
#include <string>
#include <type_traits>

#include <gtest/gtest.h>

#include "engine/core/error.hpp"
#include "engine/core/point_buffer.hpp"
#include "test_random.hpp"

namespace sarmap::test {

inline std::filesystem::path data_path(const std::string& relative) {
  return std::filesystem::path(SARMAP_TEST_DATA_DIR) / relative;
}

// A fresh folder under the system temp dir, removed with the object.
class ScratchDir {
 public:
  explicit ScratchDir(const std::string& name) {
    const auto* info = ::testing::UnitTest::GetInstance()->current_test_info();
    std::string unique = name;
    if (info != nullptr) unique += std::string("_") + info->test_suite_name() + "_" + info->name();
    for (char& c : unique) {
      if (c == '/') c = '_';
    }
    // The process id too: two suites running at once must not share a folder.
    path_ = std::filesystem::temp_directory_path() / ("sarmap_" + unique + "_" + std::to_string(::getpid()));
    std::filesystem::remove_all(path_);
    std::filesystem::create_directories(path_);
  }
  ~ScratchDir() {
    std::error_code ignored;
    std::filesystem::remove_all(path_, ignored);
  }
  std::filesystem::path operator/(const std::string& file) const { return path_ / file; }
  const std::filesystem::path& path() const { return path_; }

 private:
  std::filesystem::path path_;
};

struct CloudAttributes {
  bool colors = true, labels = true, gt_labels = true, normals = true, intensity = true, scores = true;
};

inline PointBuffer make_cloud(std::size_t n, std::uint64_t seed, CloudAttributes with = {}) {
  Random random(seed);
  PointBuffer points(n);
  if (with.colors) points.enable_colors();
  if (with.labels) points.enable_labels();
  if (with.gt_labels) points.enable_gt_labels();
  if (with.normals) points.enable_normals();
  if (with.intensity) points.enable_intensity();
  if (with.scores) {
    points.add_score("terrain");
    points.add_score("wall");
  }
  for (std::size_t i = 0; i < n; ++i) {
    points.x()[i] = random.uniform(-50.0f, 50.0f);
    points.y()[i] = random.uniform(-50.0f, 50.0f);
    points.z()[i] = random.uniform(-2.0f, 8.0f);
    if (with.colors) {
      points.red()[i] = random.byte();
      points.green()[i] = random.byte();
      points.blue()[i] = random.byte();
    }
    if (with.labels) points.labels()[i] = static_cast<std::uint8_t>(random.next() % 6);
    if (with.gt_labels) points.gt_labels()[i] = static_cast<std::uint8_t>(random.next() % 6);
    if (with.normals) {
      points.normal_x()[i] = random.uniform(-1.0f, 1.0f);
      points.normal_y()[i] = random.uniform(-1.0f, 1.0f);
      points.normal_z()[i] = random.uniform(-1.0f, 1.0f);
    }
    if (with.intensity) points.intensity()[i] = random.uniform(0.0f, 4096.0f);
    for (std::size_t s = 0; s < points.score_count(); ++s) points.score(s)[i] = random.uniform(0.0f, 1.0f);
  }
  return points;
}

template <class A, class B>
void expect_same_array(const A& a, const B& b, const std::string& what) {
  ASSERT_EQ(a.size(), b.size()) << what;
  for (std::size_t i = 0; i < a.size(); ++i) {
    // Bitwise for floats, so -0.0 and every last digit must survive.
    if constexpr (std::is_floating_point_v<std::decay_t<decltype(a[0])>>) {
      ASSERT_EQ(std::bit_cast<std::uint32_t>(a[i]), std::bit_cast<std::uint32_t>(b[i]))
          << what << "[" << i << "]: " << a[i] << " vs " << b[i];
    } else {
      ASSERT_EQ(+a[i], +b[i]) << what << "[" << i << "]";
    }
  }
}

// Every enabled attribute and every value equal.
inline void expect_same_cloud(const PointBuffer& expected, const PointBuffer& actual) {
  ASSERT_EQ(expected.size(), actual.size());
  expect_same_array(expected.x(), actual.x(), "x");
  expect_same_array(expected.y(), actual.y(), "y");
  expect_same_array(expected.z(), actual.z(), "z");
  ASSERT_EQ(expected.has_colors(), actual.has_colors());
  ASSERT_EQ(expected.has_labels(), actual.has_labels());
  ASSERT_EQ(expected.has_gt_labels(), actual.has_gt_labels());
  ASSERT_EQ(expected.has_normals(), actual.has_normals());
  ASSERT_EQ(expected.has_intensity(), actual.has_intensity());
  ASSERT_EQ(expected.score_names(), actual.score_names());
  if (expected.has_colors()) {
    expect_same_array(expected.red(), actual.red(), "red");
    expect_same_array(expected.green(), actual.green(), "green");
    expect_same_array(expected.blue(), actual.blue(), "blue");
  }
  if (expected.has_labels()) expect_same_array(expected.labels(), actual.labels(), "label");
  if (expected.has_gt_labels()) expect_same_array(expected.gt_labels(), actual.gt_labels(), "gt_label");
  if (expected.has_normals()) {
    expect_same_array(expected.normal_x(), actual.normal_x(), "nx");
    expect_same_array(expected.normal_y(), actual.normal_y(), "ny");
    expect_same_array(expected.normal_z(), actual.normal_z(), "nz");
  }
  if (expected.has_intensity()) expect_same_array(expected.intensity(), actual.intensity(), "intensity");
  for (std::size_t s = 0; s < expected.score_count(); ++s) {
    expect_same_array(expected.score(s), actual.score(s), "score " + expected.score_names()[s]);
  }
}

// Runs fn, which must throw sarmap::Error; returns it (a failed expectation
// and an Io error otherwise).
inline Error error_from(const std::function<void()>& fn) {
  try {
    fn();
  } catch (const Error& e) {
    return e;
  }
  ADD_FAILURE() << "expected a sarmap::Error";
  return Error(ErrorCode::Io, "<no error thrown>");
}

}  // namespace sarmap::test
