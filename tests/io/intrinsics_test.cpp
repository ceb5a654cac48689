#include "engine/io/intrinsics.hpp"

#include <gmock/gmock.h>
#include <gtest/gtest.h>

#include "engine/core/error.hpp"
#include "error_message.hpp"
#include "scratch_folder.hpp"

namespace sarmap {
namespace {

using test::error_message;
using ::testing::HasSubstr;

TEST(Intrinsics, ReadsJsonAndMatrixText) {
  test::ScratchFolder dir;
  const auto json = dir.write(
      "k.json", R"({"fx": 525.0, "fy": 520.5, "cx": 319.5, "cy": 239.5, "width": 640, "height": 480})");
  PinholeIntrinsics k = read_intrinsics_file(json);
  EXPECT_EQ(k.fx, 525.0);
  EXPECT_EQ(k.fy, 520.5);
  EXPECT_EQ(k.cx, 319.5);
  EXPECT_EQ(k.cy, 239.5);
  EXPECT_EQ(k.width, 640);
  EXPECT_EQ(k.height, 480);

  const auto text = dir.write("k.txt", "# camera matrix\n585 0 320\n0 586.5 240\n\n0 0 1\n");
  k = read_intrinsics_file(text);
  EXPECT_EQ(k.fx, 585.0);
  EXPECT_EQ(k.fy, 586.5);
  EXPECT_EQ(k.cx, 320.0);
  EXPECT_EQ(k.cy, 240.0);
  EXPECT_EQ(k.width, 0);  // unknown
}

TEST(Intrinsics, BadFilesNameTheProblem) {
  test::ScratchFolder dir;
  auto msg = [&](const std::string& name, const std::string& text) {
    const auto path = dir.write(name, text);
    return error_message([&] { read_intrinsics_file(path); });
  };
  EXPECT_THAT(msg("a.json", R"({"fx": 1, "fy": 1, "cx": 0})"), HasSubstr("missing key \"cy\""));
  EXPECT_THAT(msg("b.json", R"({"fx": 1, "fy": 1, "cx": 0, "cy": 0, "k1": 0.1})"),
              HasSubstr("unknown key \"k1\""));
  EXPECT_THAT(msg("c.json", R"({"fx": "big", "fy": 1, "cx": 0, "cy": 0})"),
              HasSubstr("fx: expected a number"));
  EXPECT_THAT(msg("d.json", R"({"fx": -5, "fy": 1, "cx": 0, "cy": 0})"), HasSubstr("must be positive"));
  EXPECT_THAT(msg("e.json", R"({"fx": 1, "fy": 1, "cx": 0, "cy": 0, "width": 640})"),
              HasSubstr("width and height must be given together"));
  EXPECT_THAT(msg("f.json", R"({"fx": 1,)"), HasSubstr("invalid JSON"));
  EXPECT_THAT(msg("g.txt", "585 0 320\n0 585 240\n"), HasSubstr("got 2 lines"));
  const std::string bad_number = msg("h.txt", "585 0 320\n0 abc 240\n0 0 1\n");
  EXPECT_THAT(bad_number, HasSubstr("h.txt:2"));
  EXPECT_THAT(bad_number, HasSubstr("K[1][1]: expected a number, got 'abc'"));
  EXPECT_THAT(msg("i.txt", "585 2 320\n0 585 240\n0 0 1\n"), HasSubstr("skew"));
  EXPECT_THAT(msg("j.txt", "585 0 320\n0 585 240\n0 0 2\n"), HasSubstr("not a pinhole camera matrix"));
  EXPECT_THAT(msg("k.txt", "585 0 320\n0 585\n0 0 1\n"), HasSubstr("k.txt:2: expected 3 values"));
  EXPECT_THAT(msg("l.txt", "585 0 320\n0 nan 240\n0 0 1\n"), HasSubstr("expected a finite number"));
  EXPECT_THAT(error_message([&] { read_intrinsics_file(dir / "absent.json"); }), HasSubstr("cannot open"));
}

TEST(Intrinsics, FindPrefersTheOptionAndNamesItWhenNothingIsThere) {
  test::ScratchFolder dir;
  const auto option = dir.write("opt.json", R"({"fx": 2, "fy": 2, "cx": 1, "cy": 1})");
  const auto folder_file = dir / "intrinsics.json";
  std::string msg = error_message([&] { find_intrinsics(std::nullopt, folder_file, "TUM RGB-D folder"); });
  EXPECT_THAT(msg, HasSubstr("intrinsics_file"));
  EXPECT_THAT(msg, HasSubstr("--intrinsics"));
  EXPECT_THAT(msg, HasSubstr("intrinsics.json"));
  dir.write("intrinsics.json", R"({"fx": 3, "fy": 3, "cx": 1, "cy": 1})");
  EXPECT_EQ(find_intrinsics(std::nullopt, folder_file, "x").fx, 3.0);
  EXPECT_EQ(find_intrinsics(option, folder_file, "x").fx, 2.0);
}

}  // namespace
}  // namespace sarmap
