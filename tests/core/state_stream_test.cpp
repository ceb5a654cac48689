// The checkpoint byte stream: values, arrays and strings read back as
// written; tags, truncation and impossible counts are errors naming the
// stream and the offset, before anything is allocated.
#include "engine/core/state_stream.hpp"

#include <gtest/gtest.h>

#include <cmath>
#include <cstdint>
#include <functional>
#include <limits>
#include <string>
#include <vector>

#include "engine/core/error.hpp"
#include "engine/core/point_buffer.hpp"
#include "engine/core/stage_profile.hpp"

namespace sarmap {
namespace {

std::string error_of(const std::function<void()>& f) {
  try {
    f();
  } catch (const Error& e) {
    EXPECT_EQ(e.code(), ErrorCode::Parse);
    return e.what();
  }
  return "";
}

TEST(StateStream, ReadsBackWhatWasWritten) {
  StateWriter out;
  out.tag("TEST");
  out.put<double>(-0.1);
  out.put<std::uint8_t>(7);
  out.put_vector(std::vector<float>{1.5f, std::numeric_limits<float>::infinity(), -0.0f});
  out.put_vector(std::vector<std::uint64_t>{});
  out.put_string("wall");
  StateReader in(out.bytes(), "state.bin");
  in.expect_tag("TEST");
  EXPECT_EQ(in.get<double>(), -0.1);
  EXPECT_EQ(in.get<std::uint8_t>(), 7);
  const std::vector<float> floats = in.get_vector<float>();
  ASSERT_EQ(floats.size(), 3u);
  EXPECT_EQ(floats[0], 1.5f);
  EXPECT_TRUE(std::signbit(floats[2]));
  EXPECT_TRUE(in.get_vector<std::uint64_t>().empty());
  EXPECT_EQ(in.get_string(), "wall");
  EXPECT_NO_THROW(in.expect_end());
}

TEST(StateStream, ErrorsNameTheStreamAndOffset) {
  StateWriter out;
  out.tag("ABCD");
  out.put<std::uint32_t>(1);
  std::string e = error_of([&] {
    StateReader in(out.bytes(), "ck.bin");
    in.expect_tag("WXYZ");
  });
  EXPECT_NE(e.find("ck.bin (byte offset 0)"), std::string::npos) << e;
  EXPECT_NE(e.find("WXYZ"), std::string::npos) << e;
  e = error_of([&] {
    StateReader in(out.bytes(), "ck.bin");
    in.expect_tag("ABCD");
    in.get<std::uint64_t>();
  });
  EXPECT_NE(e.find("truncated"), std::string::npos) << e;
  e = error_of([&] {
    StateReader in(out.bytes(), "ck.bin");
    in.expect_tag("ABCD");
    in.expect_end();
  });
  EXPECT_NE(e.find("4 bytes follow"), std::string::npos) << e;
}

TEST(StateStream, ImpossibleCountsAreRefusedBeforeAllocating) {
  for (std::uint64_t count : {std::uint64_t{3}, std::uint64_t{1} << 40, ~std::uint64_t{0}}) {
    StateWriter out;
    out.put(count);
    out.put<std::uint64_t>(0);  // 8 bytes: room for 2 floats, not 3
    StateReader in(out.bytes(), "s");
    const std::string e = error_of([&] { in.get_vector<float>(); });
    EXPECT_NE(e.find("does not fit"), std::string::npos) << count << ": " << e;
  }
}

TEST(StateStream, PointBufferRoundTripsEveryAttribute) {
  PointBuffer points;
  points.push_back(1, 2, 3);
  points.push_back(-4, 5.5f, 6);
  points.enable_labels();
  points.labels()[1] = 3;
  points.enable_gt_labels();
  points.enable_colors();
  points.red()[0] = 200;
  points.enable_intensity();
  points.enable_normals();
  points.normal_z()[1] = 1;
  points.score(points.add_score("wall"))[0] = 0.25f;
  StateWriter out;
  points.save_state(out);
  PointBuffer loaded;
  StateReader in(out.bytes(), "s");
  loaded.load_state(in);
  in.expect_end();
  StateWriter again;
  loaded.save_state(again);
  EXPECT_EQ(out.bytes(), again.bytes());
  EXPECT_EQ(loaded.labels()[1], 3);
  EXPECT_EQ(loaded.red()[0], 200);
  EXPECT_EQ(loaded.score(loaded.find_score("wall"))[0], 0.25f);
  // Every truncation fails and leaves the target as it was.
  for (std::size_t size = 0; size < out.bytes().size(); ++size) {
    PointBuffer target;
    target.push_back(9, 9, 9);
    StateReader cut(std::string_view(out.bytes()).substr(0, size), "s");
    EXPECT_THROW(target.load_state(cut), Error) << size;
    EXPECT_EQ(target.size(), 1u);
  }
}

TEST(StateStream, ProfileGoesOnCountingAfterALoad) {
  StageProfile profile;
  profile.begin_scan();
  profile.add_time("metric", 0.5);
  profile.add_count("metric", "rays", 10);
  profile.skip_scan(3, "frame 3", "bad", false);
  StateWriter out;
  profile.save_state(out);
  StageProfile loaded;
  StateReader in(out.bytes(), "s");
  loaded.load_state(in);
  loaded.begin_scan();
  loaded.add_time("metric", 0.25);
  loaded.add_count("metric", "rays", 5);
  EXPECT_EQ(loaded.scan_count(), 2u);
  EXPECT_EQ(loaded.counter("metric", "rays"), 15);
  EXPECT_EQ(loaded.skipped_scans(), 1u);
  EXPECT_DOUBLE_EQ(loaded.stats("metric").total_s, 0.75);
}

}  // namespace
}  // namespace sarmap
